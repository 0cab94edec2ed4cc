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

use super::inplane::InPlaneStudyError;
pub use super::inplane_discrepancy::{measured_loops, MeasuredLoops};
use super::own::OwnAnalysis;
use crate::discrepancy::Run;
use crate::effects::Effect;
use crate::loading::inplane::{History, InPlaneParams};
use crate::loading::inplane_loops::{loop_damping_ratio, LOOP_MIN_DRIFT_PCT};
use rayon::prelude::*;
use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};
use std::fmt::Write as _;
use std::path::Path;

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
    /// It fits them with no bearing friction of `rig_friction`'s range.
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
            LoopVerdict::Refuted => "refuted by the loops".into(),
            LoopVerdict::NotRead => format!("not read: no cycle of at least {LOOP_MIN_DRIFT_PCT} % drift"),
        }
    }

    /// Whether the loops refute the model (never so when they were not read).
    pub fn refutes(self) -> bool {
        self == LoopVerdict::Refuted
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

impl LoopCheck {
    /// The models the loops do not refute whose peaks were refit with the friction their
    /// loops read ([`LoopModel::peaks`]), best held-out error first: what both readings
    /// leave standing. Empty when none.
    pub fn standing(&self) -> Vec<&LoopModel> {
        let mut v: Vec<&LoopModel> = self.models.iter().filter(|m| Self::stands(m) && m.peaks.is_some()).collect();
        v.sort_by(|a, b| {
            let e = |m: &LoopModel| m.peaks.as_ref().map_or(f64::INFINITY, |p| p.heldout_error);
            e(a).total_cmp(&e(b))
        });
        v
    }

    /// Whether a model fits the loops as fitted (its χ²'s p-value at least 0.05).
    pub fn fits(m: &LoopModel) -> bool {
        m.verdict == LoopVerdict::Fits
    }

    /// Whether the loops were read and leave a model standing (it fits them, as fitted or
    /// with the friction they read); a model they did not read is neither standing nor
    /// refuted.
    fn stands(m: &LoopModel) -> bool {
        matches!(m.verdict, LoopVerdict::Fits | LoopVerdict::FitsWithFriction)
    }

    /// How the runs' histories were chosen, in words.
    fn histories_run(&self) -> String {
        let groups = self.models.first().map_or(0, |m| m.groups.len());
        if self.own_histories == groups {
            "each specimen on its own measured history (its curve's turning points, in the laboratory's order) on a \
             layout of its own"
                .to_string()
        } else if self.own_histories == 0 {
            format!("the study's history on {LOOP_REALIZATIONS} layouts a stress")
        } else {
            format!(
                "each specimen on its own measured history where its group has them ({} of {groups} stresses), \
                 elsewhere the study's history on {LOOP_REALIZATIONS} layouts",
                self.own_histories
            )
        }
    }

    /// The report's section (Markdown).
    pub fn markdown(&self) -> String {
        let mut md = String::new();
        let _ = writeln!(md, "## The cyclic loops: a reading the fit does not hold\n");
        let _ = writeln!(
            md,
            "The loops' equivalent viscous damping ratio ξ_eq = E_d / (4π E_s), the median over the cycles of at \
             least {} % drift, of each cyclic specimen's whole measured curve and of each model run cyclic at its \
             fitted parameters, {} ({} runs): the baseline, every candidate asked before it could be named and the \
             models of the tie (a model whose wall is the baseline's, the scatter hypothesis or effects at their \
             neutral values, takes the baseline's loops). A model whose χ² fails (p < 0.05) and exceeds the baseline's by more than {} is \
             refuted by the loops and not named (the verdict's list of refuted candidates). A friction against the motion \
             (`rig_friction`) dissipates `4 μ_r N a` a cycle, a force of the displacement alone (`jack_tilt`, the \
             joints' closure) nothing. Per stress: the specimens' median against the model's mean, z their difference \
             over the standard errors (the specimens' spread σ = {:.4}, pooled); a model fits the loops when Σ z² is \
             below the χ² 95th percentile. The last columns read each run's curve of the wall's own shear again \
             with a bearing friction μ_r in place of the model's (no new run): the μ_r of least χ², its 95 % profile \
             interval, and the χ² there.\n",
            self.min_drift_pct,
            self.histories_run(),
            self.runs,
            2.0 * crate::discrepancy::REFUTE_NATS,
            self.measured_sigma
        );
        let Some(first) = self.models.first() else {
            return md;
        };
        let mut head = String::from("| model |");
        let mut rule = String::from("| --- |");
        for g in &first.groups {
            let _ = write!(head, " {} (z) |", g.group);
            rule.push_str(" --- |");
        }
        head.push_str(" χ² | p | fits the loops | μ_r the loops read (95 %) | χ² there |");
        rule.push_str(" --- | --- | --- | --- | --- |");
        let _ = writeln!(md, "{head}\n{rule}");
        let mut measured = String::from("| measured (median of the specimens) |");
        for g in &first.groups {
            let v: Vec<f64> = g.measured.iter().map(|(_, x)| *x).collect();
            let _ = write!(measured, " {:.4} ({}) |", median(&v), v.len());
        }
        measured.push_str(" | | | | |");
        let _ = writeln!(md, "{measured}");
        for m in &self.models {
            let wall = if m.baseline_wall { " (the baseline's wall)" } else { "" };
            let mut line = format!("| `{}`{wall} |", m.name);
            for g in &m.groups {
                let _ = write!(line, " {:.4} ({:+.1}) |", crate::stats::mean(&finite(&g.simulated)), g.z);
            }
            let fits = match m.verdict {
                LoopVerdict::NotRead => "not read",
                _ if Self::fits(m) => "yes",
                _ => "no",
            };
            let _ = write!(line, " {:.1} | {:.2e} | {fits} |", m.chi2, m.p_value);
            match &m.friction_read {
                Some(f) => {
                    let _ = write!(line, " {:.4} [{:.4}, {:.4}] | {:.1} |", f.friction, f.low, f.high, f.chi2);
                }
                None => line.push_str(" – | – |"),
            }
            let _ = writeln!(md, "{line}");
        }
        let _ = writeln!(md);
        let named = |v: LoopVerdict| -> Vec<String> {
            self.models
                .iter()
                .filter(|m| m.verdict == v)
                .map(|m| match (&m.friction_read, v) {
                    (Some(f), LoopVerdict::FitsWithFriction) if m.friction > 0.0 => format!(
                        "`{}` (μ_r {:.4} [{:.4}, {:.4}] in place of its {:.4})",
                        m.name, f.friction, f.low, f.high, m.friction
                    ),
                    (Some(f), LoopVerdict::FitsWithFriction) => {
                        format!("`{}` (μ_r {:.4} [{:.4}, {:.4}] added)", m.name, f.friction, f.low, f.high)
                    }
                    _ => format!("`{}`", m.name),
                })
                .collect()
        };
        let _ = writeln!(md, "What the loops say of each model:\n");
        for v in [LoopVerdict::Fits, LoopVerdict::FitsWithFriction, LoopVerdict::Refuted, LoopVerdict::NotRead] {
            let n = named(v);
            if v == LoopVerdict::NotRead && n.is_empty() {
                continue;
            }
            let _ = writeln!(md, "- {}: {}", v.words(), if n.is_empty() { "none".into() } else { n.join(", ") });
        }
        let _ = writeln!(md);
        self.peaks_markdown(&mut md);
        md
    }

    /// The section's part on the peaks refit with the friction the loops read.
    fn peaks_markdown(&self, md: &mut String) {
        if !self.models.iter().any(|m| m.peaks.is_some()) {
            return;
        }
        let _ = writeln!(
            md,
            "### The analysis's observations with the friction the loops read
"
        );
        let cause = self.cause.as_ref().map(|(n, e)| format!(", the cause's (`{n}`) {e:.2}")).unwrap_or_default();
        let _ = writeln!(
            md,
            "Each model with `rig_friction` added or its own replaced, its other parameters refit to the analysis's \
             observations with the bearing friction held at the μ_r its loops read (the analysis's surrogates read \
             again, no run), scored as the ranking scores: held-out error per specimen, against the baseline's {:.2}{cause}.\n",
            self.baseline_heldout_error
        );
        let _ = writeln!(md, "| model | loops say | μ_r held | held-out error (± se of the gain) | parameters |");
        let _ = writeln!(md, "| --- | --- | --- | --- | --- |");
        for m in &self.models {
            let (Some(p), Some(f)) = (&m.peaks, &m.friction_read) else { continue };
            let params: Vec<String> = p
                .parameters
                .iter()
                .filter(|(n, _)| !n.starts_with("rig_friction."))
                .map(|(n, v)| if v.abs() >= 0.1 || *v == 0.0 { format!("{n} {v:.3}") } else { format!("{n} {v:.2e}") })
                .collect();
            let _ = writeln!(
                md,
                "| `{}` | {} | {:.4} | {:.2} (± {:.2}) | {} |",
                m.name,
                m.verdict.words(),
                f.friction,
                p.heldout_error,
                p.difference_se,
                if params.is_empty() { "–".into() } else { params.join(", ") }
            );
        }
        let standing = self.standing();
        let _ = writeln!(md);
        match standing.first().and_then(|m| m.peaks.as_ref().map(|p| (m, p))) {
            Some((m, p)) => {
                let others: Vec<String> = standing[1..]
                    .iter()
                    .filter_map(|o| o.peaks.as_ref().map(|q| format!("`{}` {:.2}", o.name, q.heldout_error)))
                    .collect();
                let _ = writeln!(
                    md,
                    "What both readings leave standing: `{}` with μ_r {:.4} held (held-out error {:.2}, gain on the \
                     baseline {:.2} ± {:.2} per specimen){}.\n",
                    m.name,
                    m.friction_read.map_or(f64::NAN, |f| f.friction),
                    p.heldout_error,
                    self.baseline_heldout_error - p.heldout_error,
                    p.difference_se,
                    if others.is_empty() { String::new() } else { format!("; then {}", others.join(", ")) }
                );
            }
            None => {
                let _ = writeln!(md, "What both readings leave standing: none of the models checked.\n");
            }
        }
    }
}

fn finite(x: &[f64]) -> Vec<f64> {
    x.iter().copied().filter(|v| v.is_finite()).collect()
}

fn median(x: &[f64]) -> f64 {
    crate::stats::quantile(&finite(x), 0.5)
}

/// The cyclic loops as the analysis's held reading ([`crate::discrepancy::HeldReading`]):
/// asked of each candidate that may be named before it is confirmed or named (a model whose
/// loops' χ² fails, p < 0.05, and exceeds the baseline's by more than `2 ×`
/// [`crate::discrepancy::REFUTE_NATS`] is refuted by them), and reported after the analysis
/// for the baseline, every model it judged and the models of the tie (module
/// documentation). Each model's loops are run once (by its name and parameters).
pub struct LoopsReading {
    /// The analysis's groups, solver and seed.
    setup: crate::discrepancy::Setup,
    /// The measured groups.
    groups: Vec<MeasuredLoops>,
    /// The study's test (its history, shear span, solver settings), at each group's σ0.
    test: InPlaneParams,
    /// The walls' mean course height, m.
    course_m: f64,
    /// The models checked, in the order first asked: name, parameters' bits and the check of
    /// that model alone.
    checked: std::sync::Mutex<Vec<(String, Vec<u64>, LoopCheck)>>,
}

/// The baseline's entry in the check.
fn baseline_candidate() -> LoopCandidate {
    ("baseline".into(), vec![], vec![])
}

impl LoopsReading {
    /// The loops of the in-plane study `path` analysed as `input`; `None` when the study has
    /// no cyclic specimen with a measured curve (`[measured] curves`).
    ///
    /// # Errors
    /// The study or its measured files unreadable (named).
    pub fn of(path: &Path, input: &OwnAnalysis) -> Result<Option<LoopsReading>, InPlaneStudyError> {
        let Some((groups, test)) = measured_loops(path, input)? else {
            return Ok(None);
        };
        Ok(Some(LoopsReading {
            course_m: crate::discrepancy::course_height(&input.setup),
            setup: input.setup.clone(),
            groups,
            test,
            checked: std::sync::Mutex::new(vec![]),
        }))
    }

    /// The check of one model, run once.
    fn model(
        &self,
        m: &LoopCandidate,
        progress: crate::discrepancy::Progress<'_>,
    ) -> Result<LoopCheck, InPlaneStudyError> {
        let bits: Vec<u64> = m.1.iter().map(|(_, v)| v.to_bits()).collect();
        let lock = || self.checked.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((_, _, c)) = lock().iter().find(|(n, b, _)| *n == m.0 && *b == bits) {
            return Ok(c.clone());
        }
        let params = |sigma0_mpa: f64| InPlaneParams { sigma0_mpa, ..self.test.clone() };
        let c = check_models(&self.setup, &params, &self.groups, std::slice::from_ref(m), progress)?;
        lock().push((m.0.clone(), bits, c.clone()));
        Ok(c)
    }

    fn held_error(e: InPlaneStudyError) -> crate::discrepancy::DiscrepancyError {
        crate::discrepancy::DiscrepancyError::Held { reading: "cyclic loops".into(), message: e.to_string() }
    }

    /// The check of the baseline, every model judged (at its latest parameters) and the
    /// models of `run`'s tie, with the peaks refit at the friction each model's loops read
    /// ([`refit_peaks`]).
    ///
    /// # Errors
    /// A fitted parameter refused, a run's layout not made.
    pub fn check(&self, run: &Run, progress: crate::discrepancy::Progress<'_>) -> Result<LoopCheck, InPlaneStudyError> {
        let mut models: Vec<LoopCandidate> = vec![baseline_candidate()];
        let judged: Vec<String> = {
            let all = self.checked.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
            let mut names: Vec<String> = vec![];
            for (n, _, _) in all.iter() {
                if n != "baseline" && !names.contains(n) {
                    names.push(n.clone());
                }
            }
            names
        };
        // The tie's models whose wall is the baseline's take the baseline's loops.
        let mut as_baseline: Vec<(String, Vec<(String, f64)>)> = vec![];
        for name in judged.iter().chain(run.analysis.tie.iter().filter(|t| !judged.contains(t))) {
            if run.is_baseline_model(name) {
                let parameters = run.analysis.candidates.iter().find(|r| &r.name == name).map(|r| r.parameters.clone());
                as_baseline.push((name.clone(), parameters.unwrap_or_default()));
                continue;
            }
            let effects = run
                .fitted_effects(name, self.course_m)
                .map_err(|e| InPlaneStudyError::Write(format!("the loops of {name}: {e}")))?;
            let Some(effects) = effects else { continue };
            let parameters = run
                .analysis
                .candidates
                .iter()
                .find(|r| &r.name == name)
                .map(|r| r.parameters.clone())
                .unwrap_or_default();
            models.push((name.clone(), parameters, effects));
        }
        let checks: Vec<LoopCheck> = models.iter().map(|m| self.model(m, progress)).collect::<Result<_, _>>()?;
        let runs =
            self.checked.lock().unwrap_or_else(std::sync::PoisonError::into_inner).iter().map(|c| c.2.runs).sum();
        let first = &checks[0];
        let mut check = LoopCheck {
            min_drift_pct: first.min_drift_pct,
            measured_sigma: first.measured_sigma,
            models: checks
                .iter()
                .flat_map(|c| c.models.first().cloned())
                .chain(as_baseline.into_iter().filter_map(|(name, parameters)| {
                    let base = checks[0].models.first()?;
                    Some(LoopModel { name, parameters, baseline_wall: true, ..base.clone() })
                }))
                .collect(),
            runs,
            own_histories: first.own_histories,
            baseline_heldout_error: f64::NAN,
            cause: None,
        };
        refit_peaks(&mut check, run);
        Ok(check)
    }

    /// The lines the command prints of `check`.
    pub fn summary(check: &LoopCheck) -> Vec<String> {
        let mut summary =
            vec!["the cyclic loops (a reading the fit does not hold): the loops' damping ratio, χ² over the stresses"
                .to_string()];
        for m in &check.models {
            let read = m
                .friction_read
                .map(|f| format!("  μ_r read {:.4} [{:.4}, {:.4}], χ² {:.1}", f.friction, f.low, f.high, f.chi2))
                .unwrap_or_default();
            let peaks = m
                .peaks
                .as_ref()
                .map(|p| format!("; held-out error with it {:.2}", p.heldout_error))
                .unwrap_or_default();
            summary.push(format!(
                "  {:<36} χ² {:>8.1}  p {:.2e}  {}{read}{peaks}",
                m.name,
                m.chi2,
                m.p_value,
                m.verdict.words()
            ));
        }
        if let Some((m, p)) = check.standing().first().and_then(|m| m.peaks.as_ref().map(|p| (m, p))) {
            summary.push(format!(
                "  both readings leave standing: {} with μ_r {:.4} held, held-out error {:.2} (baseline {:.2})",
                m.name,
                m.friction_read.map_or(f64::NAN, |f| f.friction),
                p.heldout_error,
                check.baseline_heldout_error
            ));
        }
        summary
    }
}

impl crate::discrepancy::HeldReading for LoopsReading {
    fn name(&self) -> &str {
        "loops"
    }

    fn judge(
        &self,
        name: &str,
        parameters: &[(String, f64)],
        effects: &[Effect],
        progress: crate::discrepancy::Progress<'_>,
    ) -> Result<Option<crate::discrepancy::Refutation>, crate::discrepancy::DiscrepancyError> {
        progress(&format!("the cyclic loops of {name}, before it may be named"));
        let base = self.model(&baseline_candidate(), progress).map_err(Self::held_error)?;
        let m = self
            .model(&(name.to_string(), parameters.to_vec(), effects.to_vec()), progress)
            .map_err(Self::held_error)?;
        let (Some(b), Some(m)) = (base.models.first(), m.models.first()) else { return Ok(None) };
        // A baseline with nothing read is no yardstick: its χ² counts as 0.
        let base_chi2 = if b.chi2.is_finite() { b.chi2 } else { 0.0 };
        let excess = m.chi2 - base_chi2;
        let read = m.groups.iter().filter(|g| g.z.is_finite()).count();
        Ok((m.p_value < 0.05 && excess > 2.0 * crate::discrepancy::REFUTE_NATS).then(|| {
            crate::discrepancy::Refutation {
                candidate: name.to_string(),
                reading: "loops".into(),
                nats: excess / 2.0,
                words: format!(
                    "the cyclic loops' damping ratio: χ² {:.1} (p {:.1e}) over {read} stresses against the baseline's {:.1}",
                    m.chi2, m.p_value, base_chi2
                ),
            }
        }))
    }

    fn report(
        &self,
        run: &Run,
        progress: crate::discrepancy::Progress<'_>,
    ) -> Result<Option<crate::discrepancy::HeldReport>, crate::discrepancy::DiscrepancyError> {
        let check = self.check(run, progress).map_err(Self::held_error)?;
        let json =
            serde_json::to_value(&check).map_err(|e| Self::held_error(InPlaneStudyError::Write(e.to_string())))?;
        Ok(Some(crate::discrepancy::HeldReport {
            key: "loops",
            markdown: check.markdown(),
            summary: Self::summary(&check),
            json,
        }))
    }
}

/// Refits each model of `check` with a friction read to `run`'s observations with the
/// bearing friction held at that read ([`LoopModel::peaks`]), and records the baseline's
/// and the cause's held-out errors beside them.
pub fn refit_peaks(check: &mut LoopCheck, run: &Run) {
    for m in &mut check.models {
        let Some(f) = m.friction_read else { continue };
        let effects: Vec<&str> = if m.name == "baseline" { vec![] } else { m.name.split('+').collect() };
        m.peaks = run.refit_held(&effects, "rig_friction", f.friction);
    }
    check.baseline_heldout_error = run.analysis.baseline_heldout_error;
    check.cause = run.analysis.cause.as_ref().map(|c| (c.name.clone(), c.heldout_error));
}

/// A model of the check: its name, its parameters (`effect.param`, value) and its effects.
pub type LoopCandidate = (String, Vec<(String, f64)>, Vec<Effect>);

/// The check's core (module documentation): each model of `models` run by `params(σ0)`
/// (a cyclic test) on [`LOOP_REALIZATIONS`] layouts of each measured group of `setup`
/// (`effects::realize` with the group's effects and the model's), its loops read and set
/// against `measured`.
///
/// # Errors
/// `groups` empty (no measured group), or fewer than two specimens in every group (no
/// spread to read).
pub fn check_models(
    setup: &crate::discrepancy::Setup,
    params: &(dyn Fn(f64) -> InPlaneParams + Sync),
    groups: &[MeasuredLoops],
    models: &[LoopCandidate],
    progress: crate::discrepancy::Progress<'_>,
) -> Result<LoopCheck, InPlaneStudyError> {
    if groups.is_empty() {
        return Err(InPlaneStudyError::Write("the loops: no measured group".into()));
    }
    // The specimens' spread within their groups, pooled: Shamos's estimator, 1.0483 times
    // the median of the absolute differences of the pairs of one group.
    let differences: Vec<f64> = groups
        .iter()
        .flat_map(|(_, _, r, _)| (0..r.len()).flat_map(move |i| (i + 1..r.len()).map(move |j| (r[i].1 - r[j].1).abs())))
        .collect();
    let measured_sigma = 1.0483 * median(&differences);
    if !measured_sigma.is_finite() {
        return Err(InPlaneStudyError::Write("the loops: no group with two specimens read".into()));
    }
    let solver = setup.solver;
    // Per group, the runs: `(realization, the history's index)`, each specimen's own history
    // where the group has them, else the study's history on `LOOP_REALIZATIONS` layouts.
    let runs_of = |gi: usize| -> Vec<(u64, Option<usize>)> {
        let histories = &groups[gi].3;
        if histories.iter().all(Vec::is_empty) {
            (0..LOOP_REALIZATIONS).map(|r| (r, None)).collect()
        } else {
            histories.iter().enumerate().filter(|(_, h)| !h.is_empty()).map(|(i, _)| (i as u64, Some(i))).collect()
        }
    };
    let jobs: Vec<(usize, usize, u64, Option<usize>)> = (0..models.len())
        .flat_map(|mi| (0..groups.len()).flat_map(move |gi| runs_of(gi).into_iter().map(move |(r, h)| (mi, gi, r, h))))
        .collect();
    progress(&format!(
        "the cyclic loops: {} models at {} stresses, {} cyclic runs",
        models.len(),
        groups.len(),
        jobs.len()
    ));
    // The bearing frictions the loops are read again at: the range of `rig_friction`.
    let friction_max = crate::effects::Library::builtin()
        .get("rig_friction")
        .ok()
        .and_then(|d| d.parameters.first().map(|p| p.max))
        .unwrap_or(0.05);
    let frictions: Vec<f64> =
        (0..=FRICTION_READ_STEPS).map(|k| friction_max * k as f64 / FRICTION_READ_STEPS as f64).collect();
    // Per job: the model's reading, and the readings with each friction in place of its own.
    let readings: Vec<(f64, Vec<f64>)> = jobs
        .par_iter()
        .map(|&(mi, gi, r, history)| {
            let failed = (f64::NAN, vec![f64::NAN; frictions.len()]);
            let (k, sigma0, _, histories) = &groups[gi];
            let g = &setup.groups[*k];
            let all: Vec<Effect> = g.effects.iter().chain(&models[mi].2).cloned().collect();
            let Ok((_, layout)) = crate::effects::realize(&g.wall, setup.seed, r, &g.name, &all) else {
                return failed;
            };
            let test = match history.map(|i| &histories[i]) {
                Some(h) => {
                    let reach = h.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    let base = params(*sigma0);
                    InPlaneParams {
                        history: History::Cyclic,
                        amplitudes_pct: None,
                        drift_pct: base.drift_pct.max(reach),
                        reversals_pct: Some(h.clone()),
                        ..base
                    }
                }
                None => params(*sigma0),
            };
            match crate::protocol::run(&crate::protocol::InPlane(test), &layout, solver, &mut ()) {
                Ok(crate::protocol::InPlaneRun::Penalty(Ok(res)) | crate::protocol::InPlaneRun::Nscd(Ok(res))) => {
                    let read = |c: &[crate::loading::inplane::CurvePoint]| {
                        let curve: Vec<(f64, f64)> = c.iter().map(|p| (p.drift_pct, p.force_kn)).collect();
                        loop_damping_ratio(&curve, LOOP_MIN_DRIFT_PCT)
                    };
                    let again = frictions
                        .iter()
                        .map(|&friction| {
                            let rig = crate::layout::VerticalLoadRig { friction, ..*res.vertical_load_rig };
                            let mut curve = res.wall_curve.clone();
                            crate::loading::inplane::add_rig_force(
                                rig,
                                res.vertical_force_n,
                                res.measuring_height_m,
                                &mut curve,
                            );
                            read(&curve)
                        })
                        .collect();
                    (read(&res.curve), again)
                }
                _ => failed,
            }
        })
        .collect();
    // A χ² on `dof` degrees of freedom (at least 1).
    let chi_of = |dof: usize| ChiSquared::new(dof.max(1) as f64).map_err(|e| InPlaneStudyError::Write(e.to_string()));
    let chi_by_read: Vec<ChiSquared> = (0..=groups.len()).map(chi_of).collect::<Result<_, _>>()?;
    // A group's z for the model's readings `simulated` (one per realization).
    let z_of = |read: &[(String, f64)], simulated: &[f64]| {
        let sim = finite(simulated);
        let meas: Vec<f64> = read.iter().map(|(_, x)| *x).collect();
        let se_meas = 1.2533 * measured_sigma / (meas.len() as f64).sqrt();
        let se_sim = if sim.len() > 1 { crate::stats::sd(&sim) / (sim.len() as f64).sqrt() } else { 0.0 };
        (median(&meas) - crate::stats::mean(&sim)) / se_meas.hypot(se_sim)
    };
    let p_of = |chi: &ChiSquared, chi2: f64| if chi2.is_finite() { 1.0 - chi.cdf(chi2) } else { 0.0 };
    // `Σ z²` over the groups read (a group with no measured or no simulated cycle past
    // the minimum drift has no z and is left out), with their number; NaN when none.
    let sum_read = |z: &mut dyn Iterator<Item = f64>| {
        let read: Vec<f64> = z.filter(|z| z.is_finite()).collect();
        let sum = if read.is_empty() { f64::NAN } else { read.iter().map(|z| z * z).sum() };
        (sum, read.len())
    };
    let out: Vec<LoopModel> = models
        .iter()
        .enumerate()
        .map(|(mi, (name, parameters, _))| {
            // The model's jobs of group `gi`.
            let of = |gi: usize| -> Vec<&(f64, Vec<f64>)> {
                jobs.iter().zip(&readings).filter(|((m, g, _, _), _)| *m == mi && *g == gi).map(|(_, v)| v).collect()
            };
            let per: Vec<LoopGroup> = groups
                .iter()
                .enumerate()
                .map(|(gi, (k, _, read, _))| {
                    let simulated: Vec<f64> = of(gi).iter().map(|v| v.0).collect();
                    let z = z_of(read, &simulated);
                    LoopGroup { group: setup.groups[*k].name.clone(), measured: read.clone(), simulated, z }
                })
                .collect();
            let (chi2, groups_read) = sum_read(&mut per.iter().map(|g| g.z));
            // Nothing read: no p-value (the verdict is `NotRead`, not a refutation).
            let p_value = if groups_read == 0 { f64::NAN } else { p_of(&chi_by_read[groups_read], chi2) };
            // χ² with each friction of the grid in place of the model's.
            let profile: Vec<f64> = (0..frictions.len())
                .map(|f| {
                    sum_read(&mut groups.iter().enumerate().map(|(gi, (_, _, read, _))| {
                        let simulated: Vec<f64> = of(gi).iter().map(|v| v.1[f]).collect();
                        z_of(read, &simulated)
                    }))
                    .0
                })
                .collect();
            let chi_read = &chi_by_read[groups_read.saturating_sub(1)];
            let friction_read = profile
                .iter()
                .enumerate()
                .filter(|(_, c)| groups_read > 0 && c.is_finite())
                .min_by(|a, b| a.1.total_cmp(b.1))
                .map(|(best, &least)| {
                    let inside: Vec<f64> = frictions
                        .iter()
                        .zip(&profile)
                        .filter(|(_, c)| c.is_finite() && **c <= least + 3.84)
                        .map(|(f, _)| *f)
                        .collect();
                    FrictionRead {
                        friction: frictions[best],
                        low: inside.iter().copied().fold(f64::INFINITY, f64::min),
                        high: inside.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                        chi2: least,
                        p_value: p_of(chi_read, least),
                    }
                });
            // The model's own friction: the value of a `RigFriction` step's parameter.
            let friction = models[mi]
                .2
                .iter()
                .flat_map(|e| {
                    e.def.steps.iter().filter_map(move |s| match s {
                        crate::effects::Step::RigFriction { parameter } => {
                            e.def.parameters.iter().position(|p| &p.name == parameter).and_then(|i| e.values.get(i))
                        }
                        _ => None,
                    })
                })
                .fold(0.0, |a, b| a + b);
            let verdict = LoopVerdict::of(p_value, friction_read.as_ref());
            LoopModel {
                name: name.clone(),
                parameters: parameters.clone(),
                groups: per,
                chi2,
                p_value,
                friction,
                friction_read,
                verdict,
                peaks: None,
                baseline_wall: false,
            }
        })
        .collect();
    Ok(LoopCheck {
        min_drift_pct: LOOP_MIN_DRIFT_PCT,
        measured_sigma,
        models: out,
        runs: jobs.len(),
        own_histories: (0..groups.len()).filter(|&gi| runs_of(gi).iter().any(|(_, h)| h.is_some())).count(),
        baseline_heldout_error: f64::NAN,
        cause: None,
    })
}
