//! Every preset wall loads in the DEM and stands at α = 0: from the generated layout at
//! rest, gravity alone brings it to equilibrium (unbalanced-force ratio below 1e-4) with no
//! block moving more than a tenth of a mean course height (the joints close by a fraction of
//! a millimetre each; a falling block would move by centimetres).

use drystone::dem::RunToEquilibrium;
use drystone::dem::{Simulation, SolverParams};
use drystone::generator::{generate, Wall};
use std::path::PathBuf;
use std::time::Instant;

fn preset(name: &str) -> Wall {
    Wall::from_file(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/walls").join(format!("{name}.toml")))
        .unwrap()
}

/// Settles realization 0 of seed 2021 under gravity; returns (blocks, steps, largest
/// centroid displacement in m, mean course height in m).
fn stands(name: &str, max_steps: u64) -> (usize, u64, f64, f64) {
    let w = preset(name);
    let g = generate(&w, 2021, 0).unwrap();
    let layout = g.check().unwrap();
    let mut sim = Simulation::new(&layout, SolverParams::default());
    let t0 = Instant::now();
    let ok = sim.run_to_equilibrium(1e-4, max_steps).unwrap();
    let moved = sim.state.bodies.iter().map(|b| (b.pos - b.pos0).norm()).fold(0.0, f64::max);
    println!(
        "{name}: {} blocks, equilibrium {ok} after {} steps (dt {:.2e} s, {:.2} s), largest displacement {:.3e} m",
        sim.state.bodies.len(),
        sim.state.steps,
        sim.dt(),
        t0.elapsed().as_secs_f64(),
        moved
    );
    assert!(ok, "{name}: no equilibrium at alpha = 0 within {max_steps} steps");
    (sim.state.bodies.len(), sim.state.steps, moved, w.course_height.mean())
}

#[test]
fn cbl_stands_at_alpha_zero() {
    let (_, _, moved, h) = stands("cbl", 200_000);
    assert!(moved < 0.1 * h, "{moved}");
}

#[test]
fn sbl_stands_at_alpha_zero() {
    let (_, _, moved, h) = stands("sbl", 200_000);
    assert!(moved < 0.1 * h, "{moved}");
}

#[test]
fn sbr_stands_at_alpha_zero() {
    let (_, _, moved, h) = stands("sbr", 200_000);
    assert!(moved < 0.1 * h, "{moved}");
}

#[test]
fn full_scale_walls_stand_at_alpha_zero() {
    for name in ["full_scale", "full_scale_continuous", "full_scale_discontinuous"] {
        let (_, _, moved, h) = stands(name, 200_000);
        assert!(moved < 0.1 * h, "{name}: {moved}");
    }
}
