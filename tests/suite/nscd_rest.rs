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
//!   one-sine pulses that cross the block's and a running-bond wall's capacity in both
//!   directions must give the same verdict and the same largest rotation;
//! * the wall's static capacity by the limit analysis: below it, the wall must not move.

use drystone::dem::SolverParams;
use drystone::layout::{BaseSliding, Layout};
use drystone::limit::{limit_tilt, LimitParams};
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

/// What a run under a one-sine pulse did: the largest rocking rotation (rad) of every free
/// block about x, in either sense and each sense apart (positive, negative), whether a
/// block turned past 30°, the steps taken and how many were certified.
struct Pulse {
    peak: f64,
    signed: (f64, f64),
    fell: bool,
    steps: u64,
    certified: u64,
}

/// A run over `t_end` s under a one-sine pulse of amplitude `amp_g` g and period `tp` s.
fn pulse(layout: &Layout, params: NscdParams, amp_g: f64, tp: f64, t_end: f64) -> Pulse {
    let mut sim = NscdSimulation::new(layout, &params).unwrap();
    let a = amp_g * G;
    let (mut peak, mut signed, mut steps) = (0.0f64, (0.0f64, 0.0f64), 0);
    while sim.time() < t_end {
        sim.step(|t| Vec3::new(0.0, if t <= tp { a * (2.0 * PI * t / tp).sin() } else { 0.0 }, 0.0)).unwrap();
        steps += 1;
        for k in 0..sim.bodies().len() {
            let r = sim.rotation_vector(k).x;
            peak = peak.max(r.abs());
            signed = (signed.0.max(r), signed.1.max(-r));
        }
        if peak > 30f64.to_radians() {
            return Pulse { peak, signed, fell: true, steps, certified: sim.certified_steps().0 };
        }
    }
    Pulse { peak, signed, fell: false, steps, certified: sim.certified_steps().0 }
}

/// A block under one-sine pulses whose amplitude crosses its capacity g b/h (both signs of
/// the pulse cross it): the certified run and the fully swept run agree on the verdict and
/// on the largest rotation to 1 %, and the certified run did certify its steps at rest.
#[test]
fn a_rocking_block_is_the_same_with_and_without_the_certificate() {
    let (b, h) = (0.15, 0.6);
    for amp in [0.2, 0.3, 0.5, 1.0] {
        let solve = NscdParams { rest: RestRule::Solve, ..NscdParams::default() };
        let Pulse { peak: solved, fell: fell_s, certified: none, .. } = pulse(&block(b, h, 80.0), solve, amp, 0.4, 1.2);
        let c = pulse(&block(b, h, 80.0), NscdParams::default(), amp, 0.4, 1.2);
        let (certified, fell_c) = (c.peak, c.fell);
        assert_eq!(none, 0);
        assert!(c.certified > 0, "amplitude {amp} g: no step certified");
        assert_eq!(fell_s, fell_c, "amplitude {amp} g: verdicts differ");
        let tol = 0.01 * solved.max(certified) + 1e-6;
        assert!((solved - certified).abs() <= tol, "amplitude {amp} g: peak {certified} rad certified, {solved} swept");
    }
}

/// The running-bond wall (`data/layouts/running_bond_wall.json`, 7 courses, symmetric
/// about its mid-plane y = 0) under a one-sine pulse below its capacity and one just above
/// it, with and without the certificate.
///
/// Below (0.15 g): every step certified and the wall stays exactly where it is, which is
/// the truth, since its static capacity under a base acceleration along y, the tilting
/// table's `λ = tan α` of the limit analysis (an independent solver: a linear program on
/// the rigid blocks, no time stepping), is more than twice the pulse's largest
/// acceleration: a wall whose every load is statically admissible does not move. (This
/// case used to be compared with a run swept at every step, which costs as much as the
/// case above the capacity and only showed that the sweeps hold the wall too.)
///
/// Above (0.45 g: it leaves its rest and rocks a few hundredths of a degree), stepped by
/// the sweeps alone at a fine step (0.25 ms, velocity tolerance 1e-9 g h): the same
/// verdict and largest rotation (to 3 % or 0.01°) with and without the certificate. The
/// sweeps make the two runs comparable step for step. Both directions from one run: the
/// one-sine pulse pushes the wall past its capacity towards +y in its first half and
/// towards −y in its second, and the largest rotation in each sense is compared apart (each
/// is about 0.0217°, the first at 0.105 s, the second at 0.255 s); the pulse of the
/// opposite sign is the mirror image of this one on this symmetric wall, so it is not run
/// again. Not further above its capacity: from 0.5 g this wall's rocking depends on the
/// last digits of every step (its largest rotation after ±0.5 g spans 0.26° to 1.0° between
/// runs whose every step meets the natural-map residual 1e-4 and that differ only in the
/// time step or in the certificate; docs/nscd.md, "A step of motion"), so it would test
/// the wall's sensitivity, not the certificate, which the block above checks into rocking.
#[test]
fn a_wall_under_pulses_is_the_same_with_and_without_the_certificate() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/layouts/running_bond_wall.json");
    let wall = Layout::from_file(&path).unwrap();
    let fine = NscdParams { dt_s: 2.5e-4, tolerance: 1e-9, step_solver: StepSolver::Nsgs, ..NscdParams::default() };
    // Below the capacity.
    let below = 0.15;
    let capacity = limit_tilt(&wall, &SolverParams::default(), &LimitParams::default()).unwrap().load_multiplier;
    assert!(capacity > 2.0 * below, "the wall's capacity {capacity} g by the limit analysis");
    let certified = pulse(&wall, fine, below, 0.3, 0.8);
    assert_eq!(certified.certified, certified.steps, "amplitude {below} g, below the capacity {capacity} g");
    assert!(!certified.fell && certified.peak == 0.0, "amplitude {below} g: it moved by {} rad", certified.peak);
    // Above it.
    let amp = 0.45;
    let close = |sense: &str, solved: f64, certified: f64| {
        let tol = (0.03 * solved.max(certified)).max(0.01f64.to_radians());
        assert!(
            (solved - certified).abs() <= tol,
            "amplitude {amp} g, {sense}: peak {certified} rad certified, {solved} swept"
        );
    };
    let solved = pulse(&wall, NscdParams { rest: RestRule::Solve, ..fine }, amp, 0.3, 0.8);
    let certified = pulse(&wall, fine, amp, 0.3, 0.8);
    assert!(certified.certified > 0, "amplitude {amp} g: no step certified");
    assert!(certified.certified < certified.steps, "amplitude {amp} g: every step certified");
    // It does rock both ways, well above the 0.01° floor of the tolerance.
    let least = solved.signed.0.min(solved.signed.1);
    assert!(least > 0.015f64.to_radians(), "amplitude {amp} g: {:?} rad swept", solved.signed);
    assert_eq!(solved.fell, certified.fell, "amplitude {amp} g: verdicts differ");
    close("either sense", solved.peak, certified.peak);
    close("towards +y", solved.signed.0, certified.signed.0);
    close("towards −y", solved.signed.1, certified.signed.1);
}
