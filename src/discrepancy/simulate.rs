//! Running the model, baseline or extended by effects, as an ensemble with common random
//! numbers: realization `i` of a group uses the same generated layout (`Purpose::Layout`)
//! and the same effect draws (`Purpose::Effect`) in every model, so that the differences
//! between models are the effects' and not the sampling's.

use super::effects::Effect;
use super::observations::{Measure, Observable};
use crate::dem::SolverParams;
use crate::ensemble::{run_scheduled, Item};
use crate::generator::{generate, Wall};
use crate::loading::tilt::{run_tilt, TiltParams};
use crate::rng::{rng_for, Purpose};
use crate::units::m_to_cm;
use serde::Serialize;

/// One group of walls the model is run for.
#[derive(Debug, Clone)]
pub struct GroupSetup {
    /// Group name (as in the observations).
    pub name: String,
    /// The wall description.
    pub wall: Wall,
    /// Realizations run for this group.
    pub realizations: u64,
    /// The walls have end restraints.
    pub restrained: bool,
    /// Every realization of the wall is the same layout (a wall without random input):
    /// a model without random effects then runs it once.
    pub deterministic: bool,
}

/// What the model is run with: groups, master seed, solver and tilting-table parameters.
#[derive(Debug, Clone)]
pub struct Setup {
    /// Groups.
    pub groups: Vec<GroupSetup>,
    /// Master seed of the layouts and of the effects' random forms.
    pub seed: u64,
    /// Solver parameters.
    pub solver: SolverParams,
    /// Tilting-table parameters.
    pub tilt: TiltParams,
}

/// The outcome of one realization of one model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Outcome {
    /// Collapse angle α_max, degrees (`max_angle_deg` if the wall stood); `None` if the run
    /// failed.
    pub collapse_deg: Option<f64>,
    /// Stable tilts, degrees.
    pub tilt_deg: Vec<f64>,
    /// Left, centre and right top displacements at each stable tilt, cm.
    pub top_cm: Vec<[f64; 3]>,
    /// Displacement recorded for a tilt beyond collapse, cm: the collapse criterion's top
    /// displacement (the wall fell, so it moved at least that much).
    pub censor_cm: f64,
    /// Why the run failed, if it did.
    pub error: Option<String>,
}

impl Outcome {
    fn failed(error: String) -> Outcome {
        Outcome { collapse_deg: None, tilt_deg: vec![], top_cm: vec![], censor_cm: 0.0, error: Some(error) }
    }

    /// The value of an observable (degrees or cm); `None` for a failed run.
    pub fn value(&self, obs: &Observable) -> Option<f64> {
        self.error.is_none().then_some(())?;
        match *obs {
            Observable::CollapseAngle => self.collapse_deg,
            Observable::Displacement { measure, tilt_deg } => {
                match self.tilt_deg.iter().position(|t| (t - tilt_deg).abs() < 1e-9) {
                    Some(i) => {
                        let [l, c, r] = self.top_cm[i];
                        Some(measure.of(l, c, r))
                    }
                    None if self.collapse_deg.is_some_and(|a| a < tilt_deg) => Some(match measure {
                        Measure::MeanOfLeftCenterRight => self.censor_cm,
                        Measure::CenterMinusMeanOfEnds => self.censor_cm,
                    }),
                    None => None,
                }
            }
        }
    }
}

/// Runs one realization of one group with `effects` applied to its layout.
pub fn run_one(setup: &Setup, group: usize, realization: u64, effects: &[Effect]) -> Outcome {
    let g = &setup.groups[group];
    let generated = match generate(&g.wall, setup.seed, realization) {
        Ok(w) => w,
        Err(e) => return Outcome::failed(e.to_string()),
    };
    let mut layout = match generated.check() {
        Ok(l) => l,
        Err(e) => return Outcome::failed(e.to_string()),
    };
    let mut rng = rng_for(setup.seed, realization, Purpose::Effect);
    for e in effects {
        if let Err(err) = e.apply(&mut layout, &generated.course_tops_m, &mut rng) {
            return Outcome::failed(err.to_string());
        }
    }
    match run_tilt(&layout, setup.solver, &setup.tilt) {
        Ok(t) => {
            let find = |name: &str| t.monitors.iter().position(|m| m == name);
            let idx = [find("top_left"), find("top_centre"), find("top_right")];
            let mut tilt_deg = Vec::new();
            let mut top_cm = Vec::new();
            for inc in t.increments.iter().filter(|i| i.stable) {
                tilt_deg.push(inc.alpha_deg);
                top_cm.push(idx.map(|i| i.map_or(f64::NAN, |i| m_to_cm(inc.displacement_m[i]))));
            }
            Outcome {
                collapse_deg: Some(t.collapse_angle_deg),
                tilt_deg,
                top_cm,
                censor_cm: m_to_cm(setup.tilt.collapse_displacement_fraction * t.wall_width_m),
                error: None,
            }
        }
        Err(e) => Outcome::failed(e.to_string()),
    }
}

/// The outcomes of several models: `[model][group][realization]`.
pub type Outcomes = Vec<Vec<Vec<Outcome>>>;

/// Runs every model on every group and realization, in parallel on the current rayon pool;
/// the result does not depend on the number of threads. A model whose effects cannot act on
/// a group (e.g. `restraint_stiffness` on free walls) reuses `reuse`'s outcomes for it
/// (`reuse[group]`, the baseline's), when given.
pub fn run_models(setup: &Setup, models: &[Vec<Effect>], reuse: Option<&[Vec<Outcome>]>) -> Outcomes {
    let acts = |m: &[Effect], g: &GroupSetup| m.is_empty() || m.iter().any(|e| e.kind.acts_on(g.restrained));
    let mut tasks = Vec::new();
    for (mi, m) in models.iter().enumerate() {
        for (gi, g) in setup.groups.iter().enumerate() {
            if reuse.is_some() && !acts(m, g) {
                continue;
            }
            let random = models[mi].iter().any(|e| e.random);
            let n = if g.deterministic && !random { g.realizations.min(1) } else { g.realizations };
            for r in 0..n {
                tasks.push((mi, gi, r));
            }
        }
    }
    // Restrained walls creep longest near collapse: schedule them first.
    let items: Vec<Item> = tasks
        .iter()
        .enumerate()
        .map(|(index, &(mi, gi, r))| Item { index, group: gi, point: mi, realization: r })
        .collect();
    let cost: Vec<f64> = tasks.iter().map(|&(_, gi, _)| if setup.groups[gi].restrained { 2.0 } else { 1.0 }).collect();
    let results: Vec<Outcome> =
        run_scheduled(&items, &cost, "discrepancy", |it| run_one(setup, it.group, it.realization, &models[it.point]));
    let mut out: Outcomes = models.iter().map(|_| setup.groups.iter().map(|_| Vec::new()).collect()).collect();
    for ((mi, gi, _), o) in tasks.into_iter().zip(results) {
        out[mi][gi].push(o);
    }
    if let Some(base) = reuse {
        for (mi, m) in models.iter().enumerate() {
            for (gi, g) in setup.groups.iter().enumerate() {
                if !acts(m, g) {
                    out[mi][gi] = base[gi].clone();
                }
            }
        }
    }
    out
}
