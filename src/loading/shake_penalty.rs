//! The shaking table by the penalty DEM ([`run_shake_penalty`]): explicit dynamics of the
//! sub-contact spring model with true masses, no local damping and normal contact
//! dashpots set by a coefficient of restitution (see [`super::shake`] for the protocol and
//! what is measured).
//!
//! The engine's stages are those of every penalty run ([`crate::dem::Simulation::step`]:
//! contact detection, the contact pass with the dashpots of [`crate::dem::damping`], the
//! load pass, central-difference integration); only the loads differ: the weight and the
//! d'Alembert force `−m a_g(t)` of every free block in the frame of the table, set as the
//! body force `m (g − a_g(t))` at the start of each step (time `tⁿ` of the scheme's
//! positions). The time step is the critical step of the assembly's joint stiffness
//! (its highest frequency against the true masses, `dem::timestep`) times
//! `timestep_safety` (0.95), [`ShakeParams::penalty_step_fraction`] (0.1: a contact's
//! impact in about thirty steps) and the dashpots' factor
//! ([`crate::dem::damping::ContactDamping::step_factor`]); it only shrinks as contacts
//! change.
//!
//! The wall settles on the still table for `settle_s` by the same integration (the blocks
//! sink into their bed joints and the dashpots damp the oscillation), then the motion
//! starts.

use super::shake::{base_acceleration, ShakeError, ShakeParams, ShakeResult, Watch, Work};
use crate::dem::damping::ContactDamping;
use crate::dem::state::Body;
use crate::dem::{DensityScaling, Simulation, SolverKind, SolverParams};
use crate::ground::Motion;
use crate::layout::Layout;
use std::time::Instant;

/// Runs the shaking-table test by the penalty DEM in explicit dynamics: the joints of the
/// layout (Kn, Ks, friction, cohesion and tension as given), `solver`'s contact and
/// step settings (`contact_margin_m`, `subcontact_subdivisions`, `quadrature`,
/// `timestep_safety` times [`ShakeParams::penalty_step_fraction`], ...) with local damping 0 and density scaling off whatever `solver`
/// says, and dashpots of restitution [`ShakeParams::contact_restitution`]. Called by
/// [`super::shake::run_shake_observed`], which has checked `params` and the motion.
///
/// # Errors
/// [`ShakeError::Parameter`] for a solver parameter out of range, [`ShakeError::Dem`] if
/// the integration blows up.
pub(super) fn run_shake_penalty(
    layout: &Layout,
    solver: SolverParams,
    motion: &Motion,
    params: &ShakeParams,
    observe: &mut dyn FnMut(f64, &[Body]),
) -> Result<ShakeResult, ShakeError> {
    let t0 = Instant::now();
    let sp = SolverParams {
        damping: 0.0,
        density_scaling: DensityScaling::Off,
        timestep_safety: solver.timestep_safety * params.penalty_step_fraction,
        ..solver
    };
    sp.validate().map_err(ShakeError::Parameter)?;
    let damping = ContactDamping::from_restitution(params.contact_restitution).map_err(ShakeError::Parameter)?;
    let mut sim = Simulation::new(layout, sp);
    sim.set_contact_damping(Some(damping));
    super::shake::check_steps(motion, params, sim.dt())?;
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
            wall_time_s: t0.elapsed().as_secs_f64(),
        },
    ))
}
