//! The implicit relaxation of the static increments (`dem::drivers::implicit`): it finds the
//! equilibrium dynamic relaxation finds, in a fraction of the work, and it changes the
//! cost of a tilting-table test, not its result.

use drystone::closure::{Hyperbolic, Seating};
use drystone::dem::drivers::implicit::{implicit_relaxation, ImplicitSolve, Solved};
use drystone::dem::RunToEquilibrium;
use drystone::dem::{Simulation, SolverParams};
use drystone::layout::{Closure, Layout};
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use std::path::Path;

use crate::common;

fn layout(name: &str) -> Layout {
    Layout::from_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("data/layouts").join(name)).unwrap()
}

/// Settled under gravity at α = 0, then tilted to `alpha_deg` (not relaxed).
fn settled_and_tilted(l: &Layout, alpha_deg: f64) -> Simulation {
    let mut sim = Simulation::new(l, SolverParams::default());
    assert!(sim.run_to_equilibrium(1e-6, 200_000).unwrap());
    sim.set_tilt(alpha_deg.to_radians());
    sim
}

/// The implicit iteration and dynamic relaxation (to a ratio 100 times tighter) from the
/// same tilted state: every block's out-of-plane (y) motion the same to within 1 % of the
/// largest motion; the implicit state a true equilibrium (dynamic relaxation from it to the
/// tighter ratio moves no block more than 1 % of the largest motion); and fewer iterations
/// than a tenth of the relaxation's steps. (The vertical position of a block wedged by
/// friction between its neighbours depends on the path and is not compared.)
fn agrees_with_dynamic_relaxation(l: &Layout, alpha_deg: f64) {
    let base = settled_and_tilted(l, alpha_deg);
    let mut implicit = base.clone();
    let out = implicit_relaxation(&mut implicit, 1e-6, &ImplicitSolve::default(), |_| None::<()>);
    let Solved::Equilibrium(iterations) = out else { panic!("no equilibrium: {out:?}") };
    assert!(implicit.stats().unbalanced_ratio < 1e-6);
    let mut dr = base.clone();
    let before = dr.state.steps;
    assert!(dr.run_to_equilibrium(1e-8, 2_000_000).unwrap());
    let steps = dr.state.steps - before;
    let n = base.state.bodies.len();
    let motion = |s: &Simulation, k: usize| s.state.bodies[k].pos - base.state.bodies[k].pos;
    let largest = (0..n).map(|k| motion(&dr, k).norm()).fold(0.0, f64::max);
    assert!(largest > 1e-7, "the tilt moves the wall: {largest} m");
    for k in 0..n {
        let (a, b) = (motion(&implicit, k).y, motion(&dr, k).y);
        assert!((a - b).abs() <= 0.01 * largest, "block {k}: y {a} vs {b} m (largest {largest} m)");
    }
    let mut confirmed = implicit.clone();
    assert!(confirmed.run_to_equilibrium(1e-8, 2_000_000).unwrap());
    for k in 0..n {
        let d = (confirmed.state.bodies[k].pos - implicit.state.bodies[k].pos).norm();
        assert!(d <= 0.01 * largest, "block {k} moved {d} m from the implicit equilibrium (largest {largest} m)");
    }
    assert!(u64::from(iterations) * 10 < steps, "{iterations} iterations against {steps} steps");
}

/// The 24-block running-bond wall tilted at once from 0° to 6° (slip at the joints of the
/// top course included).
#[test]
fn the_implicit_iteration_finds_the_equilibrium_dynamic_relaxation_finds() {
    agrees_with_dynamic_relaxation(&layout("running_bond_wall.json"), 6.0);
}

/// A hyperbolic closure law (the tangent stiffens with closure) and seating beds (the
/// tangent starts at zero): the preconditioner is no longer the tangent, and the iteration
/// still reaches the relaxed state.
#[test]
fn the_implicit_iteration_follows_nonlinear_closure_laws() {
    for closure in
        [Closure::Hyperbolic(Hyperbolic { max_closure_m: 2e-4 }), Closure::Seating(Seating { max_gap_m: 1e-4 })]
    {
        let mut l = layout("running_bond_wall.json");
        for m in &mut l.materials {
            m.closure = closure;
        }
        agrees_with_dynamic_relaxation(&l, 4.0);
    }
}

/// The 0.1125 × 0.375 m block (toppling limit atan(b/h) = 16.7°) tilted to 25° has no
/// equilibrium: the iteration never reports one, and a collapse check (the block moved a
/// twentieth of its width) stops it.
#[test]
fn the_implicit_iteration_reports_no_false_equilibrium() {
    let l = layout("single_block.json");
    let base = settled_and_tilted(&l, 25.0);
    let mut sim = base.clone();
    let out = implicit_relaxation(&mut sim, 1e-4, &ImplicitSolve::default(), |_| None::<()>);
    assert!(matches!(out, Solved::Unsolved(..)), "{out:?}");
    let mut sim = base.clone();
    let x0 = base.state.bodies[0].pos;
    let out = implicit_relaxation(&mut sim, 1e-4, &ImplicitSolve::default(), |s| {
        ((s.state.bodies[0].pos - x0).norm() > 0.1125 / 20.0).then_some("moved")
    });
    assert!(matches!(out, Solved::Stopped("moved", _)), "{out:?}");
}

/// The tilting-table test of the running-bond wall with and without the implicit
/// relaxation: the collapse angle within one bracket, the displacement of every stable
/// increment up to 80 % of it within 2 % of the largest, and under a fifth of the
/// relaxation steps.
#[test]
fn implicit_relaxation_changes_the_cost_not_the_result() {
    let l = layout("running_bond_wall.json");
    let params = TiltParams::default();
    assert!(params.implicit);
    let with = run_tilt(&l, SolverParams::default(), &params).unwrap();
    let without = run_tilt(&l, SolverParams::default(), &TiltParams { implicit: false, ..params }).unwrap();
    common::assert_same_tilt_result(&with, &without, params.resolution_deg);
    assert!(with.iterations > 0 && without.iterations == 0);
    assert!(
        with.steps * 5 < without.steps,
        "{} steps with the implicit relaxation, {} without",
        with.steps,
        without.steps
    );
}
