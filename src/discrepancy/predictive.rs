//! The predictive distribution of an observation under a model, and the likelihood of a
//! reading.
//!
//! A model is run for `R` realizations (layouts); their values of an observable have mean
//! `m` and standard deviation `s`. A new specimen's reading is predicted as Student-t with
//! location `m` and scale `S`,
//!
//! `S² = s² (1 + 1/R) + σ_meas² + σ_sur² + b²/12`,
//!
//! the prediction variance of a new draw (Geisser 1993), the measurement error, the
//! surrogate's own error at the point (its leave-one-node-out estimate, [`super::fit`]) and
//! the quantization of a collapse angle bracketed to `b` (the tilt resolution). Its degrees
//! of freedom are Welch–Satterthwaite's, `ν = S⁴ (R − 1) / (s² (1 + 1/R))²`: with few
//! realizations the spread is itself uncertain and the tails are heavy; with many, or when
//! the measurement error dominates, the predictive is Gaussian.
//!
//! A reading is an interval: a value rounded to its resolution `r` (0.5° for the paper's
//! angles, 0.1 cm for its displacements) means the truth is in `[y − r/2, y + r/2]`. Its
//! score is the negative log of the predictive probability of that interval, plus `ln r`
//! (so that for a fine resolution it is the negative log predictive density, NLPD: a proper
//! scoring rule, which charges a wrong mean and a wrong spread alike).
//!
//! **Mechanisms.** A failure height (a fraction of the wall's height) is scored as an
//! interval reading like the angles, against the Student-t predictive of the
//! realizations' failure heights; its measurement σ (0.05 of the height by default) is
//! also the smoothing width of a few realizations' values. A kind or a start is a
//! category: of `R` realizations, `k` showed the observed one (which covers `m` of the `K`
//! simulated categories: `random` covers `end` and `centre`); its probability is smoothed
//! for the finite ensemble with the Jeffreys prior, `p = (k + m/2) / (R + K/2)`, and read
//! with a misreading probability `ε` (\[0.1\]: one reading in ten is another category,
//! uniformly), `q = (1 − ε) p + ε (1 − p) m / (K − 1)`. Its score is `−ln q` where the
//! category was seen, `−ln (1 − q)` where it was not (synthetic data sets).

use super::observations::{Observable, Observation};
use super::simulate::Outcome;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, StudentsT};

/// Mean and standard deviation of a model's simulated values of one observable (degrees
/// or cm), the number of realizations they came from, and the surrogate's error there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Simulated {
    /// Mean over the realizations.
    pub mean: f64,
    /// Sample standard deviation (0 for one realization).
    pub sd: f64,
    /// Realizations that gave a value.
    pub n: usize,
    /// Standard error of the surrogate at this point (0 at a simulated node).
    pub err: f64,
}

impl Simulated {
    /// From the outcomes of one group: every realization that gave a value (a collapse
    /// angle is the middle of its bracket; a displacement at a tilt only from realizations
    /// that stood there).
    pub fn of(outcomes: &[Outcome], obs: &Observable) -> Simulated {
        let v: Vec<f64> = outcomes.iter().filter_map(|o| o.value(obs)).filter(|x| x.is_finite()).collect();
        Simulated::from_values(&v)
    }

    /// From values.
    pub fn from_values(v: &[f64]) -> Simulated {
        if v.is_empty() {
            return Simulated { mean: f64::NAN, sd: 0.0, n: 0, err: 0.0 };
        }
        Simulated {
            mean: crate::stats::mean(v),
            sd: if v.len() > 1 { crate::stats::sd(v) } else { 0.0 },
            n: v.len(),
            err: 0.0,
        }
    }
}

/// How readings were taken: their resolutions (the interval a rounded value stands for).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Reading {
    /// Collapse angles read to this, degrees \[0.5\] (the paper's Table 2).
    pub angle_deg: f64,
    /// Displacements read to this, cm \[0.1\] (the paper's Table 3).
    pub displacement_cm: f64,
    /// Probability that a mechanism's kind or start is read as another category \[0.1\].
    pub misreading: f64,
}

impl Default for Reading {
    fn default() -> Self {
        Reading { angle_deg: 0.5, displacement_cm: 0.1, misreading: 0.1 }
    }
}

impl Reading {
    /// The resolution of an observable's readings.
    pub fn of(&self, o: &Observable) -> f64 {
        match o {
            Observable::CollapseAngle => self.angle_deg,
            Observable::Displacement { .. } => self.displacement_cm,
            Observable::FailureHeight { width } => *width,
            Observable::MechanismKind { .. } | Observable::MechanismStart { .. } => 0.0,
        }
    }

    /// `v` rounded to the resolution of `o` (a failure height also kept in [0, 1]; a
    /// category's indicator as it is).
    pub fn round(&self, o: &Observable, v: f64) -> f64 {
        match o {
            Observable::MechanismKind { .. } | Observable::MechanismStart { .. } => v,
            Observable::FailureHeight { width } => {
                let r = if *width > 0.0 { (v / width).round() * width } else { v };
                r.clamp(0.0, 1.0)
            }
            _ => {
                let r = self.of(o);
                (v / r).round() * r
            }
        }
    }

    /// The probability that a reading of category `o` (covering `m` of `K` simulated
    /// categories, [`Observable::category`]) says "seen", from the share `sim.mean` of
    /// `sim.n` realizations that showed it: Jeffreys-smoothed and misread at
    /// [`Reading::misreading`] (module documentation). `None` for a number.
    pub fn category_probability(&self, o: &Observable, sim: &Simulated) -> Option<f64> {
        let (m, k) = o.category()?;
        let (m, k) = (m as f64, k as f64);
        let n = sim.n as f64;
        let share = if sim.n > 0 && sim.mean.is_finite() { sim.mean.clamp(0.0, 1.0) } else { 0.0 };
        let p = (n * share + 0.5 * m) / (n + 0.5 * k);
        let e = self.misreading;
        Some(((1.0 - e) * p + e * (1.0 - p) * m / (k - 1.0)).clamp(1e-12, 1.0 - 1e-12))
    }
}

/// A Student-t predictive distribution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Predictive {
    /// Location.
    pub mean: f64,
    /// Scale (model spread, measurement, surrogate and bracket errors).
    pub sd: f64,
    /// Degrees of freedom (infinite: Gaussian).
    pub dof: f64,
}

/// Degrees of freedom above which the predictive is taken as Gaussian.
const GAUSSIAN_DOF: f64 = 1e4;

impl Predictive {
    /// The predictive distribution of `obs` from the simulated values; `bracket` is the
    /// width of a simulated collapse angle's bracket (degrees; 0 for displacements).
    pub fn new(sim: &Simulated, obs: &Observation, bracket: f64) -> Predictive {
        let r = sim.n.max(1) as f64;
        let b2 = match obs.observable {
            Observable::CollapseAngle => bracket * bracket / 12.0,
            _ => 0.0,
        };
        let model = sim.sd * sim.sd * (1.0 + 1.0 / r);
        let var = model + b2 + obs.sigma * obs.sigma + sim.err * sim.err;
        let dof = if sim.n >= 2 && model > 0.0 {
            (var * var * (r - 1.0) / (model * model)).min(GAUSSIAN_DOF)
        } else {
            GAUSSIAN_DOF
        };
        Predictive { mean: sim.mean, sd: var.sqrt(), dof }
    }

    /// The standardized predictive's CDF.
    fn cdf(&self, z: f64) -> f64 {
        if self.dof >= GAUSSIAN_DOF {
            0.5 * statrs::function::erf::erfc(-z / std::f64::consts::SQRT_2)
        } else {
            StudentsT::new(0.0, 1.0, self.dof.max(1.0)).map_or(f64::NAN, |t| t.cdf(z))
        }
    }

    /// Negative log predictive density of `y`.
    pub fn nlpd(&self, y: f64) -> f64 {
        if !self.mean.is_finite() || !(self.sd > 0.0) {
            return NLPD_MISSING;
        }
        let z = (y - self.mean) / self.sd;
        let nu = self.dof.max(1.0);
        let ln_pdf = if nu >= GAUSSIAN_DOF {
            -0.5 * z * z - 0.5 * (2.0 * std::f64::consts::PI).ln()
        } else {
            statrs::function::gamma::ln_gamma(0.5 * (nu + 1.0))
                - statrs::function::gamma::ln_gamma(0.5 * nu)
                - 0.5 * (nu * std::f64::consts::PI).ln()
                - 0.5 * (nu + 1.0) * (1.0 + z * z / nu).ln()
        };
        (self.sd.ln() - ln_pdf).min(NLPD_MISSING)
    }

    /// Negative log probability of a reading `y` of resolution `r` (the interval
    /// `[y − r/2, y + r/2]`), plus `ln r`; the density score where the interval's
    /// probability underflows or `r` is 0.
    pub fn score(&self, y: f64, r: f64) -> f64 {
        if !self.mean.is_finite() || !(self.sd > 0.0) {
            return NLPD_MISSING;
        }
        if r > 0.0 {
            let (a, b) = ((y - 0.5 * r - self.mean) / self.sd, (y + 0.5 * r - self.mean) / self.sd);
            // Upper tail by symmetry, for precision.
            let p = if a > 0.0 { self.cdf(-a) - self.cdf(-b) } else { self.cdf(b) - self.cdf(a) };
            if p > 1e-12 {
                return (-p.ln() + r.ln()).min(NLPD_MISSING);
            }
        }
        self.nlpd(y)
    }

    /// The predictive of a category's indicator read "seen" with probability `q`: mean `q`,
    /// standard deviation `√(q (1 − q))` (for residuals; the score is
    /// [`category_score`]).
    pub fn category(q: f64) -> Predictive {
        Predictive { mean: q, sd: (q * (1.0 - q)).sqrt().max(1e-9), dof: GAUSSIAN_DOF }
    }

    /// Standardized residual `(y − mean) / sd`.
    pub fn z(&self, y: f64) -> f64 {
        (y - self.mean) / self.sd
    }
}

/// The score of a category's indicator `y` (1: seen) read "seen" with probability `q`:
/// `−ln q` or `−ln (1 − q)`.
pub fn category_score(q: f64, y: f64) -> f64 {
    (if y >= 0.5 { -q.ln() } else { -(1.0 - q).ln() }).min(NLPD_MISSING)
}

/// The score of an observation the model cannot predict (every realization failed, or
/// none stood to its tilt).
pub const NLPD_MISSING: f64 = 50.0;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrepancy::observations::Observation;

    fn obs(sigma: f64) -> Observation {
        Observation {
            specimen: "s".into(),
            group: "g".into(),
            observable: Observable::CollapseAngle,
            value: 0.0,
            sigma,
        }
    }

    /// The smoothed, misread category probability against its closed form: 3 of 9
    /// realizations toppled (K = 4 kinds), ε = 0.1: p = (3 + ½)/(9 + 2) = 7/22, q = 0.9 p +
    /// 0.1 (1 − p)/3; none of 9 uniform starts for `random` (m = 2 of K = 3): p = 1/10.5.
    #[test]
    fn a_category_is_smoothed_for_few_realizations_and_misread() {
        use crate::loading::mechanism::{FailureKind, FailureStart};
        let r = Reading::default();
        let sim = Simulated { mean: 3.0 / 9.0, sd: 0.0, n: 9, err: 0.0 };
        let q = r.category_probability(&Observable::MechanismKind { kind: FailureKind::Toppling }, &sim).unwrap();
        let p = 7.0 / 22.0;
        assert!((q - (0.9 * p + 0.1 * (1.0 - p) / 3.0)).abs() < 1e-15, "{q}");
        let none = Simulated { mean: 0.0, sd: 0.0, n: 9, err: 0.0 };
        let q = r.category_probability(&Observable::MechanismStart { start: FailureStart::Random }, &none).unwrap();
        let p = 1.0 / 10.5;
        assert!((q - (0.9 * p + 0.1 * (1.0 - p))).abs() < 1e-15, "{q}");
        assert!(
            (category_score(q, 1.0) + q.ln()).abs() < 1e-15 && (category_score(q, 0.0) + (1.0 - q).ln()).abs() < 1e-15
        );
        assert_eq!(r.category_probability(&Observable::CollapseAngle, &sim), None);
    }

    #[test]
    fn gaussian_limit_matches_the_normal_density() {
        let p = Predictive { mean: 1.0, sd: 2.0, dof: f64::INFINITY };
        let z: f64 = 0.75;
        let want = 0.5 * z * z + 2f64.ln() + 0.5 * (2.0 * std::f64::consts::PI).ln();
        assert!((p.nlpd(2.5) - want).abs() < 1e-12);
    }

    #[test]
    fn few_realizations_give_heavy_tails() {
        let sim = Simulated { mean: 10.0, sd: 1.0, n: 3, err: 0.0 };
        let p = Predictive::new(&sim, &obs(1e-3), 0.0);
        assert!(p.dof < 3.0, "{p:?}");
        let g = Predictive { dof: f64::INFINITY, ..p };
        // Far out the t density is much larger than the Gaussian one.
        assert!(p.nlpd(16.0) < g.nlpd(16.0) - 5.0);
    }

    #[test]
    fn interval_score_tends_to_the_density_score() {
        let p = Predictive { mean: 0.0, sd: 1.0, dof: 5.0 };
        assert!((p.score(0.3, 1e-4) - p.nlpd(0.3)).abs() < 1e-6);
        // A coarse reading is more probable than its density times its width suggests only
        // through curvature: still close for r << sd.
        assert!((p.score(0.3, 0.1) - p.nlpd(0.3)).abs() < 1e-2);
    }
}
