//! Study files, the ensemble runner, shards and merge.

use drystone::ensemble::row::{RealizationRow, Status};
use drystone::ensemble::Shard;
use drystone::study::Study;
use drystone::study::{read_shards, write_outputs};
use drystone::study::{run_item, run_study};
use std::path::{Path, PathBuf};

use crate::common;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn mini() -> Study {
    Study::from_file(&root().join("tests/studies/good/mini_sweep.toml")).unwrap()
}

fn zero_wall_time(mut rows: Vec<RealizationRow>) -> Vec<RealizationRow> {
    for r in &mut rows {
        r.wall_time_s = 0.0;
    }
    rows
}

#[test]
fn every_shipped_study_loads() {
    let mut n = 0;
    for dir in ["studies", "tests/studies/good"] {
        for e in std::fs::read_dir(root().join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "toml") {
                if drystone::study::is_suite(&p) {
                    for full in [false, true] {
                        drystone::study::Suite::from_file(&p, full).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                    }
                } else {
                    let s = Study::from_file(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                    // A shipped study is written in today's keys.
                    let old: Vec<String> = s.warnings().into_iter().filter(|w| w.contains("deprecated")).collect();
                    assert!(old.is_empty(), "{}: {old:?}", p.display());
                }
                n += 1;
            }
        }
    }
    assert!(n >= 2);
}

#[test]
fn each_bad_study_fails_with_its_expected_message() {
    let mut n = 0;
    for e in std::fs::read_dir(root().join("tests/studies/bad")).unwrap() {
        let p = e.unwrap().path();
        let text = std::fs::read_to_string(&p).unwrap();
        let expect = text.lines().next().and_then(|l| l.strip_prefix("# expect: ")).expect("first line: # expect: ...");
        let err = Study::from_file(&p).err().unwrap_or_else(|| panic!("{} loaded", p.display())).to_string();
        assert!(err.contains(expect), "{}: expected {expect:?} in {err:?}", p.display());
        assert!(err.contains(p.file_name().unwrap().to_str().unwrap()), "the message names the file: {err}");
        n += 1;
    }
    assert!(n >= 8);
}

#[test]
fn sweep_is_a_cartesian_grid_with_overrides() {
    let s = mini();
    assert_eq!(s.points.len(), 2);
    assert_eq!(s.items().len(), 2 * 2 * 2);
    assert!((s.groups[1].walls[0].length - 0.4).abs() < 1e-12);
    let kn: Vec<f64> = s.groups[0].walls.iter().map(|w| w.materials[0].kn_pa_per_m).collect();
    assert_eq!(kn, vec![1.75e8, 3.5e8]);
    // Ks follows Kn at the material's own ratio.
    let w = &s.groups[0].walls[1];
    assert!((w.materials[0].ks_pa_per_m / w.materials[0].kn_pa_per_m - 0.86 / 1.75).abs() < 1e-12);
}

#[test]
fn ensemble_is_bit_identical_on_1_and_2_threads_and_alone() {
    let s = mini();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        zero_wall_time(pool.install(|| run_study(&s, Shard::ALL)))
    };
    let one = run(1);
    let two = run(2);
    assert_eq!(one.len(), 8);
    assert!(one.iter().all(|r| r.status == Status::Collapsed), "{one:#?}");
    assert_eq!(one, two);
    // Realization 1 of group 1, point 1, alone.
    let items = s.items();
    let it = items.iter().find(|i| i.group == 1 && i.point == 1 && i.realization == 1).unwrap();
    let mut alone = run_item(&s, it);
    alone.wall_time_s = 0.0;
    assert_eq!(alone, one[it.index]);
    // Different realizations are different walls.
    assert_ne!(one[0].collapse.collapse_angle_deg, None);
}

fn tmp(name: &str) -> common::Scratch {
    common::Scratch::new(&format!("studies-{name}"))
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn shards_merge_into_exactly_the_unsharded_run() {
    let s = mini();
    let arg = root().join("tests/studies/good/mini_sweep.toml");
    let all = zero_wall_time(run_study(&s, Shard::ALL));
    let whole = tmp("whole");
    write_outputs(&s, &arg, Shard::ALL, &all, &whole).unwrap();
    let mut dirs = Vec::new();
    let mut scratch = Vec::new();
    for k in 1..=3 {
        let sh = Shard::parse(&format!("{k}/3")).unwrap();
        let rows = zero_wall_time(run_study(&s, sh));
        let d = tmp(&format!("shard{k}"));
        write_outputs(&s, &arg, sh, &rows, &d).unwrap();
        assert!(!d.join("report.md").exists(), "a shard writes no report");
        dirs.push(d.to_path_buf());
        scratch.push(d);
    }
    let (manifest, rows) = read_shards(&dirs).unwrap();
    assert_eq!(rows, all);
    let merged = tmp("merged");
    write_outputs(&s, &manifest.study, Shard::ALL, &rows, &merged).unwrap();
    for f in ["realizations.csv", "summary.csv", "report.md", "collapse_angle_histograms.svg", "fragility.svg"] {
        assert_eq!(read(&whole.join(f)), read(&merged.join(f)), "{f} differs");
    }
    // Parquet round trip.
    let back = drystone::io::table::read_realizations(&merged.join("realizations.parquet")).unwrap();
    assert_eq!(back, all);
    // An incomplete set of shards is refused.
    let err = read_shards(&dirs[..2]).unwrap_err().to_string();
    assert!(err.contains("missing") || err.contains("of 8 items"), "{err}");
}

#[test]
fn a_failed_realization_becomes_a_row_and_the_ensemble_goes_on() {
    let mut s = mini();
    let drystone::study::StudyProtocol::Tilt(tilt) = &mut s.protocol else { panic!("a tilting-table study") };
    let _ = tilt;
    s.solver.penalty.max_steps = 5; // no equilibrium at alpha = 0 in 5 steps
    let rows = run_study(&s, Shard::parse("1/4").unwrap());
    assert_eq!(rows.len(), 2);
    for r in &rows {
        assert_eq!(r.status, Status::NoInitialEquilibrium);
        assert!(r.error.contains("no equilibrium"), "{}", r.error);
        assert_eq!(r.collapse.collapse_angle_deg, None);
    }
    let dir = tmp("failed");
    let arg = root().join("tests/studies/good/mini_sweep.toml");
    write_outputs(&s, &arg, Shard::ALL, &rows, &dir).unwrap();
    let report = String::from_utf8(read(&dir.join("report.md"))).unwrap();
    assert!(report.contains("no_initial_equilibrium"), "{report}");
}

/// The fragility figure tells the simulation from the test: the ensemble's empirical points
/// are labelled `simulated`, and the measured specimens of the group (data/paper, 3 CBL
/// walls) are drawn and labelled `measured`, once per group at the first sweep point.
#[test]
fn the_fragility_figure_labels_simulated_points_and_draws_the_measured_specimens() {
    let s = mini();
    let arg = root().join("tests/studies/good/mini_sweep.toml");
    let rows = run_study(&s, Shard::ALL);
    let dir = tmp("fragility");
    write_outputs(&s, &arg, Shard::ALL, &rows, &dir).unwrap();
    let svg = String::from_utf8(read(&dir.join("fragility.svg"))).unwrap();
    let simulated = svg.lines().filter(|l| l.ends_with(" simulated")).count();
    let measured = svg.lines().filter(|l| l.ends_with(" measured")).count();
    assert!(simulated >= 2, "the ensembles' points are labelled simulated ({simulated})");
    assert_eq!(measured, 2, "one measured legend entry per group at the first sweep point");
}

/// The report names the solver that ran and the stages its static solves ran, whatever
/// spelled them: `accelerated` is not reported as the implicit iteration, the deprecated
/// `[tilt] implicit = false` under `penalty` reports what it runs, and a method without
/// static solves is reported without the penalty DEM's settings.
#[test]
fn the_report_names_the_solver_and_the_stages_it_ran() {
    use drystone::dem::SolverKind;
    let arg = root().join("tests/studies/good/mini_sweep.toml");
    let report = |kind: SolverKind, implicit: bool| {
        let mut s = mini();
        s.solver.kind = kind;
        s.solver.penalty.max_steps = 5; // every realization stops at once: the report is of the study
        let drystone::study::StudyProtocol::Tilt(tilt) = &mut s.protocol else { panic!("a tilting-table study") };
        tilt.implicit = implicit;
        let rows = run_study(&s, Shard::parse("1/4").unwrap());
        let dir = tmp(&format!("report-{kind}-{implicit}"));
        write_outputs(&s, &arg, Shard::ALL, &rows, &dir).unwrap();
        String::from_utf8(read(&dir.join("report.md"))).unwrap()
    };
    let accelerated = report(SolverKind::Accelerated, true);
    assert!(
        accelerated.contains(
            "solver `accelerated`: the penalty DEM, static states by accelerated dynamic relaxation, without the implicit iteration"
        ),
        "{accelerated}"
    );
    assert!(!accelerated.contains("implicit relaxation on"), "{accelerated}");
    let penalty = report(SolverKind::Penalty, true);
    assert!(
        penalty.contains("solver `penalty`: the penalty DEM, static states by the implicit iteration, then accelerated dynamic relaxation, equilibrium at unbalanced-force ratio"),
        "{penalty}"
    );
    let deprecated = report(SolverKind::Penalty, false);
    assert!(deprecated.contains("solver `penalty`: the penalty DEM, static states by accelerated dynamic relaxation, without the implicit iteration"), "{deprecated}");
    let rigid = report(SolverKind::Limit, true);
    assert!(rigid.contains("solver `limit`: limit analysis."), "{rigid}");
    assert!(!rigid.contains("secant predictor"), "{rigid}");
}

/// A protocol within a kind is named in a study file (`protocol = "tilt_by_hand"`,
/// `"pushover"`, its `drystone.supports` name) or chosen by its kind's table (`[tilt]
/// by_hand`, `[lateral] pushover = true`, the former spelling, still read): both spellings
/// resolve to the same study, and run the same protocol by the same default solver.
#[test]
fn a_protocol_named_or_chosen_by_its_table_is_the_same_study() {
    use drystone::protocol::Loading;
    for (old, new, protocol) in [
        ("mini_by_hand", "mini_by_hand_named", Loading::TiltByHand),
        ("mini_pushover", "mini_pushover_named", Loading::Pushover),
    ] {
        let path = |n: &str| root().join(format!("tests/studies/good/{n}.toml"));
        let (mut a, mut b) = (Study::from_file(&path(old)).unwrap(), Study::from_file(&path(new)).unwrap());
        // The files themselves (their provenance) differ; everything read from them is the same.
        (a.inputs, b.inputs) = (Vec::new(), Vec::new());
        assert_eq!(a.protocol_at(0).loading(), protocol);
        assert_eq!(b.protocol_at(0).loading(), protocol);
        let shown = |s: &Study, n: &str| format!("{s:?}").replace(&format!("{n}.toml"), "STUDY.toml");
        assert_eq!(shown(&a, old), shown(&b, new), "{new}");
        assert!(b.warnings().iter().all(|w| !w.contains("deprecated")), "{:?}", b.warnings());
    }
}
