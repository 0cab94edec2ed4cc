//! drystone at high joint stiffness against the rigid-block collapse tilts LMGC90 finds for
//! the same layouts (`data/lmgc90_rigid_limits.csv`, made by
//! `scripts/lmgc90/rigid_limits.py`; non-smooth contact dynamics with hard contacts).
//!
//! A no-tension elastic joint tips before the rigid limit by a loss that shrinks as
//! Kn^(-1/3). Each case runs drystone at Kn 1e11 Pa/m and requires its bracket to lie
//! below LMGC90's (never above the rigid limit, within 0.05°) and above it by no more than
//! the Winkler loss of the governing joint at that Kn (from the collapse of a block on a
//! Winkler joint, `common/winkler.rs`) plus 0.05°.

use crate::winkler;

use drystone::dem::SolverParams;
use drystone::layout::Layout;
use drystone::loading::tilt::{CollapseReason, TiltParams};
use drystone::protocol::run_tilt;
use drystone::units::STANDARD_GRAVITY as G;
use std::path::Path;

const KN: f64 = 1e11;

/// (last stable, first unstable) of LMGC90 for a case of the table, degrees.
fn lmgc90(case: &str) -> (f64, f64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/lmgc90_rigid_limits.csv");
    let text = std::fs::read_to_string(path).expect("table");
    let row = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|r| r[0] == case)
        .unwrap_or_else(|| panic!("no row {case}"));
    (row[2].parse().unwrap(), row[3].parse().unwrap())
}

fn check(case: &str, layout: &str, loss_deg: f64) {
    let (lo, hi) = lmgc90(case);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(layout);
    let mut l = Layout::from_file(&path).expect("layout");
    for m in &mut l.materials {
        m.kn = KN;
        m.ks = KN / 2.0;
    }
    let p = TiltParams { resolution_deg: 0.0625, ..TiltParams::default() };
    let r = run_tilt(&l, SolverParams::default(), &p).expect("stands");
    let up = r.first_unstable_deg.expect("collapses");
    assert_ne!(r.collapse_reason, Some(CollapseReason::StepBudget), "{case}: step budget at {up}°");
    assert!(r.last_stable_deg <= hi + 0.05, "{case}: stable at {}° above LMGC90's [{lo}, {hi}]", r.last_stable_deg);
    assert!(
        up >= lo - loss_deg - 0.05,
        "{case}: unstable at {up}°, LMGC90 stable to {lo}°, more than the Winkler loss {loss_deg:.3}° below"
    );
}

/// Loss (degrees) of a block `b × h` on a Winkler joint of stiffness KN below atan(b/h).
fn block_loss(b: f64, h: f64, rho: f64) -> f64 {
    (b / h).atan().to_degrees() - winkler::block(b, h, rho, G, KN).alpha_deg
}

#[test]
fn a_single_block_collapses_within_the_winkler_loss_below_lmgc90() {
    check("single_block", "data/layouts/rigid/single_block.json", block_loss(0.15, 0.30, 2500.0));
}

#[test]
fn an_offset_stack_collapses_at_its_interface_within_the_winkler_loss_below_lmgc90() {
    let (b, h, e) = (0.15f64, 0.075f64, 0.06f64);
    let rigid = ((b - 2.0 * e) / h).atan().to_degrees();
    let loss = rigid - winkler::offset_stack(b, h, e, 2500.0, G, KN, KN / 2.0).alpha_deg;
    check("offset_stack", "data/layouts/rigid/offset_stack.json", loss);
}

#[test]
fn a_running_bond_wall_of_13_boxes_collapses_within_the_winkler_loss_below_lmgc90() {
    // The wall overturns as one body about its base edge: t/H with t = 0.1 m, H = 0.3 m.
    check("running_bond_13", "data/layouts/rigid/running_bond_13.json", block_loss(0.1, 0.3, 2500.0));
}
