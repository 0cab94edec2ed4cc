//! Real stones: four scanned stones of the StonePacking-3D data set (MIT licence,
//! `data/stones/README.md`), stacked into a wall of three courses by `data/stones/stack.py`
//! (`data/stones/wall/`), imported by `drystone import` and tilted to collapse by the penalty
//! DEM and by non-smooth contact dynamics, against limit analysis.
//!
//! The expected volumes and sizes are those `stack.py` computes from the meshes (its own
//! convex hull and divergence theorem, in Python), never the code under test's.

use drystone::dem::{SolverKind, SolverParams};
use drystone::layout::{Layout, MaterialSpec};
use drystone::limit::{limit_tilt, FlowRule, LimitParams};
use drystone::loading::mechanism::MechanismKind;
use drystone::loading::tilt::{CollapseReason, TiltParams};
use drystone::protocol::run_tilt;
use drystone::survey::{import, ImportOptions, ImportedWall, LengthUnit, SurveyMaterials};
use std::path::Path;

/// The joint the wall fails at: stone_110 (course 2) tips off stone_067 (course 1), taking
/// stone_089 (course 3) with it.
const GOVERNING: &str = "c1_stone_067/c2_stone_110";

/// The wall as `drystone import data/stones/wall --unit cm --density 2600 --kn 1e10
/// --ks 5e9 --friction-deg 35` reads it.
fn wall() -> ImportedWall {
    let stone = MaterialSpec {
        name: "stone".into(),
        density_kg_per_m3: 2600.0,
        kn_pa_per_m: 1e10,
        ks_pa_per_m: 5e9,
        friction_deg: 35.0,
        cohesion_pa: 0.0,
        tensile_strength_pa: 0.0,
        closure: Default::default(),
    };
    let options = ImportOptions {
        format: None,
        scale_m_per_unit: None,
        section: None,
        hull_nonconvex: false,
        unit: Some(LengthUnit::Cm),
        y_up: false,
        materials: SurveyMaterials::one(stone),
        base_sliding: Default::default(),
        name: None,
        max_hull_vertices: None,
        full_hull: false,
    };
    import(&Path::new(env!("CARGO_MANIFEST_DIR")).join("data/stones/wall"), &options).expect("the wall imports")
}

/// Each stone's block is its mesh's convex hull: the stone's own volume and its hull's are
/// those `stack.py` reports (cm³, to 1e-9), the hulls add 8–16 %, the block's mass
/// properties are the mesh's (its volume and centroid), and the two stones of course 1
/// stand on the table.
#[test]
fn a_wall_of_scanned_stones_imports_with_each_stones_volume_and_its_hulls() {
    let w = wall();
    let expected = [
        ("c1_stone_003", 1142.1408772938353, 1324.0451678701806),
        ("c1_stone_067", 1109.2903556567169, 1265.2602725349664),
        ("c2_stone_110", 1094.7690372504956, 1185.3901400662667),
        ("c3_stone_089", 463.55171435061317, 537.7216333369906),
    ];
    assert_eq!(w.stones.len(), expected.len());
    for (s, (id, stone_cm3, hull_cm3)) in w.stones.iter().zip(expected) {
        assert_eq!(s.id, id);
        assert!(s.hulled, "{id}");
        let (stone, hull) = (s.survey_volume_m3 * 1e6, s.block_volume_m3 * 1e6);
        assert!((stone - stone_cm3).abs() < 1e-9 * stone_cm3, "{id}: mesh {stone} cm³, stack.py {stone_cm3}");
        assert!((hull - hull_cm3).abs() < 1e-9 * hull_cm3, "{id}: hull {hull} cm³, stack.py {hull_cm3}");
        let excess = hull / stone - 1.0;
        assert!((0.05..0.20).contains(&excess), "{id}: the hull adds {:.1} %", 100.0 * excess);
    }
    // Each block's mass properties are its mesh's: its volume, and its centroid as
    // `stack.py`'s `volume_centroid` gives it from the mesh (in the wall's table frame: x
    // from the leftmost point, y centred, z from the lowest, metres).
    let centroids = [
        [0.07002438692031474, -0.007461321858874263, 0.048438210266151235],
        [0.2158597143837619, -0.020569587736314395, 0.04024605928917988],
        [0.10978754027715391, 0.015984706178737835, 0.13000738709758375],
        [0.09284770645532943, 0.018110994200081002, 0.1963323772539728],
    ];
    for ((b, s), c) in w.layout.blocks.iter().zip(&w.stones).zip(centroids) {
        let own = b.own_mass.unwrap_or_else(|| panic!("{}: no own mass", b.id));
        assert_eq!(own.volume_m3, s.survey_volume_m3, "{}", b.id);
        for k in 0..3 {
            assert!(
                (own.centroid_m[k] - c[k]).abs() < 1e-12,
                "{}: centroid {:?}, stack.py {c:?}",
                b.id,
                own.centroid_m
            );
        }
    }
    assert!((w.added_m3() - (w.volume_m3() - w.stones.iter().map(|s| s.survey_volume_m3).sum::<f64>())).abs() < 1e-15);
    assert_eq!(w.on_table(), 2);
    assert!((w.length_m - 0.29386092585551303).abs() < 1e-9, "{}", w.length_m);
    assert!((w.height_m - 0.24451011099692057).abs() < 1e-9, "{}", w.height_m);
    w.layout.resolve().expect("the layout resolves");
}

/// Limit analysis, nscd and the penalty DEM on the same wall, each from the contacts as
/// built (every stone on a face of its hull, face to face with the stones below).
///
/// * Limit analysis: nothing slides in its mechanism at φ = 35° (stone_110 and stone_089
///   tip off stone_067 as one body), so its associative answer needs no non-associative
///   correction and is the rigid limit of the wall's contacts: 23.672° with the stones'
///   own masses (their meshes'; 22.835° with their hulls' masses, which put the tipping
///   stones' centroids further out).
/// * nscd (rigid blocks, the same contact detection): its bisection holds that limit and
///   names the same joint, within 0.1°. A trial a few hundredths of a degree past the limit
///   sets the mechanism off at about g sin δ, slowly enough that the trial's growth test
///   may not tell it from settling (the bracket is [23.75, 23.83]).
/// * The penalty DEM: a no-tension elastic joint tips before the rigid limit, by a loss that
///   shrinks with Kn (3.8° at 1e10 Pa/m; docs/survey.md): at 1e10 the bracket must lie
///   below the rigid limit and within 5° of it. Two sub-contact subdivisions: a
///   hull's faces are triangles, each fanned into three sub-contacts, and at one
///   subdivision their three shear springs hold too little twist about the joint's normal
///   (the wall collapses at 4.88°, the top stone sliding off).
#[test]
fn a_wall_of_scanned_stones_collapses_by_both_dynamic_methods_within_the_bracket_of_limit_analysis() {
    let layout: Layout = wall().layout.resolve().unwrap();
    let la = limit_tilt(&layout, &SolverParams::default(), &LimitParams::default()).expect("limit analysis");
    let alpha = la.collapse_angle_deg.expect("an angle");
    assert_eq!(la.governing, FlowRule::Associative, "{:?}", la.mechanism);
    assert!(la.non_associative.is_none(), "nothing slides: no correction");
    assert_eq!(la.mechanism.kind, MechanismKind::Toppling);
    assert_eq!(la.mechanism.joint, GOVERNING);
    assert!((alpha - 23.672).abs() < 0.01, "limit analysis {alpha}°");

    let params = TiltParams::default();
    let nscd = run_tilt(&layout, SolverParams { kind: SolverKind::Nscd, ..SolverParams::default() }, &params)
        .expect("nscd tilt");
    let up = nscd.first_unstable_deg.expect("nscd: collapses");
    assert!(nscd.bracket_reliable);
    assert!(
        nscd.last_stable_deg - 0.1 <= alpha && alpha <= up + 0.1,
        "nscd [{}, {up}] misses the limit analysis {alpha}° by more than 0.1°",
        nscd.last_stable_deg
    );
    assert_eq!(nscd.mechanism.joint, GOVERNING, "{:?}", nscd.mechanism);

    let penalty = SolverParams { subcontact_subdivisions: 2, ..SolverParams::default() };
    let dem = run_tilt(&layout, penalty, &params).expect("penalty tilt");
    let up = dem.first_unstable_deg.expect("penalty: collapses");
    assert_ne!(dem.collapse_reason, Some(CollapseReason::StepBudget), "step budget at {up}°");
    assert!(
        dem.last_stable_deg < alpha && up >= alpha - 5.0,
        "penalty DEM [{}, {up}] against the limit analysis {alpha}°: not below it, or more than 5° below",
        dem.last_stable_deg
    );
}

/// A study whose group names the folder of scanned stones: every realization is the wall
/// as scanned (no uncertainty is drawn around meshes), run by the study's protocol and
/// method as the imported layout is run alone: by limit analysis, the limit of the layout
/// `drystone import` makes, and by nscd, its bracket, the same in every realization. The
/// keys of a traced elevation are refused naming the group's key.
#[test]
fn a_study_of_scanned_stones_runs_the_wall_as_scanned_in_every_realization() {
    use drystone::ensemble::Shard;
    use drystone::study::{run_study, Study};
    let dir = crate::common::Scratch::created("survey-scanned-study");
    let stones = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/stones/wall");
    let import = "unit = \"cm\"\ndensity = 2600\nkn = 1e10\nks = 5e9\nfriction_deg = 35\n";
    let study = |name: &str, solver: &str, extra: &str| {
        let text = format!(
            "version = 1\nname = \"{name}\"\nseed = 3\nrealizations = 2\nprotocol = \"tilt\"\n[solver]\nkind = \
             \"{solver}\"\n[[groups]]\nname = \"stones\"\nsurvey = {:?}\n[groups.import]\n{import}{extra}",
            stones.display().to_string()
        );
        let p = dir.join(format!("{name}.toml"));
        std::fs::write(&p, text).unwrap();
        p
    };
    let layout: Layout = wall().layout.resolve().unwrap();
    let la = limit_tilt(&layout, &SolverParams::default(), &LimitParams::default()).unwrap();
    let alpha = la.collapse_angle_deg.unwrap();
    let nscd =
        run_tilt(&layout, SolverParams { kind: SolverKind::Nscd, ..SolverParams::default() }, &TiltParams::default())
            .unwrap();
    for (name, solver, want) in [("by_limit", "limit", alpha), ("by_nscd", "nscd", nscd.collapse_angle_deg())] {
        let s = Study::from_file(&study(name, solver, "")).unwrap();
        let rows = run_study(&s, Shard::ALL);
        assert_eq!(rows.len(), 2, "{name}");
        for r in &rows {
            let got = r.collapse.collapse_angle_deg.unwrap_or_else(|| panic!("{name} r{}: {}", r.realization, r.error));
            assert_eq!(r.blocks, 4, "{name}");
            assert!((got - want).abs() < 1e-9, "{name} r{}: {got}° against the layout alone {want}°", r.realization);
        }
    }
    for (key, line) in [("tolerance_m", "tolerance_m = 0.001\n"), ("thickness_m", "thickness_m = 0.2\n")] {
        let e = Study::from_file(&study("bad", "limit", line)).unwrap_err().to_string();
        assert!(e.contains(&format!("groups[stones].import.{key}")) && e.contains("scanned"), "{e}");
    }
    let text = std::fs::read_to_string(study("bad_unit", "limit", "")).unwrap().replace("\"cm\"", "\"inch\"");
    std::fs::write(dir.join("bad_unit.toml"), text).unwrap();
    let e = Study::from_file(&dir.join("bad_unit.toml")).unwrap_err().to_string();
    assert!(e.contains("groups[stones].import.unit") && e.contains("inch"), "{e}");
}
