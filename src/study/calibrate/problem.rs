//! One calibration step as a root-finding problem for argmin: every evaluation an ensemble
//! of the step's group at one parameter value, logged and cached.

use super::{CalibrateSpec, Evaluation, StepError, StepResult};
use crate::ensemble::row::Status;
use crate::ensemble::Shard;
use crate::stats;
use crate::study::run::run_study;
use crate::study::{Study, StudyError, SweepKey, SweepValue};
use argmin::core::{CostFunction, Executor};
use argmin::solver::brent::BrentRoot;
use std::sync::Mutex;

/// One calibration step's root-finding problem: the parameter value at which the group's
/// mean collapse angle meets the target, with the log of every evaluation and its first error.
pub(super) struct RootProblem<'a> {
    study: &'a Study,
    group: usize,
    spec: &'a CalibrateSpec,
    given: Vec<(SweepKey, SweepValue)>,
    target: f64,
    log: Mutex<Vec<Evaluation>>,
    error: Mutex<Option<StudyError>>,
}

impl<'a> RootProblem<'a> {
    /// The step `spec` on group `group` with the values `given` in force, aiming at the
    /// mean collapse angle `target`, degrees.
    pub(super) fn new(
        study: &'a Study,
        group: usize,
        spec: &'a CalibrateSpec,
        given: Vec<(SweepKey, SweepValue)>,
        target: f64,
    ) -> RootProblem<'a> {
        RootProblem { study, group, spec, given, target, log: Mutex::new(Vec::new()), error: Mutex::new(None) }
    }

    /// The first error of an evaluation (a wall that did not resolve), if any.
    pub(super) fn take_error(&self) -> Option<StudyError> {
        self.error.lock().ok().and_then(|mut e| e.take())
    }

    /// Every evaluation so far, in order.
    pub(super) fn log(&self) -> Vec<Evaluation> {
        self.log.lock().map(|l| l.clone()).unwrap_or_default()
    }

    /// The ensemble at search variable `x` (log10 Kn or φ), cached by `x` so that the
    /// solver's repeated points cost nothing.
    pub(super) fn evaluate(&self, x: f64) -> Evaluation {
        if let Some(e) = self.log.lock().map(|l| l.iter().find(|e| e.x == x).cloned()).ok().flatten() {
            return e;
        }
        let value = self.spec.value_at(x);
        let mut values = self.given.clone();
        values.push((self.spec.key(), SweepValue::Number(value)));
        let ev = match self.study.wall_with(self.group, &values) {
            Ok(wall) => {
                let mut one = self.study.clone();
                let mut g = one.groups[self.group].clone();
                g.walls = vec![wall];
                one.groups = vec![g];
                one.points = vec![Vec::new()];
                let rows = run_study(&one, Shard::ALL);
                let a: Vec<f64> = rows
                    .iter()
                    .filter(|r| r.status == Status::Collapsed)
                    .filter_map(|r| r.collapse.collapse_angle_deg)
                    .collect();
                Evaluation { x, value, mean_deg: stats::mean(&a), sd_deg: stats::sd(&a), n: a.len() }
            }
            Err(e) => {
                if let Ok(mut slot) = self.error.lock() {
                    slot.get_or_insert(e);
                }
                Evaluation { x, value, mean_deg: f64::NAN, sd_deg: f64::NAN, n: 0 }
            }
        };
        if let Ok(mut l) = self.log.lock() {
            l.push(ev.clone());
        }
        ev
    }

    /// Brent's search for the root in `[x0, x1]`, then the slope at the root, the 95 %
    /// interval and the specimen spread, into `result` (`calibrated`).
    ///
    /// # Errors
    /// [`StepError::Search`]: the root finder's error.
    pub(super) fn search(&self, x0: f64, x1: f64, realizations: u64, result: &mut StepResult) -> Result<(), StepError> {
        let spec = self.spec;
        let tol = spec.tolerance.unwrap_or(if spec.is_kn() { 0.02 } else { 0.5 });
        let solver = BrentRoot::new(x0, x1, tol);
        let res = Executor::new(Residual(self), solver)
            .configure(|s| s.param(x1).max_iters(spec.max_iters))
            .run()
            .map_err(StepError::Search)?;
        let x = res.state.best_param.or(res.state.param).unwrap_or(0.5 * (x0 + x1));
        let log = self.log();
        let slope = slope_near(&log, x, if spec.is_kn() { 0.3 } else { 10.0 });
        let at = log.iter().filter(|e| e.n > 0).min_by(|a, b| (a.x - x).abs().total_cmp(&(b.x - x).abs())).cloned();
        result.outcome = "calibrated".into();
        result.value = Some(spec.value_at(x));
        result.slope = Some(slope);
        if let Some(at) = at {
            if slope.is_finite() && slope.abs() > 0.0 {
                // One realization: no ensemble spread to propagate, the interval is the
                // measurement's alone (said in the note).
                let se_sim = if at.n > 1 { at.sd_deg / (at.n as f64).sqrt() } else { 0.0 };
                let (_, sd_meas, n_meas) = result.measured;
                let se_meas = sd_meas / (n_meas as f64).sqrt();
                let sx = (se_sim.powi(2) + se_meas.powi(2)).sqrt() / slope.abs();
                if sx.is_finite() {
                    result.interval95 = Some((spec.value_at(x - 1.96 * sx), spec.value_at(x + 1.96 * sx)));
                }
                let sp = at.sd_deg / slope.abs();
                if at.n > 1 && sp.is_finite() {
                    result.spread = Some((spec.value_at(x - sp), spec.value_at(x + sp)));
                }
            }
        }
        result.note = format!(
            "{} = {} makes the mean collapse angle of {} match the measured {:.2}° (Brent, {} evaluations)",
            spec.parameter,
            super::report::fmt_value(spec, spec.value_at(x)),
            spec.group,
            result.measured.0,
            log.len()
        ) + if realizations < 2 {
            "; one realization per evaluation, so the 95 % interval holds the measurement's standard error only"
        } else {
            ""
        };
        Ok(())
    }
}

/// The slope dα/dx at `x`: least squares over the evaluations within `window` of it, or
/// the two nearest if fewer.
fn slope_near(log: &[Evaluation], x: f64, window: f64) -> f64 {
    let mut pts: Vec<(f64, f64)> =
        log.iter().filter(|e| e.n > 0).map(|e| (e.x, e.mean_deg)).filter(|(xi, _)| (xi - x).abs() <= window).collect();
    if pts.len() < 2 {
        let mut all: Vec<(f64, f64)> = log.iter().filter(|e| e.n > 0).map(|e| (e.x, e.mean_deg)).collect();
        all.sort_by(|a, b| (a.0 - x).abs().total_cmp(&(b.0 - x).abs()));
        pts = all.into_iter().take(2).collect();
    }
    ls_slope(&pts)
}

/// The cost function handed to argmin: a borrow of the problem, so that its log can be
/// read after the run.
struct Residual<'a, 'b>(&'a RootProblem<'b>);

impl CostFunction for Residual<'_, '_> {
    type Param = f64;
    type Output = f64;

    fn cost(&self, x: &f64) -> Result<f64, argmin::core::Error> {
        let p = self.0;
        let e = p.evaluate(*x);
        if e.n == 0 {
            return Err(argmin::core::Error::msg(format!(
                "no realization collapsed at {} = {}",
                p.spec.parameter,
                p.spec.value_at(*x)
            )));
        }
        Ok(e.mean_deg - p.target)
    }
}

/// Least-squares slope of (x, y) points; NaN with fewer than two distinct x.
fn ls_slope(p: &[(f64, f64)]) -> f64 {
    if p.len() < 2 {
        return f64::NAN;
    }
    let n = p.len() as f64;
    let mx = p.iter().map(|q| q.0).sum::<f64>() / n;
    let my = p.iter().map(|q| q.1).sum::<f64>() / n;
    let sxx: f64 = p.iter().map(|q| (q.0 - mx).powi(2)).sum();
    let sxy: f64 = p.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    if sxx > 0.0 {
        sxy / sxx
    } else {
        f64::NAN
    }
}
