//! The tilting table at the rigid limit by non-smooth contact dynamics
//! (`loading::tilt_nscd::run_tilt_nscd`) against the exact rigid-block limits (closed forms
//! computed here) and LMGC90's bisections of the same layouts
//! (`data/lmgc90_rigid_limits.csv`, made by `scripts/lmgc90/rigid_limits.py`).

use drystone::layout::{BaseSliding, Layout};
use drystone::loading::tilt::{MechanismKind, TiltError, TiltParams, TiltResult};
use drystone::loading::tilt_nscd::run_tilt_nscd;
use drystone::nscd::{NscdError, NscdParams};
use drystone::verify::{box_vertices, layout_of};
use std::path::Path;

fn tilt() -> TiltParams {
    TiltParams { resolution_deg: 0.05, ..TiltParams::default() }
}

fn run(layout: &Layout) -> TiltResult {
    run_tilt_nscd(layout, &NscdParams::default(), &tilt()).expect("tilt")
}

fn file(p: &str) -> Layout {
    Layout::from_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join(p)).expect("layout")
}

/// (last stable, first unstable) of LMGC90 for a case of the table, degrees.
fn lmgc90(case: &str) -> (f64, f64) {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("data/lmgc90_rigid_limits.csv"))
        .expect("table");
    let row: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').collect())
        .find(|r: &Vec<&str>| r[0] == case)
        .unwrap_or_else(|| panic!("no row {case}"));
    (row[2].parse().unwrap(), row[3].parse().unwrap())
}

/// The bracket holds the exact limit (degrees) and is at most 0.05° wide.
fn brackets(name: &str, r: &TiltResult, exact: f64) {
    let up = r.first_unstable_deg.unwrap_or_else(|| panic!("{name}: stood to the largest tilt"));
    assert!(up - r.last_stable_deg <= 0.05 + 1e-9, "{name}: bracket [{}, {up}]", r.last_stable_deg);
    assert!(
        r.last_stable_deg <= exact && exact <= up,
        "{name}: bracket [{:.4}, {up:.4}] misses the exact rigid limit {exact:.4}°",
        r.last_stable_deg
    );
}

/// The layouts LMGC90 bisected: each bracket holds the closed form, and each end lies
/// within 0.05° of LMGC90's.
#[test]
fn the_rigid_layouts_bracket_their_exact_limits_within_0_05_deg_of_lmgc90() {
    let cases = [
        ("single_block", "data/layouts/rigid/single_block.json", 0.5f64.atan(), "table/b0"),
        ("offset_stack", "data/layouts/rigid/offset_stack.json", (0.03f64 / 0.075).atan(), "b0/b1"),
        ("running_bond_13", "data/layouts/rigid/running_bond_13.json", (1.0f64 / 3.0).atan(), "table/c0b0"),
    ];
    for (case, path, exact, joint) in cases {
        let r = run(&file(path));
        brackets(case, &r, exact.to_degrees());
        let (lo, hi) = lmgc90(case);
        let up = r.first_unstable_deg.unwrap();
        assert!(
            (r.last_stable_deg - lo).abs() <= 0.05 && (up - hi).abs() <= 0.05,
            "{case}: nscd [{:.4}, {up:.4}], LMGC90 [{lo}, {hi}]",
            r.last_stable_deg
        );
        assert_eq!(r.mechanism.kind, MechanismKind::Toppling, "{case}: {:?}", r.mechanism);
        assert_eq!(r.mechanism.joint, joint, "{case}: {:?}", r.mechanism);
    }
}

/// Single blocks b × h from 5 cm to 1 m topple at tan α = b/h; a squat block slides at
/// tan α = tan φ; symmetric trapezoids (base B, top T, height H) topple about their
/// downhill base edge, tan α = 3B(B + T) / (2H(B + 2T)) (the centroid's lever over its
/// height).
#[test]
fn blocks_trapezoids_and_sliding_blocks_bracket_their_closed_forms() {
    for (b, h) in [(0.05, 0.15), (0.1, 0.4), (0.3, 0.5), (0.5, 1.0), (1.0, 1.5)] {
        let l =
            layout_of(vec![box_vertices([0.0, -b / 2.0, 0.0], [0.3, b / 2.0, h])], 1e13, 5e12, 60.0, BaseSliding::Free);
        let r = run(&l);
        brackets(&format!("box {b} × {h}"), &r, (b / h).atan().to_degrees());
        assert_eq!(r.mechanism.kind, MechanismKind::Toppling);
    }
    for phi in [15.0f64, 25.0, 35.0] {
        let l = layout_of(vec![box_vertices([0.0, -0.2, 0.0], [0.3, 0.2, 0.1])], 1e13, 5e12, phi, BaseSliding::Free);
        let r = run(&l);
        brackets(&format!("sliding φ {phi}"), &r, phi);
        assert_eq!(r.mechanism.kind, MechanismKind::Sliding);
    }
    for (bb, tt, hh) in [(0.15, 0.077, 0.375), (0.3, 0.2, 0.5), (0.6, 0.3, 1.0)] {
        let l = layout_of(vec![drystone::verify::trapezoid_block(bb, tt, hh)], 1e13, 5e12, 60.0, BaseSliding::Free);
        // The centroid of the trapezoid section: height ȳ = H (B + 2T) / (3 (B + T)) over
        // the base; its lever to the downhill base edge is B/2.
        let zc = hh * (bb + 2.0 * tt) / (3.0 * (bb + tt));
        brackets(&format!("trapezoid {bb}/{tt}/{hh}"), &run(&l), (0.5 * bb / zc).atan().to_degrees());
    }
}

/// Two blocks b × h, the top one offset downhill by e: the interface governs
/// (tan α = (b − 2e)/h) when e > b/3, the base (tan α = (b − e)/(2h)) when e < b/3.
#[test]
fn an_offset_stack_fails_at_the_interface_or_the_base_as_its_offset_says() {
    let (b, h) = (0.15, 0.075);
    for (e, joint) in [(0.06, "b0/b1"), (0.02, "table/b0")] {
        let l = layout_of(
            vec![
                box_vertices([0.0, -b / 2.0, 0.0], [0.3, b / 2.0, h]),
                box_vertices([0.0, -b / 2.0 + e, h], [0.3, b / 2.0 + e, 2.0 * h]),
            ],
            1e13,
            5e12,
            60.0,
            BaseSliding::Free,
        );
        let exact = ((b - 2.0 * e) / h).atan().min(((b - e) / (2.0 * h)).atan());
        let r = run(&l);
        brackets(&format!("offset {e}"), &r, exact.to_degrees());
        assert_eq!(r.mechanism.joint, joint, "offset {e}: {:?}", r.mechanism);
    }
}

/// The same test twice gives the same result bit for bit (the wall-clock time aside).
#[test]
fn the_rigid_limit_is_deterministic() {
    let l = file("data/layouts/rigid/offset_stack.json");
    let mut a = run(&l);
    let mut b = run(&l);
    a.wall_time_s = 0.0;
    b.wall_time_s = 0.0;
    assert_eq!(serde_json::to_string(&a).unwrap(), serde_json::to_string(&b).unwrap());
}

/// A joint with cohesion is refused, naming the joint; a parameter out of range or an
/// unknown key is refused, naming the key.
#[test]
fn cohesion_and_bad_parameters_are_refused_by_name() {
    let mut l = file("data/layouts/rigid/single_block.json");
    l.materials[0].cohesion = 1000.0;
    let e = run_tilt_nscd(&l, &NscdParams::default(), &tilt()).unwrap_err();
    assert!(matches!(e, TiltError::Nscd(NscdError::Cohesion { .. })), "{e:?}");
    assert!(e.to_string().contains("table/b0") && e.to_string().contains("cohesion"), "{e}");
    let l = file("data/layouts/rigid/single_block.json");
    let e = run_tilt_nscd(&l, &NscdParams { theta: 0.3, ..NscdParams::default() }, &tilt()).unwrap_err();
    assert!(e.to_string().contains("theta"), "{e}");
    let e = serde_json::from_str::<NscdParams>(r#"{"dt_s": 1e-3, "thetta": 0.5}"#).unwrap_err();
    assert!(e.to_string().contains("thetta"), "{e}");
    let p: NscdParams = serde_json::from_str(r#"{"restitution": 0.5}"#).unwrap();
    assert_eq!(p, NscdParams { restitution: 0.5, ..NscdParams::default() });
}

/// The rigid pushover of a block b × h (0.3 m long) under a uniform pressure p on its
/// −y face: it topples when p l h · h/2 = W b/2, or slides when p l h = μ W, whichever
/// multiplier of p is smaller; the bracket of λ holds it to 0.5 %.
#[test]
fn a_pushed_block_topples_or_slides_at_its_load_multiplier() {
    use drystone::loading::lateral::LateralParams;
    use drystone::loading::lateral_nscd::run_lateral_nscd;
    let (l, p) = (0.3, 1000.0);
    for (b, h, phi) in [(0.15f64, 0.3f64, 60.0f64), (0.3, 0.1, 20.0)] {
        let layout =
            layout_of(vec![box_vertices([0.0, -b / 2.0, 0.0], [l, b / 2.0, h])], 1e13, 5e12, phi, BaseSliding::Free);
        let w = drystone::verify::DENSITY * b * h * l * layout.gravity;
        let exact = (w * b / (p * l * h * h)).min(phi.to_radians().tan() * w / (p * l * h));
        let lat = LateralParams {
            pressure_base_pa: p,
            pressure_top_pa: p,
            pushover_resolution: Some(5e-3),
            ..LateralParams::default()
        };
        let r = run_lateral_nscd(&layout, &NscdParams::default(), &lat).expect("pushover");
        let up_ = r.lambda_unstable.expect("collapses");
        assert!(
            up_ - r.lambda_stable <= 5e-3 * up_,
            "the bracket of the resolution given: [{}, {up_}]",
            r.lambda_stable
        );
        let up = r.lambda_unstable.expect("collapses");
        assert!(r.lambda_stable <= exact && exact <= up, "{b} × {h}: λ [{}, {up}], exact {exact}", r.lambda_stable);
        assert!((r.resultant_n.y - p * l * h).abs() < 1e-9 * p * l * h, "{:?}", r.resultant_n);
    }
}
