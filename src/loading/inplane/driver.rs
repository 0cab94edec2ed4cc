//! The driver of the in-plane test by the penalty DEM ([`run_in_plane_penalty`]): the wall
//! settled under the vertical force, then the imposed path, increment by increment, each a
//! static solve from a predicted state.

use super::increments::Stepper;
use super::vertical::{stand_under_vertical_force, VerticalPhase};
use super::{check_cyclic_slip_range, check_drift_reach, check_joint_closure, mechanism_joints, result_of};
use super::{
    BeamRotation, CurvePoint, Excursion, HalfCycle, InPlaneError, InPlaneParams, InPlaneResult, Poses, Rig, Work,
};
use crate::dem::motion::poses;
use crate::dem::state::Body;
use crate::dem::{solve_static, DemError, End, Simulation, SolveOutcome, SolveStage, SolverParams, StaticSolve};
use crate::layout::Layout;
use crate::loading::excursion::JointNeighbours;
use crate::math::Vec3;
use std::time::Instant;

/// The in-plane test of a wall by the penalty DEM: the driver of the protocol's penalty
/// way (`protocol::inplane`). `observe(drift_pct, converged, state)` sees the state under
/// the vertical force (drift 0) and every increment's.
///
/// # Errors
/// See [`InPlaneError`]: bad parameters, a top course not level, a wall that does not stand
/// under gravity or under the vertical force (naming the block), a blow-up.
pub fn run_in_plane_penalty(
    wall: &Layout,
    solver: SolverParams,
    params: &InPlaneParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<InPlaneResult, InPlaneError> {
    let t0 = Instant::now();
    check_cyclic_slip_range(wall, params)?;
    let rig = Rig::build(wall, params)?;
    check_joint_closure(wall, params)?;
    check_drift_reach(params, solver.face_angle_tolerance_deg)?;
    solver.validate_static().map_err(InPlaneError::Solver)?;
    let solver = SolverParams { density_scaling: solver.density_scaling.without_block(), ..solver };
    let VerticalPhase { mut sim, relax, vertical_modulus_mpa, .. } =
        stand_under_vertical_force(&rig, solver, params.beam_rotation, params.sigma0_mpa, &mut |_| {})?;
    let bi = rig.beam;
    observe(0.0, true, &sim);
    let reference = poses(&sim);
    let ref_joints = mechanism_joints(&sim);
    let beam_ref = sim.state.bodies[bi].clone();
    let walked = walk_path(&mut sim, &rig, params, &relax, &reference, &beam_ref, observe)?;
    let ids: Vec<String> = sim.state.bodies.iter().map(|b| b.id.clone()).collect();
    let anchor = sim.state.bodies[bi].hold.dof().expect("set").anchor_world(&beam_ref);
    let mechanism = walked.half.mechanism(&ref_joints, &ids, bi, anchor, &reference, &walked.reading);
    let work = Work {
        unconverged: walked.unconverged,
        retried: walked.retried,
        newton_handed_over: relax.cascade.newton.then_some(walked.handed_over),
        steps: sim.state.steps,
        dt_s: sim.dt(),
        t0,
        vertical_modulus_mpa,
        excursion: walked.excursion,
    };
    Ok(result_of(&rig, params, walked.curve, mechanism, &walked.reading.1, work))
}

/// The actuator's horizontal force on the beam, body `beam`, N (positive towards +x): the
/// reaction of the hold, the opposite of the contact forces on the beam.
fn actuator_force(sim: &Simulation, beam: usize) -> f64 {
    let mut fx = 0.0;
    for c in &sim.state.contacts {
        if c.b == beam {
            fx += c.force.x;
        }
        if c.a == Some(beam) {
            fx -= c.force.x;
        }
    }
    -fx
}

/// What the walk along the imposed path gave ([`walk_path`]).
struct Walked {
    /// The force–displacement curve, the state under the vertical force first.
    curve: Vec<CurvePoint>,
    /// Increments that did not converge.
    unconverged: usize,
    /// Increments solved again from their start.
    retried: usize,
    /// Of the increments kept, those the Newton stage handed over.
    handed_over: usize,
    /// The largest positive displacement (m) and the poses there.
    reading: (f64, Poses),
    /// The half-cycle that led to the reading.
    half: HalfCycle,
    /// The largest excursion of a block from its course.
    excursion: Excursion,
}

/// Walks the simulation `sim`, standing under the vertical force (the poses `reference`,
/// the beam's body `beam_ref` there), along the imposed path of `params`, one static solve
/// (`relax`) per increment; `observe` sees every increment's state.
///
/// # Errors
/// A blow-up that no restart of its increment can avoid.
fn walk_path(
    sim: &mut Simulation,
    rig: &Rig,
    params: &InPlaneParams,
    relax: &StaticSolve,
    reference: &Poses,
    beam_ref: &Body,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<Walked, InPlaneError> {
    let bi = rig.beam;
    let neighbours = JointNeighbours::of(&rig.layout);
    let mut excursion = Excursion::default();
    let top_local = beam_ref.to_body(&Vec3::new(beam_ref.pos.x, beam_ref.pos.y, rig.measure_z_m));
    let top_x0 = beam_ref.to_world(&top_local).x;
    let anchor_x0 = sim.state.bodies[bi].hold.dof().expect("set").anchor_world(beam_ref).x;
    let mut curve =
        vec![CurvePoint { top_mm: 0.0, drift_pct: 0.0, force_kn: actuator_force(sim, bi) * 1e-3, converged: true }];
    let mut unconverged = 0;
    let mut handed_over = 0;
    let mut reading = (f64::NEG_INFINITY, reference.clone());
    // Where the half-cycle that led to the reading started (module doc, the mechanism).
    let mut half = HalfCycle::new(reference);
    let mut steps = Stepper::new(rig, params, sim.state.bodies.len());
    // The drift history is imposed at the actuator: a drift d moves it by d H0 (free
    // rotation: a rotation of the wall about its base reads the drift d at its top) or
    // d H (the beam held level).
    let lever = match params.beam_rotation {
        BeamRotation::Free => rig.anchor_z_m,
        BeamRotation::Fixed => rig.height_m,
    };
    let walk_bound = WalkBound::of(rig, params.sigma0_mpa, lever);
    let radii: Vec<f64> = sim.state.bodies.iter().map(|b| b.radius).collect();
    for u in params.path(lever) {
        while (u - steps.u_prev).abs() > 1e-15 {
            let Some(du) = steps.next(u) else {
                continue;
            };
            if let Some(c) = sim.state.bodies[bi].hold.dof_mut() {
                c.set_target(0, anchor_x0 + steps.u_prev);
            }
            let start = poses(sim);
            let (dpos, drot) = steps.predict(du, sim, rig.anchor_z_m);
            let before = sim.clone();
            sim.predict(&dpos, &drot);
            let solved = match solve_static(sim, relax, &start, |_| None::<()>) {
                Ok(out) => Some(out),
                // A predicted jump the dynamics of the relaxation could not take: the
                // increment again from its start, warming up from the smallest one.
                Err(DemError::NonFinite { .. }) if !steps.is_warm_up(du) => None,
                Err(e) => return Err(e.into()),
            };
            let now = poses(sim);
            // A block that walked from every joint neighbour by more than the increment can
            // move it ([`WalkBound`]) in a dynamic relaxation has left the path: the
            // relaxation threw it to an equilibrium the loading would not reach (a loose
            // block launched in one relaxation, or a stiff wall and its beam swung off their
            // supports by the contact springs' energy). The increment again from its start,
            // warming up from the smallest one; where even that throws a block, the
            // increment is not converged, however well balanced the state it ended in. An
            // equilibrium of the static iterations (implicit, Newton) has no kinetic energy
            // to throw a block with: it is the one next to the predicted motion, and its
            // elastic redistribution (a joint's stresses concentrating as it opens) may
            // exceed the bound's elastic part on stiff joints without leaving the path; but
            // it may still be another branch of the mechanism (a block rocking between the
            // table and a beam held level snapped to its mirror diagonal, the actuator's
            // force reversed), which moves a block many times the bound
            // ([`STATIC_WALK_FACTOR`]).
            let thrown = |o: &SolveOutcome<()>| {
                let walk = neighbours.largest_walk(&start, &now, &radii).0;
                let bound = walk_bound.at(du);
                walk > if o.stage == SolveStage::Relaxation { bound } else { STATIC_WALK_FACTOR * bound }
            };
            let off_path = solved.as_ref().is_some_and(thrown);
            let Some(out) = solved.filter(|_| !off_path || steps.from_start) else {
                steps.restart(sim, before, du, off_path, bi, anchor_x0);
                continue;
            };
            steps.from_start = false;
            let shed = excursion.read(&neighbours, reference, &now, &rig.layout);
            let now_for_reading = now.clone();
            steps.learn(&neighbours, &start, &now, du, sim, bi);
            // Equilibrium of the wall as a whole (the unbalanced-force ratio is a mean over
            // the bodies) and of each block: a block whose own out-of-balance force is a
            // share of its weight is moving, whatever the mean says; and on the path: no
            // block thrown from the wall in the increment, and none shed from it over the
            // history.
            let converged = out.end == End::Equilibrium && every_block_balanced(sim, bi) && !off_path && !shed;
            unconverged += usize::from(!converged);
            handed_over += usize::from(out.newton_unsolved.is_some());
            let top = sim.state.bodies[bi].to_world(&top_local).x - top_x0;
            let drift = 100.0 * top / rig.measure_z_m;
            let force_kn = actuator_force(sim, bi) * 1e-3;
            curve.push(CurvePoint { top_mm: top * 1e3, drift_pct: drift, force_kn, converged });
            observe(drift, converged, sim);
            half.step(top, &now_for_reading);
            if top >= reading.0 {
                reading = (top, now_for_reading);
                half.keep();
            }
        }
    }
    Ok(Walked { curve, unconverged, retried: steps.retried, handed_over, reading, half, excursion })
}

/// How many times the walk bound ([`WalkBound`]) a block may walk in one increment solved
/// by a static iteration (implicit, Newton) before the increment is taken as another branch
/// of the mechanism \[10\]: the iterations' elastic redistribution on stiff joints stays
/// within a few times the bound; a block snapped to another branch moves by its own size's
/// order (a block of 1.2 m rocking between the table and a level beam at 0.05 mm of drift
/// moved 3 mm).
const STATIC_WALK_FACTOR: f64 = 10.0;

/// The most a block may walk from every one of its joint neighbours in one increment of a
/// quasi-static path ([`crate::loading::excursion::JointNeighbours::largest_walk`]), m: the
/// mechanism's relative motion plus the joints' own deformation.
///
/// The actuator drives every motion of the wall: its parts turn about points of the wall
/// (a toe, a crack's foot) or slide along its joints, by at most `dθ = du / lever` (`du` the
/// actuator's increment, over the lever it acts over). A block turned by `dθ` about a point
/// within the rig's diagonal `D` (wall and beam, the farthest two points) moves by at most
/// `dθ D` at its centroid and turns by `dθ`, which the walk counts at the block's radius
/// (at most `D`): `2 D du / lever` (at least `2 du`, the beam's own translation). A block's
/// joints deform elastically by at most the slip
/// displacement of the stiffest-slipping joint under the vertical stress, `μ σ0 / Ks` (the
/// largest over the materials). A block that walked farther in one increment was thrown
/// by the relaxation (squeezed out of a closing crack, or twisted in its bed by a swing)
/// to an equilibrium the loading would not reach.
#[derive(Debug, Clone, Copy)]
struct WalkBound {
    /// Twice the diagonal over the lever, ≥ 2.
    spread: f64,
    /// The largest `μ σ0 / Ks`, m.
    slip_m: f64,
}

impl WalkBound {
    /// The bound of the rig `rig` under the vertical stress `sigma0_mpa` (MPa), the drift
    /// imposed over `lever` (m).
    fn of(rig: &Rig, sigma0_mpa: f64, lever: f64) -> WalkBound {
        let e = rig.layout.bounds().extent();
        let spread = 2.0 * (e.x.hypot(e.z) / lever).max(1.0);
        let slip_m = rig
            .layout
            .materials
            .iter()
            .map(|m| m.friction.tan().max(1e-3) * sigma0_mpa * 1e6 / m.ks)
            .fold(0.0, f64::max);
        WalkBound { spread, slip_m }
    }

    /// The bound for an increment `du` (m) of the actuator, m.
    fn at(&self, du: f64) -> f64 {
        self.spread * du.abs() + self.slip_m
    }
}

/// The share of a block's own load (its weight and the magnitudes of its contact forces)
/// its out-of-balance force may reach at equilibrium \[0.1\]: a loose block with more is
/// accelerating at a tenth of gravity, in flight or sliding, however small it is beside the
/// wall's mean (the unbalanced-force ratio's); a loaded block is held to the same share of
/// what it carries.
pub const BLOCK_IMBALANCE_SHARE: f64 = 0.1;

/// Whether every free body but `beam` has an out-of-balance force of at most
/// [`BLOCK_IMBALANCE_SHARE`] of its own load.
fn every_block_balanced(sim: &Simulation, beam: usize) -> bool {
    let load = sim.carried_loads();
    sim.state
        .bodies
        .iter()
        .enumerate()
        .all(|(k, b)| k == beam || b.fixed() || sim.unbalanced(k).0.norm() <= BLOCK_IMBALANCE_SHARE * load[k])
}
