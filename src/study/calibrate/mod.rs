//! Calibration of joint parameters against the measured collapse angles (the paper's
//! Table 9: shale Kn 5e7 Pa/m, φ 35°; cobblestone Kn 1.75e8 Pa/m, φ 32°).
//!
//! A study with `protocol = "tilt"`, measured collapse angles and `[[calibrate]]` steps:
//!
//! ```toml
//! [[calibrate]]
//! group = "SBL"                 # fit this group's simulated mean α_max to its measured mean
//! parameter = "kn_pa_per_m"     # or "friction_deg"
//! lower = 1.0e7                 # search interval (Pa/m, or degrees)
//! upper = 1.0e9
//! tolerance = 0.02              # on log10(Kn), or on φ in degrees  [0.02 / 0.5]
//! max_iters = 12                # Brent iterations after the two end evaluations  [12]
//! carry_to = ["SBR"]            # later steps on these groups use the value found
//! paper_value = 5.0e7           # the paper's calibrated value, for the report (optional)
//! ```
//!
//! Each step solves mean α_max(x) − measured mean = 0 for x (log10 Kn, or φ) with Brent's
//! root finder from the `argmin` crate ([`argmin::solver::brent::BrentRoot`]); every
//! evaluation runs the group's ensemble (the study's realizations, in parallel, common
//! random numbers: the same layouts at every x). The steps run in file order; a value found
//! is applied to the step's own group and to its `carry_to` groups in the later steps.
//!
//! **Identifiability.** Before searching, the two ends of the interval are evaluated. The
//! *resolution* is the tilt bracket width plus twice the standard error of the difference
//! between a simulated and the measured mean (√(SE²_sim + SE²_meas)). In this order:
//! 1. the measured mean lies farther than the resolution outside the simulated range: no
//!    value in the interval fits (`out_of_range`);
//! 2. the mean collapse angle changes by less than the resolution across the interval: the
//!    parameter is `not_identifiable` from this group (e.g. φ of a free-standing wall that
//!    topples);
//! 3. the measured mean lies within the resolution of the simulated mean at an end of the
//!    interval (just outside the range, or inside it with α_max on a plateau there): the
//!    data cannot exclude that end, every value towards it fits (`not_identifiable`; e.g.
//!    φ of a wall whose α_max stops changing once φ is large enough for it to topple);
//! 4. otherwise Brent's method finds the value (`calibrated`).
//!
//! Nothing is forced: each outcome is reported as such.
//!
//! **Uncertainty.** The slope s = dα/dx is the least-squares slope of the evaluations within
//! a window around the root (±0.3 in log10 Kn, ±10° in φ; at least the two nearest). The
//! standard error of x is √(SE²_sim + SE²_meas) / |s| with SE_sim = σ_sim/√n at the root and
//! SE_meas = σ_meas/√n_meas (the delta method); the specimen spread σ_sim / |s| says how
//! far apart single walls of the same material would put x.

mod problem;
mod report;

pub use report::{markdown, write_calibration};

pub use super::spec::CalibrateSpec;

use super::checks::check_calibration;
use super::{Study, SweepKey, SweepValue};
use crate::stats;
use problem::RootProblem;
use serde::Serialize;
use std::path::PathBuf;

/// Calibration errors, each naming the step (0-based, in file order).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CalibrateError {
    /// The step does not fit the study.
    #[error("calibrate[{step}]: {reason}")]
    Check {
        /// The step.
        step: usize,
        /// What is wrong.
        #[source]
        reason: crate::study::CalibrationSpecError,
    },
    /// The step could not run: a wall that no longer checks, no collapse at an end of the
    /// interval, the root finder failed.
    #[error("calibrate[{step}] ({group}): {reason}")]
    Step {
        /// The step.
        step: usize,
        /// Its group.
        group: String,
        /// What went wrong.
        #[source]
        reason: StepError,
    },
    /// Writing an output file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

impl From<crate::io::FileError> for CalibrateError {
    fn from(e: crate::io::FileError) -> Self {
        CalibrateError::Io { path: e.path, source: e.source }
    }
}

/// Why a calibration step could not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StepError {
    /// The wall at a trial value no longer checks (e.g. a Kn so low that the joints close
    /// beyond the layout's limit).
    #[error(transparent)]
    Wall(Box<crate::study::StudyError>),
    /// No realization collapsed at an end of the interval, so nothing can be matched.
    #[error("no realization collapsed at an end of the interval {lower} .. {upper}")]
    NoCollapse {
        /// The interval's lower end, in the parameter's unit.
        lower: f64,
        /// The interval's upper end.
        upper: f64,
    },
    /// Brent's root finder (argmin) failed.
    #[error("{0}")]
    Search(argmin::core::Error),
}

/// The staging directory and manifest of `drystone calibrate`'s set in its output
/// directory (a run's default directory too: the two sets stand side by side).
pub const OUTPUT_SET: super::outputs::SetNames =
    super::outputs::SetNames { staging: ".drystone-staging-calibration", manifest: "calibration-manifest.json" };

impl CalibrateSpec {
    /// Search variable from a parameter value: log10(Kn) or φ.
    fn to_x(&self, v: f64) -> f64 {
        if self.is_kn() {
            v.log10()
        } else {
            v
        }
    }

    /// Parameter value at a search variable: the inverse of `to_x`.
    fn value_at(&self, x: f64) -> f64 {
        if self.is_kn() {
            10f64.powf(x)
        } else {
            x
        }
    }
}

/// One ensemble evaluation of a step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    /// Search variable: log10 Kn, or φ in degrees.
    pub x: f64,
    /// Parameter value (Pa/m or degrees).
    pub value: f64,
    /// Mean collapse angle, degrees.
    pub mean_deg: f64,
    /// σ of the collapse angle, degrees.
    pub sd_deg: f64,
    /// Collapsed realizations.
    pub n: usize,
}

/// The outcome of one step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepResult {
    /// The step.
    pub group: String,
    /// Parameter.
    pub parameter: String,
    /// Values of the other calibrated parameters in force.
    pub given: Vec<(String, f64)>,
    /// Measured mean and σ, degrees, and the number of specimens.
    pub measured: (f64, f64, usize),
    /// `calibrated`, `not_identifiable` or `out_of_range`.
    pub outcome: String,
    /// The value found (Pa/m or degrees) when calibrated.
    pub value: Option<f64>,
    /// 95 % interval of the value from the standard errors (delta method).
    pub interval95: Option<(f64, f64)>,
    /// Specimen spread: the interval of ±1 σ_sim / |slope| around the value.
    pub spread: Option<(f64, f64)>,
    /// Slope dα/dx at the root (degrees per decade of Kn, or per degree of φ).
    pub slope: Option<f64>,
    /// The paper's value.
    pub paper_value: Option<f64>,
    /// Every evaluation, in order.
    pub evaluations: Vec<Evaluation>,
    /// A sentence for the report.
    pub note: String,
}

/// Runs the calibration steps of a study in order. Deterministic: every evaluation is an
/// ensemble with the study's seed.
///
/// # Errors
/// [`CalibrateError`] naming the step that could not run (bad wall, no collapse at an end).
pub fn calibrate(study: &Study, steps: &[CalibrateSpec]) -> Result<Vec<StepResult>, CalibrateError> {
    calibrate_with(study, steps, &|_| {})
}

/// [`calibrate`], reporting each step as it starts and ends to `progress` (one line
/// each, no trailing newline).
///
/// # Errors
/// As [`calibrate`].
pub fn calibrate_with(
    study: &Study,
    steps: &[CalibrateSpec],
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Vec<StepResult>, CalibrateError> {
    // The values found so far, per group: applied to the group's later steps.
    let mut carried: Vec<(String, Vec<(SweepKey, SweepValue)>)> =
        study.groups.iter().map(|g| (g.name.clone(), Vec::new())).collect();
    let mut out = Vec::new();
    for (si, spec) in steps.iter().enumerate() {
        check_calibration(spec, study).map_err(|reason| CalibrateError::Check { step: si, reason })?;
        let gi = study.groups.iter().position(|g| g.name == spec.group).unwrap_or(0);
        let given: Vec<(SweepKey, SweepValue)> =
            carried[gi].1.iter().filter(|(k, _)| *k != spec.key()).cloned().collect();
        progress(&format!(
            "step {}/{} ({}): {} in {} .. {}",
            si + 1,
            steps.len(),
            spec.group,
            spec.parameter,
            report::fmt_value(spec, spec.lower),
            report::fmt_value(spec, spec.upper)
        ));
        let result = step(study, gi, spec, given).map_err(|reason| CalibrateError::Step {
            step: si,
            group: spec.group.clone(),
            reason,
        })?;
        progress(&format!(
            "step {}/{} ({}): {}{} after {} evaluation(s)",
            si + 1,
            steps.len(),
            spec.group,
            result.outcome.replace('_', " "),
            result.value.map_or(String::new(), |v| format!(" at {}", report::fmt_value(spec, v))),
            result.evaluations.len()
        ));
        if let Some(x) = result.value {
            let value = SweepValue::Number(x);
            for g in std::iter::once(&spec.group).chain(&spec.carry_to) {
                if let Some((_, v)) = carried.iter_mut().find(|(n, _)| n == g) {
                    v.retain(|(k, _)| *k != spec.key());
                    v.push((spec.key(), value.clone()));
                }
            }
        }
        out.push(result);
    }
    Ok(out)
}

/// Measured mean, σ and count of the collapse angle of group `gi`.
fn measured(study: &Study, gi: usize) -> (f64, f64, usize) {
    let mg = &study.groups[gi].measured_group;
    let meas: Vec<f64> =
        study.measured.collapse.iter().filter(|m| &m.group == mg).map(|m| m.collapse_angle_deg).collect();
    (stats::mean(&meas), stats::sd(&meas), meas.len())
}

/// One step: the ends of the interval evaluated, then out of range, not identifiable, or
/// Brent's search.
fn step(
    study: &Study,
    gi: usize,
    spec: &CalibrateSpec,
    given: Vec<(SweepKey, SweepValue)>,
) -> Result<StepResult, StepError> {
    let measured = measured(study, gi);
    let mut result = StepResult {
        group: spec.group.clone(),
        parameter: spec.parameter.clone(),
        given: given.iter().filter_map(|(k, v)| Some((k.as_str().to_string(), v.number()?))).collect(),
        measured,
        outcome: String::new(),
        value: None,
        interval95: None,
        spread: None,
        slope: None,
        paper_value: spec.paper_value,
        evaluations: Vec::new(),
        note: String::new(),
    };
    let problem = RootProblem::new(study, gi, spec, given, measured.0);
    let (x0, x1) = (spec.to_x(spec.lower), spec.to_x(spec.upper));
    let (e0, e1) = (problem.evaluate(x0), problem.evaluate(x1));
    if let Some(e) = problem.take_error() {
        return Err(StepError::Wall(Box::new(e)));
    }
    if e0.n == 0 || e1.n == 0 {
        return Err(StepError::NoCollapse { lower: spec.lower, upper: spec.upper });
    }
    let se = |e: &Evaluation| if e.n > 1 { e.sd_deg / (e.n as f64).sqrt() } else { 0.0 };
    // What the data can tell apart: the tilt bracket plus twice the standard error of
    // the difference between a simulated mean and the measured mean.
    let se_meas = if measured.2 > 1 { measured.1 / (measured.2 as f64).sqrt() } else { 0.0 };
    let resolution = study.protocol.tilt().copied().unwrap_or_default().resolution_deg
        + 2.0 * (se(&e0).max(se(&e1)).powi(2) + se_meas.powi(2)).sqrt();
    if let Some((outcome, note)) = unidentified(spec, measured.0, resolution, &e0, &e1) {
        result.outcome = outcome.into();
        result.note = note;
    } else {
        problem.search(x0, x1, study.realizations, &mut result)?;
    }
    result.evaluations = problem.log();
    Ok(result)
}

/// The outcome and note of a step whose interval ends already decide it: the measurement
/// outside the simulated range (`out_of_range`), or a parameter the data cannot pin down
/// (`not_identifiable`); `None` when a search is worth it.
fn unidentified(
    spec: &CalibrateSpec,
    target: f64,
    resolution: f64,
    e0: &Evaluation,
    e1: &Evaluation,
) -> Option<(&'static str, String)> {
    let (lo_a, hi_a) = (e0.mean_deg.min(e1.mean_deg), e0.mean_deg.max(e1.mean_deg));
    let beyond = (lo_a - target).max(target - hi_a);
    // Does the simulated mean at an end already match the measurement?
    let fit0 = (target - e0.mean_deg).abs() <= resolution;
    let fit1 = (target - e1.mean_deg).abs() <= resolution;
    if beyond > resolution {
        return Some(("out_of_range", format!(
            "no value in {} .. {} fits: the simulated mean collapse angle spans {:.2}° .. {:.2}°, the measured mean {:.2}° lies {:.2}° beyond (resolution {:.2}°)",
            spec.lower, spec.upper, lo_a, hi_a, target, beyond, resolution
        )));
    }
    if hi_a - lo_a < resolution {
        return Some(("not_identifiable", format!(
            "not identifiable from {}: the mean collapse angle changes by only {:.2}° (resolution {:.2}°) over {} = {} .. {}",
            spec.group,
            hi_a - lo_a,
            resolution,
            spec.parameter,
            spec.lower,
            spec.upper
        )));
    }
    if !(fit0 || fit1) {
        return None;
    }
    // The simulated mean at an end of the interval already matches the measurement
    // within the resolution (α_max on its plateau there, or the target just past the
    // end): the data cannot exclude that end, so no single value is identified.
    let end = if fit0 && fit1 {
        None
    } else if fit0 {
        Some((spec.lower, e0.mean_deg))
    } else {
        Some((spec.upper, e1.mean_deg))
    };
    Some(("not_identifiable", match end {
        Some((end, at)) => format!(
            "not identifiable from {}: the measured mean {:.2}° lies within the resolution {:.2}° of the simulated mean at {} = {} ({:.2}°), on the plateau of α_max; values towards {} all fit",
            spec.group, target, resolution, spec.parameter, end, at, end
        ),
        None => format!(
            "not identifiable from {}: the measured mean {:.2}° lies within the resolution {:.2}° of the simulated means at both ends, {} = {} ({:.2}°) and {} ({:.2}°): every value in between fits",
            spec.group, target, resolution, spec.parameter, spec.lower, e0.mean_deg, spec.upper, e1.mean_deg
        ),
    }))
}
