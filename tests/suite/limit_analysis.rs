//! Limit analysis (`drystone::limit`) against closed forms of rigid blocks on the tilting
//! table (tan α = b/h, the offset stack's two joints, α = φ for sliding,
//! the trapezoid 3B(B+T)/(2H(B+2T)), the 13-box wall's t/H), each within 0.01°, and against
//! LMGC90's rigid-limit brackets (`data/lmgc90_rigid_limits.csv`, within ± 0.05°). Every
//! expected value is computed here from the geometry, never by the code under test.

use drystone::dem::SolverParams;
use drystone::layout::{BaseSliding, Layout};
use drystone::limit::{limit_lateral, limit_tilt, FlowRule, JointMode, LimitError, LimitParams, LimitResult};
use drystone::loading::lateral::LateralParams;
use drystone::loading::mechanism::MechanismKind;
use drystone::verify::{box_vertices, layout_of, trapezoid_block};
use std::path::Path;

const KN: f64 = 1e9;

fn tilt(l: &Layout) -> LimitResult {
    limit_tilt(l, &SolverParams::default(), &LimitParams::default()).expect("limit analysis")
}

fn deg(r: &LimitResult) -> f64 {
    r.collapse_angle_deg.expect("tilt gives an angle")
}

fn assert_deg(case: &str, got: f64, want: f64) {
    assert!((got - want).abs() < 0.01, "{case}: {got:.5}° against the closed form {want:.5}°");
}

/// A box of width `b` (y, centred on `y0`), height `h` from `z0`, length 0.3 m (x).
fn block(b: f64, h: f64, y0: f64, z0: f64) -> Vec<[f64; 3]> {
    box_vertices([0.0, y0 - b / 2.0, z0], [0.3, y0 + b / 2.0, z0 + h])
}

#[test]
fn single_blocks_tip_at_atan_b_over_h() {
    for (b, h) in [(0.15, 0.30), (0.10, 0.30), (0.20, 0.45), (0.05, 0.40), (0.30, 0.50)] {
        let l = layout_of(vec![block(b, h, 0.0, 0.0)], KN, KN / 2.0, 40.0, BaseSliding::Free);
        let r = tilt(&l);
        assert_deg(&format!("block {b} x {h}"), deg(&r), (b / h).atan().to_degrees());
        assert_eq!(r.governing, FlowRule::Associative, "a toppling block needs no correction");
        assert_eq!(r.mechanism.kind, MechanismKind::Toppling);
        assert_eq!(r.mechanism.joint, "table/b0");
        assert_eq!(r.joints.len(), 1);
        assert_eq!(r.joints[0].mode, JointMode::Hinge, "{:?}", r.joints);
        // The block turns about its downhill toe (+y, z = 0): its top goes to +y (a negative
        // rotation about x) and its centroid rises, v = ω × (c − toe).
        let v = &r.velocities[0];
        assert!(v.rotation.x < 0.0 && v.translation.y > 0.0 && v.translation.z > 0.0, "{v:?}");
        let arm = nalgebra::Vector3::new(0.0, -b / 2.0, h / 2.0);
        assert!((v.translation - v.rotation.cross(&arm)).norm() < 1e-6 * v.translation.norm(), "{v:?}");
    }
}

#[test]
fn offset_stacks_fail_at_the_interface_or_the_base_whichever_is_lower() {
    // Two identical blocks b × h, the top one offset by e downhill:
    // interface tan α = (b − 2e)/h, base tan α = (b − e)/(2h).
    for (b, h, e) in [(0.15, 0.075, 0.06), (0.15, 0.30, 0.01), (0.2, 0.1, 0.05), (0.2, 0.1, 0.06)] {
        let l = layout_of(vec![block(b, h, 0.0, 0.0), block(b, h, e, h)], KN, KN / 2.0, 40.0, BaseSliding::Free);
        let r = tilt(&l);
        let interface = ((b - 2.0 * e) / h).atan().to_degrees();
        let base = ((b - e) / (2.0 * h)).atan().to_degrees();
        assert_deg(&format!("offset stack {b} {h} {e}"), deg(&r), interface.min(base));
        let governs = if interface < base { "b0/b1" } else { "table/b0" };
        assert_eq!(r.mechanism.joint, governs, "{:?}", r.joints);
        let moving = if governs == "b0/b1" { vec!["b1".to_string()] } else { vec!["b0".into(), "b1".into()] };
        assert_eq!(r.mechanism.blocks, moving);
    }
}

#[test]
fn a_squat_block_slides_at_phi_with_the_non_associative_answer() {
    for phi in [15.0f64, 25.0, 30.0] {
        let l = layout_of(vec![block(0.4, 0.1, 0.0, 0.0)], KN, KN / 2.0, phi, BaseSliding::Free);
        let r = tilt(&l);
        assert_deg(&format!("sliding at {phi}°"), deg(&r), phi);
        assert_deg("associative", r.associative.atan().to_degrees(), phi);
        let na = r.non_associative.as_ref().expect("sliding runs the correction");
        assert!(na.converged, "{na:?}");
        assert_eq!(r.governing, FlowRule::NonAssociative);
        assert_eq!(r.mechanism.kind, MechanismKind::Sliding);
        assert_eq!(r.joints[0].mode, JointMode::Slide);
        // The associative-only answer is the same number, marked associative.
        let p = LimitParams { non_associative: false, ..LimitParams::default() };
        let a = limit_tilt(&l, &SolverParams::default(), &p).unwrap();
        assert_eq!(a.governing, FlowRule::Associative);
        assert!(a.non_associative.is_none());
        assert_deg("associative only", deg(&a), phi);
    }
}

#[test]
fn a_cohesive_block_slides_at_tan_phi_plus_c_a_over_w_whatever_its_tensile_strength() {
    // Coulomb with cohesion on the base: the shear capacity is μ W + c A, and sliding opens
    // nothing, so the tensile strength adds nothing: λ = tan φ + c A / W. The block is squat
    // (tipping at b/h = 4, far above), and associative sliding of a single block on the
    // table does no work against any other normal force, so the associative λ is exact.
    let (b, h, len, phi) = (0.4, 0.1, 0.3, 20.0f64);
    for (c, t) in [(400.0, 0.0), (400.0, 10_000.0), (0.0, 10_000.0), (1_000.0, 50.0)] {
        let mut l = layout_of(vec![block(b, h, 0.0, 0.0)], KN, KN / 2.0, phi, BaseSliding::Free);
        for m in &mut l.materials {
            m.cohesion = c;
            m.tensile_strength = t;
        }
        let w = l.materials[0].density * l.gravity * b * h * len;
        let want = phi.to_radians().tan() + c * b * len / w;
        let p = LimitParams { non_associative: false, ..LimitParams::default() };
        let r = limit_tilt(&l, &SolverParams::default(), &p).expect("limit analysis");
        assert!(
            (r.load_multiplier - want).abs() < 1e-6 * want,
            "c {c} Pa, T {t} Pa: λ {} against tan φ + c A / W = {want}",
            r.load_multiplier
        );
        assert_eq!(r.joints[0].mode, JointMode::Slide, "c {c} Pa, T {t} Pa");
    }
}

#[test]
fn trapezoid_monoliths_tip_at_their_closed_form() {
    for (bb, tt, hh) in [(0.15, 0.077, 0.375), (0.45, 0.25, 1.0), (0.3, 0.1, 0.5)] {
        let l = layout_of(vec![trapezoid_block(bb, tt, hh)], KN, KN / 2.0, 40.0, BaseSliding::Free);
        let want = (3.0 * bb * (bb + tt) / (2.0 * hh * (bb + 2.0 * tt))).atan().to_degrees();
        assert_deg(&format!("trapezoid {bb} {tt} {hh}"), deg(&tilt(&l)), want);
    }
}

fn rigid(name: &str) -> Layout {
    Layout::from_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("data/layouts/rigid").join(name)).expect("layout")
}

#[test]
fn the_13_box_running_bond_wall_overturns_whole_at_t_over_h() {
    let l = rigid("running_bond_13.json");
    let r = tilt(&l);
    // t = 0.1 m, H = 0.3 m: the wall overturns as one body about its base edge.
    assert_deg("running_bond_13", deg(&r), (0.1f64 / 0.3).atan().to_degrees());
    assert_eq!(r.mechanism.blocks.len(), 13);
    assert!(r.joints.iter().all(|j| j.joint.starts_with("table/") && j.mode == JointMode::Hinge), "{:?}", r.joints);
    assert!(r.wall_time_s < 1.0);
}

/// (last stable, first unstable) of LMGC90 for a case of the table, degrees.
fn lmgc90(case: &str) -> (f64, f64) {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("data/lmgc90_rigid_limits.csv"))
        .expect("table");
    let row = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').map(str::to_string).collect::<Vec<_>>())
        .find(|r| r[0] == case)
        .unwrap_or_else(|| panic!("no row {case}"));
    (row[2].parse().unwrap(), row[3].parse().unwrap())
}

#[test]
fn the_lmgc90_cases_fall_in_lmgc90s_brackets() {
    for case in ["single_block", "offset_stack", "running_bond_13"] {
        let (lo, hi) = lmgc90(case);
        let a = deg(&tilt(&rigid(&format!("{case}.json"))));
        assert!(a >= lo - 0.05 && a <= hi + 0.05, "{case}: limit analysis {a:.4}°, LMGC90 [{lo}, {hi}]");
    }
}

#[test]
fn a_lateral_pressure_on_a_block_has_its_moment_closed_form() {
    // A block b × h × l under a uniform pressure p on its −y face tips about its +y toe
    // when λ p h l · h/2 = W b/2 (sliding above, φ = 40°): λ = W b / (p l h²).
    let (b, h, len, p) = (0.2f64, 0.6f64, 0.3f64, 1000.0f64);
    let l = layout_of(vec![block(b, h, 0.0, 0.0)], KN, KN / 2.0, 40.0, BaseSliding::Free);
    let lat = LateralParams { pressure_base_pa: p, pressure_top_pa: p, ..LateralParams::default() };
    let r = limit_lateral(&l, &SolverParams::default(), &lat, &LimitParams::default()).unwrap();
    let w = drystone::verify::DENSITY * b * h * len * l.gravity;
    let want = w * b / (p * len * h * h);
    assert!((r.load_multiplier - want).abs() < 1e-6 * want, "{} against {want}", r.load_multiplier);
    assert!(r.collapse_angle_deg.is_none());
    // A trapezoidal pressure p0 → p1 over the height: the moment about the toe is
    // l h² (p0/6 + p1/3).
    let (p0, p1) = (1000.0, 500.0);
    let lat = LateralParams { pressure_base_pa: p0, pressure_top_pa: p1, ..LateralParams::default() };
    let r = limit_lateral(&l, &SolverParams::default(), &lat, &LimitParams::default()).unwrap();
    let want = w * b / 2.0 / (len * h * h * (p0 / 6.0 + p1 / 3.0));
    assert!((r.load_multiplier - want).abs() < 1e-6 * want, "{} against {want}", r.load_multiplier);
}

#[test]
fn bad_layouts_are_clear_errors_naming_the_block() {
    // A block in the air, beside one on the table.
    let l = layout_of(vec![block(0.1, 0.1, 0.0, 0.0), block(0.1, 0.1, 1.0, 0.5)], KN, KN, 30.0, BaseSliding::Free);
    let e = limit_tilt(&l, &SolverParams::default(), &LimitParams::default()).unwrap_err();
    assert_eq!(e, LimitError::Untouched { block: "b1".into() });
    assert!(e.to_string().contains("block b1 touches nothing"), "{e}");
    // Two blocks touching each other only, in the air.
    let l = layout_of(
        vec![block(0.1, 0.1, 0.0, 0.0), block(0.1, 0.1, 1.0, 0.5), block(0.1, 0.1, 1.0, 0.6)],
        KN,
        KN,
        30.0,
        BaseSliding::Free,
    );
    let e = limit_tilt(&l, &SolverParams::default(), &LimitParams::default()).unwrap_err();
    assert_eq!(e, LimitError::Floating { block: "b1".into(), others: 1 });
    // A base held against sliding and a squat block: nothing resists only by friction, it
    // still tips (tan α = b/h = 4).
    let l = layout_of(vec![block(0.4, 0.1, 0.0, 0.0)], KN, KN, 20.0, BaseSliding::Held);
    assert_deg("held base", deg(&tilt(&l)), 4.0f64.atan().to_degrees());
    // Zero lateral pressure: no live load.
    let l = layout_of(vec![block(0.1, 0.1, 0.0, 0.0)], KN, KN, 30.0, BaseSliding::Free);
    let lat = LateralParams { pressure_base_pa: 0.0, pressure_top_pa: 0.0, ..LateralParams::default() };
    let e = limit_lateral(&l, &SolverParams::default(), &lat, &LimitParams::default()).unwrap_err();
    assert_eq!(e, LimitError::NoLiveLoad);
    // A pressure the lateral load refuses (below 0, not finite) is refused by name, not
    // solved (a negative base pressure gave a λ; NaN and ∞ a solver failure).
    for (base, top) in [(-5.0, 500.0), (f64::NAN, 500.0), (1000.0, f64::INFINITY)] {
        let lat = LateralParams { pressure_base_pa: base, pressure_top_pa: top, ..LateralParams::default() };
        let e = limit_lateral(&l, &SolverParams::default(), &lat, &LimitParams::default()).unwrap_err();
        let key = if base == 1000.0 { "pressure_top_pa" } else { "pressure_base_pa" };
        assert!(matches!(e, LimitError::Parameter(ref o) if o.key == key), "{base} {top}: {e}");
    }
    // Bad parameters.
    let p = LimitParams { relaxation: 0.0, ..LimitParams::default() };
    let e = limit_tilt(&l, &SolverParams::default(), &p).unwrap_err();
    assert!(matches!(e, LimitError::Parameter(ref o) if o.key == "relaxation"), "{e}");
}

#[test]
fn the_solvers_limit_table_reaches_limit_analysis_through_the_protocol_seam() {
    // `SolverParams::limit` (a study's `[solver.limit]`, Python's `"limit"` key, the
    // `--limit-*` options) is what the seam runs: associative only, the squat block's
    // answer is marked associative; with the default, the correction runs.
    use drystone::dem::SolverKind;
    use drystone::loading::tilt::TiltParams;
    use drystone::protocol::{Protocol, ProtocolRun, TiltRun};
    let l = layout_of(vec![block(0.4, 0.1, 0.0, 0.0)], KN, KN / 2.0, 25.0, BaseSliding::Free);
    let run = |limit: LimitParams| {
        let solver = SolverParams { kind: SolverKind::Limit, limit, ..SolverParams::default() };
        match Protocol::tilting(TiltParams::default()).run(&l, solver) {
            ProtocolRun::Tilt(TiltRun::Limit(r)) => r.expect("limit analysis"),
            other => panic!("expected a limit analysis, got {other:?}"),
        }
    };
    let full = run(LimitParams::default());
    assert_eq!(full.governing, FlowRule::NonAssociative);
    assert!(full.non_associative.is_some());
    let assoc = run(LimitParams { non_associative: false, ..LimitParams::default() });
    assert_eq!(assoc.governing, FlowRule::Associative);
    assert!(assoc.non_associative.is_none());
    assert_deg("associative through the seam", deg(&assoc), 25.0);
    // Out of range: refused naming the key, not run with a silently different value.
    let solver = SolverParams {
        kind: SolverKind::Limit,
        limit: LimitParams { relaxation: 0.0, ..LimitParams::default() },
        ..SolverParams::default()
    };
    match Protocol::tilting(TiltParams::default()).run(&l, solver) {
        ProtocolRun::Tilt(TiltRun::Limit(Err(e))) => assert!(e.to_string().contains("relaxation"), "{e}"),
        other => panic!("expected the parameter refused, got {other:?}"),
    }
}

/// The rigid methods have no crushing law: a block whose faces crush (the `crushing`
/// closure law, what the effect `toe_crushing` sets) is refused by limit analysis (the
/// tilting table, the lateral load, the in-plane test) and by nscd (the tilting table, the
/// in-plane test), naming the law and the material, instead of analysing the plain block.
/// Without the law the same block still tips at atan(b/h) by both.
#[test]
fn a_block_whose_faces_crush_is_refused_by_the_rigid_methods_naming_its_material() {
    use drystone::closure::{Closure, Crushing};
    use drystone::limit::inplane::limit_in_plane;
    use drystone::loading::inplane::{InPlaneError, InPlaneParams};
    use drystone::loading::inplane_nscd::run_in_plane_nscd;
    use drystone::loading::tilt::{TiltError, TiltParams};
    use drystone::loading::tilt_nscd::run_tilt_nscd;
    use drystone::nscd::{NscdError, NscdParams};
    let crush = |mut l: Layout| {
        for m in &mut l.materials {
            m.closure = Closure::Crushing(Crushing { strength_pa: 2e6 });
        }
        l
    };
    let (b, h) = (0.15, 0.30);
    let plain = layout_of(vec![block(b, h, 0.0, 0.0)], KN, KN / 2.0, 40.0, BaseSliding::Free);
    let crushing = crush(plain.clone());
    let says = |text: &str, method: &str, layout: &Layout| {
        let material = format!("material {}", layout.material_names[0]);
        for part in [method, "no crushing law", &material, "strength 2.0000 MPa", "toe_crushing", "use the penalty DEM"]
        {
            assert!(text.contains(part), "`{part}` not in: {text}");
        }
    };
    let s = SolverParams::default();
    let e = limit_tilt(&crushing, &s, &LimitParams::default()).unwrap_err();
    assert!(matches!(e, LimitError::Crushing { .. }), "{e:?}");
    says(&e.to_string(), "limit analysis has no crushing law", &crushing);
    let e = limit_lateral(&crushing, &s, &LateralParams::default(), &LimitParams::default()).unwrap_err();
    says(&e.to_string(), "limit analysis has no crushing law", &crushing);
    let table = TiltParams { resolution_deg: 0.05, ..TiltParams::default() };
    match run_tilt_nscd(&crushing, &NscdParams::default(), &table) {
        Err(TiltError::Nscd(e @ NscdError::Crushing { .. })) => {
            says(&e.to_string(), "nscd solver has no crushing law", &crushing)
        }
        other => panic!("expected the crushing law refused by nscd, got {other:?}"),
    }
    // The in-plane test's monolith, by its limit analysis and its nscd driver.
    let wall = crush(drystone::verify::inplane::inplane_block(45.0, KN));
    let p = InPlaneParams { sigma0_mpa: 0.5, shear_span_m: Some(1.325), drift_pct: 0.5, ..InPlaneParams::default() };
    match limit_in_plane(&wall, &s, &p, &s.limit) {
        Err(InPlaneError::Unsupported(text)) => says(&text, "limit analysis has no crushing law", &wall),
        other => {
            panic!("expected the crushing law refused by the in-plane limit analysis, got {:?}", other.map(|_| ()))
        }
    }
    match run_in_plane_nscd(&wall, &NscdParams::default(), &p) {
        Err(e @ InPlaneError::Nscd(NscdError::Crushing { .. })) => {
            says(&e.to_string(), "nscd solver has no crushing law", &wall)
        }
        other => panic!("expected the crushing law refused by the in-plane nscd run, got {:?}", other.map(|_| ())),
    }
    // Without the law: the closed form, by both methods.
    let exact = (b / h).atan().to_degrees();
    assert_deg("the plain block", deg(&tilt(&plain)), exact);
    let r = run_tilt_nscd(&plain, &NscdParams::default(), &table).unwrap();
    let up = r.first_unstable_deg.expect("the plain block tips");
    assert!(r.last_stable_deg <= exact && exact <= up, "nscd bracket [{}, {up}] misses {exact}", r.last_stable_deg);
}
