//! The tilting table's parameters ([`TiltParams`]).

use super::hand::HandTilt;
use crate::dem::drivers::accelerate::SecantAcceleration;
use crate::dem::drivers::implicit::ImplicitSolve;
use crate::dem::{Cascade, MovedKey, MovedValue, SolverKind};
use crate::range::{check_ranges, OutOfRange};
use serde::{Deserialize, Serialize};

/// Tilting-table parameters. Defaults in brackets.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TiltParams {
    /// Tilt increment, degrees \[0.5\] (the paper's DEM used 0.5°).
    pub step_deg: f64,
    /// Width of the final collapse bracket, degrees \[0.125\]: three bisections of the
    /// 0.5° step. The trial nearest α_max is the slowest of a test (the wall creeps for tens
    /// of thousands of steps before it settles or fails), so each further halving costs
    /// about 30 % more steps; the last-stable α_max is then on average 1/16° below the
    /// critical tilt, with a spread (σ 0.036°) well under the realization-to-realization σ.
    pub resolution_deg: f64,
    /// Largest tilt tried, degrees \[80\].
    pub max_angle_deg: f64,
    /// Collapse when a top point has moved (in y) since α = 0 more than this fraction of the
    /// wall width, or the elastic displacement scale of the joints ([`elastic_scale`](super::elastic_scale)) if
    /// that is larger \[0.5\].
    pub collapse_displacement_fraction: f64,
    /// Collapse when, within one increment, a block moves (centroid motion plus rotation
    /// times its radius) more than this fraction of the wall width, or the elastic
    /// displacement scale of the joints ([`elastic_scale`](super::elastic_scale)) if that is larger \[0.05\]. Also
    /// the reach of the probe that confirms the stability indicator.
    pub collapse_increment_fraction: f64,
    /// Deprecated: choose the solver instead (`[solver] kind = "relaxation"`, `--solver
    /// relaxation`). `false` turns the secant acceleration of slow creep and its stability
    /// indicator off in whichever penalty solver runs ([`TiltParams::cascade`]) \[true\].
    pub accelerate: bool,
    /// Deprecated: choose the solver instead (`[solver] kind = "accelerated"`, `--solver
    /// accelerated`). `false` turns the implicit iteration of each increment off in
    /// whichever penalty solver runs ([`TiltParams::cascade`]) \[true\].
    pub implicit: bool,
    /// Deprecated: `[solver.penalty] tolerance` ([`PenaltyParams::tolerance`](crate::dem::PenaltyParams::tolerance)), which this
    /// key still sets, with a warning \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// Deprecated: `[solver.penalty] max_steps` ([`PenaltyParams::max_steps`](crate::dem::PenaltyParams::max_steps)), which this
    /// key still sets, with a warning \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_steps_per_increment: Option<u64>,
    /// Deprecated: `[solver.penalty] predictor` ([`PenaltyParams::predictor`](crate::dem::PenaltyParams::predictor)), which this
    /// key still sets, with a warning \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub predictor: Option<bool>,
    /// Deprecated: `[solver.penalty] acceleration` ([`PenaltyParams::acceleration`](crate::dem::PenaltyParams::acceleration)), which
    /// this key still sets, with a warning \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub acceleration: Option<SecantAcceleration>,
    /// Deprecated: `[solver.penalty] implicit_solve` ([`PenaltyParams::implicit_solve`](crate::dem::PenaltyParams::implicit_solve)),
    /// which this key still sets, with a warning \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub implicit_solve: Option<ImplicitSolve>,
    /// The table rolled by hand (`loading::tilt_hand`): each increment run as a motion
    /// whose stop kicks the wall, by non-smooth contact dynamics (`[solver] kind =
    /// "nscd"` only; `[tilt] by_hand = { rate_deg_per_s = 2.5, ramp_s = 0.1 }`, any key of
    /// [`HandTilt`] left out takes its default) \[none: the quasi-static test\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub by_hand: Option<HandTilt>,
}

impl Default for TiltParams {
    fn default() -> Self {
        TiltParams {
            step_deg: 0.5,
            resolution_deg: 0.125,
            max_angle_deg: 80.0,
            collapse_displacement_fraction: 0.5,
            collapse_increment_fraction: 0.05,
            accelerate: true,
            implicit: true,
            by_hand: None,
            tolerance: None,
            max_steps_per_increment: None,
            predictor: None,
            acceleration: None,
            implicit_solve: None,
        }
    }
}

impl TiltParams {
    /// The stages of the static solve of every increment and trial with the solver `kind`:
    /// the tilting table's default is [`Cascade::IMPLICIT`] (the implicit iteration, its
    /// stall probe, accelerated and probed dynamic relaxation; `--solver newton` puts the
    /// semi-smooth Newton solve before them); the deprecated [`TiltParams::implicit`]
    /// (both implicit stages) and [`TiltParams::accelerate`] switch stages off.
    /// `Cascade::RELAXATION` for a solver that is not a penalty method (which does not run
    /// this protocol).
    pub fn cascade(&self, kind: SolverKind) -> Cascade {
        let c = kind.cascade(Cascade::IMPLICIT).unwrap_or(Cascade::RELAXATION);
        Cascade {
            newton: c.newton && self.implicit,
            implicit: c.implicit && self.implicit,
            accelerate: c.accelerate && self.accelerate,
        }
    }

    /// The penalty settings written under this table's former keys (deprecated; see
    /// [`MovedKey`]), in field order.
    pub fn moved(&self) -> Vec<MovedKey> {
        [
            self.tolerance.map(|v| MovedKey::new("tolerance", MovedValue::Tolerance(v))),
            self.max_steps_per_increment.map(|v| MovedKey::new("max_steps_per_increment", MovedValue::MaxSteps(v))),
            self.predictor.map(|v| MovedKey::new("predictor", MovedValue::Predictor(v))),
            self.acceleration.map(|v| MovedKey::new("acceleration", MovedValue::Acceleration(v))),
            self.implicit_solve.map(|v| MovedKey::new("implicit_solve", MovedValue::ImplicitSolve(v))),
        ]
        .into_iter()
        .flatten()
        .collect()
    }

    /// The deprecation lines (without `warning: `) of the switches of the penalty cascade
    /// turned off ([`Self::accelerate`], [`Self::implicit`]: the stages are the solver's,
    /// `[solver] kind`), with the table's name `table`; none when both are on.
    pub fn cascade_warnings(&self, table: &str) -> Vec<String> {
        let instead = match (self.implicit, self.accelerate) {
            (false, true) => "kind = \"accelerated\"",
            (false, false) => "kind = \"relaxation\"",
            (true, false) => "no kind turns the acceleration off alone",
            (true, true) => return Vec::new(),
        };
        [("accelerate", self.accelerate), ("implicit", self.implicit)]
            .into_iter()
            .filter(|(_, on)| !on)
            .map(|(key, _)| {
                format!(
                    "{table}.{key} = false is deprecated: the stages of the penalty DEM are chosen with \
                     [solver] kind ({instead}); it still turns its stage off"
                )
            })
            .collect()
    }

    /// These parameters without the former keys ([`Self::moved`]), once they are applied
    /// to the solver's settings.
    pub fn without_moved(self) -> TiltParams {
        TiltParams {
            tolerance: None,
            max_steps_per_increment: None,
            predictor: None,
            acceleration: None,
            implicit_solve: None,
            ..self
        }
    }

    /// Checks ranges.
    ///
    /// # Errors
    /// The first parameter out of its range, with the range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            ("step_deg", self.step_deg, self.step_deg > 0.0 && self.step_deg <= 10.0, "in (0, 10]"),
            (
                "resolution_deg",
                self.resolution_deg,
                self.resolution_deg > 0.0 && self.resolution_deg <= self.step_deg,
                "in (0, step_deg]",
            ),
            ("max_angle_deg", self.max_angle_deg, self.max_angle_deg > 0.0 && self.max_angle_deg < 90.0, "in (0, 90)"),
            (
                "collapse_displacement_fraction",
                self.collapse_displacement_fraction,
                self.collapse_displacement_fraction > 0.0,
                "> 0",
            ),
            (
                "collapse_increment_fraction",
                self.collapse_increment_fraction,
                self.collapse_increment_fraction > 0.0,
                "> 0",
            ),
        ])?;
        for m in self.moved() {
            m.check()?;
        }
        if let Some(h) = &self.by_hand {
            h.validate().map_err(|e| OutOfRange { key: format!("by_hand.{}", e.key), ..e })?;
        }
        Ok(())
    }
}
