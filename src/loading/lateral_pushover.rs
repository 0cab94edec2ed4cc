//! The collapse load multiplier of the lateral pressure by the penalty DEM (pushover).
//!
//! The pressure of [`LateralParams`] (trapezoidal over the height, on the exposed faces
//! facing −y, computed once on the settled configuration by [`pressure_loads`](super::lateral::pressure_loads), as the
//! static lateral load does) is scaled by a load multiplier λ and applied as a dead load
//! with gravity straight down. The joints are the layout's: finite Kn and Ks, friction,
//! cohesion and tensile strength, which drop to zero for good where a joint fails (see
//! `dem::contact::law`).
//!
//! 1. Gravity only: the layout settles to equilibrium (λ = 0), the reference state of every
//!    displacement.
//! 2. λ is raised from 1 (the service load, [`LateralParams`]'s pressure itself) by
//!    doubling, each increment solved to equilibrium from the last stable state, until an
//!    increment is unstable; the bracket `[last stable, first unstable]` is then bisected
//!    from the last stable state to a relative width
//!    [`LateralParams::pushover_resolution`].
//! 3. Each increment and trial is the tilting table's (`loading::tilt`, with λ in place of
//!    the tilt α): the same static solve through the solver seam
//!    ([`crate::dem::solve_static`]; the secant predictor, the implicit iteration, the
//!    accelerated and probed dynamic relaxation), the same collapse criteria (a block moving
//!    more than the per-increment collapse displacement, a top point more than
//!    [`LateralParams::collapse_displacement_fraction`] of the wall width, the stability
//!    indicator with its probe, or the step budget [`PenaltyParams::max_steps`](crate::dem::PenaltyParams::max_steps) with no
//!    decision), both displacements at least the joints' elastic scale
//!    ([`elastic_scale`](super::tilt::elastic_scale)), and the same reading of the mechanism
//!    ([`crate::loading::mechanism::mechanism`]) from the last stable and the first
//!    unstable state.
//!
//! The collapse load multiplier lies in `[lambda_stable, lambda_unstable]` (unless the
//! upper end is a [`CollapseReason::StepBudget`]). With finite Kn it lies below the rigid
//! limit of the same layout (`crate::limit`, `drystone limit --protocol lateral`): the
//! joints close under the hinges and slide elastically before a mechanism forms (the
//! no-tension Winkler loss, as Kn^(-1/3) for a block), and a joint keeps no cohesion
//! where it has slipped or opened, whereas limit analysis takes every joint at its full
//! strength at once. A joint without tensile strength keeps no cohesion where a
//! sub-contact has carried no compression (`dem::contact::law::evaluate`), as one between
//! blocks placed just touching does at its first step: its DEM collapse multiplier is then
//! that of the cohesionless joint, while limit analysis gives its cone c A at any normal
//! force; the rigid limit of such a wall is limit analysis with c = 0.

use super::lateral::{prepare, LateralError, LateralParams, SettledUnderLoad};
use super::lateral_nscd::MAX_LOAD_MULTIPLIER;
use super::mechanism::{mechanism, Mechanism};
use super::tilt::path::{Ctx, StablePath};
use super::tilt::{CollapseReason, Increment, TiltParams};
use crate::dem::{Simulation, SolverParams};
use crate::layout::Layout;
use crate::math::Vec3;
use serde::{Deserialize, Serialize};

/// The bisection stops below this load multiplier (a wall that cannot carry even this
/// share of the pressure has `lambda_stable` 0).
pub const MIN_LOAD_MULTIPLIER: f64 = 1e-3;

/// One load increment or bisection trial of a pushover.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PushoverIncrement {
    /// Load multiplier λ of the pressure.
    pub load_multiplier: f64,
    /// Equilibrium reached.
    pub stable: bool,
    /// Engine steps of this increment.
    pub steps: u64,
    /// Iterations of the implicit relaxation in this increment.
    pub iterations: u32,
    /// Out-of-plane (y) displacement of each monitor from the gravity-only state, m
    /// (positive in the direction of the load), in the order of
    /// [`LateralPushover::monitors`].
    pub displacement_m: Vec<f64>,
    /// Unbalanced-force ratio at the end of the increment.
    pub unbalanced_ratio: f64,
}

impl From<Increment> for PushoverIncrement {
    fn from(i: Increment) -> Self {
        PushoverIncrement {
            load_multiplier: i.alpha_deg,
            stable: i.stable,
            steps: i.steps,
            iterations: i.iterations,
            displacement_m: i.displacement_m,
            unbalanced_ratio: i.unbalanced_ratio,
        }
    }
}

/// Outcome of a DEM pushover. The fields shared with the rigid pushover
/// ([`super::lateral_nscd::LateralLimit`]) have its names and meanings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LateralPushover {
    /// Largest multiplier of the pressure found stable (0 if even λ = 1 was not).
    pub lambda_stable: f64,
    /// Smallest multiplier found unstable (`None`: stood up to [`MAX_LOAD_MULTIPLIER`]).
    pub lambda_unstable: Option<f64>,
    /// Why the trial at `lambda_unstable` was unstable (the tilting table's reasons).
    pub collapse_reason: Option<CollapseReason>,
    /// The collapse mechanism, read from the last stable and the first unstable state;
    /// `None` if the wall stood.
    pub mechanism: Option<Mechanism>,
    /// Monitor names (by default `top_left`, `top_centre`, `top_right`).
    pub monitors: Vec<String>,
    /// Every increment and trial: the stable ones by λ, then the unstable ones by λ.
    pub increments: Vec<PushoverIncrement>,
    /// Resultant of the pressure at λ = 1 (world frame, N): y is the lateral force.
    pub resultant_n: Vec3,
    /// Weight of the movable blocks, N.
    pub weight_n: f64,
    /// Loaded faces.
    pub loaded_faces: usize,
    /// Wall height H (z extent of the layout), m.
    pub height_m: f64,
    /// Wall width (y extent of the layout), m.
    pub width_m: f64,
    /// The joints' elastic displacement scale ([`elastic_scale`](super::tilt::elastic_scale)), m.
    pub elastic_scale_m: f64,
    /// Increments and trials run.
    pub trials: usize,
    /// Engine steps in all (settling included).
    pub steps: u64,
    /// Time step, s.
    pub dt_s: f64,
    /// Wall-clock time, s (not deterministic).
    pub wall_time_s: f64,
}

impl LateralPushover {
    /// The monitors' displacements (m) at the service load λ = 1, if it was stable.
    pub fn service_displacement_m(&self) -> Option<&[f64]> {
        self.increments.iter().find(|i| i.stable && i.load_multiplier == 1.0).map(|i| i.displacement_m.as_slice())
    }
}

/// Runs the DEM pushover of a layout under the lateral pressure of `params` (see the module
/// doc) by the penalty DEM: the driver of the pushover's penalty way (`protocol::pushover`),
/// which the protocol seam calls once it has chosen the method (`solver.kind` names the
/// cascade of static solves). Run a pushover through `protocol::Protocol::run`, which
/// chooses the method.
///
/// # Errors
/// [`LateralError::DoesNotStand`] if the layout does not stand as given under gravity,
/// [`LateralError::Dem`] if the state blows up (after the fall-backs of the density
/// scaling), [`LateralError::Parameter`] for bad parameters, [`LateralError::NoLoad`] for
/// a pressure that loads no face. A collapse is the result, not an error.
pub fn run_lateral_pushover(
    layout: &Layout,
    solver: SolverParams,
    params: &LateralParams,
) -> Result<LateralPushover, LateralError> {
    run_lateral_pushover_observed(layout, solver, params, &mut |_, _, _| {})
}

/// As [`run_lateral_pushover`], handing every state to `observe(load_multiplier, stable,
/// state)` as it is reached: the settled state (λ = 0), then every increment and trial in
/// the order tried. Observing changes nothing in the test.
///
/// # Errors
/// As [`run_lateral_pushover`].
pub fn run_lateral_pushover_observed(
    layout: &Layout,
    solver: SolverParams,
    params: &LateralParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<LateralPushover, LateralError> {
    super::lateral::check_pushover_load(params).map_err(LateralError::Parameter)?;
    // Scalar density scaling at most, as the static lateral load (its module doc).
    let SettledUnderLoad { sim, monitors, reference, loads, loaded_faces, width, height, weight_n, elastic, t0 } =
        prepare(layout, solver, params, observe)?;
    let penalty = crate::dem::with_moved(solver, &params.moved()).penalty;
    super::lateral::check_pushover_force(params, &loads, loaded_faces).map_err(LateralError::NoLoad)?;
    let resultant_n = loads.iter().fold(Vec3::zeros(), |s, (f, _)| s + f);
    let tilt =
        TiltParams { collapse_displacement_fraction: params.collapse_displacement_fraction, ..TiltParams::default() };
    let scale = |sim: &mut Simulation, lambda: f64| {
        for (k, (f, m)) in loads.iter().enumerate() {
            sim.state.external_force[k] = f * lambda;
            sim.state.external_torque[k] = m * lambda;
        }
    };
    let solve = crate::dem::StaticSolve::of(&penalty, tilt.cascade(solver.kind), None);
    let mut ctx = Ctx { params: &tilt, load: &scale, solve, monitors: &monitors, reference, width, elastic };
    ctx.solve.reach = Some(ctx.inc_limit());
    let mut increments = Vec::new();
    let mut path = StablePath::new(sim, penalty.predictor);
    let mut first_unstable = None;
    let mut lambda = 1.0;
    while lambda <= MAX_LOAD_MULTIPLIER {
        if let Some((reason, failed)) = path.try_at(&ctx, lambda, &mut increments, observe)? {
            first_unstable = Some((lambda, reason, failed));
            break;
        }
        lambda *= 2.0;
    }
    let mut mech = None;
    let mut bracket = (path.last_stable, None, None);
    if let Some((mut up, mut reason, mut failed)) = first_unstable {
        while up - path.last_stable > params.penalty_pushover_resolution() * up && up > MIN_LOAD_MULTIPLIER {
            let mid = 0.5 * (up + path.last_stable);
            if let Some((r, trial)) = path.try_at(&ctx, mid, &mut increments, observe)? {
                (up, reason, failed) = (mid, r, trial);
            }
        }
        mech = Some(mechanism(&path.sim, &failed));
        bracket = (path.last_stable, Some(up), Some(reason));
    }
    let trials = increments.len();
    increments.sort_by(|a, b| (!a.stable).cmp(&!b.stable).then(a.alpha_deg.total_cmp(&b.alpha_deg)));
    Ok(LateralPushover {
        lambda_stable: bracket.0,
        lambda_unstable: bracket.1,
        collapse_reason: bracket.2,
        mechanism: mech,
        monitors: monitors.iter().map(|m| m.name.clone()).collect(),
        increments: increments.into_iter().map(PushoverIncrement::from).collect(),
        resultant_n,
        weight_n,
        loaded_faces,
        height_m: height,
        width_m: width,
        elastic_scale_m: elastic,
        trials,
        steps: path.total_steps,
        dt_s: path.sim.dt(),
        wall_time_s: t0.elapsed().as_secs_f64(),
    })
}
