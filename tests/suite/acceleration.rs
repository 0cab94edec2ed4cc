//! The secant acceleration of slow creep and its stability indicator (`dem::drivers::accelerate`):
//! it changes the steps, not the result, and it names an overloaded block unstable.

use drystone::dem::drivers::accelerate::SecantAcceleration;
use drystone::dem::drivers::relax::{dynamic_relaxation, Relaxed};
use drystone::dem::RunToEquilibrium;
use drystone::dem::{Simulation, SolverParams};
use drystone::layout::Layout;
use drystone::loading::tilt::{CollapseReason, TiltParams};
use drystone::protocol::run_tilt;
use std::path::Path;

use crate::common;

fn running_bond_wall() -> Layout {
    Layout::from_file(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/layouts/running_bond_wall.json"))).unwrap()
}

/// The 24-block running-bond wall relaxed dynamically with and without the acceleration: the collapse angle
/// within one bracket, the displacements of every stable increment up to 80 % of it equal
/// to within 2 % of the largest (both are equilibria to the same unbalanced-force
/// tolerance), and fewer steps in all.
#[test]
fn the_acceleration_changes_the_steps_not_the_result() {
    let l = running_bond_wall();
    // Dynamic relaxation only: the acceleration acts on its steps.
    let params = TiltParams { implicit: false, ..TiltParams::default() };
    let with = run_tilt(&l, SolverParams::default(), &params).unwrap();
    let without = run_tilt(&l, SolverParams::default(), &TiltParams { accelerate: false, ..params }).unwrap();
    common::assert_same_tilt_result(&with, &without, params.resolution_deg);
    assert!(with.steps < without.steps, "{} steps with the acceleration, {} without", with.steps, without.steps);
}

/// A 0.15 × 0.3 m block (rigid limit atan(b/h) = 26.57°) settled on the table and tilted at
/// once to 30°: no equilibrium exists, and the stability indicator says so (negative
/// stiffness along the rocking motion) long before plain relaxation has carried the block a
/// twentieth of its width; tilted to 20° instead it comes to rest, indicator silent.
#[test]
fn the_indicator_names_an_overloaded_block_and_only_that() {
    let (b, d, h) = (0.2, 0.15, 0.3);
    let vertices: Vec<String> = (0..8)
        .map(|i| {
            format!(
                "[{}, {}, {}]",
                if i & 1 == 0 { 0.0 } else { b },
                if i & 2 == 0 { 0.0 } else { d },
                if i & 4 == 0 { 0.0 } else { h }
            )
        })
        .collect();
    let json = format!(
        r#"{{"version": 1, "materials": [{{"name": "m", "density_kg_per_m3": 2500, "kn_pa_per_m": 1e11,
            "ks_pa_per_m": 5e10, "friction_deg": 40, "cohesion_pa": 0, "tensile_strength_pa": 0}}],
            "table": {{"material": "m"}},
            "blocks": [{{"id": "b0", "material": "m", "vertices": [{}]}}]}}"#,
        vertices.join(", ")
    );
    let l = drystone::layout::LayoutSpec::from_json(&json).unwrap().resolve().unwrap();
    let settled = || {
        let mut sim = Simulation::new(&l, SolverParams::default());
        assert!(sim.run_to_equilibrium(1e-6, 100_000).unwrap());
        sim
    };
    let mut over = settled();
    over.set_tilt(30f64.to_radians());
    let r = dynamic_relaxation(&mut over, 1e-4, 200_000, Some(SecantAcceleration::default()), |_| None::<()>).unwrap();
    let Relaxed::Unstable(steps, _) = r else { panic!("30°: {r:?}") };
    let mut plain = settled();
    plain.set_tilt(30f64.to_radians());
    let start: Vec<_> = plain.state.bodies.iter().map(|b| (b.pos, b.rot)).collect();
    let moved = dynamic_relaxation(&mut plain, 1e-4, 200_000, None, |s| {
        (drystone::loading::monitors::largest_motion(s, &start) > 0.05 * 0.15).then_some(())
    })
    .unwrap();
    let Relaxed::Stopped((), plain_steps) = moved else { panic!("plain relaxation at 30°: {moved:?}") };
    assert!(
        steps < plain_steps,
        "indicator after {steps} steps, plain relaxation moved 5 % of the width after {plain_steps}"
    );
    let mut under = settled();
    under.set_tilt(20f64.to_radians());
    let r = dynamic_relaxation(&mut under, 1e-4, 200_000, Some(SecantAcceleration::default()), |_| None::<()>).unwrap();
    assert!(matches!(r, Relaxed::Equilibrium(_)), "20°: {r:?}");
    let tilt = run_tilt(&l, SolverParams::default(), &TiltParams::default()).unwrap();
    assert!(tilt.collapse_reason.is_some());
    assert!(matches!(
        tilt.collapse_reason,
        Some(CollapseReason::NegativeStiffness | CollapseReason::IncrementDisplacement)
    ));
}
