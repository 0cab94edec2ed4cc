//! The check's core: the cyclic runs of each model at each measured stress, their loops read, and the χ² against the specimens.

use super::{finite, median, FrictionRead, LoopCandidate, LoopCheck, LoopGroup, LoopModel, LoopVerdict, MeasuredLoops};
use super::{FRICTION_READ_STEPS, LOOP_REALIZATIONS};
use crate::effects::Effect;
use crate::loading::inplane::{History, InPlaneParams};
use crate::loading::inplane_loops::{loop_damping_ratio, LOOP_MIN_DRIFT_PCT};
use crate::study::inplane::InPlaneStudyError;
use rayon::prelude::*;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// A cyclic run of the check: `(model, group, realization, the history's index)`; the
/// history's index `None` for the study's history.
type Job = (usize, usize, u64, Option<usize>);

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
    let measured_sigma = pooled_spread(groups)?;
    let jobs: Vec<Job> = (0..models.len())
        .flat_map(|mi| {
            (0..groups.len()).flat_map(move |gi| runs_of(groups, gi).into_iter().map(move |(r, h)| (mi, gi, r, h)))
        })
        .collect();
    progress(&format!(
        "the cyclic loops: {} models at {} stresses, {} cyclic runs",
        models.len(),
        groups.len(),
        jobs.len()
    ));
    let frictions = bearing_frictions();
    let readings: Vec<(f64, Vec<f64>)> =
        jobs.par_iter().map(|&job| read_job(setup, params, groups, models, &frictions, job)).collect();
    let score = Scoring::new(measured_sigma, groups.len())?;
    let out: Vec<LoopModel> = models
        .iter()
        .enumerate()
        .map(|(mi, model)| {
            // The model's jobs of group `gi`.
            let of = |gi: usize| -> Vec<&(f64, Vec<f64>)> {
                jobs.iter().zip(&readings).filter(|((m, g, _, _), _)| *m == mi && *g == gi).map(|(_, v)| v).collect()
            };
            score.model(setup, groups, model, &frictions, &of)
        })
        .collect();
    let mut out = out;
    // A model the loops misfit but that predicts them no worse than the baseline by the
    // analysis's margin is not refuted by them (`refutes_beyond_baseline`).
    super::judge_against_baseline(&mut out);
    Ok(LoopCheck {
        min_drift_pct: LOOP_MIN_DRIFT_PCT,
        measured_sigma,
        models: out,
        runs: jobs.len(),
        own_histories: (0..groups.len()).filter(|&gi| runs_of(groups, gi).iter().any(|(_, h)| h.is_some())).count(),
        baseline_heldout_error: f64::NAN,
        cause: None,
    })
}

/// The specimens' spread within their groups, pooled: Shamos's estimator, 1.0483 times the
/// median of the absolute differences of the pairs of one group.
///
/// # Errors
/// No group with two specimens read.
fn pooled_spread(groups: &[MeasuredLoops]) -> Result<f64, InPlaneStudyError> {
    let differences: Vec<f64> = groups
        .iter()
        .flat_map(|(_, _, r, _)| (0..r.len()).flat_map(move |i| (i + 1..r.len()).map(move |j| (r[i].1 - r[j].1).abs())))
        .collect();
    let measured_sigma = 1.0483 * median(&differences);
    if !measured_sigma.is_finite() {
        return Err(InPlaneStudyError::Write("the loops: no group with two specimens read".into()));
    }
    Ok(measured_sigma)
}

/// Group `gi`'s runs: `(realization, the history's index)`, each specimen's own history
/// where the group has them, else the study's history on [`LOOP_REALIZATIONS`] layouts.
fn runs_of(groups: &[MeasuredLoops], gi: usize) -> Vec<(u64, Option<usize>)> {
    let histories = &groups[gi].3;
    if histories.iter().all(Vec::is_empty) {
        (0..LOOP_REALIZATIONS).map(|r| (r, None)).collect()
    } else {
        histories.iter().enumerate().filter(|(_, h)| !h.is_empty()).map(|(i, _)| (i as u64, Some(i))).collect()
    }
}

/// The bearing frictions the loops are read again at: [`FRICTION_READ_STEPS`] steps over
/// the range of `rig_friction` (0 to its upper bound).
fn bearing_frictions() -> Vec<f64> {
    let friction_max = crate::effects::Library::builtin()
        .get("rig_friction")
        .ok()
        .and_then(|d| d.parameters.first().map(|p| p.max))
        .unwrap_or(0.05);
    (0..=FRICTION_READ_STEPS).map(|k| friction_max * k as f64 / FRICTION_READ_STEPS as f64).collect()
}

/// One cyclic run: the model's loops' reading, and the readings with each friction of
/// `frictions` in place of its own (NaN where the layout or the run failed).
fn read_job(
    setup: &crate::discrepancy::Setup,
    params: &(dyn Fn(f64) -> InPlaneParams + Sync),
    groups: &[MeasuredLoops],
    models: &[LoopCandidate],
    frictions: &[f64],
    (mi, gi, r, history): Job,
) -> (f64, Vec<f64>) {
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
    match crate::protocol::run(&crate::protocol::InPlane(test), &layout, setup.solver, &mut ()) {
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
}

/// The statistics of the check (module documentation): the measured readings' pooled
/// spread and the χ² distributions on 1 to the groups' number of degrees of freedom.
struct Scoring {
    measured_sigma: f64,
    /// `χ²` on `max(k, 1)` degrees of freedom at index `k`.
    chi_by_read: Vec<ChiSquared>,
}

impl Scoring {
    fn new(measured_sigma: f64, groups: usize) -> Result<Scoring, InPlaneStudyError> {
        let chi_of =
            |dof: usize| ChiSquared::new(dof.max(1) as f64).map_err(|e| InPlaneStudyError::Write(e.to_string()));
        Ok(Scoring { measured_sigma, chi_by_read: (0..=groups).map(chi_of).collect::<Result<_, _>>()? })
    }

    /// A group's z for the model's readings `simulated` (one per realization) against the
    /// specimens' `read`.
    fn z(&self, read: &[(String, f64)], simulated: &[f64]) -> f64 {
        let sim = finite(simulated);
        let meas: Vec<f64> = read.iter().map(|(_, x)| *x).collect();
        let se_meas = 1.2533 * self.measured_sigma / (meas.len() as f64).sqrt();
        let se_sim = if sim.len() > 1 { crate::stats::sd(&sim) / (sim.len() as f64).sqrt() } else { 0.0 };
        (median(&meas) - crate::stats::mean(&sim)) / se_meas.hypot(se_sim)
    }

    fn p(chi: &ChiSquared, chi2: f64) -> f64 {
        if chi2.is_finite() {
            1.0 - chi.cdf(chi2)
        } else {
            0.0
        }
    }

    /// `Σ z²` over the groups read (a group with no measured or no simulated cycle past the
    /// minimum drift has no z and is left out), with their number; NaN when none.
    fn sum_read(z: &mut dyn Iterator<Item = f64>) -> (f64, usize) {
        let read: Vec<f64> = z.filter(|z| z.is_finite()).collect();
        let sum = if read.is_empty() { f64::NAN } else { read.iter().map(|z| z * z).sum() };
        (sum, read.len())
    }

    /// The model `(name, parameters, effects)` of the check from its runs' readings (`of(gi)`:
    /// its runs of group `gi`, each its reading and its readings at `frictions`).
    fn model<'r>(
        &self,
        setup: &crate::discrepancy::Setup,
        groups: &[MeasuredLoops],
        (name, parameters, effects): &LoopCandidate,
        frictions: &[f64],
        of: &dyn Fn(usize) -> Vec<&'r (f64, Vec<f64>)>,
    ) -> LoopModel {
        let per: Vec<LoopGroup> = groups
            .iter()
            .enumerate()
            .map(|(gi, (k, _, read, _))| {
                let simulated: Vec<f64> = of(gi).iter().map(|v| v.0).collect();
                let z = self.z(read, &simulated);
                LoopGroup { group: setup.groups[*k].name.clone(), measured: read.clone(), simulated, z }
            })
            .collect();
        let (chi2, groups_read) = Self::sum_read(&mut per.iter().map(|g| g.z));
        // Nothing read: no p-value (the verdict is `NotRead`, not a refutation).
        let p_value = if groups_read == 0 { f64::NAN } else { Self::p(&self.chi_by_read[groups_read], chi2) };
        // χ² with each friction of the grid in place of the model's.
        let profile: Vec<f64> = (0..frictions.len())
            .map(|f| {
                Self::sum_read(&mut groups.iter().enumerate().map(|(gi, (_, _, read, _))| {
                    let simulated: Vec<f64> = of(gi).iter().map(|v| v.1[f]).collect();
                    self.z(read, &simulated)
                }))
                .0
            })
            .collect();
        let chi_read = &self.chi_by_read[groups_read.saturating_sub(1)];
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
                    p_value: Self::p(chi_read, least),
                }
            });
        let friction = own_friction(effects);
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
    }
}

/// The model's own bearing friction: the sum of its `RigFriction` steps' parameters (0
/// without one).
fn own_friction(effects: &[Effect]) -> f64 {
    effects
        .iter()
        .flat_map(|e| {
            e.def.steps.iter().filter_map(move |s| match s {
                crate::effects::Step::RigFriction { parameter } => {
                    e.def.parameters.iter().position(|p| &p.name == parameter).and_then(|i| e.values.get(i))
                }
                _ => None,
            })
        })
        .fold(0.0, |a, b| a + b)
}
