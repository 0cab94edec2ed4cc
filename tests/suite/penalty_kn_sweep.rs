//! The penalty solver approaches the rigid limit monotonically as the joint stiffness
//! grows: a single block b × h = 0.15 × 0.30 m (0.3 m long, φ 60°, so
//! it topples) on the tilting table, Kn from 1e7 to 1e13 Pa/m (Ks = Kn / 2), each
//! bracketed by the penalty tilt at 1/16°, against the exact rigid limit tan α = b / h
//! (26.565°) and the non-smooth solver's bracket of the same block.
//!
//! A block on a no-tension Winkler joint topples before the rigid block does: the joint
//! closes under the downhill edge and the block rotates by θ before it loses equilibrium,
//! a loss that shrinks as Kn^(-1/3) (`common/winkler.rs`, integrated here independently of
//! the library: 9.3° at 1e7 Pa/m, 0.09° at 1e13). So, as Kn grows, the penalty brackets
//! must rise, never fall, never end on a step budget, hold the Winkler reference (within
//! the allowance of `tests/suite/stiffness_range.rs`, `0.01° + 5°·θ/rad`, for the terms of order
//! θ it leaves out), their distance to the rigid limit shrinking at every decade, to the
//! Winkler loss alone at 1e13, where the non-smooth solver's bracket holds the rigid limit.

use crate::winkler;

use drystone::dem::{PenaltyParams, SolverParams};
use drystone::layout::BaseSliding;
use drystone::loading::tilt::{CollapseReason, TiltParams};
use drystone::loading::tilt_nscd::run_tilt_nscd;
use drystone::nscd::NscdParams;
use drystone::protocol::run_tilt;
use drystone::units::STANDARD_GRAVITY as G;
use drystone::verify::{box_vertices, layout_of, DENSITY};

const RESOLUTION_DEG: f64 = 0.0625;
const B: f64 = 0.15;
const H: f64 = 0.30;

/// The penalty bracket (last stable, first unstable) at joint stiffness `kn`, degrees.
fn penalty_bracket(kn: f64) -> (f64, f64) {
    let l =
        layout_of(vec![box_vertices([0.0, -B / 2.0, 0.0], [0.3, B / 2.0, H])], kn, kn / 2.0, 60.0, BaseSliding::Free);
    // Ten times the default step budget at Kn ≥ 1e11 (the knife-edge contact of a stiff
    // joint creeps for longer; as `tests/suite/stiffness_range.rs`).
    let base = PenaltyParams::default().max_steps;
    let budget = if kn >= 1e11 { 10 * base } else { base };
    let p = TiltParams { resolution_deg: RESOLUTION_DEG, ..TiltParams::default() };
    let solver = SolverParams {
        penalty: PenaltyParams { max_steps: budget, ..PenaltyParams::default() },
        ..SolverParams::default()
    };
    let r = run_tilt(&l, solver, &p).expect("stands at α = 0");
    assert_ne!(r.collapse_reason, Some(CollapseReason::StepBudget), "Kn {kn:e}: a step budget is not a bracket");
    (r.last_stable_deg, r.first_unstable_deg.expect("collapses"))
}

#[test]
fn the_penalty_collapse_tilt_rises_towards_the_rigid_limit_as_kn_grows_to_1e13() {
    let rigid = (B / H).atan().to_degrees();
    let l = layout_of(vec![box_vertices([0.0, -B / 2.0, 0.0], [0.3, B / 2.0, H])], 1e13, 5e12, 60.0, BaseSliding::Free);
    let nscd = run_tilt_nscd(
        &l,
        &NscdParams::default(),
        &TiltParams { resolution_deg: RESOLUTION_DEG, ..TiltParams::default() },
    )
    .expect("nscd tilt");
    let nscd_up = nscd.first_unstable_deg.expect("topples");
    assert!(nscd.last_stable_deg <= rigid && rigid <= nscd_up, "nscd [{}, {nscd_up}]", nscd.last_stable_deg);

    let mut previous: Option<(f64, f64)> = None;
    let mut softest = None;
    let mut last_loss = f64::INFINITY;
    println!("| Kn (Pa/m) | penalty bracket (°) | Winkler reference (°) | rigid − last stable (°) |");
    for kn in [1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13] {
        let (lo, up) = penalty_bracket(kn);
        let winkler = winkler::block(B, H, DENSITY, G, kn);
        println!("| {kn:.0e} | [{lo:.4}, {up:.4}] | {:.4} | {:.4} |", winkler.alpha_deg, rigid - lo);
        // Below the rigid limit: a finite joint can only lose capacity.
        assert!(lo <= rigid, "Kn {kn:e}: stable at {lo}° above the rigid limit {rigid}°");
        // The Winkler collapse of the same block, within the allowance.
        let tol = 0.01 + 5.0 * winkler.rotation;
        assert!(
            lo <= winkler.alpha_deg + tol && up >= winkler.alpha_deg - tol,
            "Kn {kn:e}: [{lo}, {up}] misses the Winkler collapse {:.4}° ± {tol:.4}°",
            winkler.alpha_deg
        );
        // Monotone, and closer to the rigid limit at every decade.
        if let Some((plo, pup)) = previous {
            assert!(lo >= plo - 1e-9 && up >= pup - 1e-9, "Kn {kn:e}: [{lo}, {up}] below the softer [{plo}, {pup}]");
            assert!(rigid - lo < rigid - plo, "Kn {kn:e}: no closer to the rigid limit than at Kn / 10");
        }
        previous = Some((lo, up));
        softest.get_or_insert(lo);
        last_loss = rigid - winkler.alpha_deg + tol;
    }
    let (lo, up) = previous.expect("swept");
    // At 1e13 what separates the penalty bracket from the rigid limit (and the nscd
    // bracket) is the Winkler loss of the finite joint alone.
    assert!(rigid - up <= last_loss, "Kn 1e13: [{lo}, {up}] is {}° below the rigid limit", rigid - up);
    assert!(
        nscd.last_stable_deg - up <= last_loss,
        "Kn 1e13: [{lo}, {up}] is {}° below the nscd bracket",
        nscd.last_stable_deg - up
    );
    let soft = softest.expect("swept");
    assert!(rigid - soft > 4.0 * RESOLUTION_DEG, "Kn 1e7: loss {}° is not resolved", rigid - soft);
}
