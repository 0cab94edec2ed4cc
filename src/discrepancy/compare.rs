//! Per-specimen statistics of model comparison: how a specimen's observations are weighted,
//! the per-specimen sums of scores, the standard error of two models' held-out score
//! difference, and AICc. The specimen is the independent unit throughout (a wall tested
//! once gives one collapse angle, several displacements and one mechanism, read three
//! ways).

use super::observations::{Observation, Share};

/// The weights that make a specimen's displacements one observation and its mechanism
/// another ([`Share`]): 1 for a collapse angle or an in-plane measure (the in-plane test's
/// three measures are three observables of one curve, each weighed alone like a collapse
/// angle), `1/k` for each of a specimen's `k` displacements, `1/k` for each of its `k`
/// mechanism observations (failure height, kind, start, mode: one mechanism seen, read
/// several ways).
pub fn specimen_weights(obs: &[Observation]) -> Vec<f64> {
    obs.iter()
        .map(|o| match o.observable.share() {
            Share::Own => 1.0,
            share @ (Share::Displacements | Share::Mechanism) => {
                let k = obs.iter().filter(|p| p.specimen == o.specimen && p.observable.share() == share).count();
                1.0 / k.max(1) as f64
            }
        })
        .collect()
}

/// AICc = 2k − 2 ln L + 2k(k+1)/(n − k − 1) (Hurvich & Tsai 1989) from the summed score at
/// the full-data fit, `k` parameters and `n` specimens (the independent units).
pub fn aicc(nlpd: f64, k: usize, n: usize) -> f64 {
    let (k, n) = (k as f64, n as f64);
    let corr = if n - k - 1.0 > 0.0 { 2.0 * k * (k + 1.0) / (n - k - 1.0) } else { f64::INFINITY };
    2.0 * k + 2.0 * nlpd + corr
}

/// Per-specimen sums of per-observation scores (`specimens` order).
pub fn per_specimen(scores: &[f64], obs: &[Observation], specimens: &[String]) -> Vec<f64> {
    specimens.iter().map(|s| (0..obs.len()).filter(|&j| &obs[j].specimen == s).map(|j| scores[j]).sum()).collect()
}

/// The standard error of the summed difference of two models' held-out scores over `n`
/// specimens, `sqrt(n · var(dᵢ))` (Vehtari, Gelman & Gabry 2017; ArviZ `compare`'s `dse`),
/// from the per-specimen differences `d`.
pub fn difference_se(d: &[f64]) -> f64 {
    if d.len() < 2 {
        return f64::INFINITY;
    }
    let n = d.len() as f64;
    n.sqrt() * crate::stats::sd(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn difference_se_is_sqrt_n_times_sd() {
        let d = [1.0, 2.0, 3.0, 4.0];
        assert!((difference_se(&d) - 2.0 * crate::stats::sd(&d)).abs() < 1e-12);
    }

    #[test]
    fn aicc_adds_the_small_sample_correction() {
        // k = 1, n = 4: 2 + 2·3 + 2·1·2/(4 − 2) = 10 (Hurvich & Tsai 1989).
        assert!((aicc(3.0, 1, 4) - 10.0).abs() < 1e-12);
        assert!(aicc(3.0, 3, 4).is_infinite());
    }
}
