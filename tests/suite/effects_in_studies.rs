//! The extended model everywhere: a study with effects runs, realization by realization,
//! the numbers of the discrepancy engine's extended ensemble (the same layouts, the same
//! effect streams: both go through `effects::realize`), and effects change the result.

use drystone::discrepancy::{run_models, Setup};
use drystone::ensemble::Shard;
use drystone::study::discrepancy::setup_of;
use drystone::study::{run_study, Study};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn a_study_with_effects_reproduces_the_discrepancy_ensemble_bit_for_bit() {
    let study = Study::from_file(&root().join("tests/studies/good/mini_effects.toml")).unwrap();
    let names: Vec<Vec<&str>> = study.groups.iter().map(|g| g.effects.iter().map(|e| e.name()).collect()).collect();
    assert_eq!(names, vec![vec!["seating_gap", "initial_lean", "timber_base"], vec!["seating_gap"]]);
    let rows = run_study(&study, Shard::ALL);
    // The engine's baseline of this study is the study's own model (its effects included).
    let setup = setup_of(&study, study.realizations);
    let engine = run_models(&setup, &[vec![]], None).remove(0);
    // The engine's candidate path: the plain walls with FREE's effects as a candidate.
    let plain = Setup {
        groups: setup
            .groups
            .iter()
            .map(|g| drystone::discrepancy::GroupSetup { effects: vec![], ..g.clone() })
            .collect(),
        ..setup.clone()
    };
    let candidate = run_models(&plain, &[study.groups[0].effects.clone()], None).remove(0);
    let baseline = run_models(&plain, &[vec![]], None).remove(0);
    let mut changed = 0;
    for r in &rows {
        let g = study.groups.iter().position(|g| g.name == r.group).unwrap();
        let i = r.realization as usize;
        assert_eq!(r.collapse.collapse_angle_deg, engine[g][i].observed.collapse_deg, "{} r{}", r.group, r.realization);
        if g == 0 {
            assert_eq!(r.collapse.collapse_angle_deg, candidate[0][i].observed.collapse_deg, "candidate path, r{i}");
        }
        if r.collapse.collapse_angle_deg != baseline[g][i].observed.collapse_deg {
            changed += 1;
        }
    }
    assert_eq!(rows.len(), 4);
    assert!(changed >= 3, "the effects change the collapse angles ({changed} of 4 changed)");
}

/// The extended study a discrepancy analysis writes is self-contained (walls with their
/// distributions inline, the effect files and the measured data copied) and runs, at the
/// same seed, the ensemble of the engine's extended model.
#[test]
fn the_written_extended_study_runs_the_extended_model() {
    let study = Study::from_file(&root().join("tests/studies/good/mini_effects.toml")).unwrap();
    let extra = vec![study.library.parse("edge_rounding=0.004", 0.05).unwrap()];
    let dir = std::env::temp_dir().join(format!("drystone-extended-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let fitted = vec![drystone::study::FittedParameter {
        name: "edge_rounding.radius_m".into(),
        value: 0.004,
        interval: (0.002, 0.006),
    }];
    let path = drystone::study::write_extended(&study, &extra, &fitted, "test", &dir).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("edge_rounding.radius_m = 4.0000e-3, interval [2.0000e-3, 6.0000e-3]"), "{text}");
    let ext = Study::from_file(&path).unwrap();
    let rows = run_study(&ext, Shard::ALL);
    let setup = setup_of(&study, study.realizations);
    let engine = run_models(&setup, &[extra], None).remove(0);
    for r in &rows {
        let g = ext.groups.iter().position(|g| g.name == r.group).unwrap();
        assert_eq!(
            r.collapse.collapse_angle_deg, engine[g][r.realization as usize].observed.collapse_deg,
            "{} r{}",
            r.group, r.realization
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
