//! The in-plane test's convergence keeps the wall whole: an increment whose
//! relaxation threw a block from the wall is not converged. A small running-bond wall
//! (four courses of 0.15 m, 0.6 m long, 0.2 m thick; blocks 0.2 m long, half blocks at the
//! ends of every other course) cycled at 0.5 MPa to ±0.5 and ±1 % drift: between two
//! increments reported converged, no block walks from every one of its joint neighbours by
//! more than the quasi-static increment can move it, the mechanism's relative motion (twice
//! the actuator's increment times the rig's diagonal over the lever: a turn about a point of
//! the wall, counted at the centroid and at the block's radius) plus the joints' elastic
//! slip range `μ σ0 / Ks`, computed here from the rig's geometry and the joints' law. Over
//! normal stiffnesses of 1e10–1e11 Pa/m (Ks = Kn / 20, the granite wall's ratio), by the
//! default solve and by the Newton solve: a loose block at the wall's top corners thrown by
//! millimetres or twisted in plan by tens of mrad fails it.

use drystone::dem::SolverParams;
use drystone::layout::BaseSliding;
use drystone::loading::excursion::JointNeighbours;
use drystone::loading::inplane::{run_in_plane_penalty, History, InPlaneParams};
use drystone::math::Vec3;
use drystone::verify::{box_vertices, layout_of};

const L: f64 = 0.6;
const T: f64 = 0.2;
const COURSE: f64 = 0.15;
const COURSES: usize = 4;
const BLOCK: f64 = 0.2;
const H0: f64 = 0.7;
const SIGMA0_MPA: f64 = 0.5;
const PHI_DEG: f64 = 32.2;

/// The wall's blocks, course by course, left to right.
fn blocks() -> Vec<Vec<[f64; 3]>> {
    let mut out = Vec::new();
    for c in 0..COURSES {
        let mut xs = vec![0.0];
        if c % 2 == 1 {
            xs.push(BLOCK / 2.0);
        }
        while xs.last().unwrap() + BLOCK < L - 1e-9 {
            let next = xs.last().unwrap() + BLOCK;
            xs.push(next);
        }
        xs.push(L);
        let (z0, z1) = (c as f64 * COURSE, (c + 1) as f64 * COURSE);
        for w in xs.windows(2) {
            out.push(box_vertices([w[0], -T / 2.0, z0], [w[1], T / 2.0, z1]));
        }
    }
    out
}

type Poses = Vec<(Vec3, nalgebra::UnitQuaternion<f64>)>;

/// Cycles the wall on joints of normal stiffness `kn` (Ks = Kn / 20) by `solver` and
/// asserts that no block walks from every joint neighbour by more than the bound of the
/// module doc between two increments reported converged, over more than 100 increments.
fn assert_whole(kn: f64, solver: SolverParams) {
    let ks = kn / 20.0;
    let wall = layout_of(blocks(), kn, ks, PHI_DEG, BaseSliding::Free);
    let p = InPlaneParams {
        sigma0_mpa: SIGMA0_MPA,
        shear_span_m: Some(H0),
        drift_pct: 1.0,
        history: History::Cyclic,
        reversals_pct: Some(vec![0.5, -0.5, 1.0, -1.0]),
        ..InPlaneParams::default()
    };
    // The rig's layout: the wall and the beam (its block last), for the joint neighbours.
    let rig = drystone::loading::inplane::Rig::build(&wall, &p).unwrap();
    let neighbours = JointNeighbours::of(&rig.layout);
    let e = rig.layout.bounds().extent();
    let spread = 2.0 * (e.x.hypot(e.z) / H0).max(1.0);
    let slip = PHI_DEG.to_radians().tan() * SIGMA0_MPA * 1e6 / ks;
    let mut last: Option<(f64, Poses)> = None;
    let mut worst = (0.0_f64, String::new(), 0.0_f64);
    let mut increments = 0;
    let r = run_in_plane_penalty(&wall, solver, &p, &mut |drift, converged, sim| {
        let now: Poses = sim.state.bodies.iter().map(|b| (b.pos, b.rot)).collect();
        let radii: Vec<f64> = sim.state.bodies.iter().map(|b| b.radius).collect();
        if let (Some((d0, before)), true) = (&last, converged) {
            // The actuator's increment, m, from the drift read over the shear span.
            let du = (drift - d0).abs() / 100.0 * H0;
            let (walk, k) = neighbours.largest_walk(before, &now, &radii);
            let share = walk / (spread * du + slip);
            if share > worst.0 {
                worst = (share, k.map_or_else(String::new, |k| sim.state.bodies[k].id.clone()), walk);
            }
        }
        increments += 1;
        last = Some((drift, now));
    })
    .unwrap();
    assert!(increments > 100, "Kn {kn:e}: {increments} increments");
    assert!(
        worst.0 <= 1.0 + 1e-9,
        "Kn {kn:e}: block {} walked {:.3} mm in a converged increment, {:.2} times the bound ({} unconverged, {:?} handed over)",
        worst.1,
        worst.2 * 1e3,
        worst.0,
        r.unconverged,
        r.newton_handed_over
    );
}

#[test]
fn converged_increments_of_a_cycled_wall_keep_every_block_with_a_neighbour() {
    for kn in [1e10, 2e10, 1e11] {
        assert_whole(kn, SolverParams::default());
    }
}

/// The semi-smooth Newton solve (`--solver newton`) on the same wall at Kn 1e10 Pa/m:
/// between two increments reported converged no block walks from every one of its joint
/// neighbours by more than the bound above. Its steps are bounded by the joints' gaps
/// (`dem::drivers::newton`): a line search on the out-of-balance force alone accepts steps
/// that throw the lightly loaded blocks at the wall's top corners off their neighbours
/// (an open joint carries no force, so the merit falls).
#[test]
fn the_newton_solve_keeps_the_cycled_wall_whole() {
    assert_whole(1e10, SolverParams { kind: drystone::dem::SolverKind::Newton, ..SolverParams::default() });
}
