//! The collapse-mechanism reading (`loading::tilt::mechanism`) against failed states built
//! by hand: rigid rotations and slides of known groups of blocks of a settled stack, so
//! that the right answer (the failing joints, the moving blocks, toppling or sliding) is
//! known exactly.

use drystone::dem::RunToEquilibrium;
use drystone::dem::{Simulation, SolverParams};
use drystone::layout::BaseSliding;
use drystone::loading::tilt::{mechanism, Mechanism, MechanismKind};
use drystone::verify::{box_vertices, layout_of, RIGID_KN};
use drystone::Vec3;

/// `n` aligned blocks, `l` long (x), `b` wide (y), `h` high (z), settled under gravity on
/// stiff joints (φ = 30°).
fn settled_stack(n: usize, l: f64, b: f64, h: f64) -> Simulation {
    let blocks =
        (0..n).map(|k| box_vertices([0.0, -b / 2.0, k as f64 * h], [l, b / 2.0, (k + 1) as f64 * h])).collect();
    let layout = layout_of(blocks, RIGID_KN, RIGID_KN / 2.0, 30.0, BaseSliding::Free);
    let mut sim = Simulation::new(&layout, SolverParams::default());
    assert!(sim.run_to_equilibrium(1e-6, 200_000).unwrap(), "the stack settles");
    sim
}

/// `sim` with blocks `from..` turned rigidly by `theta` (rad) about the x-parallel edge
/// at y = b/2, z = `z_pivot` (toppling towards +y).
fn toppled(sim: &Simulation, from: usize, b: f64, z_pivot: f64, theta: f64) -> Simulation {
    let mut s = sim.clone();
    let pivot = Vec3::new(0.0, b / 2.0, z_pivot);
    let rot = nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), -theta);
    for body in &mut s.state.bodies[from..] {
        let arm = body.pos - Vec3::new(body.pos.x, pivot.y, pivot.z);
        body.pos = Vec3::new(body.pos.x, pivot.y, pivot.z) + rot * arm;
        body.rotate(Vec3::x() * -theta);
    }
    s
}

fn blocks(m: &Mechanism) -> Vec<&str> {
    m.blocks.iter().map(String::as_str).collect()
}

#[test]
fn a_whole_stack_toppling_about_its_toe_fails_at_the_base_joint() {
    let (b, h) = (0.15, 0.075);
    let sim = settled_stack(5, 0.3, b, h);
    let m = mechanism(&sim, &toppled(&sim, 0, b, 0.0, 0.05));
    assert_eq!(m.kind, MechanismKind::Toppling, "{m:?}");
    assert_eq!(m.joint, "table/b0", "{m:?}");
    assert_eq!(m.joints, vec![("table/b0".to_string(), MechanismKind::Toppling)], "{m:?}");
    assert_eq!(blocks(&m), ["b0", "b1", "b2", "b3", "b4"]);
}

/// The case a per-block motion threshold gets wrong: in a slender stack of short blocks
/// the base block moves (centroid plus rotation times radius) less than a quarter as far as
/// the top one, yet it rotates with the stack; the joint under it is the one that opens.
#[test]
fn the_foot_of_a_slender_toppling_stack_counts_as_moving() {
    let (b, h) = (0.15, 0.075);
    let sim = settled_stack(12, 0.05, b, h);
    let failed = toppled(&sim, 0, b, 0.0, 0.05);
    let motion = |k: usize| {
        let (s, f) = (&sim.state.bodies[k], &failed.state.bodies[k]);
        (f.pos - s.pos).norm() + (f.rot * s.rot.inverse()).angle() * s.radius
    };
    assert!(motion(0) < 0.25 * motion(11), "the premise: {} vs {}", motion(0), motion(11));
    let m = mechanism(&sim, &failed);
    assert_eq!(m.joint, "table/b0", "{m:?}");
    assert_eq!(m.kind, MechanismKind::Toppling, "{m:?}");
    assert_eq!(m.blocks.len(), 12, "{m:?}");
}

#[test]
fn the_top_of_a_stack_toppling_on_an_upper_joint_fails_there() {
    let (b, h) = (0.15, 0.075);
    let sim = settled_stack(5, 0.3, b, h);
    let m = mechanism(&sim, &toppled(&sim, 3, b, 3.0 * h, 0.05));
    assert_eq!(m.kind, MechanismKind::Toppling, "{m:?}");
    assert_eq!(m.joint, "b2/b3", "{m:?}");
    assert_eq!(blocks(&m), ["b3", "b4"]);
}

#[test]
fn a_top_block_sliding_off_is_a_sliding_mechanism_at_its_joint() {
    let (b, h) = (0.15, 0.075);
    let sim = settled_stack(5, 0.3, b, h);
    let mut failed = sim.clone();
    failed.state.bodies[4].pos.y += 0.01;
    let m = mechanism(&sim, &failed);
    assert_eq!(m.kind, MechanismKind::Sliding, "{m:?}");
    assert_eq!(m.joint, "b3/b4", "{m:?}");
    assert_eq!(blocks(&m), ["b4"]);
}

#[test]
fn no_motion_is_no_mechanism() {
    let sim = settled_stack(3, 0.3, 0.15, 0.075);
    let m = mechanism(&sim, &sim.clone());
    assert_eq!(m.kind, MechanismKind::None, "{m:?}");
    assert!(m.blocks.is_empty() && m.joints.is_empty(), "{m:?}");
}
