//! The in-plane shear–compression test (`loading::inplane`, `limit::inplane`,
//! `drystone in-plane`) against closed forms computed here by hand: a monolithic wall
//! rocking about its toe (`V = N_total L / (2 H0)`; double-fixed `(N L + W L / 2) / H`),
//! sliding on its base (`V = μ N_total`), its elastic stiffness on penalty joints; the two
//! directions of a cyclic history of a symmetric wall; bit-for-bit repetition; the refusals
//! of bad input by name.

use drystone::dem::SolverParams;
use drystone::layout::Layout;
use drystone::limit::inplane::limit_in_plane;
use drystone::loading::inplane::{
    run_in_plane_penalty, BeamRotation, History, InPlaneError, InPlaneParams, MechanismKind,
};
use drystone::loading::inplane_nscd::run_in_plane_nscd;
use drystone::verify::inplane::inplane_block;
use drystone::verify::{box_vertices, layout_of, DENSITY, RIGID_KN};
use std::process::Command;

const G: f64 = drystone::units::STANDARD_GRAVITY;
/// The wall: L × t × H = 1.0 × 0.2 × 1.2 m; σ0 = 0.5 MPa; H0 = 1.325 m.
const L: f64 = 1.0;
const T: f64 = 0.2;
const H: f64 = 1.2;
const H0: f64 = 1.325;
const SIGMA0: f64 = 0.5e6;

fn params(drift_pct: f64) -> InPlaneParams {
    InPlaneParams { sigma0_mpa: SIGMA0 * 1e-6, shear_span_m: Some(H0), drift_pct, ..InPlaneParams::default() }
}

/// A fresh folder `<temp>/<name>-<pid>` holding `wall.json`: one block L × t × H (1.0 × 0.2 ×
/// 1.2 m), Kn 1e10, Ks 4e9 Pa/m, φ 45°, on the table. Returns the folder and the file.
fn one_block_file(name: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let layout = dir.join("wall.json");
    let text = serde_json::json!({
        "version": 1, "name": "one block",
        "materials": [{"name": "m", "density_kg_per_m3": 2200, "kn_pa_per_m": 1e10, "ks_pa_per_m": 4e9, "friction_deg": 45}],
        "table": {"material": "m"},
        "blocks": [{"id": "wall", "material": "m", "vertices": box_vertices([0.0, -T / 2.0, 0.0], [L, T / 2.0, H])}]
    });
    std::fs::write(&layout, text.to_string()).unwrap();
    (dir, layout)
}

/// The applied force and the wall's weight, N.
fn forces() -> (f64, f64) {
    (SIGMA0 * L * T, DENSITY * G * L * T * H)
}

#[test]
fn a_monolith_rocks_about_its_toe_at_its_closed_form() {
    let (n, w) = forces();
    let v = (n + w) * L / (2.0 * H0);
    let wall = inplane_block(45.0, RIGID_KN);
    let s = SolverParams::default();
    let la = limit_in_plane(&wall, &s, &params(1.0), &s.limit).unwrap();
    assert!((la.peak_force_kn * 1e3 / v - 1.0).abs() < 1e-6, "limit analysis {} kN vs {v} N", la.peak_force_kn);
    assert_eq!(la.mechanism.kind, MechanismKind::Rocking, "{:?}", la.mechanism);
    let dem = run_in_plane_penalty(&wall, s, &params(0.5), &mut |_, _, _| {}).unwrap();
    let peak = dem.positive.unwrap().peak_force_kn * 1e3;
    assert!((peak / v - 1.0).abs() < 0.02, "DEM peak {peak} N vs {v} N");
    assert_eq!(dem.unconverged, 0);
    // The mechanism, at the granite joints' stiffness.
    let dem = run_in_plane_penalty(&inplane_block(45.0, 1e10), s, &params(1.0), &mut |_, _, _| {}).unwrap();
    assert_eq!(dem.mechanism.kind, MechanismKind::Rocking, "{:?}", dem.mechanism);
    assert_eq!(dem.mechanism.joints, vec!["table/wall".to_string()]);
}

/// Before its peak a monolith on the granite joints (Kn 1e10, Ks 1e9 Pa/m, μ = 1) pushed to
/// 0.2 % drift carries about 83 % of its rocking force with its base opening, and neither
/// joint can slip (μN is 100 kN at the beam's bed, 105 kN at the base): it rocks. The
/// beam's bed shears elastically by V / (Ks A) ≈ 0.16 mm, 6 % of the beam's motion, which
/// is not the joint moving: the mechanism is rocking at the base, not sliding at the beam.
#[test]
fn a_monolith_rocking_before_its_peak_is_not_read_as_its_beams_elastic_shear() {
    let mut wall = inplane_block(45.0, 1e10);
    for m in &mut wall.materials {
        m.ks = 1e9;
    }
    let dem = run_in_plane_penalty(&wall, SolverParams::default(), &params(0.2), &mut |_, _, _| {}).unwrap();
    let (n, w) = forces();
    let rocking = (n + w) * L / (2.0 * H0);
    let peak = dem.positive.as_ref().unwrap().peak_force_kn * 1e3;
    assert!(peak > 0.7 * rocking && peak < rocking, "{peak} N against the rocking force {rocking} N");
    assert_eq!(dem.mechanism.kind, MechanismKind::Rocking, "{:?}", dem.mechanism);
    assert_eq!(dem.mechanism.joints, vec!["table/wall".to_string()]);
}

/// A monolith whose faces crush at fc (`closure::Crushing`) rocks on a stress block of
/// width a = N_total / (fc t) at its toe: V = N_total (L − a) / (2 H0), by hand here, and
/// the DEM's peak within 2 % of it (10 MPa: a = 53 mm, 5.3 % below the rigid toe's).
#[test]
fn a_monolith_on_crushing_faces_rocks_on_its_stress_block() {
    use drystone::closure::{Closure, Crushing};
    let (n, w) = forces();
    let fc = 10e6;
    let a = (n + w) / (fc * T);
    let v = (n + w) * (L - a) / (2.0 * H0);
    let mut wall = inplane_block(45.0, 1e11);
    for m in &mut wall.materials {
        m.closure = Closure::Crushing(Crushing { strength_pa: fc });
    }
    let s = SolverParams::default();
    let dem = run_in_plane_penalty(&wall, s, &params(0.5), &mut |_, _, _| {}).unwrap();
    let peak = dem.positive.unwrap().peak_force_kn * 1e3;
    let rigid = (n + w) * L / (2.0 * H0);
    assert!((peak / v - 1.0).abs() < 0.02, "DEM peak {peak} N vs {v} N (rigid toe {rigid} N)");
    assert!(peak < 0.97 * rigid, "the crushing toe does not lower the peak: {peak} N vs {rigid} N");
    assert_eq!(dem.unconverged, 0);
}

/// A wall whose faces crush below the vertical stress (0.3 MPa under 0.5 MPa) cannot carry
/// the beam's force: the run says so before any displacement, naming the joint rule, its
/// strength and the stress at the base (before, it named the beam sinking through the
/// crushed wall as a block that moved), and counts it a wall that does not stand.
#[test]
fn a_wall_that_cannot_carry_the_vertical_force_says_it_crushes() {
    use drystone::closure::{Closure, Crushing};
    let mut wall = inplane_block(45.0, 1e10);
    for m in &mut wall.materials {
        m.closure = Closure::Crushing(Crushing { strength_pa: 0.3e6 });
    }
    let s = SolverParams::default();
    match run_in_plane_penalty(&wall, s, &params(0.5), &mut |_, _, _| {}) {
        Err(e @ InPlaneError::Crushes { .. }) => {
            let text = e.to_string();
            assert!(text.contains("crushes the wall") && text.contains("fc = 0.300 MPa of material"), "{text}");
            assert!(e.does_not_stand() && !e.is_refusal(), "{text}");
        }
        other => panic!("expected the vertical force refused, got {other:?}"),
    }
}

#[test]
fn a_monolith_with_the_beam_held_level_rocks_in_double_curvature() {
    let (n, w) = forces();
    let v = (n * L + w * L / 2.0) / H;
    let wall = inplane_block(45.0, RIGID_KN);
    let s = SolverParams::default();
    let p = InPlaneParams { beam_rotation: BeamRotation::Fixed, shear_span_m: None, ..params(1.0) };
    let la = limit_in_plane(&wall, &s, &p, &s.limit).unwrap();
    assert!((la.peak_force_kn * 1e3 / v - 1.0).abs() < 1e-6, "limit analysis {} kN vs {v} N", la.peak_force_kn);
}

#[test]
fn a_monolith_on_a_slippery_base_slides_at_mu_n() {
    let (n, w) = forces();
    let mu = 0.2;
    let v = mu * (n + w);
    let wall = inplane_block(mu.atan().to_degrees(), RIGID_KN);
    let s = SolverParams::default();
    let la = limit_in_plane(&wall, &s, &params(1.0), &s.limit).unwrap();
    assert!((la.peak_force_kn * 1e3 / v - 1.0).abs() < 1e-6, "limit analysis {} kN vs {v} N", la.peak_force_kn);
    assert_eq!(la.mechanism.kind, MechanismKind::Sliding, "{:?}", la.mechanism);
    let dem = run_in_plane_penalty(&wall, s, &params(0.5), &mut |_, _, _| {}).unwrap();
    let peak = dem.positive.unwrap().peak_force_kn * 1e3;
    assert!((peak / v - 1.0).abs() < 0.02, "DEM peak {peak} N vs {v} N");
    assert_eq!(dem.mechanism.kind, MechanismKind::Sliding, "{:?}", dem.mechanism);
}

/// The block on its base joint under the beam on a joint of the same law, small
/// displacements, vertical loads staying vertical (first-order P–Δ), derived here: with
/// slips s = V/(Ks A) at both joints and rotations θ (base) and ψ (beam joint) about the
/// joints' centres, the beam's centroid (at H0, where V and N act) moves
/// u = 2s + θH + (θ+ψ)(H0−H); moments about the base and the beam joint's centres:
/// Kn I θ = V H0 + N u + W (s + θ H/2) and Kn I ψ = V (H0−H) + N (s + (θ+ψ)(H0−H)); the
/// displacement is read where the database reads it, on the beam at the actuator's height
/// H0, which moves u itself.
#[test]
fn the_elastic_stiffness_of_one_block_is_its_closed_form() {
    let (n, w) = forces();
    for kn in [1e8, 1e9, 1e10, 1e11] {
        let ks = kn / 2.5;
        let (a, i) = (L * T, T * L * L * L / 12.0);
        let (kr, e) = (kn * i, H0 - H);
        // θ and ψ per unit V from the two moment equations with u eliminated:
        // u = 2V/(Ks A) + θH + (θ+ψ)e.
        // [kr − N H − W H/2 − N e, −N e] [θ]   [H0 + 2N/(Ks A) + W/(Ks A)]
        // [−N e,          kr − N e] [ψ] = [e + N/(Ks A)              ] V
        let m = nalgebra::Matrix2::new(kr - n * H - w * H / 2.0 - n * e, -n * e, -n * e, kr - n * e);
        let rhs = nalgebra::Vector2::new(H0 + 2.0 * n / (ks * a) + w / (ks * a), e + n / (ks * a));
        let x = m.lu().solve(&rhs).unwrap();
        let k = 1.0 / (2.0 / (ks * a) + x[0] * H + (x[0] + x[1]) * e);
        let wall = inplane_block(45.0, kn);
        // To half the force that decompresses the base (V H0 = N_total L / 6): a force well
        // above the equilibrium tolerance's share of the contact forces.
        let drift_pct = 100.0 * 0.5 * (n + w) * L / (6.0 * H0) / k / H0;
        let p = InPlaneParams { step_mm: drift_pct * H0 * 10.0 / 20.0, ..params(drift_pct) };
        let r = run_in_plane_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
        let sim = r.positive.unwrap().initial_stiffness_kn_per_mm * 1e6;
        assert!((sim / k - 1.0).abs() < 0.01, "Kn {kn:e}: {sim} N/m vs {k} N/m");
    }
}

/// The vertical loading phase as the laboratory reads it (the database's `Epc`): a stack
/// of `c` rigid blocks between the table and the beam, every joint linear of Kn, shortens
/// by (c + 1) Δσ / Kn under the stress Δσ the actuator adds, so the wall's vertical
/// modulus is Kn H / (c + 1), by hand here; and a measuring point above the actuator reads
/// the drift over its own height.
#[test]
fn the_vertical_modulus_of_a_stack_is_its_joints_in_series() {
    for (courses, kn) in [(1usize, 1e9), (2, 1e10), (4, 2e10)] {
        let h = H / courses as f64;
        let blocks = (0..courses).map(|c| box_vertices([0.0, 0.0, c as f64 * h], [L, T, (c + 1) as f64 * h])).collect();
        let wall = layout_of(blocks, kn, kn / 2.5, 45.0, Default::default());
        let r = run_in_plane_penalty(&wall, SolverParams::default(), &params(0.05), &mut |_, _, _| {}).unwrap();
        let e = kn * H / (courses + 1) as f64 * 1e-6;
        assert!(
            (r.wall_vertical_modulus_mpa / e - 1.0).abs() < 1e-3,
            "{courses} courses, Kn {kn:e}: {} MPa vs {e} MPa",
            r.wall_vertical_modulus_mpa
        );
        assert_eq!(r.measuring_height_m, H0);
    }
    // Read at the actuator's point (the default), the displacement is the one imposed
    // there and the drift the history's own; read 0.2 m higher, the drift is that point's
    // displacement over its own height.
    let wall = inplane_block(45.0, RIGID_KN);
    let r = run_in_plane_penalty(&wall, SolverParams::default(), &params(0.5), &mut |_, _, _| {}).unwrap();
    let last = r.curve.last().unwrap();
    // (to the beam hold's penalty, some 1e-7 of the displacement)
    assert!((last.top_mm / (0.5e-2 * H0 * 1e3) - 1.0).abs() < 1e-6, "{last:?}");
    assert!((last.drift_pct / 0.5 - 1.0).abs() < 1e-6, "{last:?}");
    let p = InPlaneParams { measuring_height_m: Some(H0 + 0.2), ..params(0.5) };
    let r = run_in_plane_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
    assert_eq!(r.measuring_height_m, H0 + 0.2);
    for c in &r.curve[1..] {
        assert!((c.drift_pct / (c.top_mm * 1e-1 / (H0 + 0.2)) - 1.0).abs() < 1e-12, "{c:?}");
    }
    // Below the wall's top: refused by name.
    let p = InPlaneParams { measuring_height_m: Some(1.0), ..params(0.5) };
    let e = run_in_plane_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap_err().to_string();
    assert!(e.contains("measuring_height_m") && e.contains("below the wall's height"), "{e}");
}

#[test]
fn a_cyclic_history_loads_a_symmetric_wall_alike_both_ways() {
    let wall = inplane_block(45.0, 1e10);
    let p = InPlaneParams { history: History::Cyclic, amplitudes_pct: Some(vec![0.1, 0.3]), ..params(0.3) };
    let r = run_in_plane_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
    let (pos, neg) = (r.positive.unwrap(), r.negative.unwrap());
    assert!((pos.peak_force_kn / neg.peak_force_kn - 1.0).abs() < 0.02, "{pos:?} vs {neg:?}");
    // The imposed history: two cycles an amplitude, 0 → a → −a → 0, at two amplitudes.
    let path = p.path(H0);
    let turns = path.windows(3).filter(|w| (w[1] - w[0]) * (w[2] - w[1]) < 0.0).count();
    assert_eq!(turns, 2 * 2 * 2, "direction changes of the history");
    assert_eq!(path.last().copied(), Some(0.0));
    let top = r.curve.iter().map(|c| c.drift_pct).fold(0.0_f64, f64::max);
    let bottom = r.curve.iter().map(|c| c.drift_pct).fold(0.0_f64, f64::min);
    assert!((top - 0.3).abs() < 0.01 && (bottom + 0.3).abs() < 0.01, "drifts {bottom} to {top} %");
}

#[test]
fn a_run_repeats_bit_for_bit() {
    let wall = inplane_block(45.0, 1e10);
    let p = params(0.2);
    let a = run_in_plane_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
    let b = run_in_plane_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
    assert_eq!(a.curve, b.curve);
    assert_eq!(a.steps, b.steps);
}

fn refused(wall: &Layout, p: InPlaneParams) -> String {
    let e = run_in_plane_penalty(wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap_err();
    let s = SolverParams::default();
    let la = limit_in_plane(wall, &s, &p, &s.limit).unwrap_err();
    assert_eq!(e.to_string(), la.to_string(), "both methods refuse alike");
    e.to_string()
}

#[test]
fn bad_input_is_refused_by_name_before_any_run() {
    let wall = inplane_block(45.0, 1e9);
    for (p, key) in [
        (InPlaneParams { sigma0_mpa: 0.0, ..params(1.0) }, "sigma0_mpa"),
        (InPlaneParams { sigma0_mpa: -1.0, ..params(1.0) }, "sigma0_mpa"),
        (InPlaneParams { sigma0_mpa: f64::NAN, ..params(1.0) }, "sigma0_mpa"),
        (InPlaneParams { sigma0_mpa: f64::INFINITY, ..params(1.0) }, "sigma0_mpa"),
        (params(0.0), "drift_pct"),
        (params(50.5), "drift_pct"),
        (InPlaneParams { shear_span_m: None, ..params(1.0) }, "shear_span_m"),
        (InPlaneParams { shear_span_m: Some(1.0), ..params(1.0) }, "shear_span_m"),
        (InPlaneParams { step_mm: 0.0, ..params(1.0) }, "step_mm"),
        (InPlaneParams { step_mm: 1e-12, ..params(1.0) }, "step_mm"),
        (InPlaneParams { history: History::Cyclic, ..params(50.0) }, "step_mm"),
        (InPlaneParams { sigma0_mpa: 1e9, ..params(1.0) }, "sigma0_mpa"),
        (InPlaneParams { sigma0_mpa: 1e-12, ..params(1.0) }, "sigma0_mpa"),
        (
            InPlaneParams { history: History::Cyclic, amplitudes_pct: Some(vec![0.5, 0.5]), ..params(1.0) },
            "amplitudes_pct",
        ),
        (
            InPlaneParams { history: History::Cyclic, amplitudes_pct: Some(vec![0.5, 2.0]), ..params(1.0) },
            "amplitudes_pct",
        ),
    ] {
        let e = refused(&wall, p.clone());
        assert!(e.contains(key), "{p:?}: {e}");
    }
    // A top course with a block 30 mm low carries the beam on too little of its length.
    let low = layout_of(
        vec![box_vertices([0.0, -0.1, 0.0], [0.5, 0.1, 1.2]), box_vertices([0.5, -0.1, 0.0], [1.0, 0.1, 1.17])],
        1e9,
        4e8,
        35.0,
        drystone::layout::BaseSliding::Free,
    );
    let e = refused(&low, params(1.0));
    assert!(e.contains("not level") && e.contains("b1"), "{e}");
    assert!(matches!(
        run_in_plane_penalty(&low, SolverParams::default(), &params(1.0), &mut |_, _, _| {}),
        Err(InPlaneError::NotLevel { .. })
    ));
}

#[test]
fn the_command_line_prints_the_keys_and_refuses_by_flag() {
    let (dir, layout) = one_block_file("drystone-inplane");
    let bin = env!("CARGO_BIN_EXE_drystone");
    for (solver, method) in [("penalty", "penalty"), ("newton", "penalty"), ("nscd", "nscd"), ("limit", "limit")] {
        let o = Command::new(bin)
            .args(["in-plane", layout.to_str().unwrap(), "--sigma0-mpa", "0.5", "--shear-span-m", "1.325"])
            .args(if solver == "limit" { &[][..] } else { &["--drift-pct", "0.5"][..] })
            .args(["--solver", solver, "--json"])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        for key in ["peak_force_kn", "drift_at_peak_pct", "initial_stiffness_kn_per_mm", "mechanism"] {
            assert!(j.get(key).is_some(), "{solver}: no {key} in {j}");
        }
        assert_eq!(j["mechanism"], "rocking", "{solver}");
        // The method that ran, and the solver chosen where it says more (the penalty DEM's
        // Newton solve is not "penalty" alone).
        assert_eq!(j["method"], method, "{solver}");
        if method != "limit" {
            assert_eq!(j["solver"], solver, "{solver}");
        }
    }
    for (args, needle) in [
        (vec!["--sigma0-mpa", "-1", "--shear-span-m", "1.325"], "--sigma0-mpa"),
        (vec!["--sigma0-mpa", "0.5", "--shear-span-m", "0.9"], "shear_span_m"),
        (vec!["--sigma0-mpa", "0.5"], "--shear-span-m"),
        (vec!["--sigma0-mpa", "0.5", "--shear-span-m", "1.325", "--svg", "/nonexistent/x.svg"], "/nonexistent"),
    ] {
        let o = Command::new(bin).args(["in-plane", layout.to_str().unwrap()]).args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The bundled specimens: 14 rows; the README's first check, that a monolith's rocking
/// capacity `N_total L / (2 H0)` is 0.377 N_total and the measured positive peaks lie at
/// 0.34–0.37 N_total, holds on the table as read.
#[test]
fn the_bundled_specimens_are_read_whole() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/inplane_granite");
    let s = drystone::study::inplane::read_specimens(&root.join("walls.csv"), Some(&root.join("envelopes"))).unwrap();
    assert_eq!(s.len(), 14);
    assert_eq!(s.iter().filter(|s| s.loading == "Cyclic").count(), 10);
    for sp in &s {
        assert!(!sp.envelope.is_empty(), "{}: no envelope", sp.unit);
        let n_total = sp.sigma0_mpa * 1e3 * 1.0 * 0.2 + 20.0 * 1.0 * 1.2 * 0.2;
        let ratio = sp.vmax_pos_kn / n_total;
        assert!((0.33..=0.38).contains(&ratio), "{}: V/N = {ratio}", sp.unit);
    }
    assert!((1.0_f64 / (2.0 * 1.325) - 0.377).abs() < 5e-4);
    // The whole curves: every cyclic specimen's loops read, no monotonic one's; a folder
    // that is not there is refused by name.
    let mut s = s;
    drystone::study::inplane::read_loops(&mut s, &root.join("curves")).unwrap();
    for sp in &s {
        assert_eq!(sp.damping_ratio.is_finite(), sp.loading == "Cyclic", "{}: {}", sp.unit, sp.damping_ratio);
    }
    let e = drystone::study::inplane::read_loops(&mut s, &root.join("no_such_folder")).unwrap_err().to_string();
    assert!(e.contains("no_such_folder") && e.contains("curves"), "{e}");
}

/// A small in-plane study runs, writes its rows, statistics, comparison, figures and report,
/// and repeats bit for bit.
#[test]
fn an_in_plane_study_writes_its_outputs() {
    let dir = std::env::temp_dir().join(format!("drystone-inplane-study-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let study = dir.join("study.toml");
    std::fs::write(
        &study,
        format!(
            r#"version = 1
name = "small"
seed = 7
realizations = 2
protocol = "in_plane"
[in_plane]
shear_span_m = 1.325
drift_pct = 0.6
[[groups]]
name = "0.5 MPa"
wall = "{}"
sigma0_mpa = 0.5
specimens = ["WS.100"]
[measured]
walls = "{}"
envelopes = "{}"
"#,
            root.join("studies/walls/granite_vasconcelos.toml").display(),
            root.join("data/inplane_granite/walls.csv").display(),
            root.join("data/inplane_granite/envelopes").display()
        ),
    )
    .unwrap();
    let a = crate::common::run_study_file(&study, &dir.join("a")).unwrap();
    let b = crate::common::run_study_file(&study, &dir.join("b")).unwrap();
    assert_eq!(a.rows.len(), 2);
    assert!(a.rows.iter().all(|r| r.status.is_ok()), "{:?}", a.rows);
    for f in ["realizations.csv", "journal.jsonl", "manifest.json", "summary.csv", "comparison.csv", "report.md"] {
        assert!(dir.join("a").join(f).exists(), "{f}");
    }
    assert!(dir.join("a/curves_0_5_mpa.svg").exists() && dir.join("a/mechanism_0_5_mpa.svg").exists());
    let csv = |d: &str| {
        std::fs::read_to_string(dir.join(d).join("realizations.csv"))
            .unwrap()
            .lines()
            .map(|l| l.rsplitn(3, ',').nth(2).unwrap_or_default().to_string())
            .collect::<Vec<_>>()
    };
    assert_eq!(csv("a"), csv("b"), "bit for bit, the wall-clock column aside");
    let peak = |r: &drystone::ensemble::row::RealizationRow| crate::common::in_plane(r).peak_pos_kn.to_bits();
    assert_eq!(peak(&b.rows[0]), peak(&a.rows[0]));
    let comparison = std::fs::read_to_string(dir.join("a/comparison.csv")).unwrap();
    assert!(comparison.contains("WS.100,peak_pos_kn,37,"), "{comparison}");
    // The study core reads it: its groups, and the in-plane test with each group's values.
    let st = drystone::study::Study::from_file(&study).unwrap();
    let test = st.protocol.in_plane().expect("an in-plane study");
    assert_eq!((st.groups.len(), test.groups[0].sigma0_mpa, test.specimens.len() > 1), (1, 0.5, true));
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, std::fs::read_to_string(&study).unwrap().replace("\"WS.100\"", "\"WS.999\"")).unwrap();
    let e = crate::common::run_study_file(&bad, &dir.join("c")).unwrap_err();
    assert!(e.contains("groups[0.5 MPa].specimens") && e.contains("WS.999"), "{e}");
    // The model extended by the study's effects: the same walls, the force read with the
    // leaning jack's N u / L on top (N = σ0 L t of the 1.0 × 0.2 m plan), named in the report.
    let text = std::fs::read_to_string(&study).unwrap();
    let extended = dir.join("extended.toml");
    std::fs::write(
        &extended,
        text.replace("[in_plane]", "[effects]\njack_tilt = { inverse_length_per_m = 0.5 }\n\n[in_plane]"),
    )
    .unwrap();
    let e = crate::common::run_study_file(&extended, &dir.join("e")).unwrap();
    for (x, a) in e.rows.iter().zip(&a.rows) {
        let (x, a) = (crate::common::in_plane(x).curve(), crate::common::in_plane(a).curve());
        assert_eq!(x.len(), a.len());
        // (drift %, kN): the extra force over the drift is N H0 / (100 L), the same at every
        // point, with H0 the height where the drift is read (the shear span, 1.325 m).
        for (p, q) in x.iter().zip(&a).filter(|(p, _)| p.0 > 0.05) {
            assert_eq!(p.0, q.0);
            let per_pct = (p.1 - q.1) / p.0;
            let expected = 0.5e3 * 1.0 * 0.2 * 0.5 / 100.0;
            assert!(
                (per_pct / expected - 1.325).abs() < 0.02,
                "{per_pct} kN per % against {expected} kN per % per m of height"
            );
        }
    }
    let report = std::fs::read_to_string(dir.join("e/report.md")).unwrap();
    assert!(report.contains("extended by `jack_tilt` (inverse_length_per_m = 0.5)"), "{report}");
    std::fs::write(
        &extended,
        text.replace("[in_plane]", "[effects]\njack_tilt = { inverse_length_per_m = 7.0 }\n\n[in_plane]"),
    )
    .unwrap();
    let err = crate::common::run_study_file(&extended, &dir.join("f")).unwrap_err();
    assert!(err.contains("effects.jack_tilt") && err.contains('7'), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The implicit iteration (`--solver implicit`) holds the beam's constrained degrees of
/// freedom (its stiffness leaves them out, its jumps put the anchor back on its target):
/// the monolith rocks about its toe and slides on a slippery base at the closed forms
/// above, every increment converged, and its elastic stiffness is the closed form's.
#[test]
fn the_implicit_iteration_holds_the_beam_at_the_closed_forms() {
    let s = SolverParams { kind: drystone::dem::SolverKind::Implicit, ..SolverParams::default() };
    let (n, w) = forces();
    let rocking = (n + w) * L / (2.0 * H0);
    let dem = run_in_plane_penalty(&inplane_block(45.0, RIGID_KN), s, &params(0.5), &mut |_, _, _| {}).unwrap();
    let peak = dem.positive.unwrap().peak_force_kn * 1e3;
    assert!((peak / rocking - 1.0).abs() < 0.02, "rocking: {peak} N vs {rocking} N");
    assert_eq!(dem.unconverged, 0);
    let mu = 0.2;
    let sliding = mu * (n + w);
    let wall = inplane_block(mu.atan().to_degrees(), RIGID_KN);
    let dem = run_in_plane_penalty(&wall, s, &params(0.5), &mut |_, _, _| {}).unwrap();
    let peak = dem.positive.unwrap().peak_force_kn * 1e3;
    assert!((peak / sliding - 1.0).abs() < 0.02, "sliding: {peak} N vs {sliding} N");
    assert_eq!(dem.mechanism.kind, MechanismKind::Sliding, "{:?}", dem.mechanism);
    // The same wall by dynamic relaxation (the default) gives the same initial stiffness.
    let wall = inplane_block(45.0, 1e9);
    let p = InPlaneParams { step_mm: 0.05, ..params(0.1) };
    let implicit = run_in_plane_penalty(&wall, s, &p, &mut |_, _, _| {}).unwrap();
    let relaxed = run_in_plane_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
    let (a, b) =
        (implicit.positive.unwrap().initial_stiffness_kn_per_mm, relaxed.positive.unwrap().initial_stiffness_kn_per_mm);
    assert!((a / b - 1.0).abs() < 0.01, "implicit {a} kN/mm vs relaxation {b} kN/mm");
    assert_eq!(implicit.unconverged, 0);
}

/// The rigid monolith by non-smooth contact dynamics (the beam's degrees of freedom held
/// in the contact dynamics, `nscd::held`): its peak force is the closed form of the
/// mechanism it moves in, within 1 % (the P–Δ of 0.2 % drift and the inertia of the start
/// are under 0.3 %): rocking about the toe `N_total L / (2 H0)`, rocking in double
/// curvature with the beam held level `(N L + W L / 2) / H`, sliding `μ N_total`.
fn nscd_peak(wall: &Layout, p: &InPlaneParams) -> (f64, MechanismKind) {
    let r = run_in_plane_nscd(wall, &SolverParams::default().nscd, p).unwrap();
    assert_eq!(r.unconverged, 0);
    (r.positive.unwrap().peak_force_kn * 1e3, r.mechanism.kind)
}

#[test]
fn nscd_rocks_a_monolith_about_its_toe_at_its_closed_form() {
    let (n, w) = forces();
    let v = (n + w) * L / (2.0 * H0);
    let (peak, kind) = nscd_peak(&inplane_block(45.0, RIGID_KN), &params(0.2));
    assert!((peak / v - 1.0).abs() < 0.01, "nscd peak {peak} N vs {v} N");
    assert_eq!(kind, MechanismKind::Rocking);
}

#[test]
fn nscd_rocks_a_monolith_in_double_curvature_with_the_beam_held_level() {
    let (n, w) = forces();
    let v = (n * L + w * L / 2.0) / H;
    let p = InPlaneParams { beam_rotation: BeamRotation::Fixed, shear_span_m: None, ..params(0.2) };
    let (peak, _) = nscd_peak(&inplane_block(45.0, RIGID_KN), &p);
    assert!((peak / v - 1.0).abs() < 0.01, "nscd peak {peak} N vs {v} N");
}

#[test]
fn nscd_slides_a_monolith_on_a_slippery_base_at_mu_n() {
    let (n, w) = forces();
    let mu = 0.2;
    let v = mu * (n + w);
    let (peak, kind) = nscd_peak(&inplane_block(mu.atan().to_degrees(), RIGID_KN), &params(0.2));
    assert!((peak / v - 1.0).abs() < 0.01, "nscd peak {peak} N vs {v} N");
    assert_eq!(kind, MechanismKind::Sliding);
}

/// The rig's vertical load (`Layout::vertical_load_rig`, the effects `rig_friction` and
/// `jack_tilt`) against the closed forms of a monolith sliding on a base of μ = 0.2: the
/// wall's shear is `μ N_total` while it slides, so the actuator reads `μ N_total + μ_r
/// N_jack` both ways of a cyclic history (the bearing resisting each way's motion), and
/// `μ N_total + N_jack u / L` at the largest displacement u of a monotonic push (the
/// leaning jack pulling the beam back); limit analysis, without displacement, adds the
/// friction alone to the rocking capacity. `N_jack` is the applied vertical force `σ0 L t`.
#[test]
fn the_rigs_vertical_load_adds_its_bearing_friction_and_its_jacks_lean_to_the_actuators_force() {
    let (n, w) = forces();
    let mu: f64 = 0.2;
    let s = SolverParams::default();
    let base = inplane_block(mu.atan().to_degrees(), 1e10);
    let plain = run_in_plane_penalty(&base, s, &params(0.5), &mut |_, _, _| {}).unwrap();
    let n_jack = n;
    // Friction, both ways.
    let mu_r = 0.03;
    let mut wall = base.clone();
    wall.vertical_load_rig.friction = mu_r;
    let p = InPlaneParams { history: History::Cyclic, amplitudes_pct: Some(vec![0.5]), ..params(0.5) };
    let r = run_in_plane_penalty(&wall, s, &p, &mut |_, _, _| {}).unwrap();
    let v = mu * (n + w) + mu_r * n_jack;
    for (way, d) in [("positive", r.positive.unwrap()), ("negative", r.negative.unwrap())] {
        assert!((d.peak_force_kn * 1e3 / v - 1.0).abs() < 0.01, "{way}: {} kN vs {v} N", d.peak_force_kn);
    }
    assert_eq!(r.unconverged, 0);
    // The leaning jack, hinges 1.5 m apart: the force grows with the displacement while the
    // wall slides, and the peak is at the largest displacement.
    let inv_l = 1.0 / 1.5;
    let mut wall = base.clone();
    wall.vertical_load_rig.inverse_jack_length_per_m = inv_l;
    let r = run_in_plane_penalty(&wall, s, &params(0.5), &mut |_, _, _| {}).unwrap();
    let last = r.curve.last().unwrap();
    let v = mu * (n + w) + n_jack * last.top_mm * 1e-3 * inv_l;
    let d = r.positive.unwrap();
    assert!((d.peak_force_kn * 1e3 / v - 1.0).abs() < 0.01, "leaning jack: {} kN vs {v} N", d.peak_force_kn);
    assert!(
        (d.drift_at_peak_pct - last.drift_pct).abs() < 1e-9,
        "peak at {} % of {} %",
        d.drift_at_peak_pct,
        last.drift_pct
    );
    assert!(plain.positive.unwrap().drift_at_peak_pct < 0.9 * last.drift_pct);
    // The wall's state is the plain run's: the curves differ by N_jack u / L alone.
    assert_eq!(r.curve.len(), plain.curve.len());
    for (a, b) in r.curve.iter().zip(&plain.curve) {
        assert_eq!(a.top_mm, b.top_mm);
        let extra = (a.force_kn - b.force_kn) * 1e3;
        assert!((extra - n_jack * a.top_mm * 1e-3 * inv_l).abs() < 1e-6 * v, "{extra} N at {} mm", a.top_mm);
    }
    // Limit analysis: the rocking capacity plus the friction.
    let mut wall = inplane_block(45.0, RIGID_KN);
    wall.vertical_load_rig =
        drystone::layout::VerticalLoadRig { inverse_jack_length_per_m: inv_l, friction: mu_r, ..Default::default() };
    let la = limit_in_plane(&wall, &s, &params(1.0), &s.limit).unwrap();
    let v = (n + w) * L / (2.0 * H0) + mu_r * n_jack;
    assert!((la.peak_force_kn * 1e3 / v - 1.0).abs() < 1e-6, "limit analysis {} kN vs {v} N", la.peak_force_kn);
}

/// The loops of a cyclic history (`loading::inplane_loops`) against what each mechanism
/// dissipates, by hand: a monolith rocking on its toe is elastic and dissipates nothing; one
/// sliding on its base is a rectangle of height `2 μ N_total`, `E_d = 4 μ N_total (a − u_y)`
/// with `u_y` its elastic displacement before the slip, so `ξ_eq → (1 − u_y / a) / π`; the
/// rig's bearing under the rocking monolith adds `μ_r N` against each way's motion, `4 μ_r N a`
/// a cycle of amplitude `a` (the curve read at the increments' ends loses the trapezoid across
/// the force's change of sign, `μ_r N h` a reversal, `h` the top's first move after it: the
/// rocked wall unloads elastically there, h ≈ 0.03 mm of a ≈ 3 mm, under 1 %).
#[test]
fn the_loops_of_a_cyclic_history_dissipate_what_their_mechanism_does() {
    use drystone::loading::inplane_loops::cycles;
    let (n, w) = forces();
    let s = SolverParams::default();
    let p = InPlaneParams { history: History::Cyclic, amplitudes_pct: Some(vec![0.25, 0.5]), ..params(0.5) };
    let loops = |wall: &Layout| {
        let r = run_in_plane_penalty(wall, s, &p, &mut |_, _, _| {}).unwrap();
        assert_eq!(r.unconverged, 0);
        let curve: Vec<(f64, f64)> = r.curve.iter().map(|c| (c.top_mm, c.force_kn)).collect();
        (cycles(&curve), r)
    };
    // Rocking: elastic.
    let rocking = inplane_block(45.0, 1e10);
    let (c, _) = loops(&rocking);
    assert_eq!(c.len(), 3, "{c:?}");
    for cy in &c {
        assert!(cy.damping_ratio.abs() < 0.005, "rocking: {cy:?}");
    }
    // Rocking with the rig's bearing: its friction's work, cycle by cycle.
    let mu_r = 0.03;
    let mut wall = rocking.clone();
    wall.vertical_load_rig.friction = mu_r;
    let (cf, r) = loops(&wall);
    assert_eq!(cf.len(), c.len());
    for (a, b) in cf.iter().zip(&c) {
        let by_hand = mu_r * n * 1e-3 * 4.0 * a.amplitude; // kN mm
        let extra = a.dissipated - b.dissipated;
        assert!((extra / by_hand - 1.0).abs() < 0.01, "{extra} kN mm vs {by_hand} (amplitude {} mm)", a.amplitude);
    }
    assert!(r.positive.is_some());
    // Sliding: the rectangle less the elastic part.
    let mu: f64 = 0.2;
    let (cs, r) = loops(&inplane_block(mu.atan().to_degrees(), 1e10));
    let k = r.positive.unwrap().initial_stiffness_kn_per_mm; // kN/mm
    let u_y = mu * (n + w) * 1e-3 / k; // mm
    for cy in &cs {
        let by_hand = (1.0 - u_y / cy.amplitude) / std::f64::consts::PI;
        assert!((cy.damping_ratio / by_hand - 1.0).abs() < 0.05, "sliding: {cy:?} vs ξ {by_hand}");
    }
}

/// The robust readings of an envelope against a bilinear envelope worked by hand: a rise
/// of 40 kN per % of drift to 20 kN at 0.5 %, then a plateau falling 1 kN per % to 3 %.
/// The force at 0.25, 0.5, 1, 2 % is 10, 20, 19.5, 18.5 kN; 80 % of the peak (16 kN) is
/// reached at 0.4 %, 95 % (19 kN) at 0.475 %; the plateau's least-squares slope from
/// 0.475 % on is that of its straight line, −1 kN per %, and the measured side reads the
/// same by the same function whichever way the file lists its points.
#[test]
fn the_envelope_is_read_at_fixed_drifts_and_shares_of_its_peak_by_hand() {
    use drystone::loading::inplane::envelope_readings;
    use drystone::study::inplane::EnvelopeReadings;
    let force = |d: f64| if d <= 0.5 { 40.0 * d } else { 20.0 - (d - 0.5) };
    let env: Vec<(f64, f64)> = (0..=60).map(|i| 0.05 * f64::from(i)).map(|d| (d, force(d))).collect();
    let ip = 10;
    let (f, d80, d95, slope) = envelope_readings(&env, ip, 20.0);
    for (got, want) in f.iter().zip([10.0, 20.0, 19.5, 18.5]) {
        assert!((got - want).abs() < 1e-9, "{f:?}");
    }
    assert!((d80 - 0.4).abs() < 1e-9 && (d95 - 0.475).abs() < 1e-9, "{d80} {d95}");
    assert!((slope + 1.0).abs() < 1e-9, "{slope}");
    // A measured envelope listed from −3 % to +3 % with the negative side twice as strong.
    let mut file: Vec<(f64, f64)> = env.iter().rev().map(|&(d, f)| (-d, -2.0 * f)).collect();
    file.extend(env.iter().skip(1).copied());
    let (pos, neg) = (EnvelopeReadings::of(&file, 1.0), EnvelopeReadings::of(&file, -1.0));
    assert!((pos.drift_at_80_pct - 0.4).abs() < 1e-9 && (pos.plateau_slope_kn_per_pct + 1.0).abs() < 1e-9);
    assert!((neg.force_at_drift_kn[2] - 39.0).abs() < 1e-9 && (neg.drift_at_95_pct - 0.475).abs() < 1e-9);
    // Past the largest drift: no reading.
    let short: Vec<(f64, f64)> = env.iter().copied().take(16).collect();
    assert!(envelope_readings(&short, ip, 20.0).0[3].is_nan());
}

/// A measured file whose drift column is not its displacement column over the measuring
/// height is refused naming the file, the row and the column; a vertical modulus without
/// the stress it was read at is refused naming the line and the column.
#[test]
fn measured_files_that_contradict_themselves_are_refused_by_name() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/inplane_granite");
    let dir = std::env::temp_dir().join(format!("drystone_inplane_bad_{}", std::process::id()));
    let env = dir.join("envelopes");
    std::fs::create_dir_all(&env).unwrap();
    std::fs::copy(root.join("walls.csv"), dir.join("walls.csv")).unwrap();
    // WS.100's envelope with its drift read over the wall's height (1200 mm), not H0.
    let name = "envelope_WS100_Vasconcelos2005.csv";
    let text = std::fs::read_to_string(root.join("envelopes").join(name)).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let parse = |l: &str| -> Vec<f64> { l.split(',').map(|x| x.trim().parse().unwrap()).collect() };
    // The first point past 10 mm, where the two heights differ by far more than rounding.
    let i = (4..lines.len()).find(|&i| parse(&lines[i])[0] > 10.0).unwrap();
    let v = parse(&lines[i]);
    lines[i] = format!("{},{},{}", v[0], v[1], 100.0 * v[0] / 1200.0);
    std::fs::write(env.join(name), lines.join("\n")).unwrap();
    let e = drystone::study::inplane::read_specimens(&dir.join("walls.csv"), Some(&env)).unwrap_err().to_string();
    let row = format!("data row {} (line {})", i - 3, i + 1);
    assert!(e.contains(name) && e.contains(&row) && e.contains("column drift"), "{e}");
    // Epc without its stress.
    let walls = std::fs::read_to_string(root.join("walls.csv")).unwrap();
    let bad = walls.replacen(",0.5,0.524,", ",,0.524,", 1);
    std::fs::write(dir.join("walls.csv"), bad).unwrap();
    let e = drystone::study::inplane::read_specimens(&dir.join("walls.csv"), None).unwrap_err().to_string();
    assert!(e.contains("line 2") && e.contains("Epc_MPa") && e.contains("sigma0_applied_MPa"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The mechanism of a cyclic run is read over the half-cycle that opens it, as a laboratory
/// reads the push it watches: a granite wall of the bundled file (seed 20090301,
/// realization 0) cycled at 0.5 MPa to 3 % (the default ladder, three cycles an amplitude)
/// rocks, as its monotonic push does and as every specimen did (read from the state under the vertical force, the residual
/// slips of the earlier cycles made it `mixed`); its blocks stay with the wall (largest
/// excursion under 5 mm, none shed: 6.8 mm, the top course's end half-stone, when the
/// predictor repeated a loaded block's slip). The increments counted unconverged are the
/// points of the curve that say so.
#[test]
fn a_cycled_granite_wall_rocks_and_keeps_its_blocks() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("studies/walls/granite_vasconcelos.toml");
    let source = drystone::generator::DistributionSource::default_for(&path);
    let wall = drystone::generator::Wall::from_file_with(&path, &source).unwrap();
    let layout = drystone::generator::generate(&wall, 20090301, 0).unwrap().check().unwrap();
    let p = InPlaneParams { history: History::Cyclic, ..params(3.0) };
    let r = run_in_plane_penalty(&layout, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
    assert_eq!(r.mechanism.kind, MechanismKind::Rocking, "{:?}", r.mechanism.kind);
    assert!(r.largest_block_excursion_mm < 5.0, "{} mm ({})", r.largest_block_excursion_mm, r.excursion_block);
    assert!(r.shed_block.is_empty(), "{}", r.shed_block);
    assert_eq!(r.unconverged, r.curve.iter().filter(|p| !p.converged).count());
}

/// Options the run would not read, or read as a silently wrong number, are refused by name
/// before any run: a shear span or a measuring point given in millimetres (1325 for 1.325
/// m: more than ten times the wall's height; it used to be refused as `step_mm`, the path
/// of drift × H0 being too long, or, for the measuring point, run with the drift read over
/// 1.2 km); `--cycles` and `--quarter-increments` without `--cyclic` (a monotonic push
/// has no cycles: they were ignored); `--shear-span-m` with the beam held level (no shear
/// span: it was ignored, and the header printed another H0).
#[test]
fn options_the_run_would_not_read_or_would_misread_are_refused_by_name() {
    let (dir, layout) = one_block_file("drystone-inplane-unread");
    let bin = env!("CARGO_BIN_EXE_drystone");
    let base = ["--sigma0-mpa", "0.5", "--drift-pct", "0.1"];
    for (args, needle) in [
        (vec!["--shear-span-m", "1325"], "in_plane.shear_span_m = 1325 m is more than 10 times the wall's height"),
        (
            vec!["--shear-span-m", "1.325", "--measuring-height-m", "1200"],
            "in_plane.measuring_height_m = 1200 m is more than 10 times",
        ),
        (vec!["--shear-span-m", "1.325", "--cycles", "5"], "--cycles gives the cycles per amplitude"),
        (vec!["--shear-span-m", "1.325", "--quarter-increments", "20"], "--quarter-increments gives"),
        (
            vec!["--shear-span-m", "1.325", "--beam-rotation", "fixed"],
            "--shear-span-m is not read with --beam-rotation fixed",
        ),
        (vec!["--shear-span-m", "1.325", "--cyclic", "--solver", "limit"], "--cyclic is not read by limit analysis"),
    ] {
        let o = Command::new(bin).args(["in-plane", layout.to_str().unwrap()]).args(base).args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    let o = Command::new(bin)
        .args(["in-plane", layout.to_str().unwrap()])
        .args(base)
        .args(["--shear-span-m", "1.325", "--cyclic", "--cycles", "1", "--quarter-increments", "4", "--json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The shear span not given: said to be missing, not "= NaN is out of range".
    let o = Command::new(bin).args(["in-plane", layout.to_str().unwrap()]).args(base).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--shear-span-m: must be given") && !err.contains("NaN"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Options that the chosen solver does not read are refused by name, with what to do, before
/// any run: limit analysis (the collapse load from statics: no path, no displacement read,
/// no static solve) refuses `--drift-pct`, `--step-mm`, `--measuring-height-m` and
/// `--tolerance`; nscd (no static solve) refuses `--tolerance`; both, whose walls are 3D,
/// refuse `--out-of-plane`, and both, which take a contact polygon's corners, refuse the
/// penalty DEM's sub-contact mesh (`--subdivisions`). They were accepted and ignored. The
/// penalty DEM reads them all, and each solver runs without them; a mesh outside 1–64 is
/// refused naming `--subdivisions`.
#[test]
fn options_the_chosen_solver_does_not_read_are_refused_by_name() {
    let (dir, layout) = one_block_file("drystone-inplane-solver-unread");
    let bin = env!("CARGO_BIN_EXE_drystone");
    let base = ["--sigma0-mpa", "0.5", "--shear-span-m", "1.325"];
    let run = |args: &[&str]| {
        let o = Command::new(bin).args(["in-plane", layout.to_str().unwrap()]).args(base).args(args).output().unwrap();
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    for (solver, flag, value) in [
        ("limit", "--drift-pct", "0.5"),
        ("limit", "--step-mm", "0.1"),
        ("limit", "--measuring-height-m", "1.3"),
        ("limit", "--tolerance", "1e-5"),
        ("nscd", "--tolerance", "1e-5"),
        ("nscd", "--out-of-plane", "free"),
        ("limit", "--out-of-plane", "held"),
        ("nscd", "--subdivisions", "3"),
        ("limit", "--subdivisions", "1"),
    ] {
        let (code, err) = run(&["--solver", solver, flag, value]);
        assert_eq!(code, Some(2), "{solver} {flag}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(err.contains(flag) && err.contains(&format!("--solver {solver}")) && err.contains("drop"), "{err}");
    }
    // nscd reads the path's options; limit analysis runs without them.
    let (code, err) = run(&["--solver", "nscd", "--drift-pct", "0.2", "--step-mm", "0.5", "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let (code, err) = run(&["--solver", "limit", "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let (code, err) = run(&["--subdivisions", "0", "--drift-pct", "0.1"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--subdivisions 0") && err.contains("[1, 64]"), "{err}");
    let (code, err) = run(&["--subdivisions", "3", "--drift-pct", "0.1", "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// With the beam held level (`--beam-rotation fixed`) there is no shear span: the text table
/// and the JSON give none (the JSON's `shear_span_m` is null, `shear_span_definition` says
/// what it is) and name the rocking capacity's double-curvature formula, by every solver;
/// with the beam free both give H0. They printed the beam's anchor as H0 beside the
/// cantilever's formula.
#[test]
fn a_beam_held_level_reports_no_shear_span() {
    let (dir, layout) = one_block_file("drystone-inplane-fixed-h0");
    let bin = env!("CARGO_BIN_EXE_drystone");
    let run = |args: &[&str]| {
        let o = Command::new(bin)
            .args(["in-plane", layout.to_str().unwrap(), "--sigma0-mpa", "0.5"])
            .args(args)
            .output()
            .unwrap();
        assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    for solver in ["penalty", "limit"] {
        let path: &[&str] = if solver == "limit" { &[] } else { &["--drift-pct", "0.1"] };
        let fixed = [&["--beam-rotation", "fixed", "--solver", solver][..], path].concat();
        let table = run(&fixed);
        assert!(!table.contains("H0 ") && table.contains("no shear span"), "{solver}: {table}");
        assert!(table.contains("(N L + W L / 2) / H") && !table.contains("(2 H0)"), "{solver}: {table}");
        let j: serde_json::Value = serde_json::from_str(&run(&[&fixed[..], &["--json"]].concat())).unwrap();
        assert!(j["shear_span_m"].is_null(), "{solver}: {j}");
        assert_eq!(j["beam_rotation"], "fixed", "{solver}");
        assert!(j["shear_span_definition"].as_str().unwrap().contains("null with the beam held level"), "{solver}");
        let free = [&["--shear-span-m", "1.325", "--solver", solver][..], path].concat();
        assert!(run(&free).contains("H0 1.325 m"), "{solver}");
        let j: serde_json::Value = serde_json::from_str(&run(&[&free[..], &["--json"]].concat())).unwrap();
        assert_eq!(j["shear_span_m"], 1.325, "{solver}: {j}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A top course with a step is refused before any run, naming the stones: the bundled
/// granite wall (generated by the command line, its layout file edited here) with one top
/// stone raised by 2 mm, where the beam laid on it would bear on that stone alone (its
/// neighbours 2 mm below it, 160 times what their joints close under 0.5 MPa: σ0 / Kn =
/// 0.5e6 / 2e10 = 25 µm). A step within half that closure (5 µm against 12.5 µm) is taken
/// up by the joints and runs. Before, any step within 2.4 mm (0.002 of the height) passed.
#[test]
fn a_top_course_with_a_step_is_refused_naming_its_stones() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("drystone-inplane-step-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bin = env!("CARGO_BIN_EXE_drystone");
    let plain = dir.join("wall.json");
    let o = Command::new(bin)
        .args(["generate", root.join("studies/walls/granite_vasconcelos.toml").to_str().unwrap()])
        .args(["--seed", "20090301", "--out", plain.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let spec: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&plain).unwrap()).unwrap();
    let top_of = |b: &serde_json::Value| {
        b["vertices"].as_array().unwrap().iter().map(|v| v[2].as_f64().unwrap()).fold(f64::NEG_INFINITY, f64::max)
    };
    let top = spec["blocks"].as_array().unwrap().iter().map(top_of).fold(f64::NEG_INFINITY, f64::max);
    let course: Vec<String> = spec["blocks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|b| top_of(b) == top)
        .map(|b| b["id"].as_str().unwrap().to_string())
        .collect();
    assert!(course.len() >= 3, "{course:?}");
    let raised_id = course[course.len() / 2].clone();
    // The wall with its middle top stone's top face raised by `dz`.
    let raised = |dz: f64| -> (Layout, std::path::PathBuf) {
        let mut spec = spec.clone();
        for b in spec["blocks"].as_array_mut().unwrap() {
            if b["id"] == raised_id.as_str() {
                for v in b["vertices"].as_array_mut().unwrap() {
                    if v[2].as_f64().unwrap() == top {
                        v[2] = serde_json::json!(top + dz);
                    }
                }
            }
        }
        let path = dir.join(format!("raised_{dz}.json"));
        std::fs::write(&path, spec.to_string()).unwrap();
        (Layout::from_file(&path).unwrap(), path)
    };
    let p = params(1.0);
    assert!(drystone::loading::inplane::Rig::build(&Layout::from_file(&plain).unwrap(), &p).is_ok());
    assert!(drystone::loading::inplane::Rig::build(&raised(5e-6).0, &p).is_ok());
    let (wall, path) = raised(2e-3);
    let e = drystone::loading::inplane::Rig::build(&wall, &p).map(|_| ()).unwrap_err();
    assert!(matches!(e, InPlaneError::NotLevel { .. }), "{e}");
    let e = e.to_string();
    assert!(e.contains("not level") && e.contains(&format!("bear on block {raised_id}")), "{e}");
    for other in course.iter().filter(|id| **id != raised_id) {
        assert!(e.contains(other.as_str()), "{other}: {e}");
    }
    assert!(e.contains("2.000 mm below") && e.contains("0.0125 mm"), "{e}");
    // Every method refuses it: the command line by limit analysis, no run made.
    let o = Command::new(bin)
        .args(["in-plane", path.to_str().unwrap(), "--sigma0-mpa", "0.5", "--shear-span-m", "1.325"])
        .args(["--solver", "limit"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_ne!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("not level") && err.contains(&raised_id), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A study's `[in_plane]` keys that none of its runs reads are refused by name, as the
/// command line refuses the flags: the cyclic history's keys when every group is
/// monotonic, the shear span with the beam held level, the blocks free out of the plane
/// with a method other than the penalty DEM.
#[test]
fn a_study_refuses_in_plane_keys_none_of_its_runs_reads() {
    let dir = std::env::temp_dir().join(format!("drystone-inplane-study-unread-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let wall = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/walls/granite_vasconcelos.toml");
    let study = |table: &str, history: &str| {
        format!(
            "version = 1\nname = \"p\"\nseed = 1\nrealizations = 1\nprotocol = \"in_plane\"\n[in_plane]\n{table}\n\
             [[groups]]\nname = \"g\"\nwall = {:?}\nsigma0_mpa = 0.5\nhistory = \"{history}\"\n",
            wall.to_str().unwrap()
        )
    };
    for (table, history, key) in [
        ("shear_span_m = 1.325\namplitudes_pct = [0.1, 0.2]", "monotonic", "in_plane.amplitudes_pct"),
        ("shear_span_m = 1.325\ncycles = 3", "monotonic", "in_plane.cycles"),
        ("shear_span_m = 1.325\nquarter_increments = 20", "monotonic", "in_plane.quarter_increments"),
        ("shear_span_m = 1.325\nbeam_rotation = \"fixed\"", "monotonic", "in_plane.shear_span_m"),
    ] {
        let path = dir.join("s.toml");
        std::fs::write(&path, study(table, history)).unwrap();
        let err = drystone::study::Study::from_file(&path).map(|_| ()).unwrap_err().to_string();
        assert!(err.contains(key), "{table}: {err}");
    }
    let path = dir.join("s.toml");
    std::fs::write(&path, study("shear_span_m = 1.325\ncycles = 3", "cyclic")).unwrap();
    assert!(drystone::study::Study::from_file(&path).is_ok());
    // What holds the blocks out of the plane is the penalty DEM's: refused with nscd, whose
    // walls are 3D, read with the penalty DEM.
    let free = study("shear_span_m = 1.325\nout_of_plane = \"free\"", "monotonic");
    std::fs::write(&path, format!("{free}[solver]\nkind = \"nscd\"\n")).unwrap();
    let err = drystone::study::Study::from_file(&path).map(|_| ()).unwrap_err().to_string();
    assert!(err.contains("in_plane.out_of_plane") && err.contains("3D"), "{err}");
    std::fs::write(&path, free).unwrap();
    assert!(drystone::study::Study::from_file(&path).is_ok());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A cyclic history by the penalty DEM on joints whose elastic slip range `tan φ σ0 / Ks`
/// is below 20 µm is refused, naming the material, its range and the Ks that would serve
/// (its friction falls over the cycles there: `MIN_CYCLIC_SLIP_RANGE_M`); the same joints
/// pushed monotonically run, and so does the cycle on joints with the range.
#[test]
fn a_cyclic_history_on_joints_too_stiff_in_shear_for_the_penalty_dem_is_refused_by_name() {
    use drystone::loading::inplane::{InPlaneError, MIN_CYCLIC_SLIP_RANGE_M};
    let s = SolverParams::default();
    let cyclic = InPlaneParams { history: History::Cyclic, amplitudes_pct: Some(vec![0.1]), ..params(0.1) };
    // The base's φ 10° (the block's own 45°), σ0 0.5 MPa, Ks = Kn / 2.5 = 4e11 Pa/m:
    // 0.22 µm, the least of the layout's materials.
    let stiff = inplane_block(10.0, 1e12);
    let e = run_in_plane_penalty(&stiff, s, &cyclic, &mut |_, _, _| {}).unwrap_err();
    let want = 10f64.to_radians().tan() * 0.5e6 / 4e11;
    match &e {
        InPlaneError::CyclicSlipRange { range_um, ks_max_pa_per_m, .. } => {
            assert!((range_um * 1e-6 / want - 1.0).abs() < 1e-9, "{range_um} µm vs {want} m");
            assert!(
                (ks_max_pa_per_m / (10f64.to_radians().tan() * 0.5e6 / MIN_CYCLIC_SLIP_RANGE_M) - 1.0).abs() < 1e-12
            );
        }
        other => panic!("{other}"),
    }
    let text = e.to_string();
    for f in ["material ", "0.22 µm", "φ 10.0°", "20 µm", "--solver nscd", "monotonic"] {
        assert!(text.contains(f), "{f:?} not in {text}");
    }
    assert!(run_in_plane_penalty(&stiff, s, &params(0.1), &mut |_, _, _| {}).is_ok(), "monotonic runs");
    // φ 10°, Ks 4e9 Pa/m: 22 µm.
    assert!(run_in_plane_penalty(&inplane_block(10.0, 1e10), s, &cyclic, &mut |_, _, _| {}).is_ok());
}

/// A vertical stress that closes the joints past the penalty DEM's small overlaps is
/// refused by name: the monolith of 1.2 m on joints of Kn 1e9 Pa/m closes by σ0 / Kn, 20 mm
/// at 20 MPa (1.7 % of its height, over the 1 % bound), and takes at most 12 MPa.
#[test]
fn a_vertical_stress_that_closes_the_joints_past_small_overlaps_is_refused_by_name() {
    use drystone::loading::inplane::{check_joint_closure, InPlaneError, MAX_CLOSURE_SHARE};
    let s = SolverParams::default();
    let soft = inplane_block(45.0, 1e9);
    let e = run_in_plane_penalty(&soft, s, &InPlaneParams { sigma0_mpa: 20.0, ..params(0.1) }, &mut |_, _, _| {})
        .unwrap_err();
    match &e {
        InPlaneError::JointClosure { closure_mm, sigma0_max_mpa, height_mm, .. } => {
            assert!((closure_mm - 20.0).abs() < 1e-9, "{closure_mm} mm");
            assert!((height_mm - 1200.0).abs() < 1e-6, "{height_mm} mm");
            assert!((sigma0_max_mpa - MAX_CLOSURE_SHARE * 1.2 * 1e9 * 1e-6).abs() < 1e-9, "{sigma0_max_mpa} MPa");
        }
        other => panic!("{other}"),
    }
    let text = e.to_string();
    for f in ["material stone", "20 MPa", "20.000 mm", "1 %", "MPa", "--solver nscd"] {
        assert!(text.contains(f), "{f:?} not in {text}");
    }
    assert!(check_joint_closure(&soft, &InPlaneParams { sigma0_mpa: 11.9, ..params(0.1) }).is_ok());
    assert!(
        check_joint_closure(&inplane_block(45.0, 1e11), &InPlaneParams { sigma0_mpa: 1000.0, ..params(0.1) }).is_ok(),
        "stiff joints: 10 mm at 1000 MPa"
    );
}

/// A top course with stones missing is told from a block standing above the wall: two
/// courses of four 0.25 m stones (1.0 m long); with the two middle top stones left out the
/// beam would bear on the two end stones, half the length (80 % needed), and the refusal
/// names both and asks for the missing stones; one stone laid on top of the full wall
/// tops it alone and is named as a block above the wall.
#[test]
fn a_top_course_with_stones_missing_is_not_read_as_a_block_above_the_wall() {
    let stone = |i: usize, k: usize| {
        box_vertices(
            [0.25 * i as f64, -T / 2.0, 0.3 * k as f64],
            [0.25 * (i + 1) as f64, T / 2.0, 0.3 * (k + 1) as f64],
        )
    };
    let base: Vec<Vec<[f64; 3]>> = (0..4).map(|i| stone(i, 0)).collect();
    let mut gaps = base.clone();
    gaps.extend([stone(0, 1), stone(3, 1)]);
    let wall = layout_of(gaps, 1e10, 5e9, 35.0, drystone::layout::BaseSliding::Free);
    let ids: Vec<String> = wall.blocks.iter().map(|b| b.id.clone()).collect();
    let p = InPlaneParams { shear_span_m: Some(0.7), ..params(1.0) };
    let e = drystone::loading::inplane::Rig::build(&wall, &p).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains(&format!("blocks {}, {}", ids[4], ids[5])), "{e}");
    assert!(e.contains("50 %") && e.contains("stones missing from the top course"), "{e}");
    let mut above = base;
    above.extend((0..4).map(|i| stone(i, 1)));
    above.push(box_vertices([0.4, -T / 2.0, 0.6], [0.6, T / 2.0, 0.75]));
    let wall = layout_of(above, 1e10, 5e9, 35.0, drystone::layout::BaseSliding::Free);
    let lone = wall.blocks.last().unwrap().id.clone();
    let p = InPlaneParams { shear_span_m: Some(0.9), ..params(1.0) };
    let e = drystone::loading::inplane::Rig::build(&wall, &p).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains(&format!("block {lone} only")) && e.contains("above or apart from the wall"), "{e}");
}

/// A monolith 2.0 × 0.5 × 0.2 m on joints of φ = 45° under σ0 = 0.5 MPa with the force at
/// its top slides under its beam at μ N = 200 kN (its rocking capacity N_total L / (2 H0)
/// is 409 kN and its base holds μ N_total = 204 kN): the beam walks 15 mm along the top
/// while the wall stays whole. The largest block excursion is the wall's, its joints'
/// elastic deformation under the shear (μ N / (Ks L t) = 0.06 mm at the base, plus the
/// rotation's share), not the beam's slip, which is the rig's.
#[test]
fn a_beam_sliding_over_a_whole_wall_is_no_block_excursion() {
    let (l, t, h) = (2.0, 0.2, 0.5);
    let wall = layout_of(
        vec![box_vertices([0.0, -t / 2.0, 0.0], [l, t / 2.0, h])],
        1e10,
        4e9,
        45.0,
        drystone::layout::BaseSliding::Free,
    );
    let p = InPlaneParams { sigma0_mpa: 0.5, shear_span_m: Some(h), drift_pct: 3.0, ..InPlaneParams::default() };
    let dem = run_in_plane_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
    let peak = dem.positive.as_ref().unwrap().peak_force_kn;
    assert!((peak / 200.0 - 1.0).abs() < 0.005, "{peak} kN against μ N = 200 kN");
    assert_eq!(dem.mechanism.kind, MechanismKind::Sliding, "{:?}", dem.mechanism);
    assert_eq!(dem.excursion_block, "b0");
    assert!(dem.largest_block_excursion_mm < 0.5, "{} mm", dem.largest_block_excursion_mm);
}

/// The bundled granite wall (seeds 20090301 and 1, realization 0) pushed at 0.5 and
/// 0.875 MPa to 0.3 % drift by non-smooth contact dynamics rocks on a stepped crack, the
/// mechanism limit analysis finds on the same wall. A rigid part turning about a point
/// inside the wall moves its joints near the pivot by less than 5 % of the beam's motion;
/// read as joints that do not move, they joined the turning part to the table, and the
/// reading was `none` (no crack) or `diagonal` around two stray blocks.
#[test]
fn a_rigid_wall_turning_about_a_point_inside_it_reads_the_mechanism_limit_analysis_finds() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("studies/walls/granite_vasconcelos.toml");
    let source = drystone::generator::DistributionSource::default_for(&path);
    let wall = drystone::generator::Wall::from_file_with(&path, &source).unwrap();
    for (seed, sigma0_mpa) in [(20090301, 0.5), (1, 0.875)] {
        let layout = drystone::generator::generate(&wall, seed, 0).unwrap().check().unwrap();
        let p = InPlaneParams { sigma0_mpa, ..params(0.3) };
        let s = SolverParams::default();
        let la = limit_in_plane(&layout, &s, &p, &s.limit).unwrap();
        let nscd = run_in_plane_nscd(&layout, &s.nscd, &p).unwrap();
        assert_eq!(la.mechanism.kind, MechanismKind::Rocking, "seed {seed}: {:?}", la.mechanism);
        assert_eq!(nscd.mechanism.kind, la.mechanism.kind, "seed {seed}: {:?}", nscd.mechanism);
        assert_eq!(nscd.mechanism.crack, "stepped", "seed {seed}");
        assert!(!nscd.mechanism.joints.is_empty() && nscd.mechanism.moving_blocks.len() < 40, "{:?}", nscd.mechanism);
    }
}

/// Non-smooth contact dynamics' rigid contacts give the wall no elastic stiffness: its
/// curve's first points are the actuator's steps reaching the mechanism, whose secant scaled
/// with the step (317, 566 and 1,051 kN/mm at 0.5, 0.25 and 0.1 mm on the granite wall).
/// The initial stiffness is NaN by nscd, as the vertical modulus is, while the peak stays
/// within 0.5 % across the steps.
#[test]
fn nscd_reports_no_initial_stiffness_for_rigid_joints() {
    let (n, w) = forces();
    let rocking = (n + w) * L / (2.0 * H0);
    let wall = inplane_block(45.0, RIGID_KN);
    let s = SolverParams::default();
    let peaks: Vec<f64> = [0.1, 0.25]
        .into_iter()
        .map(|step_mm| {
            let r = run_in_plane_nscd(&wall, &s.nscd, &InPlaneParams { step_mm, ..params(0.3) }).unwrap();
            let d = r.positive.unwrap();
            assert!(d.initial_stiffness_kn_per_mm.is_nan(), "{}", d.initial_stiffness_kn_per_mm);
            assert!(r.wall_vertical_modulus_mpa.is_nan());
            d.peak_force_kn * 1e3
        })
        .collect();
    for p in &peaks {
        assert!((p / rocking - 1.0).abs() < 0.01, "{p} N against {rocking} N");
    }
    assert!((peaks[0] / peaks[1] - 1.0).abs() < 0.005, "{peaks:?}");
}

/// The specimens' table refuses, naming the file, the line and the column, what it read
/// before as a silently wrong or missing value: a row cut short (its last columns were read
/// as empty), a unit given twice (the comparison took one row of the two), a negative,
/// infinite or `nan` number (a negative peak force, an infinite stiffness compared as
/// such), a height of 0; the bundled table reads its 14 specimens.
#[test]
fn the_specimens_table_refuses_cut_rows_repeated_units_and_impossible_numbers() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/inplane_granite");
    let dir = std::env::temp_dir().join(format!("drystone_inplane_table_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let table = std::fs::read_to_string(root.join("walls.csv")).unwrap();
    let read = |text: &str| {
        let p = dir.join("walls.csv");
        std::fs::write(&p, text).unwrap();
        drystone::study::inplane::read_specimens(&p, None)
    };
    assert_eq!(read(&table).unwrap().len(), 14);
    let lines: Vec<&str> = table.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    // WS.100's row (line 13): no quoted field, so its cells split on commas.
    let row = lines.iter().position(|l| l.starts_with("WS.100,")).unwrap();
    assert_eq!(row + 1, 13);
    let with_cell = |column: &str, value: &str| {
        let k = header.iter().position(|h| *h == column).unwrap();
        let mut cells: Vec<String> = lines[row].split(',').map(str::to_string).collect();
        cells[k] = value.to_string();
        let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        out[row] = cells.join(",");
        out.join("\n")
    };
    let cut = {
        let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        out[row] = lines[row].split(',').take(5).collect::<Vec<_>>().join(",");
        out.join("\n")
    };
    let twice = format!("{table}{}\n", lines[row]);
    let dup_line = format!("line {}", lines.len() + 1);
    let cases: Vec<(String, Vec<&str>)> = vec![
        (cut, vec!["line 13", "5 fields", "35"]),
        (twice, vec![&dup_line, "WS.100 is given twice", "line 13"]),
        (with_cell("Vmax_pos_kN", "-30"), vec!["line 13", "column Vmax_pos_kN", "\"-30\""]),
        (with_cell("Kel_pos_kN_per_mm", "inf"), vec!["line 13", "column Kel_pos_kN_per_mm", "\"inf\""]),
        (with_cell("sigma0_applied_MPa", "nan"), vec!["line 13", "column sigma0_applied_MPa", "\"nan\""]),
        (with_cell("HLVDT_mm", "0"), vec!["line 13", "column HLVDT_mm", "0 is not a height"]),
        (with_cell("H_mm", "-1200"), vec!["line 13", "column H_mm", "\"-1200\""]),
        (with_cell("du_pos_pct", "0.5"), vec!["line 13", "column du_pos_pct", "below the drift at the peak"]),
    ];
    for (text, parts) in cases {
        let e = read(&text).unwrap_err().to_string();
        for part in parts.iter().chain(&["walls.csv"]) {
            assert!(e.contains(part), "{part:?} not in {e}");
        }
    }
    // A missing value is an empty field, as the table writes it.
    assert!(read(&with_cell("Kel_pos_kN_per_mm", "")).unwrap()[11].kel_pos.is_nan());
    // An envelope file of its four header lines alone (it read as an envelope with no point,
    // every reading of the comparison empty).
    let env = dir.join("envelopes");
    std::fs::create_dir_all(&env).unwrap();
    let name = "envelope_WS100_Vasconcelos2005.csv";
    let full = std::fs::read_to_string(root.join("envelopes").join(name)).unwrap();
    std::fs::write(env.join(name), full.lines().take(4).collect::<Vec<_>>().join("\n")).unwrap();
    let p = dir.join("walls.csv");
    std::fs::write(&p, &table).unwrap();
    let e = drystone::study::inplane::read_specimens(&p, Some(&env)).unwrap_err().to_string();
    assert!(e.contains(name) && e.contains("no reading"), "{e}");
    std::fs::write(env.join(name), &full).unwrap();
    assert!(!drystone::study::inplane::read_specimens(&p, Some(&env)).unwrap()[11].envelope.is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}
