//! The tilting table rolled by hand: each increment run as a motion of the table, by
//! non-smooth contact dynamics (`nscd`).
//!
//! The paper's table is "a semicircle wooden piece that rolls manually, controlled by a
//! lever and pulley", tilted "in increments of 5°" and stopped "to record" (Santa-Cruz et
//! al. 2021, §2.1–2.2). The quasi-static test ([`super::tilt::run_tilt_penalty`],
//! [`super::tilt_nscd::run_tilt_nscd`]) assumes the wall sees only the tilted weight; a
//! table rolled by hand also starts and stops, and every stop kicks the wall downhill. This
//! protocol runs the kicks instead of assuming them away.
//!
//! # The table's motion ([`HandTilt`])
//!
//! Increment k goes from `k Δ` to `(k + 1) Δ` (Δ = `increment_deg`): the angular speed
//! rises linearly from 0 to ω (`rate_deg_per_s`) in `ramp_s`, stays at ω, falls linearly
//! to 0 in `ramp_s` (the stop; the roll takes `Δ / ω + ramp_s`), and the table is held
//! still for `hold_s` (the reading).
//! The angular acceleration is `α̈ = ±ω / ramp_s` during the ramps, 0 otherwise.
//!
//! # The wall in the table's frame
//!
//! Bodies are followed in the frame of the table (as by the shaking table), which rotates
//! about the out-of-plane axis x through the **axis point** `A = (·, y_A, −d)`: under the
//! wall's centre in y, `d = axis_depth_m` below the table's surface (the rolling
//! semicircle's contact with the floor: for a disc rolling without slip the acceleration
//! of a point p of the rolling body is `α̈ × (p − C) − ω² (p − O)`, C the contact, O the
//! centre; the contact's drift along the table, `R α`, is neglected). With the frame's
//! angular velocity `Ω = −α̇ x̂` (a point above the axis moves downhill, +y, as α grows),
//! every block of mass m and centroid c gets, besides the weight `m g (0, sin α, −cos α)`:
//!
//! * the **Euler force** `−m Ω̇ × (c − A) = m α̈ (0, −(c_z − A_z), c_y − A_y)`: at a stop
//!   (α̈ < 0) a push downhill growing with the height above the axis, at a start a push
//!   uphill; and the Euler torque `−I Ω̇ = α̈ I x̂` (I the block's inertia in the table
//!   frame);
//! * the **centrifugal force** `m α̇² (0, c_y − A_y, c_z − A_z)` (below 1e-3 g at the
//!   rates of a hand-rolled table, kept for completeness).
//!
//! The Coriolis force `−2 m Ω × v` is left out: at ω ≤ 0.2 rad/s and the speeds of a wall
//! before collapse it is below 1e-3 of the weight. The weight and the inertial forces are
//! evaluated at `t + θ h` of every step.
//!
//! # Readings and collapse
//!
//! At the end of every hold the displacements of the monitor points since α = 0 are read
//! (a stable [`Increment`] at the increment's angle: the paper's readings). The wall
//! collapses when a block has moved more than the per-increment collapse displacement
//! ([`TiltParams::collapse_increment_fraction`] × the wall width) since the start of the
//! increment, or a top point more than [`TiltParams::collapse_displacement_fraction`] × the
//! width since α = 0 (the quasi-static tests' two criteria); the collapse angle
//! (`last_stable_deg`) is the table's angle when the increment's motion first passed a
//! fifth of the per-increment displacement (the onset the operator sees),
//! `first_unstable_deg` the angle when a criterion was met. The last increment stops at
//! [`TiltParams::max_angle_deg`] (a short one rolled slower with the same start and stop,
//! [`HandTilt::increment_of`]); a wall standing after its hold stood. The mechanism is
//! read as by the rigid tilt, from the state at the start of the collapsing increment (its
//! load-carrying joints from that state's impulses; for the first increment, those of the
//! check at α = 0).
//!
//! Rigid joints, as [`super::tilt_nscd::run_tilt_nscd`]: the layout's Kn and Ks are not
//! used. Tested against the sliding block's closed form under a stop
//! (`tests/suite/tilt_hand.rs`).

use super::mechanism::Mechanism;
use super::monitors::monitor_points;
pub use super::tilt::hand::{effective_tilt_deg, HandTilt, MAX_STEPS};
use super::tilt::params::TiltParams;
use super::tilt::result::{CollapseReason, Increment, TiltError, TiltResult};
use super::tilt_nscd::{
    displacements, largest_motion, poses, read_mechanism, released, rigid_result, stood, tilt_error, touches_something,
    Bracket, RigidWork, TrialLimits,
};
use crate::dem::{Simulation, SolverParams};
use crate::layout::Layout;
use crate::math::Vec3;
use crate::nscd::{NscdParams, NscdSimulation};
use std::time::Instant;

/// Sets the weight and the inertial forces of the rotating table frame (module doc) on
/// every body of `sim` for the table's angle `alpha` (rad), angular speed `w` (rad/s) and
/// angular acceleration `acc` (rad/s²), about the axis point `axis` (table frame, m).
pub fn set_table_motion(sim: &mut NscdSimulation, axis: Vec3, alpha: f64, w: f64, acc: f64) {
    sim.set_tilt(alpha);
    let (force, torque): (Vec<Vec3>, Vec<Vec3>) = sim
        .bodies()
        .iter()
        .map(|b| {
            if b.fixed() {
                return (Vec3::zeros(), Vec3::zeros());
            }
            let r = b.pos - axis;
            let euler = Vec3::new(0.0, -r.z, r.y) * (b.mass * acc);
            let centrifugal = Vec3::new(0.0, r.y, r.z) * (b.mass * w * w);
            let iw = b.rot_mat * b.inertia * b.rot_mat.transpose();
            (euler + centrifugal, iw * Vec3::x() * acc)
        })
        .unzip();
    sim.set_external(&force, &torque);
}

/// Why an increment collapsed, if it did: a block moved more than `inc_limit` (m) within
/// the increment, or a top monitor more than `total_limit` (m) from the reference.
fn collapse_reason(moved: f64, inc_limit: f64, top_moved: f64, total_limit: f64) -> Option<CollapseReason> {
    if moved > inc_limit {
        Some(CollapseReason::IncrementDisplacement)
    } else if top_moved > total_limit {
        Some(CollapseReason::TotalDisplacement)
    } else {
        None
    }
}

/// Runs the tilting-table test of `layout` with the table rolled by hand (see the module
/// doc): `tilt` gives the largest tilt and the per-increment collapse displacement (its
/// increment, resolution and relaxation settings do not apply: `hand` gives the motion),
/// `params` the non-smooth solver (time step, NSGS, contact detection); `tilt.by_hand` is
/// not read (`hand` is the motion; [`crate::protocol::run_tilt`] passes `tilt.by_hand`). The result is the
/// same [`TiltResult`] as the quasi-static tests': `increments` holds the readings at the
/// end of every hold (stable) and the collapse (unstable), `steps` the time steps,
/// `iterations` the NSGS sweeps, `elastic_scale_m` 0 (rigid joints).
///
/// # Errors
/// [`TiltError::Parameter`] for a field of `hand`, `tilt` or `params` out of range (its
/// key), a start or stop shorter than 5 time steps (`ramp_s`), or a run longer than
/// [`MAX_STEPS`] steps (`hold_s` or `rate_deg_per_s`, whichever makes it long, named with
/// the bound);
/// [`TiltError::DoesNotStand`] if the wall does not stand as given (the rigid tilt's
/// check); [`TiltError::Nscd`] for a joint with cohesion; [`TiltError::Dem`] if the state
/// blows up.
pub fn run_tilt_by_hand(
    layout: &Layout,
    params: &NscdParams,
    tilt: &TiltParams,
    hand: &HandTilt,
) -> Result<TiltResult, TiltError> {
    hand.validate().map_err(TiltError::Parameter)?;
    tilt.validate().map_err(TiltError::Parameter)?;
    let t0 = Instant::now();
    let base = NscdSimulation::new(layout, &params.for_trials()).map_err(tilt_error)?;
    let dt = params.dt_s;
    hand.check_run(dt, tilt.max_angle_deg).map_err(TiltError::Parameter)?;
    touches_something(&base, params)?;
    let width = layout.bounds().extent().y;
    let inc_limit = tilt.collapse_increment_fraction * width;
    // The wall stands as given: the rigid tilt's check at α = 0.
    let total_limit = tilt.collapse_displacement_fraction * width;
    let limits = TrialLimits::of(layout, &base, inc_limit, total_limit);
    let first = released(&base, &base, &limits, |sim| sim.set_tilt(0.0)).map_err(tilt_error)?;
    stood(&base, &first)?;

    let reader = Simulation::new(layout, SolverParams::default());
    let monitors = monitor_points(layout, &reader);
    let reference: Vec<Vec3> = monitors.iter().map(|m| base.bodies()[m.body].to_world(&m.local)).collect();
    let bounds = layout.bounds();
    let axis = Vec3::new(0.0, 0.5 * (bounds.min.y + bounds.max.y), -hand.axis_depth_m);
    let g_h = base.gravity_magnitude() * dt;
    let theta = params.theta;

    let mut sim = base.clone();
    let mut increments = vec![Increment {
        alpha_deg: 0.0,
        stable: true,
        steps: 0,
        iterations: 0,
        displacement_m: vec![0.0; monitors.len()],
        unbalanced_ratio: 0.0,
        newton_handed_over: false,
    }];
    let (mut last_stable, mut first_unstable, mut reason) = (0.0, None, None);
    let mut mechanism = Mechanism::none();
    let mut k = 0u32;
    loop {
        let start_deg = f64::from(k) * hand.increment_deg;
        if start_deg >= tilt.max_angle_deg - 1e-12 {
            break;
        }
        // The last increment stops at the largest tilt (rolled slower if it is short).
        let step = hand.increment_deg.min(tilt.max_angle_deg - start_deg);
        let hand = &hand.increment_of(step);
        let per_increment = ((hand.roll_s() + hand.hold_s) / dt).round().max(1.0) as u64;
        let at_start = sim.clone();
        let start = poses(&sim);
        let (steps0, it0) = (sim.steps(), sim.iterations());
        let mut onset: Option<f64> = None;
        let mut collapsed = false;
        let mut shown = Vec::new();
        for n in 0..per_increment {
            let t_mid = (n as f64 + theta) * dt;
            let (alpha, w, acc) = hand.motion(start_deg, t_mid);
            set_table_motion(&mut sim, axis, alpha, w, acc);
            sim.step(|_| Vec3::zeros()).map_err(tilt_error)?;
            let moved = largest_motion(&sim, &start);
            let alpha_now = crate::units::rad_to_deg(hand.motion(start_deg, (n + 1) as f64 * dt).0);
            if onset.is_none() && moved > 0.2 * inc_limit {
                onset = Some(alpha_now);
            }
            shown = displacements(&sim, &monitors, &reference);
            let top_moved = shown.iter().fold(0.0, |a: f64, d| a.max(d.abs()));
            let why = collapse_reason(moved, inc_limit, top_moved, total_limit);
            if why.is_some() {
                last_stable = onset.unwrap_or(alpha_now);
                first_unstable = Some(alpha_now);
                reason = why;
                // The load-carrying joints from the impulses of the state at the start of
                // the increment; the first increment starts from the reference, never
                // stepped, whose impulses are those of the check at α = 0.
                let carrying = if k == 0 { &first.sim } else { &at_start };
                mechanism = read_mechanism(&reader, &at_start, carrying, &sim, inc_limit);
                collapsed = true;
                break;
            }
        }
        let end_deg = start_deg + hand.increment_deg;
        increments.push(Increment {
            alpha_deg: if collapsed { first_unstable.unwrap_or(end_deg) } else { end_deg },
            stable: !collapsed,
            steps: sim.steps() - steps0,
            iterations: u32::try_from(sim.iterations() - it0).unwrap_or(u32::MAX),
            displacement_m: shown,
            unbalanced_ratio: sim.last_step().residual_m_per_s / g_h,
            newton_handed_over: false,
        });
        if collapsed {
            break;
        }
        last_stable = end_deg;
        k += 1;
    }
    let bracket = Bracket {
        last_stable_deg: last_stable,
        first_unstable_deg: first_unstable,
        collapse_reason: reason,
        mechanism,
    };
    let work =
        RigidWork { steps: sim.steps(), iterations: sim.iterations(), detections: sim.detections(), dt_s: dt, t0 };
    Ok(rigid_result(bracket, &monitors, increments, work, width))
}
