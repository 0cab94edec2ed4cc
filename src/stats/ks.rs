//! One-sample Kolmogorov–Smirnov test: does a sample follow a given law (e.g. do the values a
//! generated wall draws follow their distributions).
//!
//! The statistic is `D = sup_x |F_n(x) − F(x)|` (F_n the empirical CDF). The p-value is the
//! asymptotic Kolmogorov distribution with Stephens' small-sample correction
//! (Stephens 1970, J. R. Stat. Soc. B 32(1); as in Numerical Recipes §14.3):
//! `p = Q_KS((√n + 0.12 + 0.11/√n) D)`, `Q_KS(λ) = 2 Σ_{k≥1} (−1)^{k−1} exp(−2k²λ²)`,
//! evaluated through its theta-function dual for small λ.

/// The KS statistic of `samples` against the CDF `cdf`. NaN samples are not allowed.
/// Returns 0 for an empty sample.
pub fn ks_statistic(samples: &[f64], cdf: impl Fn(f64) -> f64) -> f64 {
    let mut xs = samples.to_vec();
    xs.sort_by(f64::total_cmp);
    let n = xs.len() as f64;
    let mut d: f64 = 0.0;
    for (i, &x) in xs.iter().enumerate() {
        let f = cdf(x);
        d = d.max(f - i as f64 / n).max((i + 1) as f64 / n - f);
    }
    d
}

/// Kolmogorov's limiting survival function Q_KS(λ) = P(√n D > λ) as n → ∞.
pub fn kolmogorov_q(lambda: f64) -> f64 {
    if lambda <= 0.0 {
        return 1.0;
    }
    if lambda < 1.18 {
        // Dual series: 1 − Q = √(2π)/λ Σ exp(−(2k−1)² π² / (8 λ²)).
        let y = (-std::f64::consts::PI.powi(2) / (8.0 * lambda * lambda)).exp();
        let mut s = 0.0;
        for k in 1..=20 {
            let e = (2 * k - 1) * (2 * k - 1);
            s += y.powi(e);
        }
        (1.0 - (2.0 * std::f64::consts::PI).sqrt() / lambda * s).clamp(0.0, 1.0)
    } else {
        let x = (-2.0 * lambda * lambda).exp();
        let mut s = 0.0;
        for k in 1..=100 {
            let kk = k * k;
            let term = x.powi(kk);
            s += if k % 2 == 1 { term } else { -term };
            if term < 1e-17 {
                break;
            }
        }
        (2.0 * s).clamp(0.0, 1.0)
    }
}

/// Asymptotic p-value of a KS statistic `d` from `n` samples.
pub fn ks_pvalue(d: f64, n: usize) -> f64 {
    let sn = (n as f64).sqrt();
    kolmogorov_q((sn + 0.12 + 0.11 / sn) * d)
}

/// `(D, p)` of the one-sample KS test.
pub fn ks_test(samples: &[f64], cdf: impl Fn(f64) -> f64) -> (f64, f64) {
    let d = ks_statistic(samples, cdf);
    (d, ks_pvalue(d, samples.len()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use statrs::stats_tests::ks_test::{ks_onesample, KSOneSampleAlternativeMethod};
    use statrs::stats_tests::NaNPolicy;

    #[test]
    fn q_is_continuous_across_the_two_series_and_has_known_values() {
        assert!((kolmogorov_q(1.18 - 1e-9) - kolmogorov_q(1.18 + 1e-9)).abs() < 1e-8);
        // Classical critical values: Q(1.3581) = 0.05, Q(1.6276) = 0.01.
        assert!((kolmogorov_q(1.3581) - 0.05).abs() < 1e-4);
        assert!((kolmogorov_q(1.6276) - 0.01).abs() < 1e-4);
        assert!((kolmogorov_q(0.5) - 0.9639).abs() < 1e-3);
    }

    #[test]
    fn agrees_with_statrs_on_the_statistic() {
        let xs: Vec<f64> = (0..500).map(|i| ((i as f64 * 0.618_033_988_75) % 1.0).powf(1.1)).collect();
        let u = statrs::distribution::Uniform::new(0.0, 1.0).unwrap();
        let (d_ref, p_ref) =
            ks_onesample(xs.clone(), &u, KSOneSampleAlternativeMethod::TwoSidedAsymptotic, NaNPolicy::Error).unwrap();
        let (d, p) = ks_test(&xs, |x| x.clamp(0.0, 1.0));
        assert!((d - d_ref).abs() < 1e-12, "{d} vs {d_ref}");
        // statrs uses the plain asymptotic λ = √n D; ours adds Stephens' correction.
        assert!((p - p_ref).abs() < 0.05, "{p} vs {p_ref}");
    }
}
