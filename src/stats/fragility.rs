//! Fragility against a ground-motion intensity measure from incremental dynamic analysis:
//! P(collapse | IM = x) = Φ(ln(x / θ) / β), θ and β fitted by maximum likelihood on the
//! binomial counts of collapses at each intensity level (Baker 2015, Earthquake Spectra
//! 31:579, eq. 11), with a bootstrap band.
//!
//! With `a = −ln θ / β` and `b = 1 / β` the model is a probit regression on ln x, whose
//! log-likelihood is concave in (a, b): Newton's method with step halving finds its
//! maximum from any start. No finite maximum exists when the counts do not overlap (every
//! collapse at a higher level than every survival): the fit is then refused.

use super::quantile;
use crate::rng::{rng_for, Purpose};
use rand_distr::{Binomial, Distribution};
use serde::{Deserialize, Serialize};
use statrs::distribution::{Continuous, ContinuousCDF, Normal};

/// The counts of one intensity level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LevelCount {
    /// Intensity, in the unit of the IM (g for PGA); > 0.
    pub intensity: f64,
    /// Runs at this level.
    pub runs: u64,
    /// Collapses among them.
    pub collapses: u64,
}

/// A fitted fragility curve against an intensity measure.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IntensityFragility {
    /// Median θ, in the unit of the IM: the intensity of 50 % probability of collapse.
    pub median: f64,
    /// Logarithmic standard deviation β, –.
    pub beta: f64,
}

fn normal() -> Normal {
    Normal::new(0.0, 1.0).expect("standard normal")
}

impl IntensityFragility {
    /// P(collapse | IM = x).
    pub fn probability(&self, x: f64) -> f64 {
        if x <= 0.0 {
            return 0.0;
        }
        normal().cdf((x / self.median).ln() / self.beta)
    }

    /// The maximum-likelihood fit to the counts (Baker 2015). `None` with fewer than two
    /// levels of positive intensity and runs, or where no finite maximum exists (no level
    /// with both outcomes and the collapses all above the survivals: the data fix neither
    /// θ nor β).
    pub fn fit(levels: &[LevelCount]) -> Option<IntensityFragility> {
        let data: Vec<(f64, f64, f64)> = levels
            .iter()
            .filter(|l| l.intensity > 0.0 && l.runs > 0 && l.collapses <= l.runs)
            .map(|l| (l.intensity.ln(), l.runs as f64, l.collapses as f64))
            .collect();
        if data.len() < 2 || !overlapping(&data) {
            return None;
        }
        let nd = normal();
        // Log-likelihood, gradient and Hessian in (a, b), p = Φ(a + b ln x).
        let loglik = |a: f64, b: f64| -> f64 {
            data.iter()
                .map(|&(lx, n, z)| {
                    let eta = a + b * lx;
                    let (lp, lq) = (log_cdf(&nd, eta), log_cdf(&nd, -eta));
                    z * lp + (n - z) * lq
                })
                .sum()
        };
        let mean_lx = data.iter().map(|d| d.0 * d.1).sum::<f64>() / data.iter().map(|d| d.1).sum::<f64>();
        let (mut a, mut b) = (-mean_lx, 1.0);
        let mut ll = loglik(a, b);
        for _ in 0..200 {
            let (mut g, mut h) = ([0.0; 2], [[0.0; 2]; 2]);
            for &(lx, n, z) in &data {
                let eta = a + b * lx;
                // d/dη of z ln Φ(η) + (n − z) ln Φ(−η), and its second derivative, through the
                // inverse Mills ratios (stable in the tails).
                let (m1, m2) = (mills(&nd, eta), mills(&nd, -eta));
                let d1 = z * m1 - (n - z) * m2;
                let d2 = -z * m1 * (eta + m1) - (n - z) * m2 * (m2 - eta);
                let x = [1.0, lx];
                for i in 0..2 {
                    g[i] += d1 * x[i];
                    for j in 0..2 {
                        h[i][j] += d2 * x[i] * x[j];
                    }
                }
            }
            let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
            if !(det.abs() > 0.0) {
                break;
            }
            let step = [(h[1][1] * g[0] - h[0][1] * g[1]) / det, (h[0][0] * g[1] - h[1][0] * g[0]) / det];
            let mut t = 1.0;
            let mut improved = false;
            for _ in 0..40 {
                let (na, nb) = (a - t * step[0], b - t * step[1]);
                let nl = loglik(na, nb);
                if nb > 0.0 && nl >= ll {
                    improved = nl > ll;
                    (a, b, ll) = (na, nb, nl);
                    break;
                }
                t *= 0.5;
            }
            if !improved || (step[0].abs() + step[1].abs()) * t < 1e-12 {
                break;
            }
        }
        (b > 0.0 && a.is_finite()).then(|| IntensityFragility { median: (-a / b).exp(), beta: 1.0 / b })
    }
}

/// Whether the counts overlap (some level has both outcomes, or a collapse at a level at or
/// below a survival's): a finite maximum-likelihood fit exists.
fn overlapping(data: &[(f64, f64, f64)]) -> bool {
    let lowest_collapse = data.iter().filter(|d| d.2 > 0.0).map(|d| d.0).fold(f64::INFINITY, f64::min);
    let highest_survival = data.iter().filter(|d| d.2 < d.1).map(|d| d.0).fold(f64::NEG_INFINITY, f64::max);
    data.iter().any(|d| d.2 > 0.0 && d.2 < d.1) || lowest_collapse <= highest_survival
}

/// ln Φ(x), accurate in the lower tail.
fn log_cdf(nd: &Normal, x: f64) -> f64 {
    if x > -30.0 {
        nd.cdf(x).ln()
    } else {
        // Φ(x) ≈ φ(x) / (−x) for x → −∞.
        nd.ln_pdf(x) - (-x).ln()
    }
}

/// The inverse Mills ratio φ(x) / Φ(x).
fn mills(nd: &Normal, x: f64) -> f64 {
    if x > -30.0 {
        nd.pdf(x) / nd.cdf(x)
    } else {
        -x
    }
}

/// A fragility curve with its bootstrap band at the given intensities.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FragilityBand {
    /// The maximum-likelihood fit.
    pub fit: IntensityFragility,
    /// Intensities of the band.
    pub intensity: Vec<f64>,
    /// 2.5 % quantile of P(collapse) over the bootstrap fits, per intensity.
    pub lower: Vec<f64>,
    /// 97.5 % quantile, per intensity.
    pub upper: Vec<f64>,
    /// Bootstrap replicates with a finite fit (of `replicates` drawn).
    pub fitted_replicates: usize,
    /// 2.5–97.5 % range of the median θ over the bootstrap fits (NaN without any).
    pub median_ci95: (f64, f64),
    /// 2.5–97.5 % range of β over the bootstrap fits (NaN without any).
    pub beta_ci95: (f64, f64),
}

/// The fit with a parametric bootstrap band: `replicates` sets of counts drawn level by
/// level from Binomial(runs, collapses / runs) (the observed fraction), refitted; the
/// band is the 2.5–97.5 % range of the refitted curves at `intensity`. Seeded by
/// `rng_for(seed, stream, Purpose::Bootstrap)`. `None` where the counts have no fit.
pub fn fragility_band(
    levels: &[LevelCount],
    intensity: &[f64],
    replicates: usize,
    seed: u64,
    stream: u64,
) -> Option<FragilityBand> {
    let fit = IntensityFragility::fit(levels)?;
    let mut rng = rng_for(seed, stream, Purpose::Bootstrap);
    let mut curves: Vec<Vec<f64>> = vec![Vec::with_capacity(replicates); intensity.len()];
    let mut fitted = 0;
    let (mut medians, mut betas) = (Vec::with_capacity(replicates), Vec::with_capacity(replicates));
    for _ in 0..replicates {
        let drawn: Vec<LevelCount> = levels
            .iter()
            .map(|l| {
                let p = if l.runs > 0 { l.collapses as f64 / l.runs as f64 } else { 0.0 };
                let z = Binomial::new(l.runs, p.clamp(0.0, 1.0)).map_or(0, |b| b.sample(&mut rng));
                LevelCount { collapses: z, ..*l }
            })
            .collect();
        if let Some(f) = IntensityFragility::fit(&drawn) {
            fitted += 1;
            medians.push(f.median);
            betas.push(f.beta);
            for (c, &x) in curves.iter_mut().zip(intensity) {
                c.push(f.probability(x));
            }
        }
    }
    let q = |c: &Vec<f64>, p: f64| if c.is_empty() { f64::NAN } else { quantile(c, p) };
    Some(FragilityBand {
        fit,
        intensity: intensity.to_vec(),
        lower: curves.iter().map(|c| q(c, 0.025)).collect(),
        upper: curves.iter().map(|c| q(c, 0.975)).collect(),
        fitted_replicates: fitted,
        median_ci95: (q(&medians, 0.025), q(&medians, 0.975)),
        beta_ci95: (q(&betas, 0.025), q(&betas, 0.975)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts drawn from a known curve (θ = 0.4 g, β = 0.35, 400 runs per level, by the
    /// rounding of the exact expected counts: no sampling noise) return it; the
    /// likelihood's maximum is checked against a brute-force grid.
    #[test]
    fn the_fit_recovers_a_known_curve() {
        let truth = IntensityFragility { median: 0.4, beta: 0.35 };
        let levels: Vec<LevelCount> = [0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0]
            .iter()
            .map(|&x| LevelCount { intensity: x, runs: 400, collapses: (400.0 * truth.probability(x)).round() as u64 })
            .collect();
        let f = IntensityFragility::fit(&levels).unwrap();
        assert!((f.median / 0.4 - 1.0).abs() < 0.01 && (f.beta / 0.35 - 1.0).abs() < 0.02, "{f:?}");
        // Grid search of the same likelihood.
        let ll = |t: f64, b: f64| -> f64 {
            let g = IntensityFragility { median: t, beta: b };
            levels
                .iter()
                .map(|l| {
                    let p = g.probability(l.intensity).clamp(1e-300, 1.0 - 1e-16);
                    l.collapses as f64 * p.ln() + (l.runs - l.collapses) as f64 * (1.0 - p).ln()
                })
                .sum()
        };
        let mut best = (f64::NEG_INFINITY, 0.0, 0.0);
        for i in 0..200 {
            for j in 0..200 {
                let (t, b) = (0.3 + 0.2 * i as f64 / 199.0, 0.2 + 0.3 * j as f64 / 199.0);
                let v = ll(t, b);
                if v > best.0 {
                    best = (v, t, b);
                }
            }
        }
        assert!(ll(f.median, f.beta) >= best.0 - 1e-9, "{f:?} vs grid {best:?}");
    }

    /// Counts that do not overlap have no finite fit; a band holds the fit's curve.
    #[test]
    fn separated_counts_are_refused_and_bands_hold_the_fit() {
        let sep = [
            LevelCount { intensity: 0.1, runs: 5, collapses: 0 },
            LevelCount { intensity: 0.2, runs: 5, collapses: 5 },
        ];
        assert!(IntensityFragility::fit(&sep).is_none());
        let levels: Vec<LevelCount> = [(0.1, 0), (0.2, 2), (0.3, 5), (0.4, 8), (0.6, 10)]
            .iter()
            .map(|&(x, z)| LevelCount { intensity: x, runs: 10, collapses: z })
            .collect();
        let xs = [0.15, 0.3, 0.5];
        let b = fragility_band(&levels, &xs, 200, 1, 0).unwrap();
        assert_eq!(b, fragility_band(&levels, &xs, 200, 1, 0).unwrap(), "seeded");
        for (k, &x) in xs.iter().enumerate() {
            let p = b.fit.probability(x);
            assert!(b.lower[k] <= p && p <= b.upper[k], "{x}: {} {p} {}", b.lower[k], b.upper[k]);
        }
        assert!(b.fitted_replicates > 150);
        assert!(b.median_ci95.0 <= b.fit.median && b.fit.median <= b.median_ci95.1, "{b:?}");
        assert!(b.beta_ci95.0 <= b.fit.beta && b.fit.beta <= b.beta_ci95.1, "{b:?}");
    }
}
