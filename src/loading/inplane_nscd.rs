//! The in-plane shear–compression test by non-smooth contact dynamics (rigid blocks, hard
//! Coulomb joints; [`crate::nscd`]): the rig of [`super::inplane`] with its loading beam's
//! degrees of freedom constrained in the contact dynamics ([`crate::nscd::held`]).
//!
//! # The run
//!
//! 1. The rig ([`Rig::build`]) and the beam's constraint ([`Rig::constraint_of`]): x held
//!    at the actuator's point (the shear span `H0`), y and the rotations about x and z held,
//!    the rotation about y free (cantilever) or held (double-fixed), z free.
//! 2. The vertical force `N` on the beam (its weight part of it), and steps with the beam
//!    held until every block is at rest ([`NscdParams::rest_velocity_ratio`] `× g h`, for
//!    [`QUIET_STEPS`] steps, within [`SETTLE_S`]); a block that moved more than the settling
//!    tolerance ([`super::settle::settle_tolerance`]) means the wall does not stand under
//!    the force ([`InPlaneError::UnderVerticalForce`]).
//! 3. The history's path ([`InPlaneParams::path`], the same imposed displacements as the
//!    penalty DEM's static solves) driven at the constant speed [`SPEED_M_PER_S`]: the
//!    beam's target moves by `SPEED_M_PER_S × h` a step, each increment in whole steps.
//!    A point of the curve is one increment: its force is the actuator's mean force over
//!    the increment, `V = −Σ` (the contact impulses on the beam along x) over the
//!    increment's duration, so that the impulse of a start or a reversal (the wall brought
//!    to the beam's speed in one step) counts once, spread over its increment.
//!
//! The blocks are rigid: the curve has no elastic branch (the initial stiffness is that of
//! the first increment, not a material's), and its force is the capacity of the mechanism
//! the wall moves in: rocking about a toe `N_total L / (2 H0)` (double-fixed
//! `(N L + W L / 2) / H`), sliding `μ N_total`, less the P–Δ of the drift reached
//! (`tests/suite/inplane.rs`).

use super::inplane::{result_of, InPlaneError, InPlaneParams, InPlaneResult, MechanismJoint, Rig, Work};
use super::inplane::{BeamRotation, CurvePoint};
use crate::layout::Layout;
use crate::math::Vec3;
use crate::nscd::{NscdParams, NscdSimulation};
use nalgebra::UnitQuaternion;
use std::time::Instant;

/// The speed at which the beam's anchor is driven, m/s \[0.002\]: 2 mm/s, so that the
/// inertia of a start or a reversal (the wall and beam brought to it within one step),
/// spread over an increment of the path, is under 0.1 % of the force of the test's walls
/// (2 × 700 kg × (2 mm/s)² / 0.25 mm = 22 N on a 1.2 m granite wall carrying 38 kN).
pub const SPEED_M_PER_S: f64 = 0.002;

/// The longest settling under the vertical force, s \[1\].
pub const SETTLE_S: f64 = 1.0;

/// Consecutive steps at rest that end the settling \[10\].
pub const QUIET_STEPS: u32 = 10;

/// The poses (centroid, orientation) of every body.
fn poses(sim: &NscdSimulation) -> Vec<(Vec3, UnitQuaternion<f64>)> {
    sim.bodies().iter().map(|b| (b.pos, b.rot)).collect()
}

/// The joints of the simulation's contact points, for [`read_mechanism`](super::inplane::read_mechanism): one per pair,
/// its points the midpoints of the pair's contact points.
pub fn nscd_mechanism_joints(sim: &NscdSimulation) -> Vec<MechanismJoint> {
    let bodies = sim.bodies();
    let mut out: Vec<MechanismJoint> = Vec::new();
    for c in sim.contact_points() {
        let (pa, pb) = c.world_points(bodies);
        let x = 0.5 * (pa + pb);
        match out.last_mut() {
            Some(j) if j.a == c.a && j.b == c.b => j.points.push(x),
            _ => out.push(MechanismJoint {
                a: c.a,
                b: c.b,
                name: c.joint_name(bodies),
                normal: c.normal(bodies),
                points: vec![x],
                elastic_m: 0.0,
            }),
        }
    }
    out
}

/// The actuator's force over the last step, N (positive towards +x): minus the contact
/// forces on the beam `beam` along x.
fn actuator_force(sim: &NscdSimulation, beam: usize) -> f64 {
    let mut fx = 0.0;
    for (c, f) in sim.contact_points().iter().zip(sim.point_forces()) {
        if c.b == beam {
            fx += f.x;
        }
        if c.a == Some(beam) {
            fx -= f.x;
        }
    }
    -fx
}

/// The in-plane test of a wall by non-smooth contact dynamics with the solver's settings
/// `nscd` (see the module doc): the driver of the protocol's nscd way
/// (`protocol::inplane`).
///
/// # Errors
/// See [`InPlaneError`]: bad parameters, a top course not level, a joint with cohesion or
/// tensile strength ([`InPlaneError::Nscd`]), a wall that does not stand under the vertical
/// force (naming the block), a blow-up.
pub fn run_in_plane_nscd(
    wall: &Layout,
    nscd: &NscdParams,
    params: &InPlaneParams,
) -> Result<InPlaneResult, InPlaneError> {
    let t0 = Instant::now();
    let rig = Rig::build(wall, params)?;
    let mut sim = NscdSimulation::new(&rig.layout, nscd)?;
    let bi = rig.beam;
    sim.constrain(bi, rig.constraint_of(&sim.bodies()[bi], params.beam_rotation));
    let n = sim.bodies().len();
    let mut force = vec![Vec3::zeros(); n];
    force[bi] = Vec3::new(0.0, 0.0, -(rig.vertical_force_n - rig.beam_weight_n));
    sim.set_external(&force, &vec![Vec3::zeros(); n]);
    // The rig's terms that move the wall: a moment on the beam from its pose now, applied
    // as its external torque at every step (explicit in the step, as gravity is).
    let moment = rig.beam_moment(&sim.bodies()[bi]);
    let mut torque = vec![Vec3::zeros(); n];
    let mut apply_moment = |sim: &mut NscdSimulation| {
        if let Some(m) = &moment {
            let b = &sim.bodies()[bi];
            torque[bi][m.axis] = m.moment_nm(&b.pos, &b.rot);
            sim.set_external(&force, &torque);
        }
    };
    apply_moment(&mut sim);
    let h = nscd.dt_s;
    stand_under_vertical_force(&mut sim, &rig, nscd, &mut apply_moment)?;
    let reference = poses(&sim);
    let neighbours = super::excursion::JointNeighbours::of(&rig.layout);
    let mut excursion = super::inplane::Excursion::default();
    let ref_joints = nscd_mechanism_joints(&sim);
    let beam_ref = sim.bodies()[bi].clone();
    let top_local = beam_ref.to_body(&Vec3::new(beam_ref.pos.x, beam_ref.pos.y, rig.measure_z_m));
    let top_x0 = beam_ref.to_world(&top_local).x;
    let anchor_ref = sim.constraint(bi).map_or(beam_ref.pos, |c| c.anchor_world(&beam_ref));
    let force0 = actuator_force(&sim, bi);
    let mut curve = vec![CurvePoint { top_mm: 0.0, drift_pct: 0.0, force_kn: force0 * 1e-3, converged: true }];
    let mut unconverged = 0;
    let mut reading = (f64::NEG_INFINITY, reference.clone());
    let mut half = super::inplane::HalfCycle::new(&reference);
    let lever = match params.beam_rotation {
        BeamRotation::Free => rig.anchor_z_m,
        BeamRotation::Fixed => rig.height_m,
    };
    let mut u_prev = 0.0;
    for u in params.path(lever) {
        let steps = ((u - u_prev).abs() / (SPEED_M_PER_S * h)).ceil().max(1.0) as u32;
        let (mut impulse, mut converged) = (0.0, true);
        for s in 1..=steps {
            let target = u_prev + (u - u_prev) * f64::from(s) / f64::from(steps);
            if let Some(c) = sim.constraint_mut(bi) {
                c.set_target(0, anchor_ref.x + target);
            }
            apply_moment(&mut sim);
            let step = sim.step(|_| Vec3::zeros())?;
            converged &= step.converged;
            impulse += actuator_force(&sim, bi) * h;
        }
        u_prev = u;
        let now = poses(&sim);
        // A block shed from the wall: the increment is no state of the wall.
        converged &= !excursion.read(&neighbours, &reference, &now, &rig.layout);
        unconverged += usize::from(!converged);
        let top = sim.bodies()[bi].to_world(&top_local).x - top_x0;
        let drift = 100.0 * top / rig.measure_z_m;
        let v = impulse / (f64::from(steps) * h);
        curve.push(CurvePoint { top_mm: top * 1e3, drift_pct: drift, force_kn: v * 1e-3, converged });
        half.step(top, &now);
        if top >= reading.0 {
            reading = (top, now);
            half.keep();
        }
    }
    let ids: Vec<String> = sim.bodies().iter().map(|b| b.id.clone()).collect();
    let mechanism = half.mechanism(&ref_joints, &ids, bi, anchor_ref, &reference, &reading);
    // Rigid contacts: the wall has no vertical compliance to read.
    let work = Work {
        unconverged,
        retried: 0,
        newton_handed_over: None,
        steps: sim.steps(),
        dt_s: h,
        t0,
        vertical_modulus_mpa: f64::NAN,
        excursion,
    };
    let mut result = result_of(&rig, params, curve, mechanism, &reading.1, work);
    // Rigid contacts: the curve's first points are the actuator's steps reaching the
    // mechanism, whose secant scales with the step (317, 566 and 1,051 kN/mm at 0.5, 0.25
    // and 0.1 mm on the granite wall); it is no stiffness of the wall.
    for d in result.positive.iter_mut().chain(result.negative.iter_mut()) {
        d.initial_stiffness_kn_per_mm = f64::NAN;
    }
    Ok(result)
}

/// Settles the rig's wall under the vertical force (`apply_moment` sets the rig's moment on
/// the beam before each step) until every point moves slower than the rest velocity for
/// [`QUIET_STEPS`] steps, within [`SETTLE_S`] of simulated time.
///
/// # Errors
/// [`InPlaneError::UnderVerticalForce`] naming the block that moved farthest, when the wall
/// did not come to rest or a block moved past the settling tolerance; a blow-up.
fn stand_under_vertical_force(
    sim: &mut NscdSimulation,
    rig: &Rig,
    nscd: &NscdParams,
    apply_moment: &mut dyn FnMut(&mut NscdSimulation),
) -> Result<(), InPlaneError> {
    let h = nscd.dt_s;
    let start = poses(sim);
    let rest = nscd.rest_velocity_ratio * sim.gravity_magnitude() * h;
    let mut quiet = 0;
    for _ in 0..(SETTLE_S / h).ceil() as u64 {
        apply_moment(sim);
        sim.step(|_| Vec3::zeros())?;
        quiet = if sim.max_point_speed() <= rest { quiet + 1 } else { 0 };
        if quiet >= QUIET_STEPS {
            break;
        }
    }
    let allowed = super::settle::settle_tolerance(&rig.layout);
    let worst = sim
        .bodies()
        .iter()
        .zip(&start)
        .map(|(b, (x0, _))| (b.id.clone(), (b.pos - x0).norm()))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((block, moved)) = worst {
        if quiet < QUIET_STEPS || moved > allowed {
            return Err(InPlaneError::UnderVerticalForce {
                block,
                moved_mm: moved * 1e3,
                allowed_mm: allowed * 1e3,
                force_kn: rig.vertical_force_n * 1e-3,
                equilibrium: quiet >= QUIET_STEPS,
            });
        }
    }
    Ok(())
}
