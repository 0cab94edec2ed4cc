//! The vertical compression test (`loading::compression`, `protocol = "compression"`,
//! `drystone compression`) against closed forms computed here by hand: a stack of `c`
//! full-length courses of rigid blocks on linear joints has every joint of its height in
//! series, `E = Kn H / (c + 1)`; a linear joint returns to its settlement after every
//! unloading (no residual); a crushing joint (`q = min(Kn u, fc)`) carries no more than `fc`.
//! Its first loading branch is the in-plane test's vertical phase, the same computation: the
//! two read the same modulus on the granite walls' layout. Bad input is refused by name.

use drystone::dem::SolverParams;
use drystone::layout::Layout;
use drystone::loading::compression::{run_compression_penalty, Branch, CompressionParams};
use drystone::loading::inplane::{run_in_plane_penalty, BeamRotation, InPlaneParams};
use drystone::verify::{box_vertices, layout_of};

/// The wall: L × t × H = 1.0 × 0.2 × 1.2 m.
const L: f64 = 1.0;
const T: f64 = 0.2;
const H: f64 = 1.2;

/// A stack of `courses` full-length blocks L × t × H / courses on linear joints of normal
/// stiffness `kn` (Pa/m; Ks = Kn / 2.5, φ 45°).
fn stack(courses: usize, kn: f64) -> Layout {
    let h = H / courses as f64;
    let blocks = (0..courses).map(|c| box_vertices([0.0, 0.0, c as f64 * h], [L, T, (c + 1) as f64 * h])).collect();
    layout_of(blocks, kn, kn / 2.5, 45.0, Default::default())
}

/// Realization 0 of the granite walls' layout family (`studies/walls/granite_vasconcelos.toml`,
/// the bundled in-plane study's seed).
fn granite() -> Layout {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/walls/granite_vasconcelos.toml");
    let source = drystone::generator::DistributionSource::default_for(&path);
    let wall = drystone::generator::Wall::from_file_with(&path, &source).unwrap();
    drystone::generator::generate(&wall, 20090301, 0).unwrap().check().unwrap()
}

#[test]
fn a_stack_of_courses_reads_its_joints_in_series() {
    for courses in [2usize, 5] {
        for kn in [5e9, 2e10] {
            let p = CompressionParams { sigma0_mpa: 0.5, cycles: 2, ..CompressionParams::default() };
            let r =
                run_compression_penalty(&stack(courses, kn), SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
            let e = kn * H / (courses + 1) as f64 * 1e-6;
            for (k, s) in r.loading_secants_mpa.iter().enumerate() {
                assert!(
                    (s / e - 1.0).abs() < 0.01,
                    "{courses} courses, Kn {kn:e}, cycle {}: {s} MPa vs {e} MPa",
                    k + 1
                );
            }
            assert_eq!(r.loading_secants_mpa[0], r.wall_vertical_modulus_mpa);
            // A linear joint returns to its settlement: no residual, to a micrometre's
            // thousandth of the shortening (0.18 mm at 0.5 MPa on 6 joints of 5e9 Pa/m).
            let shortening = r.curve.iter().map(|c| c.shortening_mm).fold(0.0, f64::max);
            for d in &r.residual_settlements_mm {
                assert!(d.abs() < 1e-3 * shortening, "{courses} courses, Kn {kn:e}: residual {d} mm of {shortening}");
            }
            assert_eq!(r.unconverged, 0);
            // Every loading and unloading point lies on the line of slope E (linear joints).
            for c in r.curve.iter().filter(|c| c.branch != Branch::Start) {
                let expect = (c.stress_mpa - r.beam_stress_mpa) * H / e * 1e3;
                assert!((c.shortening_mm - expect).abs() < 0.01 * shortening, "{c:?} vs {expect} mm");
            }
        }
    }
}

/// The compression test's first loading branch and the in-plane test's vertical phase are
/// one computation ([`drystone::loading::inplane::stand_under_vertical_force`]): on the granite
/// walls' layout at 0.5 MPa they read the same modulus, the beam held level or free about
/// the in-plane study's shear span.
#[test]
fn the_first_loading_is_the_in_plane_tests_vertical_phase() {
    let wall = granite();
    for (rotation, h0) in [(BeamRotation::Fixed, None), (BeamRotation::Free, Some(1.325))] {
        let c = CompressionParams { sigma0_mpa: 0.5, beam_rotation: rotation, shear_span_m: h0, ..Default::default() };
        let comp = run_compression_penalty(&wall, SolverParams::default(), &c, &mut |_, _, _| {}).unwrap();
        let i = InPlaneParams {
            sigma0_mpa: 0.5,
            beam_rotation: rotation,
            shear_span_m: h0,
            drift_pct: 0.01,
            ..Default::default()
        };
        let inplane = run_in_plane_penalty(&wall, SolverParams::default(), &i, &mut |_, _, _| {}).unwrap();
        let (a, b) = (comp.wall_vertical_modulus_mpa, inplane.wall_vertical_modulus_mpa);
        assert!((a / b - 1.0).abs() < 1e-6, "{rotation:?}: compression {a} MPa, in-plane {b} MPa");
        // A real number of the granite walls' order (the measured Epc is 3287 MPa at 0.5 MPa).
        assert!(a > 1000.0 && a < 10_000.0, "{a}");
        assert_eq!(comp.loading_secants_mpa.len(), 3);
        assert_eq!(comp.residual_settlements_mm.len(), 3);
    }
}

/// A stack on crushing joints (`q = min(Kn u, fc)`) raised past `fc` loses equilibrium there:
/// the strength's bracket holds `fc`, the stress every joint of the full-length stack carries.
#[test]
fn a_stack_on_crushing_joints_is_as_strong_as_its_joints() {
    let mut wall = stack(2, 1e10);
    let fc = 2.0e6;
    let closure: drystone::closure::Closure =
        serde_json::from_value(serde_json::json!({"crushing": {"strength_pa": fc}})).unwrap();
    for m in &mut wall.materials {
        m.closure = closure;
    }
    let p = CompressionParams {
        sigma0_mpa: 0.5,
        cycles: 1,
        raise_to_mpa: Some(3.0),
        points_per_branch: 10,
        ..Default::default()
    };
    let r = run_compression_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
    let [lo, hi] = r.strength_bracket_mpa.expect("a bracket");
    assert!(lo <= fc * 1e-6 && fc * 1e-6 < hi, "[{lo}, {hi}] MPa vs {} MPa", fc * 1e-6);
    assert!(hi - lo < 0.3 + 1e-9, "[{lo}, {hi}]");
}

/// A vertical stress at or above the joints' crushing strength is said to crush the wall,
/// naming the joint rule and both stresses, and counted as a wall that does not stand
/// (before, the static solve ran the joints closed without end and named the loading beam
/// as a block moved some 500 km).
#[test]
fn a_vertical_stress_past_the_crushing_strength_crushes_the_wall_by_name() {
    let mut wall = stack(2, 1e10);
    let closure: drystone::closure::Closure =
        serde_json::from_value(serde_json::json!({"crushing": {"strength_pa": 2.0e6}})).unwrap();
    for m in &mut wall.materials {
        m.closure = closure;
    }
    let p = CompressionParams { sigma0_mpa: 2.5, cycles: 1, ..Default::default() };
    let e = run_compression_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap_err();
    let text = e.to_string();
    assert!(e.does_not_stand(), "{text}");
    assert!(text.contains("crushes the wall") && text.contains("fc = 2.000 MPa"), "{text}");
    assert!(!text.contains("loading_beam"), "{text}");
    // Below the strength the cycles run.
    let p = CompressionParams { sigma0_mpa: 1.5, cycles: 1, ..Default::default() };
    run_compression_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap();
    // Only the upper block's bed crushes: the base joint does not, and the refusal, which
    // speaks of the base, is not given (the static solve says what the wall does).
    let mut upper_only = stack(2, 1e10);
    let top = (0..upper_only.blocks.len())
        .max_by(|&a, &b| upper_only.blocks[a].centroid().z.total_cmp(&upper_only.blocks[b].centroid().z))
        .unwrap();
    upper_only.blocks[top].bed_closure = Some(closure);
    let p = CompressionParams { sigma0_mpa: 2.5, cycles: 1, ..Default::default() };
    let e = run_compression_penalty(&upper_only, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap_err();
    assert!(e.does_not_stand() && !e.to_string().contains("crushes the wall"), "{e}");
}

#[test]
fn bad_parameters_are_refused_by_name() {
    let wall = stack(2, 1e10);
    for (p, key) in [
        (CompressionParams { sigma0_mpa: -1.0, ..Default::default() }, "compression.sigma0_mpa"),
        (CompressionParams { cycles: 0, ..Default::default() }, "compression.cycles"),
        (CompressionParams { unload_to_mpa: Some(0.6), ..Default::default() }, "compression.unload_to_mpa"),
        (CompressionParams { unload_to_mpa: Some(1e-9), ..Default::default() }, "compression.unload_to_mpa"),
        (CompressionParams { raise_to_mpa: Some(0.4), ..Default::default() }, "compression.raise_to_mpa"),
        (CompressionParams { points_per_branch: 0, ..Default::default() }, "compression.points_per_branch"),
        // 1000 MPa closes joints of 1e10 Pa/m by 0.1 m: a unit mistake, refused at its key.
        (CompressionParams { raise_to_mpa: Some(1000.0), ..Default::default() }, "compression.raise_to_mpa"),
        (CompressionParams { beam_rotation: BeamRotation::Free, ..Default::default() }, "compression.shear_span_m"),
        (
            CompressionParams { beam_rotation: BeamRotation::Free, shear_span_m: Some(1.0), ..Default::default() },
            "compression.shear_span_m",
        ),
    ] {
        let e = run_compression_penalty(&wall, SolverParams::default(), &p, &mut |_, _, _| {}).unwrap_err().to_string();
        assert!(e.starts_with(key), "{key}: {e}");
    }
    let mut rigged = wall.clone();
    rigged.vertical_load_rig.friction = 0.05;
    let e = run_compression_penalty(&rigged, SolverParams::default(), &CompressionParams::default(), &mut |_, _, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("vertical_load_rig"), "{e}");
}

/// On the command line a parameter out of range is named by its flag, as the command's
/// help spells it (the study file's key is `compression.KEY`), and a free beam without its
/// shear span names both flags; never a panic.
#[test]
fn the_command_names_the_flag_at_fault() {
    let dir = std::env::temp_dir().join(format!("drystone-compression-flags-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let layout = dir.join("wall.json");
    let text = serde_json::json!({
        "version": 1, "name": "one block",
        "materials": [{"name": "m", "density_kg_per_m3": 2200, "kn_pa_per_m": 1e10, "ks_pa_per_m": 4e9, "friction_deg": 45}],
        "table": {"material": "m"},
        "blocks": [{"id": "wall", "material": "m", "vertices": box_vertices([0.0, -T / 2.0, 0.0], [L, T / 2.0, H])}]
    });
    std::fs::write(&layout, text.to_string()).unwrap();
    let bin = env!("CARGO_BIN_EXE_drystone");
    for (args, flag) in [
        (&["--sigma0-mpa", "-1"][..], "--sigma0-mpa"),
        (&["--sigma0-mpa", "0.5", "--cycles", "0"][..], "--cycles"),
        (&["--sigma0-mpa", "0.5", "--unload-to-mpa", "0.6"][..], "--unload-to-mpa"),
        (&["--sigma0-mpa", "0.5", "--raise-to-mpa", "0.4"][..], "--raise-to-mpa"),
        (&["--sigma0-mpa", "0.5", "--points-per-branch", "0"][..], "--points-per-branch"),
        (&["--sigma0-mpa", "0.5", "--beam-rotation", "free"][..], "--shear-span-m"),
        // Refused once the wall is known: below the beam's own weight, a lever under the
        // wall's top.
        (&["--sigma0-mpa", "1e-9"][..], "--sigma0-mpa"),
        (&["--sigma0-mpa", "0.5", "--unload-to-mpa", "0"][..], "--unload-to-mpa"),
        (&["--sigma0-mpa", "0.5", "--beam-rotation", "free", "--shear-span-m", "0.01"][..], "--shear-span-m"),
    ] {
        let o = std::process::Command::new(bin)
            .args(["compression", layout.to_str().unwrap()])
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(flag) && !err.contains("compression.") && !err.contains("panicked"), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
