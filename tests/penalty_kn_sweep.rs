//! The penalty solver approaches the rigid limit monotonically as the joint stiffness
//! grows (issue 39, item 3): a single block b × h = 0.15 × 0.30 m (0.3 m long, φ 60°, so
//! it topples) on the tilting table, Kn from 1e7 to 1e13 Pa/m (Ks = Kn / 2), each
//! bracketed by the penalty tilt at 1/16°, against the exact rigid limit tan α = b / h
//! (26.565°) and the non-smooth solver's bracket of the same block.
//!
//! A block on a no-tension Winkler joint topples before the rigid block does: the joint
//! closes under the downhill edge and the block rotates by θ ∝ Kn^(-1/3) before it loses
//! equilibrium (`common/winkler.rs`, integrated here independently of the library). So,
//! as Kn grows, the penalty brackets must rise, never fall by more than the bracket's
//! width, never end on a step budget, stay below the rigid limit (within the bracket),
//! and close on it at 1e13.

#[path = "common/winkler.rs"]
mod winkler;

use drystone::dem::drivers::nscd::NscdParams;
use drystone::dem::SolverParams;
use drystone::layout::BaseSliding;
use drystone::loading::tilt::{run_tilt, CollapseReason, TiltParams};
use drystone::loading::tilt_nscd::run_tilt_nscd;
use drystone::units::STANDARD_GRAVITY as G;
use drystone::verify::{box_vertices, layout_of, DENSITY};

const RESOLUTION_DEG: f64 = 0.0625;
const B: f64 = 0.15;
const H: f64 = 0.30;

/// The penalty bracket (last stable, first unstable) at joint stiffness `kn`, degrees.
fn penalty_bracket(kn: f64) -> (f64, f64) {
    let l = layout_of(vec![box_vertices([0.0, -B / 2.0, 0.0], [0.3, B / 2.0, H])], kn, kn / 2.0, 60.0, BaseSliding::Free);
    // Ten times the default step budget at Kn ≥ 1e11 (the knife-edge contact of a stiff
    // joint creeps for longer; as `tests/stiffness_range.rs`).
    let base = TiltParams::default().max_steps_per_increment;
    let budget = if kn >= 1e11 { 10 * base } else { base };
    let p = TiltParams { resolution_deg: RESOLUTION_DEG, max_steps_per_increment: budget, ..TiltParams::default() };
    let r = run_tilt(&l, SolverParams::default(), &p).expect("stands at α = 0");
    assert_ne!(r.collapse_reason, Some(CollapseReason::StepBudget), "Kn {kn:e}: a step budget is not a bracket");
    (r.last_stable_deg, r.first_unstable_deg.expect("collapses"))
}

#[test]
fn the_penalty_collapse_tilt_rises_to_the_rigid_limit_as_kn_grows_to_1e13() {
    let rigid = (B / H).atan().to_degrees();
    let l = layout_of(vec![box_vertices([0.0, -B / 2.0, 0.0], [0.3, B / 2.0, H])], 1e13, 5e12, 60.0, BaseSliding::Free);
    let nscd = run_tilt_nscd(&l, &NscdParams::default(), &TiltParams { resolution_deg: RESOLUTION_DEG, ..TiltParams::default() })
        .expect("nscd tilt");
    let nscd_up = nscd.first_unstable_deg.expect("topples");
    assert!(nscd.last_stable_deg <= rigid && rigid <= nscd_up, "nscd [{}, {nscd_up}]", nscd.last_stable_deg);

    let mut previous: Option<(f64, f64)> = None;
    let mut softest = None;
    println!("| Kn (Pa/m) | penalty bracket (°) | Winkler reference (°) | rigid − last stable (°) |");
    for kn in [1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13] {
        let (lo, up) = penalty_bracket(kn);
        let winkler = winkler::block(B, H, DENSITY, G, kn);
        println!("| {kn:.0e} | [{lo:.4}, {up:.4}] | {:.4} | {:.4} |", winkler.alpha_deg, rigid - lo);
        // Below the rigid limit: a finite joint can only lose capacity.
        assert!(lo <= rigid, "Kn {kn:e}: stable at {lo}° above the rigid limit {rigid}°");
        // Monotone: a stiffer joint's bracket does not fall below a softer one's (ties
        // within one bracket width are the bisection's grid).
        if let Some((plo, pup)) = previous {
            assert!(lo >= plo - 1e-9 && up >= pup - 1e-9, "Kn {kn:e}: [{lo}, {up}] below the softer [{plo}, {pup}]");
        }
        previous = Some((lo, up));
        softest.get_or_insert(lo);
    }
    let (lo, up) = previous.expect("swept");
    // Closed on the rigid limit at 1e13, and on the nscd bracket of the same block.
    assert!(lo <= rigid && rigid <= up + 1e-9, "Kn 1e13: [{lo}, {up}] misses the rigid limit {rigid}°");
    assert!((lo - nscd.last_stable_deg).abs() <= RESOLUTION_DEG, "Kn 1e13: {lo}° against nscd {}°", nscd.last_stable_deg);
    // And the sweep is not flat: at 1e7 the loss is several brackets (the joint rotation).
    let soft = softest.expect("swept");
    assert!(rigid - soft > 4.0 * RESOLUTION_DEG, "Kn 1e7: loss {}° is not resolved", rigid - soft);
}
