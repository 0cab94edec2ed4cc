//! The DEM pushover of the lateral load (`loading::lateral_pushover`) against closed-form
//! statics of a single block and against limit analysis of a small wall.

use drystone::dem::SolverParams;
use drystone::layout::{BaseSliding, Layout};
use drystone::limit::{limit_lateral, LimitParams};
use drystone::loading::lateral::LateralParams;
use drystone::loading::lateral_pushover::{run_lateral_pushover, LateralPushover};
use drystone::loading::mechanism::MechanismKind;
use drystone::loading::tilt::CollapseReason;
use drystone::protocol::run_lateral;
use drystone::units::STANDARD_GRAVITY as G;
use drystone::verify::{box_vertices, layout_of, DENSITY};
use std::path::Path;

use crate::common;

/// A block L (x) × B (y) × h (z) centred on y = 0 on the table, with the layout's one
/// material given Kn = `kn`, Ks = Kn / 2, friction `phi_deg`, cohesion `c` and tensile
/// strength `t` (Pa).
fn block(l: f64, b: f64, h: f64, kn: f64, phi_deg: f64, c: f64, t: f64) -> Layout {
    let mut layout =
        layout_of(vec![box_vertices([0.0, -b / 2.0, 0.0], [l, b / 2.0, h])], kn, kn / 2.0, phi_deg, BaseSliding::Free);
    layout.materials[0].cohesion = c;
    layout.materials[0].tensile_strength = t;
    layout
}

fn uniform(p: f64, resolution: f64) -> LateralParams {
    LateralParams {
        pressure_base_pa: p,
        pressure_top_pa: p,
        pushover_resolution: Some(resolution),
        ..LateralParams::default()
    }
}

fn push(layout: &Layout, params: &LateralParams) -> LateralPushover {
    run_lateral_pushover(layout, SolverParams::default(), params).expect("pushover")
}

/// The collapse multiplier of a block L × B × h on a no-tension Winkler joint (Kn per unit
/// area) under a horizontal dead load F = λ p L h through its centroid (a uniform
/// pressure on its −y face): with the base open but for a strip a wide at the toe, the
/// joint carries N = W = Kn L θ a² / 2 at a/3 from the toe, so θ = 2 W / (Kn L a²), and
/// moments about the toe give F = W (B/2 − a/3 − θ h/2) / (h/2 + (B/2 − a/3) θ) (the
/// base shear acting at the joint). The wall collapses at the largest F along that path
/// (a shrinking from B): λ = max over a of F / (p L h). Rigid (Kn → ∞): λ = W B / (p L h²).
fn winkler_lambda(l: f64, b: f64, h: f64, kn: f64, p: f64) -> f64 {
    let w = DENSITY * G * l * b * h;
    let f = |a: f64| {
        let theta = 2.0 * w / (kn * l * a * a);
        let arm = b / 2.0 - a / 3.0;
        w * (arm - theta * h / 2.0) / (h / 2.0 + arm * theta)
    };
    // A fine scan of (0, B], then a golden-section refinement of the best bracket.
    let n = 20_000;
    let k = (1..=n).max_by(|&i, &j| f(b * i as f64 / n as f64).total_cmp(&f(b * j as f64 / n as f64))).unwrap();
    let (mut lo, mut hi) = (b * (k - 1).max(1) as f64 / n as f64, b * (k + 1).min(n) as f64 / n as f64);
    let r = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..100 {
        let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if f(x1) < f(x2) {
            lo = x1;
        } else {
            hi = x2;
        }
    }
    f(0.5 * (lo + hi)) / (p * l * h)
}

/// A slender block (B / h = 1/3, φ 40°, c 2 kPa, no tension) under a uniform pressure p
/// overturns about its toe: at the Winkler multiplier of its finite Kn
/// ([`winkler_lambda`]), which approaches the rigid statics λ = W B / (p L h²) as Kn grows
/// (sliding would need λ ≥ (c L B + W tan φ) / (p L h), over twice more; the cohesion gives
/// no overturning resistance: the heel opens and, with no tensile strength, loses it).
#[test]
fn a_block_overturns_at_the_winkler_multiplier_approaching_statics_as_kn_grows() {
    let (l, b, h, p) = (0.4, 0.2, 0.6, 1000.0);
    let w = DENSITY * G * l * b * h;
    let rigid = w * b / (p * l * h * h);
    assert!((2000.0 * l * b + w * 40f64.to_radians().tan()) / (p * l * h) > 2.0 * rigid);
    let mut errors = Vec::new();
    for kn in [1e7, 1e8, 1e9, 1e10] {
        let want = winkler_lambda(l, b, h, kn, p);
        let r = push(&block(l, b, h, kn, 40.0, 2000.0, 0.0), &uniform(p, 0.005));
        let up = r.lambda_unstable.expect("overturns");
        assert!(up > r.lambda_stable && up - r.lambda_stable <= 0.005 * up + 1e-12, "{r:?}");
        let mid = 0.5 * (r.lambda_stable + up);
        eprintln!("Kn {kn:e}: DEM [{}, {up}], Winkler {want:.4}, rigid {rigid:.4}", r.lambda_stable);
        assert!(
            (mid - want).abs() < 0.02 * want,
            "Kn {kn:e}: DEM [{}, {up}] against the Winkler {want} (rigid {rigid})",
            r.lambda_stable
        );
        let m = r.mechanism.as_ref().expect("mechanism");
        assert_eq!(m.kind, MechanismKind::Toppling, "Kn {kn:e}: {m:?}");
        assert_eq!(m.joint, "table/b0");
        assert_ne!(r.collapse_reason, Some(CollapseReason::StepBudget));
        assert!(r.lambda_stable < rigid);
        errors.push((rigid - mid) / rigid);
    }
    // Below the rigid statics by less and less as Kn grows (as Kn^(-1/3)).
    assert!(errors.windows(2).all(|e| e[1] < e[0]), "{errors:?}");
    assert!(errors[3] < 0.07 && errors[0] > 0.3, "{errors:?}");
}

/// A squat block (h / B = 0.1) slides: Coulomb with cohesion, λ p L h = c L B + W tan φ, if
/// the whole base reaches its strength at once (ductile cohesion). The cohesion of a
/// sub-contact is lost where it slips, and the shear traction of a translating block is
/// uniform while the normal traction is not (the moment of the pressure about the base):
/// the first slip, at the least-compressed edge, starts a cascade at
/// λ₁ = (c L B + W tan φ) / (p L h (1 + 3 (h/B) tan φ)) (linear normal traction
/// σ = W / (L B) ∓ 6 M / (L B²), M = λ p L h · h/2). λ lies between the two; with the
/// default sub-contacts (the base's two triangles, each judged on its resultant) the whole
/// base slips at once and λ is the ductile value to 1 %. This needs a
/// tensile strength: a joint without one keeps no cohesion where a sub-contact carries no
/// compression (`dem::contact::law::evaluate`), as this block's do at their first step
/// (it is placed on the table at zero closure), so that joint slides at the
/// cohesionless Coulomb λ = W tan φ / (p L h), as a joint with neither.
#[test]
fn a_squat_block_slides_at_coulomb_with_cohesion() {
    let (l, b, h, p) = (0.5, 1.0, 0.1, 1000.0);
    let (phi, c) = (15.0f64, 2000.0);
    let w = DENSITY * G * l * b * h;
    let t = phi.to_radians().tan();
    let ductile = (c * l * b + w * t) / (p * l * h);
    let first_slip = ductile / (1.0 + 3.0 * (h / b) * t);
    // Overturning is far off.
    assert!(w * b / (p * l * h * h) > 5.0 * ductile);
    for kn in [1e8, 1e9] {
        let r = push(&block(l, b, h, kn, phi, c, 1e4), &uniform(p, 0.005));
        let up = r.lambda_unstable.expect("slides");
        assert!(
            up >= first_slip * 0.995 && r.lambda_stable <= ductile && up >= 0.99 * ductile,
            "Kn {kn:e}: [{}, {up}] against [{first_slip}, {ductile}]",
            r.lambda_stable
        );
        eprintln!(
            "sliding, Kn {kn:e}: DEM [{}, {up}], first slip {first_slip:.4}, ductile {ductile:.4}",
            r.lambda_stable
        );
        assert_eq!(r.mechanism.as_ref().expect("mechanism").kind, MechanismKind::Sliding, "{r:?}");
    }
    let coulomb = w * t / (p * l * h);
    for (c, what) in [(0.0, "no cohesion"), (c, "cohesion without tensile strength")] {
        let r = push(&block(l, b, h, 1e9, phi, c, 0.0), &uniform(p, 0.005));
        let up = r.lambda_unstable.expect("slides");
        assert!(r.lambda_stable <= coulomb && up >= coulomb, "{what}: [{}, {up}] against {coulomb}", r.lambda_stable);
    }
}

/// The pushover's first increment is the service load (λ = 1): its displacements are the
/// static lateral load's equilibrium (the same state to the equilibrium tolerance, reached
/// by another static method).
#[test]
fn the_first_increment_is_the_service_load() {
    let layout = block(0.5, 0.3, 0.6, 1e8, 40.0, 0.0, 0.0);
    // The table's former key `tolerance` (deprecated: `[solver.penalty] tolerance`) still
    // sets the tolerance of both runs.
    let params = LateralParams { tolerance: Some(1e-6), ..uniform(500.0, 0.02) };
    let service = run_lateral(&layout, SolverParams::default(), &params).expect("stands");
    let r = push(&layout, &params);
    let d = r.service_displacement_m().expect("λ = 1 stable");
    for (a, b) in d.iter().zip(&service.displacement_m) {
        assert!((a - b).abs() < 0.01 * b.abs(), "{d:?} against {:?}", service.displacement_m);
    }
    assert_eq!(r.resultant_n, service.resultant_n);
    assert!(r.increments.iter().filter(|i| i.stable).all(|i| i.load_multiplier <= r.lambda_stable));
}

/// The 13-box running-bond wall (t 0.1 m, H 0.3 m, φ 35°, no cohesion) under a uniform
/// pressure: limit analysis of the same layout gives the rigid collapse multiplier λ_R; the
/// DEM pushover, with finite Kn, lies below it, by a gap that shrinks as Kn^(-1/3) (the
/// no-tension Winkler joint under the toe: the contact width at collapse scales so, as in
/// [`winkler_lambda`]), so that the extrapolation of two decades of Kn to Kn → ∞ meets λ_R.
#[test]
fn a_small_wall_pushed_over_approaches_limit_analysis() {
    let mut layout =
        Layout::from_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("data/layouts/rigid/running_bond_13.json"))
            .expect("layout");
    let params = uniform(1000.0, 0.005);
    let rigid = limit_lateral(&layout, &SolverParams::default(), &params, &LimitParams::default())
        .expect("limit")
        .load_multiplier;
    let mut dem = Vec::new();
    for kn in [1e8, 1e9, 1e10] {
        layout.materials[0].kn = kn;
        layout.materials[0].ks = kn / 2.0;
        let r = push(&layout, &params);
        let up = r.lambda_unstable.expect("collapses");
        assert!(r.lambda_stable < rigid, "Kn {kn:e}: {} against the rigid {rigid}", r.lambda_stable);
        dem.push(0.5 * (r.lambda_stable + up));
    }
    let decade = 10f64.powf(-1.0 / 3.0);
    let gaps: Vec<f64> = dem.iter().map(|l| rigid - l).collect();
    for g in gaps.windows(2) {
        let ratio = g[1] / g[0];
        assert!((ratio - decade).abs() < 0.08, "gap ratio per decade {ratio} against {decade}: {dem:?} vs {rigid}");
    }
    let extrapolated = (dem[2] - decade * dem[1]) / (1.0 - decade);
    eprintln!("13-box wall: DEM {dem:?} at Kn 1e8, 1e9, 1e10; extrapolated {extrapolated:.4}; limit {rigid:.4}");
    assert!((extrapolated - rigid).abs() < 0.02 * rigid, "{extrapolated} against {rigid} ({dem:?})");
}

/// Bad input: a resolution out of (0, 1) names the parameter; the static lateral load by nscd
/// is refused at the protocol seam.
#[test]
fn bad_parameters_are_named() {
    let layout = block(0.4, 0.2, 0.6, 1e8, 40.0, 0.0, 0.0);
    let e = run_lateral_pushover(&layout, SolverParams::default(), &uniform(1000.0, 1.5)).unwrap_err();
    assert!(e.to_string().contains("pushover_resolution"), "{e}");
    // The static lateral load by nscd is refused at the seam, naming the solvers that run it.
    let nscd = SolverParams { kind: drystone::dem::SolverKind::Nscd, ..SolverParams::default() };
    let e = drystone::protocol::run_lateral(&layout, nscd, &uniform(1000.0, 0.02)).unwrap_err();
    assert!(matches!(e, drystone::loading::lateral::LateralError::Unsupported(_)), "{e}");
    assert!(e.to_string().contains("penalty") && e.to_string().contains("nscd"), "{e}");
}

/// A study with `[lateral] pushover = true`: every row has the DEM and the limit
/// multipliers beside its service displacement, the DEM's below the cohesionless rigid
/// limit; the tables, the summary and the report carry them, and the Parquet table reads
/// back bit for bit. A lateral study without it writes no such column.
#[test]
fn a_pushover_study_writes_its_multipliers() {
    use drystone::ensemble::Shard;
    use drystone::study::{run_study, write_outputs, Study};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = root.join("tests/studies/good/mini_pushover.toml");
    let study = Study::from_file(&file).expect("study");
    let rows = run_study(&study, Shard::ALL);
    assert_eq!(rows.len(), 2);
    for r in &rows {
        assert!(r.status.is_ok() && r.error.is_empty(), "{r:?}");
        let p = &r.pushover;
        let (dem, up, limit) =
            (p.load_multiplier_dem.unwrap(), p.load_multiplier_dem_unstable.unwrap(), p.load_multiplier_limit.unwrap());
        assert!(dem > 1.0 && up > dem && dem < limit, "{p:?}");
        assert!(r.lateral.lateral_disp_max_cm.is_some() && !r.collapse.mechanism.is_empty(), "{r:?}");
    }
    // Cohesion (first point) raises the limit analysis' λ; the DEM's joints, with no tensile
    // strength, lose it where they open, as this wall's do.
    assert!(rows[0].pushover.load_multiplier_limit > rows[1].pushover.load_multiplier_limit);
    let dir = common::Scratch::new("pushover-study");
    write_outputs(&study, &file, Shard::ALL, &rows, &dir).expect("outputs");
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    let header = read("realizations.csv").lines().next().unwrap().to_string();
    assert!(header.ends_with("load_multiplier_dem,load_multiplier_dem_unstable,load_multiplier_limit"), "{header}");
    assert!(read("summary.csv").lines().next().unwrap().contains("load_multiplier_dem_over_limit_mean"));
    assert!(read("report.md").contains("## Collapse load multiplier of the pressure"));
    let back = drystone::io::table::read_realizations(&dir.join("realizations.parquet")).unwrap();
    assert_eq!(back, rows);
    // Without `pushover`, no such column.
    let plain = Study::from_file(&root.join("tests/studies/good/mini_lateral.toml")).expect("study");
    let rows = run_study(&plain, Shard::ALL);
    let other = common::Scratch::new("pushover-plain");
    write_outputs(&plain, &file, Shard::ALL, &rows, &other).expect("outputs");
    let text = std::fs::read_to_string(other.join("realizations.csv")).unwrap();
    assert!(!text.contains("load_multiplier"), "{}", text.lines().next().unwrap());
    assert!(!std::fs::read_to_string(other.join("summary.csv")).unwrap().contains("load_multiplier"));
}

/// The pushover of a wall is the same bit for bit run after run and inside rayon pools of
/// 1 and 2 threads (everything but the wall-clock time; the displacements by their bits).
#[test]
fn a_pushover_is_identical_on_1_and_2_threads() {
    use rayon::prelude::*;
    let layout = Layout::from_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("data/layouts/running_bond_wall.json"))
        .expect("layout");
    let params = uniform(1000.0, 0.02);
    let print = || {
        let mut r = push(&layout, &params);
        r.wall_time_s = 0.0;
        let bits: Vec<u64> = r.increments.iter().flat_map(|i| i.displacement_m.iter().map(|d| d.to_bits())).collect();
        (serde_json::to_string(&r).unwrap(), bits, r.lambda_stable.to_bits())
    };
    let reference = print();
    assert!(!reference.0.contains("\"lambda_unstable\":null"), "the wall collapses");
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let prints: Vec<_> = pool.install(|| (0..2).into_par_iter().map(|_| print()).collect());
        for p in prints {
            assert_eq!(p, reference, "{threads} threads");
        }
    }
}

/// `drystone lateral LAYOUT --pushover --json` prints the fields of the rigid pushover
/// (`--solver nscd`, the same wall) with the DEM's values, and the collapse reason.
#[test]
fn the_cli_pushover_json_has_the_rigid_pushovers_fields() {
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/layouts/running_bond_wall.json");
    let run = |extra: &[&str]| -> serde_json::Value {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_drystone"))
            .arg("lateral")
            .arg(&layout)
            .arg("--json")
            .args(extra)
            .output()
            .expect("runs");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice(&out.stdout).expect("JSON")
    };
    let dem = run(&["--pushover"]);
    let rigid = run(&["--solver", "nscd"]);
    for key in rigid.as_object().unwrap().keys().filter(|k| *k != "rigid_joints") {
        assert!(dem.get(key).is_some(), "{key} missing from {dem}");
    }
    assert_eq!(dem["load_multiplier"], dem["lambda_stable"]);
    let (lo, up) = (dem["lambda_stable"].as_f64().unwrap(), dem["lambda_unstable"].as_f64().unwrap());
    assert!(lo > 0.0 && up > lo && up - lo <= 0.02 * up + 1e-12, "{dem}");
    assert!(dem["collapse_reason"].is_string() && dem["mechanism"]["joint"].is_string(), "{dem}");
    // The rigid limit bounds the DEM's multiplier from above (finite Kn).
    assert!(lo < rigid["lambda_unstable"].as_f64().unwrap(), "{dem} against {rigid}");
    // The rigid pushover's bracket: 1 % of λ by default, and `--pushover-resolution` when
    // given (a wider bracket ends the bisection sooner, around the same limit).
    let width = |v: &serde_json::Value| {
        let (lo, up) = (v["lambda_stable"].as_f64().unwrap(), v["lambda_unstable"].as_f64().unwrap());
        (lo, up, (up - lo) / up)
    };
    let (rlo, rup, w) = width(&rigid);
    assert!(w <= 0.01 + 1e-12, "{rigid}");
    let coarse = run(&["--solver", "nscd", "--pushover-resolution", "0.1"]);
    let (clo, cup, cw) = width(&coarse);
    assert!(cw <= 0.1 + 1e-12 && cw > 0.01, "the resolution given is the one run: {coarse}");
    assert!(clo <= rup && cup >= rlo, "the brackets overlap: {coarse} against {rigid}");
}
