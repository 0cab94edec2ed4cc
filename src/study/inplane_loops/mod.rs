//! The loops of the cyclic specimens, a reading the in-plane analysis does not fit: asked of
//! each candidate before it is named, and reported for the baseline and the leading models
//! (`drystone discrepancy` on an in-plane study).
//!
//! The analysis fits each specimen's first direction pushed monotonically
//! ([`super::inplane_discrepancy`]); the whole cyclic curves the database holds are left
//! out of it, and their hysteresis loops tell apart what its observables do not: a force
//! that depends on the displacement alone (a leaning jack's `N u / L`, the joints' closure)
//! dissipates nothing over a cycle, a friction against the motion (the rig's bearing, `μ_r
//! N`) dissipates `4 μ_r N a` a cycle of amplitude `a`. The reading is the loops' equivalent
//! viscous damping ratio ([`crate::loading::inplane_loops`]) over the cycles of at least
//! [`LOOP_MIN_DRIFT_PCT`] % drift.
//!
//! Each model checked (the baseline, every candidate that may be named, asked before it
//! is confirmed or named, and the models in the analysis's tie, at their parameters fitted
//! to all the data) is run cyclic at each stress of the study's cyclic
//! specimens, on the analysis's own layouts of that group (`effects::realize`, the group's
//! effects and the model's): each specimen whose curve is read on its own history, its
//! turning points replayed in the order the laboratory ran them
//! ([`crate::loading::inplane_loops::turning_points`], [`InPlaneParams::reversals_pct`]), on
//! a layout of its own (the realization of its index in the group); a group given without
//! histories on [`LOOP_REALIZATIONS`] layouts by the study's history. Per group, the
//! measured reading is the median of the specimens' (one badly digitized loop does not move
//! it), its standard error `1.2533 σ / √n` with `σ` the specimens' spread within their
//! groups pooled over the groups (Shamos's estimator, 1.0483 times the median absolute
//! difference of the pairs of specimens of one group: robust to one bad loop, and usable
//! with three specimens a group, where the median absolute deviation is not); the
//! model's is the mean of its realizations, with their standard error. The statistic is
//! `χ² = Σ_g z_g²`, `z_g` the difference over the two errors combined, on as many degrees
//! of freedom as groups; a model fits the loops when its χ² is below the 95th percentile.
//! A group with no measured or no simulated cycle of at least the minimum drift (a history
//! that stops below it) has no `z` and is left out of the sum; a model with no group read
//! is not read ([`LoopVerdict::NotRead`]), which is never a refutation.
//!
//! **A reading that refutes.** The loops are the analysis's held reading
//! ([`LoopsReading`], [`crate::discrepancy::HeldReading`]): a candidate whose χ² fails
//! (p < 0.05) and exceeds the baseline's by more than `2 ×`
//! [`crate::discrepancy::REFUTE_NATS`] (a likelihood ratio of 20 against it) is refuted by
//! them, and the analysis names the best candidate they do not refute. A model that fails
//! the loops no worse than the baseline is not refuted: the loops are then a misfit it
//! leaves, as the baseline does.
//!
//! **The friction the loops read.** A bearing's friction acts on the readings only (the
//! beam's motion is imposed), so each run's curve of the wall's own shear
//! ([`crate::loading::inplane::InPlaneResult::wall_curve`]) is read again with the rig's
//! friction `μ_r` in place of the model's ([`crate::loading::inplane::add_rig_force`], the
//! run's own code; the model's jack kept), on a grid of [`FRICTION_READ_STEPS`] steps over
//! the range of `rig_friction`, without a new run. Per model, the `μ_r` that minimizes the
//! χ² above, and its 95 % profile interval (where χ² is within 3.84 of its least): the
//! bearing friction the loops say the model's wall had. A friction fitted to the peaks
//! outside that interval is refuted by the loops; a model whose χ² there is below the 95th
//! percentile fits the loops with that friction.

mod check;
mod reading;
mod report;

pub use super::inplane_discrepancy::{measured_loops, MeasuredLoops};
pub use check::check_models;
pub use reading::{refit_peaks, LoopsReading};

use crate::effects::Effect;
use crate::loading::inplane_loops::LOOP_MIN_DRIFT_PCT;
use serde::Serialize;

/// Realizations per group and model of the check: the simulated readings of one group
/// spread little between layouts (σ 0.0001–0.0011 on the granite walls, against the
/// specimens' 0.0020), so two realizations give the model's mean and a spread to carry.
pub const LOOP_REALIZATIONS: u64 = 2;

/// The steps of the grid of bearing frictions the loops are read again at (module
/// documentation), over the range of `rig_friction` from 0: 0.0005 apart on its 0–0.05.
pub const FRICTION_READ_STEPS: usize = 100;

/// The bearing friction a model's loops read (module documentation).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct FrictionRead {
    /// The `μ_r` of least χ², on the grid.
    pub friction: f64,
    /// Its 95 % profile interval, the grid's frictions where χ² is within 3.84 of the least
    /// (the ends: the grid's values, 0 or the range's top when the interval reaches them).
    pub low: f64,
    /// See `low`.
    pub high: f64,
    /// χ² at `friction`.
    pub chi2: f64,
    /// Its p-value (degrees of freedom: the groups read, less one for the friction read; at
    /// least 1).
    pub p_value: f64,
}

/// One group (stress) of the check.
#[derive(Debug, Clone, Serialize)]
pub struct LoopGroup {
    /// The analysis's group, `0.5 MPa`.
    pub group: String,
    /// The specimens' readings, `(unit, ξ_eq)`; those without a reading (no curve) left out.
    pub measured: Vec<(String, f64)>,
    /// The model's readings, one per realization (NaN for a run that failed).
    pub simulated: Vec<f64>,
    /// `(median measured − mean simulated) / combined standard error`.
    pub z: f64,
}

/// One model of the check.
#[derive(Debug, Clone, Serialize)]
pub struct LoopModel {
    /// `baseline` or the candidate's name.
    pub name: String,
    /// Its fitted parameters, `effect.param = value` (none for the baseline).
    pub parameters: Vec<(String, f64)>,
    /// Per group.
    pub groups: Vec<LoopGroup>,
    /// `Σ z²` over the groups read (those with a measured and a simulated cycle of at least
    /// [`LOOP_MIN_DRIFT_PCT`] % drift); NaN when none was.
    pub chi2: f64,
    /// The probability of a χ² as large under the model (degrees of freedom: the groups
    /// read); NaN when none was ([`LoopVerdict::NotRead`]).
    pub p_value: f64,
    /// The model's own bearing friction `μ_r` (`rig_friction`; 0 without it).
    pub friction: f64,
    /// The bearing friction its loops read, the model's own replaced (`None` when no run
    /// of it gave a reading).
    pub friction_read: Option<FrictionRead>,
    /// What the loops say of it.
    pub verdict: LoopVerdict,
    /// The analysis's observations refit with the bearing friction held at the one its
    /// loops read ([`crate::discrepancy::Run::refit_held`]; the model's effects with
    /// `rig_friction`, on the analysis's surrogates read again, no run). `None` without a
    /// friction read, or where the analysis has no surrogate of those effects (a two-
    /// parameter partner of both rig forces).
    pub peaks: Option<crate::discrepancy::HeldRefit>,
    /// Its wall is the baseline's ([`crate::discrepancy::Run::is_baseline_model`]: the
    /// specimen-scatter hypothesis, or every effect at its neutral value), so its loops are
    /// the baseline's, read once and not run again.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub baseline_wall: bool,
}

/// What the loops say of a model (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LoopVerdict {
    /// It fits the loops as fitted (χ²'s p-value at least 0.05).
    Fits,
    /// It does not, but its wall fits them with another bearing friction in place of its
    /// own ([`FrictionRead`], p-value at least 0.05): the loops refute its friction, not
    /// the rest of it.
    FitsWithFriction,
    /// It fits them with no bearing friction of `rig_friction`'s range, but its χ² exceeds
    /// the baseline's by at most `2 REFUTE_NATS` ([`refutes_beyond_baseline`]): worse than
    /// the baseline by less than the analysis refutes any reading at, so not refuted.
    Misfits,
    /// It fits them with no bearing friction of `rig_friction`'s range, and its χ² exceeds
    /// the baseline's by more than `2 REFUTE_NATS` ([`refutes_beyond_baseline`]).
    Refuted,
    /// Nothing to read: no group with both a measured and a simulated cycle of at least
    /// [`LOOP_MIN_DRIFT_PCT`] % drift (a history that stops below it, runs that all
    /// failed). Never a refutation: the loops say nothing of the model.
    NotRead,
}

impl LoopVerdict {
    /// The verdict of a model whose χ² over the groups read has the p-value `p_value`
    /// (NaN when no group was read) and whose loops read `read`.
    fn of(p_value: f64, read: Option<&FrictionRead>) -> LoopVerdict {
        if p_value.is_nan() {
            LoopVerdict::NotRead
        } else if p_value >= 0.05 {
            LoopVerdict::Fits
        } else if read.is_some_and(|f| f.p_value >= 0.05) {
            LoopVerdict::FitsWithFriction
        } else {
            LoopVerdict::Refuted
        }
    }

    /// The report's words.
    pub fn words(self) -> String {
        match self {
            LoopVerdict::Fits => "fits the loops".into(),
            LoopVerdict::FitsWithFriction => "fits the loops with the friction they read".into(),
            LoopVerdict::Misfits => format!(
                "misfits the loops, by less than {} nats beyond the baseline: not refuted",
                crate::discrepancy::REFUTE_NATS
            ),
            LoopVerdict::Refuted => "refuted by the loops".into(),
            LoopVerdict::NotRead => format!("not read: no cycle of at least {LOOP_MIN_DRIFT_PCT} % drift"),
        }
    }

    /// Whether the loops refute the model (never so when they were not read).
    pub fn refutes(self) -> bool {
        self == LoopVerdict::Refuted
    }
}

/// Whether a model whose loops' χ² is `chi2` with the p-value `p_value` is refuted by them
/// beside a baseline of χ² `baseline_chi2` (NaN: nothing read, counted as 0): its fit fails
/// (p below 0.05) and it predicts the loops worse than the baseline by more than
/// [`crate::discrepancy::REFUTE_NATS`] (a χ² excess of twice that), the rule by which every
/// other reading refutes a candidate (`discrepancy::refute`). The report's verdict and the
/// analysis's judge both read it.
pub fn refutes_beyond_baseline(chi2: f64, p_value: f64, baseline_chi2: f64) -> bool {
    let base = if baseline_chi2.is_finite() { baseline_chi2 } else { 0.0 };
    p_value < 0.05 && chi2 - base > 2.0 * crate::discrepancy::REFUTE_NATS
}

/// Sets [`LoopVerdict::Misfits`] on every model of `models` the loops would refute alone but
/// that predicts them no worse than the model named `baseline` by the analysis's margin
/// ([`refutes_beyond_baseline`]); nothing without a baseline among them. The one rule of a
/// check of several models and of the report's check assembled from one model at a time.
fn judge_against_baseline(models: &mut [LoopModel]) {
    let Some(base) = models.iter().find(|m| m.name == "baseline").map(|m| m.chi2) else {
        return;
    };
    for m in models.iter_mut().filter(|m| m.verdict == LoopVerdict::Refuted) {
        if !refutes_beyond_baseline(m.chi2, m.p_value, base) {
            m.verdict = LoopVerdict::Misfits;
        }
    }
}

/// What the check found.
#[derive(Debug, Clone, Serialize)]
pub struct LoopCheck {
    /// The smallest drift amplitude of the cycles read, %.
    pub min_drift_pct: f64,
    /// The measured readings' spread within their groups (σ, pooled; Shamos's estimator).
    pub measured_sigma: f64,
    /// The models, in the order checked (the baseline first, then the tie's order).
    pub models: Vec<LoopModel>,
    /// The cyclic runs made.
    pub runs: usize,
    /// The groups whose specimens were each run on their own measured history (the others
    /// ran the study's history on [`LOOP_REALIZATIONS`] layouts).
    pub own_histories: usize,
    /// The baseline's held-out error on the analysis's observations (per specimen), beside
    /// the models' [`LoopModel::peaks`]; NaN when the check ran without an analysis.
    pub baseline_heldout_error: f64,
    /// The analysis's named cause (or partial explanation) and its held-out error.
    pub cause: Option<(String, f64)>,
}

fn finite(x: &[f64]) -> Vec<f64> {
    x.iter().copied().filter(|v| v.is_finite()).collect()
}

fn median(x: &[f64]) -> f64 {
    crate::stats::quantile(&finite(x), 0.5)
}

/// A model of the check: its name, its parameters (`effect.param`, value) and its effects.
pub type LoopCandidate = (String, Vec<(String, f64)>, Vec<Effect>);

/// The baseline's entry in the check.
fn baseline_candidate() -> LoopCandidate {
    ("baseline".into(), vec![], vec![])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The loops refute a model as every other reading refutes a candidate: its fit fails
    /// and it is worse than the baseline by more than `REFUTE_NATS` (a χ² excess of 6). The
    /// in-plane analysis's `jack_tilt+load_eccentricity` on the granite walls (χ² 9.7, p
    /// 0.021, the baseline 5.1) misfits the loops without being refuted; its
    /// `rig_friction+load_eccentricity` (χ² 657) is refuted; a baseline with nothing read
    /// counts as 0.
    #[test]
    fn the_loops_refute_by_the_analysiss_margin_over_the_baseline() {
        assert!(!refutes_beyond_baseline(9.7, 0.021, 5.1));
        assert!(refutes_beyond_baseline(657.2, 0.0, 5.1));
        assert!(!refutes_beyond_baseline(11.0, 0.2, 5.0), "a fit that holds is never refuted");
        assert!(refutes_beyond_baseline(6.5, 0.01, f64::NAN));
        assert!(!refutes_beyond_baseline(5.9, 0.01, f64::NAN));
    }

    fn model(name: &str, chi2: f64, p_value: f64, verdict: LoopVerdict) -> LoopModel {
        LoopModel {
            name: name.into(),
            parameters: vec![],
            groups: vec![],
            chi2,
            p_value,
            friction: 0.0,
            friction_read: None,
            verdict,
            peaks: None,
            baseline_wall: false,
        }
    }

    /// The report's check is assembled from checks of one model each, none with the
    /// baseline beside it, so each failing fit comes in `Refuted`: judged against the
    /// baseline once assembled, a model whose χ² is below the baseline's (the granite
    /// walls' `jack_tilt+load_eccentricity` at two sub-contact subdivisions: χ² 9.3 against
    /// 9.5) misfits the loops and is not listed as refuted, as the analysis's verdict reads
    /// it; one far beyond (χ² 869.5) stays refuted.
    #[test]
    fn a_check_assembled_one_model_at_a_time_judges_each_against_the_baseline() {
        let mut models = vec![
            model("baseline", 9.5, 0.023, LoopVerdict::Refuted),
            model("jack_tilt+load_eccentricity", 9.3, 0.026, LoopVerdict::Refuted),
            model("rig_friction+jack_incline", 869.5, 0.0, LoopVerdict::Refuted),
            model("bed_stiffness", 8.5, 0.038, LoopVerdict::FitsWithFriction),
        ];
        judge_against_baseline(&mut models);
        let verdicts: Vec<LoopVerdict> = models.iter().map(|m| m.verdict).collect();
        assert_eq!(
            verdicts,
            [LoopVerdict::Misfits, LoopVerdict::Misfits, LoopVerdict::Refuted, LoopVerdict::FitsWithFriction]
        );
        let mut alone = vec![model("jack_tilt+load_eccentricity", 9.3, 0.026, LoopVerdict::Refuted)];
        judge_against_baseline(&mut alone);
        assert_eq!(alone[0].verdict, LoopVerdict::Refuted, "no baseline to judge against");
    }
}
