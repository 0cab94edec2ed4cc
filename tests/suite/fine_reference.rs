//! The tilting table at its defaults against fine references: the main job's walls
//! (`studies/tilting_table.toml`) tilted with the defaults give collapse brackets within one
//! bracket width (0.125°) of the same walls solved to an unbalanced-force ratio ten times
//! tighter (1e-5 against 1e-4), and top displacements at 5° and 10° within 2 %; and the
//! default sub-contact mesh (two subdivisions) gives the collapse bracket of a mesh twice as
//! fine.
//!
//! The reference, `data/reference/main_job_fine.csv`, is the main job's 36 walls at the
//! tighter tolerance, recorded once: `drystone run` of the study with `tolerance = 1e-5`
//! under `[solver.penalty]` (BENCHMARKS.md, "Tilting table: the fine reference"). It is the
//! convergence check of a solver change that moves results: the numerics may change, the
//! answer may not, beyond one bracket.

use drystone::ensemble::Shard;
use drystone::study::{run_study, Study};
use std::collections::HashMap;
use std::path::PathBuf;

/// `(group, realization)` → (collapse angle °, first unstable °, mean top displacement at
/// 5° and 10°, cm) of the fine reference.
fn reference() -> HashMap<(String, u64), [f64; 4]> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("data/reference/main_job_fine.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let v = |i: usize| f[i].parse::<f64>().unwrap();
            ((f[0].to_string(), f[2].parse().unwrap()), [v(3), v(4), v(5), v(6)])
        })
        .collect()
}

/// The first realizations of every group of the main job, at the defaults, against the
/// fine reference (the full 36 walls were compared when the reference was recorded).
#[test]
fn the_default_tilt_stays_within_one_bracket_of_the_fine_reference() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let study = Study::from_file(&root.join("studies/tilting_table.toml")).unwrap();
    let study = Study { realizations: 2, ..study };
    let bracket = study.protocol.tilt().unwrap().resolution_deg;
    let reference = reference();
    assert_eq!(reference.len(), 36);
    let rows = run_study(&study, Shard::ALL);
    assert_eq!(rows.len(), 6);
    for r in &rows {
        let fine = reference[&(r.group.clone(), r.realization)];
        let alpha = r.collapse.collapse_angle_deg.unwrap();
        let upper = r.collapse.first_unstable_deg.unwrap();
        let at = |t: f64| {
            let i = r.tilt.tilt_deg.iter().position(|&x| (x - t).abs() < 1e-9).unwrap();
            (r.tilt.disp_top_left_cm[i] + r.tilt.disp_top_centre_cm[i] + r.tilt.disp_top_right_cm[i]) / 3.0
        };
        let what = format!("{} realization {}", r.group, r.realization);
        assert!((alpha - fine[0]).abs() <= bracket + 1e-9, "{what}: α_max {alpha}° against {}°", fine[0]);
        assert!((upper - fine[1]).abs() <= bracket + 1e-9, "{what}: first unstable {upper}° against {}°", fine[1]);
        for (t, want) in [(5.0, fine[2]), (10.0, fine[3])] {
            let d = at(t);
            assert!((d / want - 1.0).abs() < 0.02, "{what}: {d} cm at {t}° against {want} cm");
        }
    }
}

/// The sub-contact mesh: SBR realization 0 (the rope-held wall, whose bed joints twist as it
/// bends between its ropes) at the default two subdivisions collapses within one bracket of
/// four subdivisions at the same tolerance. One subdivision (62 % of a quadrilateral joint's
/// frictional torque in its two shear springs) collapses it two brackets early, at 19.625°
/// against 19.875° (BENCHMARKS.md, "Tilting table: the fine reference").
#[test]
fn the_default_sub_contact_mesh_gives_the_collapse_of_a_mesh_twice_as_fine() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut study = Study::from_file(&root.join("studies/tilting_table.toml")).unwrap();
    study.realizations = 1;
    study.groups.retain(|g| g.name == "SBR");
    let bracket = study.protocol.tilt().unwrap().resolution_deg;
    let angles = |study: &Study| {
        let rows = run_study(study, Shard::ALL);
        assert_eq!(rows.len(), 1);
        (rows[0].collapse.collapse_angle_deg.unwrap(), rows[0].collapse.first_unstable_deg.unwrap())
    };
    let default = angles(&study);
    study.solver.subcontact_subdivisions = 4;
    let fine = angles(&study);
    assert!(
        (default.0 - fine.0).abs() <= bracket + 1e-9,
        "α_max {}° at the default mesh against {}° at 4",
        default.0,
        fine.0
    );
    assert!((default.1 - fine.1).abs() <= bracket + 1e-9, "first unstable {}° against {}°", default.1, fine.1);
}
