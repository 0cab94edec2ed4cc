//! The penalty solver against the exact finite-rotation collapse of a block on a
//! no-tension Winkler joint: blocks from squat (b/h = 2) to slender
//! (b/h = 1/4), Kn from 1e6 to 1e8 Pa/m, each tilted to collapse by the tilting-table
//! protocol, its bracket (last stable, first unstable) held against `common/winkler_exact.rs`,
//! the statics of the rotated block derived there independently of the library.
//!
//! Where the joint's shear acts is the one term of order closure/width that the Winkler
//! model leaves open (`common/winkler_exact.rs`, "Limits"): at the block's base (the exact
//! Winkler solution, the lower end) or on the joint's mid-plane, half the closure higher,
//! as the penalty joint applies it (the upper end; it raises α_max by up to 0.51°, at b/h =
//! 1 and Kn 2.5e6 Pa/m), the springs' direction anywhere between the table's normal and
//! the bisector of table and base. So a bracket must
//!
//! - not fire early: its first unstable tilt at or above the exact Winkler collapse, and
//! - not hold late: its last stable tilt at or below the mid-plane collapse,
//!
//! both within `ALLOWANCE_DEG` = 0.01°: an equilibrium is accepted at an unbalanced-force
//! ratio of 1e-4, a residual force of 1e-4 of the weight, the moment of a gravity
//! direction 1e-4 rad (0.006°) away. No case may end on a step budget.
//!
//! Kn 1e6 Pa/m takes blocks of 800 kg/m³ (a layout refuses joints closing by more than
//! 1 % of its height under its own weight, ρ g / Kn ≤ 0.01); the others 2200 kg/m³.
//! `cargo test --release --test suite penalty_exact_winkler:: -- --nocapture` prints the table of
//! BENCHMARKS.md; `-- --ignored` runs the full sweep (more stiffnesses and sizes, and the
//! bracket at 1/128°).

use crate::winkler;
use crate::winkler_exact;

use drystone::dem::SolverParams;
use drystone::layout::BaseSliding;
use drystone::loading::tilt::{CollapseReason, TiltParams};
use drystone::protocol::run_tilt;
use drystone::units::STANDARD_GRAVITY as G;
use drystone::verify::{box_vertices, layout_of};
use winkler_exact::{Block, Interface};

/// The allowance of the module doc, degrees.
const ALLOWANCE_DEG: f64 = 0.01;

/// Density for joints of stiffness `kn`: 800 kg/m³ below Kn 2.2e6 Pa/m, else 2200.
fn density(kn: f64) -> f64 {
    if kn < 2.2e6 {
        800.0
    } else {
        2200.0
    }
}

/// The exact collapse interval (degrees): from the Winkler foundation (springs normal to
/// the table or along the bisector, shear at the base) to the mid-plane shear.
fn exact_interval(blk: &Block) -> (f64, f64) {
    let at = |plane, shear_lever| winkler_exact::collapse(blk, Interface { plane, shear_lever }).alpha_deg;
    let lo = at(0.0, 0.0).min(at(0.5, 0.0));
    let hi = at(0.0, 0.5).max(at(0.5, 0.5));
    (lo, hi)
}

/// Tilts a block b × h (the larger of b, h and 0.3 m long; φ 80°: it topples) on joints
/// of stiffness `kn` (Ks = Kn / 2) to collapse at `resolution` degrees and checks its
/// bracket against the exact interval: the table row, or what is wrong.
fn case(b: f64, h: f64, kn: f64, resolution: f64) -> Result<String, String> {
    let rho = density(kn);
    // Long enough along the wall (x) for the plane section of the reference: a block
    // shorter than its width twists off its narrow closed strip on soft joints before it
    // topples (1 × 0.5 m, 0.3 m long, Kn 1e6 Pa/m: 54.7° against 55.8° at 0.6 m).
    let length = b.max(h).max(0.3);
    let mut l =
        layout_of(vec![box_vertices([0.0, -b / 2.0, 0.0], [length, b / 2.0, h])], 1e9, 5e8, 80.0, BaseSliding::Free);
    l.materials[0].density = rho;
    l.materials[0].kn = kn;
    l.materials[0].ks = kn / 2.0;
    let p = TiltParams { resolution_deg: resolution, ..TiltParams::default() };
    let r = run_tilt(&l, SolverParams::default(), &p).expect("stands at α = 0");
    let name = format!("block {b} x {h} m (b/h {:.2}), Kn {kn:.1e} Pa/m", b / h);
    if r.collapse_reason == Some(CollapseReason::StepBudget) || !r.bracket_reliable {
        return Err(format!("{name}: a step budget is not a bracket"));
    }
    let up = r.first_unstable_deg.ok_or(format!("{name}: does not topple"))?;
    let blk = Block::new(b, h, rho, G, kn);
    let (lo_exact, hi_exact) = exact_interval(&blk);
    if up < lo_exact - ALLOWANCE_DEG {
        return Err(format!(
            "{name}: unstable at {up:.4}° before the exact Winkler collapse {lo_exact:.4}° ({:?})",
            r.collapse_reason
        ));
    }
    if r.last_stable_deg > hi_exact + ALLOWANCE_DEG {
        return Err(format!("{name}: stable at {:.4}° past the mid-plane collapse {hi_exact:.4}°", r.last_stable_deg));
    }
    let theta = winkler_exact::collapse(&blk, Interface::WINKLER).rotation;
    Ok(format!(
        "| {kn:.1e} | {b} × {h} | {:.2} | {lo_exact:.3} | {hi_exact:.3} | [{:.4}, {up:.4}] | {:+.3} | {theta:.3} | {} |",
        b / h,
        r.last_stable_deg,
        up - lo_exact,
        r.collapse_reason.map(CollapseReason::name).unwrap_or("-")
    ))
}

/// Runs the cases, prints the table, and fails with every case that missed.
fn sweep(cases: &[(f64, f64, f64)], resolution: f64) {
    println!("resolution {resolution}°");
    println!("| Kn (Pa/m) | b × h (m) | b/h | exact Winkler (°) | mid-plane shear (°) | bracket (°) | first unstable − exact (°) | θ at collapse (rad) | reason |");
    println!("|---|---|---|---|---|---|---|---|---|");
    let mut missed = Vec::new();
    for &(b, h, kn) in cases {
        match case(b, h, kn, resolution) {
            Ok(row) => println!("{row}"),
            Err(e) => {
                println!("| MISSED: {e} |");
                missed.push(e);
            }
        }
    }
    assert!(missed.is_empty(), "{missed:#?}");
}

/// The four aspect ratios, squat to slender.
const ASPECTS: [(f64, f64); 4] = [(0.5, 0.25), (0.3, 0.3), (0.15, 0.3), (0.1, 0.4)];

/// The reference itself. With springs normal to the block's base and the shear at the
/// base it is the joint of `common/winkler.rs` (integrated there independently, with the
/// closure's slope θ where the exact one is tan θ): the two collapse tilts differ by
/// tan θ − θ ≈ θ³/3 (θ at the fold), to 2 % of it. The springs' direction (normal to the
/// table or to the base) matters to O(θ²) only. As Kn grows the collapse tends to the rigid limit
/// atan(b/h) from below, its loss shrinking as Kn^(-1/3).
#[test]
fn the_exact_reference_has_the_small_rotation_form_and_the_rigid_limit() {
    for (b, h) in ASPECTS {
        let rigid = (b / h).atan().to_degrees();
        for kn in [2.5e6, 1e8, 1e10] {
            let blk = Block::new(b, h, 2200.0, G, kn);
            let body = winkler_exact::collapse(&blk, Interface::BODY);
            let small = winkler::block(b, h, 2200.0, G, kn);
            let th = body.rotation;
            let slope = (th.tan() - th).to_degrees();
            assert!(
                (body.alpha_deg - small.alpha_deg - slope).abs() <= 0.02 * slope + 1e-6,
                "{b} x {h}, Kn {kn:e}: {} against the small-rotation {} (tan θ − θ = {slope}°)",
                body.alpha_deg,
                small.alpha_deg
            );
            let table = winkler_exact::collapse(&blk, Interface::WINKLER);
            assert!((table.alpha_deg - body.alpha_deg).abs() <= 10.0 * th * th, "{b} x {h}, Kn {kn:e}");
            assert!(table.alpha_deg < rigid);
        }
        let loss =
            |kn: f64| rigid - winkler_exact::collapse(&Block::new(b, h, 2200.0, G, kn), Interface::WINKLER).alpha_deg;
        for kn in [1e9, 1e11] {
            let ratio = loss(kn) / loss(kn * 1e3);
            assert!((ratio - 10.0).abs() < 1.0, "{b} x {h}: loss ratio per 1e3 in Kn {ratio}");
        }
        assert!(loss(1e13) > 0.0 && loss(1e13) < 0.1, "{b} x {h}: {}° below the rigid limit at Kn 1e13", loss(1e13));
    }
}

/// Squat to slender, Kn 1e6 to 1e8 Pa/m, at the resolution 1/16°.
#[test]
fn brackets_hold_the_exact_winkler_collapse_from_squat_to_slender_kn_1e6_to_1e8() {
    let mut cases = Vec::new();
    for kn in [1e6, 2.5e6, 1e7, 1e8] {
        for (b, h) in ASPECTS {
            cases.push((b, h, kn));
        }
    }
    sweep(&cases, 0.0625);
}

/// More stiffnesses and sizes, and the bracket narrowed to 1/128°.
#[test]
#[ignore = "full sweep: about a minute in release mode"]
fn full_sweep_of_aspect_and_stiffness() {
    let mut cases = Vec::new();
    for kn in [1e6, 2.5e6, 5e6, 1e7, 3e7, 1e8] {
        for (b, h) in ASPECTS.into_iter().chain([(1.0, 0.5), (0.5, 0.5), (1.0, 1.0), (0.1125, 0.375), (0.05, 0.2)]) {
            cases.push((b, h, kn));
        }
    }
    sweep(&cases, 0.0625);
    sweep(&cases, 1.0 / 128.0);
}
