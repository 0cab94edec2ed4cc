//! The rest certificate of the non-smooth solver (`nscd::rest`): a step of a
//! wall at rest is solved by statics where its contacts carry the load inside the reduced
//! Coulomb cones (`tan φ* = sin φ`), and by the sweeps otherwise.
//!
//! References, independent of the code under test:
//!
//! * the static capacity of a block on the table under a base acceleration along y, in
//!   closed form: it tips when `|a| > g b/h` and, with the reduced cone, slides when
//!   `|a| > g sin φ`; the certified range is `g min(b/h, sin φ)` on either side;
//! * the same motion solved with the certificate off (`RestRule::Solve`, every step swept):
//!   one-sine pulses that cross the block's and a 13-box wall's capacity in both directions
//!   must give the same verdict and the same largest rotation.

use drystone::layout::{BaseSliding, Layout};
use drystone::nscd::{NscdParams, NscdSimulation, RestRule, StepSolver};
use drystone::units::STANDARD_GRAVITY as G;
use drystone::verify::{box_vertices, layout_of};
use drystone::Vec3;
use std::f64::consts::PI;

/// A block 0.2 m long (x), `b` wide (y), `h` high (z) on the table, friction `phi_deg`.
fn block(b: f64, h: f64, phi_deg: f64) -> Layout {
    layout_of(vec![box_vertices([0.0, -b / 2.0, 0.0], [0.2, b / 2.0, h])], 1e13, 5e12, phi_deg, BaseSliding::Free)
}

/// Steps `sim` `steps` times under the constant base acceleration `a` (m/s², along y);
/// returns how many steps were certified.
fn hold(sim: &mut NscdSimulation, a: f64, steps: usize) -> usize {
    (0..steps).filter(|_| sim.step(|_| Vec3::new(0.0, a, 0.0)).expect("step").certified).count()
}

/// Below its static capacity (closed form, reduced cone) a block is certified at rest at
/// every step, in both directions, and stays exactly where it is; just above it, the
/// certificate refuses the step and the sweeps take it.
#[test]
fn a_block_is_certified_up_to_its_static_capacity_and_not_beyond() {
    // (b, h, φ): tipping governs (b/h < sin φ), then sliding with the reduced cone.
    for (b, h, phi) in [(0.2f64, 0.4f64, 60.0f64), (0.1, 0.5, 45.0), (0.4, 0.4, 30.0), (0.3, 0.2, 20.0)] {
        let capacity = G * (b / h).min(phi.to_radians().sin());
        for sign in [1.0, -1.0] {
            let mut sim = NscdSimulation::new(&block(b, h, phi), &NscdParams::default()).unwrap();
            let certified = hold(&mut sim, sign * 0.999 * capacity, 50);
            assert_eq!(certified, 50, "b {b} h {h} φ {phi}: {certified} of 50 steps certified at 0.999 of capacity");
            assert_eq!(sim.bodies()[0].pos, sim.bodies()[0].pos0, "the block moved while certified at rest");
            let mut sim = NscdSimulation::new(&block(b, h, phi), &NscdParams::default()).unwrap();
            let certified = hold(&mut sim, sign * 1.01 * capacity, 1);
            assert_eq!(certified, 0, "b {b} h {h} φ {phi}: certified at 1.01 of the capacity {capacity}");
        }
    }
}

/// The largest rocking rotation (rad) of every free block and whether a block turned past
/// 30°, over `t_end` s under a one-sine pulse of amplitude `amp_g` g and period `tp` s.
fn pulse(layout: &Layout, params: NscdParams, amp_g: f64, tp: f64, t_end: f64) -> (f64, bool, u64) {
    let mut sim = NscdSimulation::new(layout, &params).unwrap();
    let a = amp_g * G;
    let mut peak = 0.0f64;
    while sim.time() < t_end {
        sim.step(|t| Vec3::new(0.0, if t <= tp { a * (2.0 * PI * t / tp).sin() } else { 0.0 }, 0.0)).unwrap();
        for k in 0..sim.bodies().len() {
            peak = peak.max(sim.rotation_vector(k).x.abs());
        }
        if peak > 30f64.to_radians() {
            return (peak, true, sim.certified_steps().0);
        }
    }
    (peak, false, sim.certified_steps().0)
}

/// A block under one-sine pulses whose amplitude crosses its capacity g b/h (both signs of
/// the pulse cross it): the certified run and the fully swept run agree on the verdict and
/// on the largest rotation to 1 %, and the certified run did certify its steps at rest.
#[test]
fn a_rocking_block_is_the_same_with_and_without_the_certificate() {
    let (b, h) = (0.15, 0.6);
    for amp in [0.2, 0.3, 0.5, 1.0] {
        let solve = NscdParams { rest: RestRule::Solve, ..NscdParams::default() };
        let (solved, fell_s, none) = pulse(&block(b, h, 80.0), solve, amp, 0.4, 1.2);
        let (certified, fell_c, steps) = pulse(&block(b, h, 80.0), NscdParams::default(), amp, 0.4, 1.2);
        assert_eq!(none, 0);
        assert!(steps > 0, "amplitude {amp} g: no step certified");
        assert_eq!(fell_s, fell_c, "amplitude {amp} g: verdicts differ");
        let tol = 0.01 * solved.max(certified) + 1e-6;
        assert!((solved - certified).abs() <= tol, "amplitude {amp} g: peak {certified} rad certified, {solved} swept");
    }
}

/// The 13-box running-bond wall under pulses below its capacity (0.15 g: every step
/// certified) and just above it in both directions (±0.45 g: it leaves its rest and rocks
/// a few hundredths of a degree), stepped by the sweeps alone at a fine step (0.25 ms,
/// velocity tolerance 1e-9 g h): the same verdict and largest rotation (to 3 % or 0.01°)
/// with and without the certificate. The sweeps make the two runs comparable step for
/// step. Not further above its capacity: from 0.5 g this wall's rocking depends on the last
/// digits of every step (its largest rotation after ±0.5 g spans 0.26° to 1.0° between runs
/// whose every step meets the natural-map residual 1e-4 and that differ only in the time
/// step or in the certificate; docs/nscd.md, "A step of motion"), so it would test the
/// wall's sensitivity, not the certificate, which the block above checks into rocking.
#[test]
fn a_wall_under_pulses_is_the_same_with_and_without_the_certificate() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/layouts/running_bond_wall.json");
    let wall = Layout::from_file(&path).unwrap();
    let fine = NscdParams { dt_s: 2.5e-4, tolerance: 1e-9, step_solver: StepSolver::Nsgs, ..NscdParams::default() };
    for amp in [0.15, 0.45, -0.45] {
        let (solved, fell_s, _) = pulse(&wall, NscdParams { rest: RestRule::Solve, ..fine }, amp, 0.3, 0.8);
        let (certified, fell_c, steps) = pulse(&wall, fine, amp, 0.3, 0.8);
        assert!(steps > 0, "amplitude {amp} g: no step certified");
        assert!(amp.abs() < 0.3 || steps < 3200, "amplitude {amp} g: every step certified");
        assert_eq!(fell_s, fell_c, "amplitude {amp} g: verdicts differ");
        let tol = (0.03 * solved.max(certified)).max(0.01f64.to_radians());
        assert!((solved - certified).abs() <= tol, "amplitude {amp} g: peak {certified} rad certified, {solved} swept");
    }
}
