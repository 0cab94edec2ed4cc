//! Contact detection keeps the patch of a pair that has barely moved relative to it
//! (`SolverParams::patch_reuse_fraction`): the nodes of a patch are material points of its
//! two bodies, so a kept patch moves with the pair, and keeping it must change where the
//! wall ends, not only how fast it gets there. Checked against rebuilding every patch at
//! every re-detection (`patch_reuse_fraction = 0`, the detection of drystone 0.2), on the
//! 24-block running-bond wall as built and with every edge rounded by 5 mm (26-face
//! stones, where detection dominates the cost).

use drystone::dem::SolverParams;
use drystone::layout::Layout;
use drystone::loading::tilt::TiltParams;
use drystone::protocol::run_tilt;
use std::path::Path;

use crate::common;

fn wall() -> Layout {
    Layout::from_file(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/layouts/running_bond_wall.json"))).unwrap()
}

fn compare(l: &Layout) {
    let params = TiltParams { step_deg: 1.0, resolution_deg: 0.25, ..TiltParams::default() };
    let rebuilt = SolverParams { patch_reuse_fraction: 0.0, ..SolverParams::default() };
    let reference = run_tilt(l, rebuilt, &params).unwrap();
    for fraction in [0.1, 1.0] {
        let kept = SolverParams { patch_reuse_fraction: fraction, ..SolverParams::default() };
        let r = run_tilt(l, kept, &params).unwrap();
        // The same bracket within one resolution; displacements up to 80 % of the
        // collapse angle within 2 % of the largest (equilibria to the same tolerance).
        let limit = common::assert_same_tilt_result(&r, &reference, params.resolution_deg);
        assert!(limit > 0.0, "fraction {fraction}");
    }
}

#[test]
fn kept_patches_leave_the_collapse_and_the_displacements_of_a_wall_as_built() {
    compare(&wall());
}

#[test]
fn kept_patches_leave_the_collapse_and_the_displacements_of_a_wall_of_rounded_stones() {
    let mut l = wall();
    drystone::effects::geometry::round_edges(&mut l, 0.005).unwrap();
    compare(&l);
}

#[test]
fn the_reuse_fraction_is_range_checked() {
    for bad in [-0.1, 1.5, f64::NAN] {
        let p = SolverParams { patch_reuse_fraction: bad, ..SolverParams::default() };
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains("patch_reuse_fraction"), "{e}");
    }
}
