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

/// The `timestep` of every blocks entry (`part="0"`) of a `.pvd` file, with its file.
fn pvd_blocks(path: &std::path::Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let attr = |line: &str, key: &str| -> String {
        let start = line.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
        line[start..].split('"').next().unwrap().to_string()
    };
    text.lines()
        .filter(|l| l.contains("<DataSet") && l.contains("part=\"0\""))
        .map(|l| (attr(l, "timestep").parse().unwrap(), attr(l, "file")))
        .collect()
}

/// The pictures of a realization are of its row's wall: the mechanism figure of the report
/// and the ParaView series of `--vtk-realizations` run the layout with the group's effects
/// (here an initial lean and a softer table joint), as the row's run did, not the plain
/// generated wall, which collapses at another tilt.
#[test]
fn the_mechanism_figure_and_the_series_draw_the_wall_of_the_row() {
    use drystone::io::series::{tilt_frames, write_series, Recorder};
    use drystone::protocol::run_tilt_observed;
    let study = Study::from_file(&root().join("tests/studies/good/mini_effects.toml")).unwrap();
    let rows = run_study(&study, Shard::ALL);
    let dir = std::env::temp_dir().join(format!("drystone-effect-figures-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();

    // The figure: the group's representative row (the lower median collapse angle, the
    // lowest realization among equals), drawn at the tilts of its row.
    let mut free: Vec<_> =
        rows.iter().filter(|r| r.group == "FREE" && r.collapse.collapse_angle_deg.is_some()).collect();
    free.sort_by(|a, b| {
        a.collapse
            .collapse_angle_deg
            .unwrap()
            .total_cmp(&b.collapse.collapse_angle_deg.unwrap())
            .then(a.realization.cmp(&b.realization))
    });
    let row = free[(free.len() - 1) / 2];
    drystone::study::write_report(&study, &rows, &dir).unwrap();
    let svg = std::fs::read_to_string(dir.join("mechanism_FREE.svg")).unwrap();
    let drawn = format!(
        "α_max {:.2}°, first unstable {:.2}°",
        row.collapse.collapse_angle_deg.unwrap(),
        row.collapse.first_unstable_deg.unwrap()
    );
    assert!(svg.contains(&drawn), "the figure is not of the row ({drawn}): {svg}");

    // The series: the files of a run of the effected layout, byte for byte; the plain wall
    // collapses elsewhere.
    let r = row.realization;
    let files = drystone::study::write_vtk_realizations(&study, Shard::ALL, &dir, &[r]).unwrap();
    let pvd = files.iter().find(|f| f.ends_with(format!("FREE_r{r}/tilt.pvd"))).expect("FREE's series");
    let group = &study.groups[0];
    let tilt = study.protocol.tilt().unwrap();
    let series = |layout: &drystone::layout::Layout, out: &std::path::Path| {
        let mut rec = Recorder::default();
        let res = run_tilt_observed(layout, study.solver, tilt, &mut |a, s, sim| rec.observe(a, s, sim)).unwrap();
        let (frames, _) = tilt_frames(&rec, &res);
        (write_series(out, "tilt", &rec, &frames).unwrap(), res)
    };
    let (_, effected) =
        drystone::effects::realize(&group.walls[0], study.seed, r, &group.name, &group.effects).unwrap();
    let (expected, res) = series(&effected, &dir.join("expected"));
    assert_eq!(res.first_unstable_deg, row.collapse.first_unstable_deg);
    let (got, want) = (pvd_blocks(pvd), pvd_blocks(&expected));
    assert_eq!(got.iter().map(|e| e.0).collect::<Vec<_>>(), want.iter().map(|e| e.0).collect::<Vec<_>>());
    for (g, w) in got.iter().zip(&want) {
        let read = |p: std::path::PathBuf| std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert!(read(pvd.parent().unwrap().join(&g.1)) == read(dir.join("expected").join(&w.1)), "{}", g.1);
    }
    let plain = drystone::generator::generate(&group.walls[0], study.seed, r).unwrap().check().unwrap();
    let (_, bare) = series(&plain, &dir.join("plain"));
    assert_ne!(bare.first_unstable_deg, res.first_unstable_deg, "the effects change the wall's collapse");
    std::fs::remove_dir_all(&dir).unwrap();
}
