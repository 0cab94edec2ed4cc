//! The predictive distribution of an observation under a model: the spread of the
//! simulated realizations (layout randomness) plus the measurement error.
//!
//! With `R` realizations of sample mean `m` and standard deviation `s`, a new specimen's
//! measured value is predicted as Gaussian with mean `m` and variance
//! `s² (1 + 1/R) + σ_res² + σ_meas²` (the prediction variance of a new draw, Geisser 1993),
//! with `σ_res² = res²/12` the quantization of the collapse angle by the tilt resolution.
//! Scores are the negative log predictive density (NLPD, a proper scoring rule: it charges
//! a wrong mean and a wrong spread alike).

use super::observations::{Observable, Observation};
use super::simulate::Outcome;
use serde::Serialize;

/// Mean and standard deviation of a model's simulated values of one observable (degrees
/// or cm), and the number of realizations they came from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Simulated {
    /// Mean over the realizations.
    pub mean: f64,
    /// Sample standard deviation (0 for one realization).
    pub sd: f64,
    /// Realizations that gave a value.
    pub n: usize,
}

impl Simulated {
    /// From the outcomes of one group.
    pub fn of(outcomes: &[Outcome], obs: &Observable) -> Simulated {
        let v: Vec<f64> = outcomes.iter().filter_map(|o| o.value(obs)).filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return Simulated { mean: f64::NAN, sd: 0.0, n: 0 };
        }
        Simulated { mean: crate::stats::mean(&v), sd: if v.len() > 1 { crate::stats::sd(&v) } else { 0.0 }, n: v.len() }
    }
}

/// A Gaussian predictive distribution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Predictive {
    /// Mean.
    pub mean: f64,
    /// Standard deviation (model spread and measurement error).
    pub sd: f64,
}

impl Predictive {
    /// The predictive distribution of `obs` from the simulated values; `resolution_deg` is
    /// the tilt resolution of the collapse angle.
    pub fn new(sim: &Simulated, obs: &Observation, resolution_deg: f64) -> Predictive {
        let r = sim.n.max(1) as f64;
        let res2 = match obs.observable {
            Observable::CollapseAngle => resolution_deg * resolution_deg / 12.0,
            Observable::Displacement { .. } => 0.0,
        };
        let var = sim.sd * sim.sd * (1.0 + 1.0 / r) + res2 + obs.sigma * obs.sigma;
        Predictive { mean: sim.mean, sd: var.sqrt() }
    }

    /// Negative log density of `y`.
    pub fn nlpd(&self, y: f64) -> f64 {
        if !self.mean.is_finite() {
            return NLPD_MISSING;
        }
        let z = (y - self.mean) / self.sd;
        0.5 * z * z + self.sd.ln() + 0.5 * (2.0 * std::f64::consts::PI).ln()
    }

    /// Standardized residual `(y − mean) / sd`.
    pub fn z(&self, y: f64) -> f64 {
        (y - self.mean) / self.sd
    }
}

/// The score of an observation the model cannot predict (every realization failed).
pub const NLPD_MISSING: f64 = 50.0;
