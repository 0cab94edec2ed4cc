//! The secant predictor of the tilting-table protocol (`PenaltyParams::predictor`,
//! `Simulation::predict`): the joints follow a predicted jump as they follow a step, and the
//! predictor changes how fast each increment reaches equilibrium, not where it ends.

use drystone::dem::RunToEquilibrium;
use drystone::dem::{PenaltyParams, Simulation, SolverParams};
use drystone::layout::{BaseSliding, Layout};
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use drystone::verify::{box_vertices, layout_of};
use drystone::Vec3;
use std::path::Path;

use crate::common;

/// A 0.2 × 0.2 × 0.1 m block on the table: after a predicted sideways jump d (well inside
/// the elastic range), the shear springs of its base carry Ks · A · d against the jump, as
/// one step of that motion would leave them; the block starts at rest; and relaxing from
/// there brings it back to equilibrium under gravity alone.
#[test]
fn a_predicted_jump_loads_the_shear_springs_like_a_step() {
    let (kn, ks) = (5e7, 2.5e7);
    let layout = layout_of(vec![box_vertices([0.0, 0.0, 0.0], [0.2, 0.2, 0.1])], kn, ks, 35.0, BaseSliding::Free);
    let mut sim = Simulation::new(&layout, SolverParams::default());
    assert!(sim.run_to_equilibrium(1e-6, 100_000).unwrap());
    let d = 1e-6; // m; the friction limit is at W tan φ / (Ks A) ≈ 4.2e-6 m
    let weight = sim.state.bodies[0].mass * 9.81;
    let pos0 = sim.state.bodies[0].pos;
    let shear_sum = |sim: &Simulation| -> Vec3 {
        sim.state.contacts.iter().flat_map(|c| c.subs.iter().map(|s| s.state.shear)).sum()
    };
    let before = shear_sum(&sim);
    sim.predict(&[Vec3::new(0.0, d, 0.0)], &[Vec3::zeros()]);
    assert!((sim.state.bodies[0].pos.y - pos0.y - d).abs() < 1e-15);
    assert_eq!(sim.state.bodies[0].vel, Vec3::zeros());
    let shear = shear_sum(&sim) - before;
    let expected = -ks * 0.2 * 0.2 * d;
    assert!((shear.y - expected).abs() < 1e-9 * weight, "shear {shear:?}, expected y {expected}");
    assert!(shear.x.abs() < 1e-9 * weight && shear.z.abs() < 1e-9 * weight);
    assert!(sim.run_to_equilibrium(1e-6, 100_000).unwrap());
    let back = shear_sum(&sim);
    assert!(back.norm() < 1e-4 * weight, "residual shear {back:?}");
}

/// The 24-block running-bond wall relaxed dynamically with and without the predictor: the same collapse
/// bracket and, up to 80 % of the collapse angle (where the response is nearly linear and the
/// predictor at work; nearer collapse the equilibrium itself is ill-conditioned), the
/// displacements of every stable increment equal to within 2 % of the largest (both are
/// equilibria to the same unbalanced-force tolerance), reached in fewer steps. (The steps of
/// the whole test are not compared: the trials near collapse, which the predictor does not
/// touch, dominate them and vary by thousands of steps with any change of path.)
#[test]
fn the_predictor_changes_the_steps_not_the_result() {
    let l = Layout::from_file(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/layouts/running_bond_wall.json")))
        .unwrap();
    // Dynamic relaxation only (the implicit relaxation starts from the prediction too, but
    // counts iterations, not steps).
    let params = TiltParams { step_deg: 1.0, resolution_deg: 0.25, implicit: false, ..TiltParams::default() };
    let with = run_tilt(&l, SolverParams::default(), &params).unwrap();
    let off = SolverParams {
        penalty: PenaltyParams { predictor: false, ..PenaltyParams::default() },
        ..SolverParams::default()
    };
    let without = run_tilt(&l, off, &params).unwrap();
    assert_eq!(with.collapse_angle_deg(), without.collapse_angle_deg());
    assert_eq!(with.first_unstable_deg, without.first_unstable_deg);
    let limit = common::assert_same_tilt_result(&with, &without, 0.0);
    let steps = |r: &drystone::loading::tilt::TiltResult| -> u64 {
        r.increments.iter().filter(|i| i.stable && i.alpha_deg > 0.0 && i.alpha_deg <= limit).map(|i| i.steps).sum()
    };
    let (sw, so) = (steps(&with), steps(&without));
    assert!((sw as f64) < 0.8 * so as f64, "{sw} steps with the predictor, {so} without, up to {limit}°");
}
