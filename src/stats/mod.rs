//! Ensemble statistics: moments, quantiles, confidence intervals, bootstrap, fragility, and
//! the one-sample Kolmogorov–Smirnov test ([`ks`]).
//!
//! All reductions are serial and in the order of the input slice, so the same values in the
//! same order give the same numbers bit for bit. Randomness (the bootstrap) comes from
//! [`crate::rng::rng_for`] with [`Purpose::Bootstrap`].

pub mod fragility;
pub mod ks;

use crate::rng::{rng_for, Purpose};
use rand::RngExt;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, Normal, StudentsT};

/// Number of bootstrap resamples.
pub const BOOTSTRAP_RESAMPLES: usize = 2000;

/// Summary of a sample.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Sample size.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Standard deviation with the n − 1 divisor (NaN for n < 2).
    pub sd: f64,
    /// Coefficient of variation σ/mean (NaN for n < 2 or mean = 0).
    pub cov: f64,
    /// Minimum.
    pub min: f64,
    /// Maximum.
    pub max: f64,
    /// 5 % quantile (linear interpolation, R type 7).
    pub q05: f64,
    /// 25 % quantile.
    pub q25: f64,
    /// Median.
    pub median: f64,
    /// 75 % quantile.
    pub q75: f64,
    /// 95 % quantile.
    pub q95: f64,
    /// 95 % confidence interval of the mean, Student t with n − 1 degrees of freedom.
    pub mean_ci95: (f64, f64),
    /// 95 % prediction interval of one new realization: mean ± t σ √(1 + 1/n).
    pub prediction95: (f64, f64),
    /// 95 % percentile-bootstrap interval of σ.
    pub sd_boot95: (f64, f64),
    /// 95 % percentile-bootstrap interval of the COV.
    pub cov_boot95: (f64, f64),
}

/// Mean of a slice (NaN if empty).
pub fn mean(x: &[f64]) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    x.iter().sum::<f64>() / x.len() as f64
}

/// Standard deviation with the n − 1 divisor (NaN for n < 2).
pub fn sd(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return f64::NAN;
    }
    let m = mean(x);
    (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (x.len() - 1) as f64).sqrt()
}

/// Quantile `p` ∈ [0, 1] of a sample by linear interpolation between order statistics
/// (Hyndman & Fan type 7, the default of R and numpy). NaN if empty.
pub fn quantile(x: &[f64], p: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let mut s = x.to_vec();
    s.sort_by(f64::total_cmp);
    quantile_sorted(&s, p)
}

fn quantile_sorted(s: &[f64], p: f64) -> f64 {
    let h = (s.len() - 1) as f64 * p.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = h.ceil() as usize;
    s[lo] + (h - lo as f64) * (s[hi] - s[lo])
}

/// The Wilson score interval of a binomial proportion: `p` observed in `n` trials (`n`
/// may be fractional, an effective count), at the two-sided normal quantile `z` (1.96 for
/// 95 %). Returns `(low, high)` within \[0, 1\], containing `p`; `(0, 1)` when `n` is not
/// positive. Wilson, *J. Am. Stat. Assoc.* 22 (1927) 209–212; preferred to the Wald
/// interval near 0 and 1, where a design's probabilities sit (Brown, Cai & DasGupta,
/// *Statist. Sci.* 16 (2001) 101–133).
pub fn wilson(p: f64, n: f64, z: f64) -> (f64, f64) {
    if !(n > 0.0) || !p.is_finite() {
        return (0.0, 1.0);
    }
    let p = p.clamp(0.0, 1.0);
    let z2 = z * z;
    let centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
    let half = z / (1.0 + z2 / n) * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    ((centre - half).clamp(0.0, p), (centre + half).clamp(p, 1.0))
}

/// The two-sided 95 % Student t quantile with `dof` degrees of freedom.
pub fn t95(dof: f64) -> f64 {
    StudentsT::new(0.0, 1.0, dof).map(|t| t.inverse_cdf(0.975)).unwrap_or(f64::NAN)
}

/// Summarizes a sample. `seed` and `stream` feed the bootstrap's random stream (same
/// inputs, same interval).
pub fn summarize(x: &[f64], seed: u64, stream: u64) -> Summary {
    let n = x.len();
    let mut s = x.to_vec();
    s.sort_by(f64::total_cmp);
    let m = mean(x);
    let sdv = sd(x);
    let cov = if m != 0.0 { sdv / m } else { f64::NAN };
    let (q05, q25, median, q75, q95) = if n > 0 {
        (
            quantile_sorted(&s, 0.05),
            quantile_sorted(&s, 0.25),
            quantile_sorted(&s, 0.5),
            quantile_sorted(&s, 0.75),
            quantile_sorted(&s, 0.95),
        )
    } else {
        (f64::NAN, f64::NAN, f64::NAN, f64::NAN, f64::NAN)
    };
    let (mean_ci95, prediction95) = if n >= 2 {
        let t = t95((n - 1) as f64);
        let h = t * sdv / (n as f64).sqrt();
        let hp = t * sdv * (1.0 + 1.0 / n as f64).sqrt();
        ((m - h, m + h), (m - hp, m + hp))
    } else {
        ((f64::NAN, f64::NAN), (f64::NAN, f64::NAN))
    };
    let (sd_boot95, cov_boot95) = bootstrap_sd_cov(x, seed, stream);
    Summary {
        n,
        mean: m,
        sd: sdv,
        cov,
        min: s.first().copied().unwrap_or(f64::NAN),
        max: s.last().copied().unwrap_or(f64::NAN),
        q05,
        q25,
        median,
        q75,
        q95,
        mean_ci95,
        prediction95,
        sd_boot95,
        cov_boot95,
    }
}

/// Percentile-bootstrap 95 % intervals of σ and COV ([`BOOTSTRAP_RESAMPLES`] resamples).
pub fn bootstrap_sd_cov(x: &[f64], seed: u64, stream: u64) -> ((f64, f64), (f64, f64)) {
    let n = x.len();
    if n < 2 {
        return ((f64::NAN, f64::NAN), (f64::NAN, f64::NAN));
    }
    let mut rng = rng_for(seed, stream, Purpose::Bootstrap);
    let mut sds = Vec::with_capacity(BOOTSTRAP_RESAMPLES);
    let mut covs = Vec::with_capacity(BOOTSTRAP_RESAMPLES);
    let mut buf = vec![0.0; n];
    for _ in 0..BOOTSTRAP_RESAMPLES {
        for b in buf.iter_mut() {
            *b = x[rng.random_range(0..n)];
        }
        let s = sd(&buf);
        sds.push(s);
        covs.push(s / mean(&buf));
    }
    sds.sort_by(f64::total_cmp);
    covs.sort_by(f64::total_cmp);
    (
        (quantile_sorted(&sds, 0.025), quantile_sorted(&sds, 0.975)),
        (quantile_sorted(&covs, 0.025), quantile_sorted(&covs, 0.975)),
    )
}

/// A lognormal fragility curve P(collapse | α) = Φ(ln(α/θ)/β).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LognormalFragility {
    /// Median capacity θ (same unit as the data, e.g. degrees of tilt).
    pub median: f64,
    /// Logarithmic standard deviation β (dimensionless).
    pub beta: f64,
}

impl LognormalFragility {
    /// Maximum-likelihood fit to observed capacities (all > 0): θ = exp(mean ln x),
    /// β = the n-divisor standard deviation of ln x (Baker 2015, "Efficient analytical
    /// fragility function fitting", for complete capacity samples). `None` for fewer than
    /// 2 values or any value ≤ 0.
    pub fn fit(capacities: &[f64]) -> Option<Self> {
        // `!(c > 0.0)` also rejects NaN.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if capacities.len() < 2 || capacities.iter().any(|&c| !(c > 0.0)) {
            return None;
        }
        // ln x relative to the first capacity: θ = x₀ exp(mean ln(x/x₀)). Repeated
        // capacities then give exactly θ = x₀ and β = 0 (a step), where ln and exp of the raw
        // values would leave a round-off β of ~1e-16 and θ off in its last bits.
        let x0 = capacities[0];
        let l: Vec<f64> = capacities.iter().map(|c| (c / x0).ln()).collect();
        let m = mean(&l);
        let var = l.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / l.len() as f64;
        Some(LognormalFragility { median: x0 * m.exp(), beta: var.sqrt() })
    }

    /// P(collapse | α).
    pub fn probability(&self, alpha: f64) -> f64 {
        if alpha <= 0.0 {
            return 0.0;
        }
        if self.beta == 0.0 {
            return if alpha >= self.median { 1.0 } else { 0.0 };
        }
        let n = Normal::new(0.0, 1.0).expect("standard normal");
        n.cdf((alpha / self.median).ln() / self.beta)
    }
}

/// Empirical fragility: the fraction of capacities ≤ α (collapse at or below α).
pub fn empirical_fragility(capacities: &[f64], alpha: f64) -> f64 {
    if capacities.is_empty() {
        return f64::NAN;
    }
    capacities.iter().filter(|&&c| c <= alpha).count() as f64 / capacities.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_and_quantiles_match_hand_values() {
        let x = [2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0];
        assert_eq!(mean(&x), 5.0);
        assert!((sd(&x) - (32.0f64 / 7.0).sqrt()).abs() < 1e-15);
        assert_eq!(quantile(&x, 0.5), 4.5);
        assert_eq!(quantile(&x, 0.0), 2.0);
        assert_eq!(quantile(&x, 1.0), 9.0);
        // numpy.quantile([2,4,4,4,5,5,7,9], 0.25) = 4.0, 0.95 -> 8.3
        assert!((quantile(&x, 0.25) - 4.0).abs() < 1e-15);
        assert!((quantile(&x, 0.95) - 8.3).abs() < 1e-12);
    }

    /// Hand values: 50 of 100 gives 0.5 ± 0.0962 (R `prop.test(50, 100, correct = FALSE)`:
    /// 0.4038–0.5962); 0 of 10 gives (0, z²/(n + z²)) = (0, 0.2775); a fractional count is
    /// accepted, no count gives (0, 1).
    #[test]
    fn wilson_interval_matches_hand_values() {
        let (lo, hi) = wilson(0.5, 100.0, 1.96);
        assert!((lo - 0.403_83).abs() < 1e-4 && (hi - 0.596_17).abs() < 1e-4, "{lo} {hi}");
        let (lo, hi) = wilson(0.0, 10.0, 1.96);
        assert_eq!(lo, 0.0);
        assert!((hi - 3.8416 / 13.8416).abs() < 1e-12, "{hi}");
        let (lo, hi) = wilson(0.9, 37.5, 1.96);
        assert!(lo < 0.9 && hi > 0.9 && hi <= 1.0);
        assert_eq!(wilson(0.3, 0.0, 1.96), (0.0, 1.0));
    }

    #[test]
    fn t_interval_matches_tables() {
        // t_{0.975, 9} = 2.262157 (standard tables).
        assert!((t95(9.0) - 2.262157).abs() < 1e-5);
        let x: Vec<f64> = (1..=10).map(|v| v as f64).collect();
        let s = summarize(&x, 1, 0);
        let h = 2.262157 * sd(&x) / 10f64.sqrt();
        assert!((s.mean_ci95.0 - (5.5 - h)).abs() < 1e-4);
    }

    #[test]
    fn bootstrap_is_reproducible_and_brackets_the_estimate() {
        let x = [14.1, 15.2, 13.8, 16.0, 14.9, 15.5, 13.2, 14.4];
        let a = summarize(&x, 42, 3);
        let b = summarize(&x, 42, 3);
        assert_eq!(a, b);
        assert!(a.sd_boot95.0 < a.sd && a.sd < a.sd_boot95.1);
        assert!(a.cov_boot95.0 < a.cov && a.cov < a.cov_boot95.1);
    }

    #[test]
    fn lognormal_fit_recovers_its_parameters() {
        // Capacities at the quantiles of a lognormal(θ = 15, β = 0.1) sample.
        let n = Normal::new(0.0, 1.0).unwrap();
        let x: Vec<f64> = (1..200).map(|i| 15.0 * (0.1 * n.inverse_cdf(i as f64 / 200.0)).exp()).collect();
        let f = LognormalFragility::fit(&x).unwrap();
        assert!((f.median - 15.0).abs() < 0.01);
        assert!((f.beta - 0.1).abs() < 0.005);
        assert!((f.probability(15.0) - 0.5).abs() < 1e-3);
        assert!((empirical_fragility(&x, 15.0) - 0.5).abs() < 0.01);
    }

    /// Identical capacities (the six CBL realizations of the main job): a step at the
    /// capacity, exactly, where the general formulas leave β ≈ 4e-16 and a median 20.250000000000014.
    #[test]
    fn lognormal_fit_of_one_repeated_capacity_is_an_exact_step() {
        let f = LognormalFragility::fit(&[20.25; 6]).unwrap();
        assert_eq!((f.median, f.beta), (20.25, 0.0));
        assert_eq!(f.probability(20.25), 1.0);
        assert_eq!(f.probability(20.0), 0.0);
    }
}
