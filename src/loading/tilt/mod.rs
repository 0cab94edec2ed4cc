//! The tilting-table protocol (Santa-Cruz et al. 2021, §2.2 and §5.3).
//!
//! 1. Gravity only (α = 0): the layout settles to equilibrium (unbalanced-force ratio below
//!    [`PenaltyParams::tolerance`](crate::dem::PenaltyParams::tolerance)); this is the reference state of every displacement.
//! 2. α grows by [`TiltParams::step_deg`]; after each increment the model is solved to
//!    equilibrium (starting from the secant prediction of that equilibrium:
//!    [`PenaltyParams::predictor`](crate::dem::PenaltyParams::predictor); slow creep near collapse accelerated by secant steps along
//!    the motion: [`TiltParams::accelerate`]), or declared unstable when the wall has no
//!    equilibrium near the increment's path: the stiffness along a persistent motion turns
//!    negative while the out-of-balance force along it grows (the stability indicator of
//!    `dem::drivers::accelerate`) *and* that force keeps pushing the state along the motion over the
//!    whole collapse displacement ahead (the probe of the path); or, during the
//!    increment, a block moves more than the collapse displacement, or a top point moves
//!    from the reference more than the total collapse displacement. Both displacements
//!    are the larger of a fraction of the wall width
//!    ([`TiltParams::collapse_increment_fraction`],
//!    [`TiltParams::collapse_displacement_fraction`]) and the elastic displacement scale
//!    of the layout's joints ([`elastic_scale`]), so that the elastic rotation of soft
//!    joints is never taken for a mechanism. An increment that reaches neither an
//!    equilibrium nor a collapse within [`PenaltyParams::max_steps`](crate::dem::PenaltyParams::max_steps) steps is
//!    reported as such ([`CollapseReason::StepBudget`]): it bounds the bracket from above
//!    (nothing above it is known to be stable) without being a collapse.
//! 3. The bracket (last stable, first unstable) is bisected from the last stable state
//!    until it is narrower than [`TiltParams::resolution_deg`]. The collapse angle α_max is
//!    the last stable angle; the critical tilt lies in the bracket unless its upper end
//!    is a [`CollapseReason::StepBudget`], which the result says:
//!    [`TiltResult::bracket_reliable`] is then false.
//! 4. The mechanism is read from the motion between the last stable and the collapsed
//!    state ([`mechanism`]): the joints that failed (large relative motion), the groups of
//!    blocks they cut loose from the table, the joints between moving and resting bodies,
//!    and for each whether it slid (relative tangential motion dominates) or opened
//!    (toppling).
//!
//! The *wall width* is the y extent of the whole layout (the base width B of a wall).

pub use super::mechanism::{mechanism, Mechanism, MechanismKind};
use super::monitors::monitor_points;
use super::settle::settle;
use crate::dem::{Simulation, SolverParams};
use crate::layout::Layout;
use std::time::Instant;

pub mod hand;
pub(super) mod params;
pub(crate) mod path;
pub(super) mod result;

pub use params::TiltParams;
pub use path::elastic_scale;
use path::{Ctx, StablePath};
pub use result::{CollapseReason, Increment, NoLoad, RopeCatch, TiltError, TiltResult};

/// The tilting-table test of a layout to collapse by the penalty DEM: the driver of the
/// tilting table's penalty way (`protocol::tilt`), which the protocol seam calls once it has
/// chosen the method. `solver.kind` names the cascade of static solves
/// ([`TiltParams::cascade`]); `params.by_hand` is not read (the table rolled by hand is a
/// protocol of its own, run by nscd). Every state of the test goes to
/// `observe(alpha_deg, stable, state)` as it is reached: the settled state at α = 0, then
/// every increment and bisection trial in the order tried (the unstable ones in the state
/// their mechanism is read from); the last unstable state handed over at
/// `first_unstable_deg` is the first unstable state of the result. Observing changes
/// nothing in the test. Run a tilt through `protocol::run_tilt` (or
/// `protocol::Protocol::run`), which chooses the method from `solver.kind`.
///
/// # Errors
/// [`TiltError::DoesNotStand`] if the layout does not stand as given at α = 0 (a block
/// touching nothing, no equilibrium, or a block that moved while settling),
/// [`TiltError::Dem`] if the state blows up, [`TiltError::Parameter`] for bad parameters.
///
/// A wall held by ropes whose first instability is a jump its ropes catch is run again with
/// the jump let run ([`TiltResult::after_snap`]: where it falls; that run is not observed).
pub fn run_tilt_penalty(
    layout: &Layout,
    solver: SolverParams,
    params: &TiltParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<TiltResult, TiltError> {
    let mut first = run_tilt_penalty_once(layout, solver, params, observe)?;
    first.after_snap =
        after_snap(layout, params, &first, |lifted| run_tilt_penalty_once(layout, solver, lifted, &mut |_, _, _| {}))?;
    Ok(first)
}

/// [`run_tilt_penalty`] without the fall past a caught snap.
fn run_tilt_penalty_once(
    layout: &Layout,
    solver: SolverParams,
    params: &TiltParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<TiltResult, TiltError> {
    params.validate().map_err(TiltError::Parameter)?;
    let solver = crate::dem::with_moved(solver, &params.moved());
    solver.validate_static().map_err(TiltError::Parameter)?;
    let penalty = solver.penalty;
    let t0 = Instant::now();
    let mut sim = Simulation::new(layout, solver);
    let monitors = monitor_points(layout, &sim);
    let width = layout.bounds().extent().y;
    sim.set_tilt(0.0);
    let elastic = elastic_scale(layout, &sim);
    let solve = crate::dem::StaticSolve::of(&penalty, params.cascade(solver.kind), None);
    let overshoot = layout.table_overshoot_deg;
    let tilt = |sim: &mut Simulation, alpha_deg: f64| {
        sim.set_tilt(crate::units::deg_to_rad(hand::effective_tilt_deg(alpha_deg, overshoot)))
    };
    let mut ctx = Ctx { params, load: &tilt, solve, monitors: &monitors, reference: Vec::new(), width, elastic };
    ctx.solve.reach = Some(ctx.inc_limit());
    settle(&mut sim, layout, penalty.tolerance, penalty.max_steps).map_err(TiltError::from_settle)?;
    ctx.reference = monitors.iter().map(|m| sim.state.bodies[m.body].to_world(&m.local)).collect();
    let mut increments = vec![Increment {
        alpha_deg: 0.0,
        stable: true,
        steps: sim.state.steps,
        iterations: 0,
        displacement_m: vec![0.0; monitors.len()],
        unbalanced_ratio: sim.stats().unbalanced_ratio,
        newton_handed_over: false,
    }];
    observe(0.0, true, &sim);
    let mut path = StablePath::new(sim, penalty.predictor);
    let mut first_unstable: Option<(f64, CollapseReason, Simulation)> = None;
    let mut k = 1;
    loop {
        let alpha = k as f64 * params.step_deg;
        if alpha > params.max_angle_deg + 1e-9 {
            break;
        }
        if let Some((reason, next)) = path.try_at(&ctx, alpha, &mut increments, observe)? {
            first_unstable = Some((alpha, reason, next));
            break;
        }
        k += 1;
    }
    let Some((mut unstable, mut reason, mut failed)) = first_unstable else {
        let last_stable = path.last_stable;
        return Ok(TiltResult {
            last_stable_deg: last_stable,
            first_unstable_deg: None,
            collapse_reason: None,
            mechanism: Mechanism::none(),
            monitors: monitors.iter().map(|m| m.name.clone()).collect(),
            increments,
            steps: path.total_steps,
            iterations: path.total_iterations,
            dt_s: path.sim.dt(),
            wall_time_s: t0.elapsed().as_secs_f64(),
            wall_width_m: width,
            elastic_scale_m: elastic,
            detections: path.sim.detections(),
            max_density_scale: path.sim.max_density_scale(),
            scalar_fallbacks_deg: path.fallbacks,
            bracket_reliable: true,
            after_snap: None,
        });
    };
    // Time step of the first failing increment (bisection trials may replace `failed`).
    let dt_s = failed.dt();
    // Bisection of the bracket from the last stable state.
    while unstable - path.last_stable > params.resolution_deg + 1e-12 {
        let mid = 0.5 * (unstable + path.last_stable);
        if let Some((r, trial)) = path.try_at(&ctx, mid, &mut increments, observe)? {
            unstable = mid;
            reason = r;
            failed = trial;
        }
    }
    let (last_stable, stable_sim, total_steps, total_iterations, fallbacks) =
        (path.last_stable, path.sim, path.total_steps, path.total_iterations, path.fallbacks);
    // Stable increments first, sorted by α, then unstable trials by α.
    increments.sort_by(|a, b| (!a.stable).cmp(&!b.stable).then(a.alpha_deg.total_cmp(&b.alpha_deg)));
    let mechanism = mechanism(&stable_sim, &failed);
    Ok(TiltResult {
        last_stable_deg: last_stable,
        first_unstable_deg: Some(unstable),
        collapse_reason: Some(reason),
        mechanism,
        monitors: monitors.iter().map(|m| m.name.clone()).collect(),
        increments,
        steps: total_steps,
        iterations: total_iterations,
        dt_s: failed.dt().min(dt_s),
        wall_time_s: t0.elapsed().as_secs_f64(),
        wall_width_m: width,
        elastic_scale_m: elastic,
        detections: failed.detections(),
        max_density_scale: failed.max_density_scale().max(stable_sim.max_density_scale()),
        scalar_fallbacks_deg: fallbacks,
        bracket_reliable: reason != CollapseReason::StepBudget,
        after_snap: None,
    })
}

/// Where a wall held by ropes falls after a snap its ropes catch ([`TiltResult::after_snap`],
/// [`RopeCatch`]), for either solver: when `layout` has ropes and `first` (the test under
/// `params`) failed by a jump ([`CollapseReason::IncrementDisplacement`]), `run` runs the
/// test again with the per-increment collapse displacement raised to the total one; the
/// wall was caught when that run stands past the snap by more than the resolution.
///
/// # Errors
/// What `run` returns.
pub(crate) fn after_snap(
    layout: &Layout,
    params: &TiltParams,
    first: &TiltResult,
    run: impl FnOnce(&TiltParams) -> Result<TiltResult, TiltError>,
) -> Result<Option<RopeCatch>, TiltError> {
    if layout.ropes.is_empty()
        || first.collapse_reason != Some(CollapseReason::IncrementDisplacement)
        || params.collapse_increment_fraction >= params.collapse_displacement_fraction
    {
        return Ok(None);
    }
    let lifted = TiltParams { collapse_increment_fraction: params.collapse_displacement_fraction, ..*params };
    let fall = run(&lifted)?;
    if fall.last_stable_deg <= first.last_stable_deg + params.resolution_deg + 1e-9 {
        return Ok(None);
    }
    let past = first.first_unstable_deg.unwrap_or(first.last_stable_deg);
    let caught = fall
        .increments
        .iter()
        .filter(|i| i.stable && i.alpha_deg >= past - 1e-9)
        .min_by(|a, b| a.alpha_deg.total_cmp(&b.alpha_deg))
        .map_or(f64::NAN, |i| i.displacement_m.iter().fold(0.0_f64, |m, d| m.max(d.abs())));
    Ok(Some(RopeCatch {
        falls_last_stable_deg: fall.last_stable_deg,
        falls_first_unstable_deg: fall.first_unstable_deg,
        falls_reason: fall.collapse_reason,
        caught_displacement_m: caught,
    }))
}
