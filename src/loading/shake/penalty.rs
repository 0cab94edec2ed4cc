//! The shaking table by the penalty DEM: the simulation a run starts from (no local
//! damping, no density scaling, contact dashpots of a coefficient of restitution), its
//! time step, and the run itself, settling then motion.

use super::watch::{Watch, Work};
use super::{base_acceleration, check_steps, ShakeError, ShakeParams, ShakeResult};
use crate::dem::damping::ContactDamping;
use crate::dem::state::Body;
use crate::dem::{DensityScaling, Simulation, SolverKind, SolverParams};
use crate::ground::Motion;
use crate::layout::Layout;
use std::time::Instant;

// The shaking table by the penalty DEM (`run_shake_penalty`): explicit dynamics of the
// sub-contact spring model with true masses, no local damping and normal contact
// dashpots set by a coefficient of restitution.
//
// The engine's stages are those of every penalty run (`dem::Simulation::step`:
// contact detection, the contact pass with the dashpots of `dem::damping`, the
// load pass, central-difference integration); only the loads differ: the weight and the
// d'Alembert force `−m a_g(t)` of every free block in the frame of the table, set as the
// body force `m (g − a_g(t))` at the start of each step (time `tⁿ` of the scheme's
// positions). The time step is the critical step of the assembly's joint stiffness
// (its highest frequency against the true masses, `dem::timestep`) times
// `timestep_safety` (0.95), `PenaltyParams::step_fraction` (0.1: a contact's
// impact in about thirty steps) and the dashpots' factor
// (`ContactDamping::step_factor`); it only shrinks as contacts
// change.
//
// The wall settles on the still table for `settle_s` by the same integration (the blocks
// sink into their bed joints and the dashpots damp the oscillation), then the motion
// starts.

/// The simulation a penalty shaking run starts from: no local damping, no density
/// scaling, the step `timestep_safety × step_fraction` of the critical step, the normal
/// contact damping of `contact_restitution` ([`crate::dem::PenaltyParams`]).
///
/// # Errors
/// [`ShakeError::Parameter`] for a solver parameter out of range.
fn penalty_simulation(layout: &Layout, solver: SolverParams, params: &ShakeParams) -> Result<Simulation, ShakeError> {
    let solver = crate::dem::with_moved(solver, &params.moved());
    solver.validate().map_err(ShakeError::Parameter)?;
    let p = solver.penalty;
    let sp = SolverParams {
        damping: 0.0,
        density_scaling: DensityScaling::Off,
        timestep_safety: solver.timestep_safety * p.step_fraction,
        ..solver
    };
    sp.validate().map_err(ShakeError::Parameter)?;
    let damping = ContactDamping::from_restitution(p.contact_restitution).map_err(ShakeError::Parameter)?;
    let mut sim = Simulation::new(layout, sp);
    sim.set_contact_damping(Some(damping));
    Ok(sim)
}

/// The time step (s) a penalty shaking run of `layout` starts with: the critical step of
/// its blocks' masses and joint stiffnesses (and contact damping) times
/// `timestep_safety × step_fraction` ([`crate::dem::PenaltyParams`]), known before the run (with [`check_steps`], the run's step count).
///
/// # Errors
/// [`ShakeError::Parameter`] for a solver parameter out of range.
pub fn penalty_step(layout: &Layout, solver: SolverParams, params: &ShakeParams) -> Result<f64, ShakeError> {
    Ok(penalty_simulation(layout, solver, params)?.dt())
}

/// Runs the shaking-table test by the penalty DEM in explicit dynamics: the joints of the
/// layout (Kn, Ks, friction, cohesion and tension as given), `solver`'s contact and
/// step settings (`contact_margin_m`, `subcontact_subdivisions`, `quadrature`,
/// `timestep_safety` times [`crate::dem::PenaltyParams::step_fraction`], ...) with local damping 0 and
/// density scaling off whatever `solver` says, and dashpots of restitution
/// [`crate::dem::PenaltyParams::contact_restitution`] (the table's former keys applied,
/// [`ShakeParams::moved`]). Called by
/// [`super::run_shake_penalty`], which has checked `params` and the motion.
///
/// # Errors
/// [`ShakeError::Parameter`] for a solver parameter out of range, [`ShakeError::Dem`] if
/// the integration blows up.
pub(super) fn shake_penalty(
    layout: &Layout,
    solver: SolverParams,
    motion: &Motion,
    params: &ShakeParams,
    observe: &mut dyn FnMut(f64, &[Body]),
) -> Result<ShakeResult, ShakeError> {
    let t0 = Instant::now();
    let mut sim = penalty_simulation(layout, solver, params)?;
    check_steps(motion, params, sim.dt())?;
    let weight = sim.state.gravity;
    while sim.state.time < params.settle_s - 0.5 * sim.dt() {
        sim.step()?;
    }
    let start = sim.state.time;
    let mut watch = Watch::new(layout, &sim.state.bodies, motion, params);
    let motion_s = watch.motion_s;
    let total = motion_s + params.tail_s;
    let vertical = params.vertical && motion.vertical_g.is_some();
    while sim.state.time - start < total - 0.5 * sim.dt() {
        sim.state.gravity = weight - base_acceleration(motion, motion_s, vertical, sim.state.time - start);
        sim.step()?;
        if watch.after_step(sim.state.time - start, &sim.state.bodies, observe) {
            break;
        }
    }
    Ok(watch.result(
        SolverKind::Penalty,
        &sim.state.bodies,
        Work {
            simulated_s: sim.state.time - start,
            dt_s: sim.dt(),
            steps: sim.state.steps,
            iterations: 0,
            unconverged_steps: 0,
            max_natural_residual: 0.0,
            wall_time_s: t0.elapsed().as_secs_f64(),
        },
    ))
}
