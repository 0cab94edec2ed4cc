//! `drystone design` end to end on the test bed's small walls: an analysis of data the
//! engine did not make (`tests/realwalls`), the menu of follow-ups, the preposterior
//! ranking, and the best follow-up written as a study whose files the product reads.
//! Small ensembles and few simulated follow-ups: the outcome is not the point, the plumbing
//! and the files are (the ranking itself is tested on constructed ties in
//! `src/discrepancy/design/tests.rs`).

use crate::realwalls;

use drystone::discrepancy::design::{
    contenders, design, first_scores, heldout, pairs_possible, Chance, Contender, DesignSettings, FollowUp,
    FollowUpKind, Plan, RankedFollowUp, WallEdit, OUTSIDE_PRIOR,
};
use drystone::discrepancy::{analyze, prepare, prepare_after, quiet, report_json, report_markdown, Observable};
use drystone::io::table::{read_measured_collapse, read_measured_displacement, read_measured_mechanism};
use drystone::study::discrepancy::setup_of;
use drystone::study::followup::{menu, write_followup};
use drystone::study::Study;
use realwalls::{data_set, Edit, Noise};
use std::path::PathBuf;

const NOISE: Noise =
    Noise { angle_deg: 0.4, displacement_cm: 0.01, angle_reading_deg: 0.25, displacement_reading_cm: 0.01 };

/// The test bed's study with small ensembles: `grid_points` intervals, the `effects`
/// searched, the scatter hypothesis on or off, no confirmation runs.
fn small_test_bed(grid_points: usize, effects: &[&str], scatter: bool) -> (Study, drystone::discrepancy::Settings) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let st = Study::from_file(&root.join("tests/discrepancy/study.toml")).unwrap();
    let mut s = st.discrepancy.clone();
    (s.realizations, s.extension_realizations, s.null_realizations) = (2, 3, 3);
    (s.grid_points, s.null_replicates, s.check_replicates, s.bootstrap) = (grid_points, 20, 20, 100);
    s.effects = effects.iter().map(|e| e.to_string()).collect();
    (s.scatter, s.confirm) = (scatter, false);
    (st, s)
}

#[test]
fn the_best_follow_up_is_written_as_a_study_whose_templates_the_readers_read() {
    let (st, s) = small_test_bed(2, &["initial_lean", "edge_rounding"], false);
    let obs = data_set(&st, 0x5eed_da7a, 300, 3, Edit::Lean(1.5), NOISE, &[5.0, 10.0], s.sigma);
    let setup = setup_of(&st, s.most_realizations());
    let prep = prepare(&setup, &obs, &s, &st.library).unwrap();
    let mut run = analyze(&prep, obs, 300).unwrap();
    let all = menu(&st, &setup, &run).unwrap();
    // Per group: more specimens, the mechanism read, both monitors, taller and longer
    // walls; not the other end restraint: the free walls held at their ends are the HELD
    // group already, and the held walls freed the FREE group.
    let kinds = |g: &str| all.iter().filter(|f| f.from_group == g).map(|f| f.kind).collect::<Vec<_>>();
    assert!(kinds("FREE").contains(&FollowUpKind::Height) && !kinds("FREE").contains(&FollowUpKind::Restraint));
    assert!(kinds("HELD").contains(&FollowUpKind::Mechanism) && !kinds("HELD").contains(&FollowUpKind::Restraint));
    let picked: Vec<_> = all
        .into_iter()
        .filter(|f| {
            f.from_group == "FREE"
                && matches!(f.kind, FollowUpKind::MoreSpecimens | FollowUpKind::Mechanism | FollowUpKind::Height)
        })
        .collect();
    assert_eq!(picked.len(), 3);
    let ds = DesignSettings { specimens: 3, replicates: 20, draws: 50, target: 0.8 };
    let plan = design(&run, &setup, picked, &ds, 300, &quiet).unwrap();
    assert_eq!(plan.ranked.len(), 3);
    assert!(plan.truths >= 2 && plan.truths <= plan.contenders.len());
    let truths = &plan.contenders[..plan.truths];
    assert!((truths.iter().map(|c| c.prior).sum::<f64>() - 1.0).abs() < 1e-9);
    // The prior over truths is wider than the analysis's: an effect it did not rank among
    // its contenders, and the pair of the best singles wherever both campaigns could admit
    // a pair, sharing the stated weight, each simulated as a truth (a probability of its
    // own) and refit as a challenger.
    let outside: Vec<&Contender> = truths.iter().filter(|c| c.outside).collect();
    assert!(!outside.is_empty(), "{truths:?}");
    assert!((outside.iter().map(|c| c.prior).sum::<f64>() - OUTSIDE_PRIOR).abs() < 1e-9);
    assert_eq!(pairs_possible(&run), truths.iter().any(|c| c.name.contains('+')), "{truths:?}");
    assert!(pairs_possible(&run), "lean walls: the best single gains on the baseline, two singles to pair");
    for w in plan.ranked.windows(2) {
        assert!(w[0].at_budget.alone >= w[1].at_budget.alone, "ranked best first");
    }
    for r in &plan.ranked {
        assert!((0.0..=1.0).contains(&r.at_budget.alone) && (0.0..=1.0).contains(&r.at_budget.right));
        assert_eq!(r.at_budget.alone_by_truth.len(), plan.truths);
        // The surrogates answer for more specimens of a group, the analysis's runs for
        // another key of its walls (the mechanism); walls of a new kind need runs.
        assert_eq!(r.followup.new_group.is_none(), r.runs == 0, "{:?}", r.followup.kind);
    }
    // The promise is re-estimated on fresh replicates, its interval holds it, and the
    // ranking's own estimate is kept beside it.
    let r = plan.reported.as_ref().expect("a menu: a re-estimate");
    assert_eq!(r.selected, plan.ranked[0].at_budget.alone);
    assert_eq!((r.specimens, r.replicates, r.chance.alone_by_truth.len()), (3, 20, plan.truths));
    assert!(r.interval.0 <= r.chance.alone && r.chance.alone <= r.interval.1, "{r:?}");
    assert_eq!(plan.promise(), Some(r.chance.alone));
    // The report's section and the JSON's `followup`, only when designed.
    assert!(!report_markdown(&run, "t").contains("The next experiment"));
    assert!(report_json(&run).get("followup").is_none());
    // One meaning of named alone: the verdict's (a cause, and a tie of one), in the plan,
    // the report's JSON and its Markdown.
    let alone = run.analysis.named_alone().map(str::to_string);
    assert_eq!(
        alone.is_some(),
        run.analysis.verdict == drystone::discrepancy::Verdict::Explained
            && run.analysis.cause.is_some()
            && run.analysis.tie.len() == 1
    );
    assert_eq!(plan.alone_now, alone.is_some());
    assert_eq!(report_json(&run)["named_alone"].as_str().map(str::to_string), alone);
    assert_eq!(report_markdown(&run, "t").contains("Named alone: "), alone.is_some());
    run.followup = Some(plan.clone());
    assert!(report_markdown(&run, "t").contains("## The next experiment"));
    assert!(report_json(&run)["followup"]["ranked"].as_array().is_some_and(|a| a.len() == 3));
    assert!(report_json(&run)["followup"]["reported"]["interval"].as_array().is_some_and(|a| a.len() == 2));
    assert!(drystone::discrepancy::design::markdown(&plan).contains("Monte Carlo interval"));

    // Write the follow-up the tall walls would be (whatever ranked first) and the best one.
    let dir = std::env::temp_dir().join(format!("design-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut tall = plan.clone();
    tall.ranked.sort_by_key(|r| r.followup.kind != FollowUpKind::Height);
    let files = write_followup(&st, &tall, &dir.join("tall"), 4, None).unwrap().unwrap();
    let fst = Study::from_file(&files.study).unwrap();
    let names: Vec<&str> = fst.groups.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["FREE", "HELD", "FREE_tall"]);
    let h = |name: &str| fst.groups.iter().find(|g| g.name == name).unwrap().walls[0].height;
    assert!((h("FREE_tall") - 1.5 * h("FREE")).abs() < 1e-12);
    // The first campaign's walls are the study's own: the same layouts.
    assert_eq!(
        drystone::generator::generate(&fst.groups[0].walls[0], st.seed, 0).unwrap().layout.to_json(),
        drystone::generator::generate(&st.groups[0].walls[0], st.seed, 0).unwrap().layout.to_json()
    );
    assert!(read_measured_collapse(&files.templates[0]).unwrap().is_empty());
    assert!(read_measured_displacement(&files.templates[1]).unwrap().is_empty());
    let rows = read_measured_mechanism(&files.templates[2]).unwrap();
    assert_eq!(rows.len(), 4);
    assert!(rows.iter().all(|r| r.group == "FREE_tall" && r.failure_height.is_none() && r.kind.is_none()));
    assert_eq!(files.specimens.len(), 4);
    // A laboratory fills the template in: the study reads the rows with the first campaign.
    let mut text = std::fs::read_to_string(&files.measured[0]).unwrap();
    for (sp, g) in &files.specimens {
        text += &format!("{sp},{g},23.5\n");
    }
    std::fs::write(&files.measured[0], text).unwrap();
    let filled = Study::from_file(&files.study).unwrap();
    assert_eq!(filled.measured.collapse.iter().filter(|c| c.group == "FREE_tall").count(), 4);
    let best = write_followup(&st, &plan, &dir.join("best"), 3, None).unwrap().unwrap();
    assert!(Study::from_file(&best.study).is_ok());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A follow-up of the analysis's own walls that reads a key the analysis did not score
/// (the failure mechanism) reads it from the analysis's runs, its baseline and its grids:
/// the same probabilities, bit for bit, as when the design runs those walls again itself
/// (the analysis's runs hidden from it), and no run.
#[test]
fn a_follow_up_of_the_analysis_s_own_walls_reads_the_analysis_s_runs() {
    let (st, s) = small_test_bed(2, &["initial_lean", "edge_rounding"], false);
    let obs = data_set(&st, 0x5eed_da7a, 300, 3, Edit::Lean(1.5), NOISE, &[5.0, 10.0], s.sigma);
    let setup = setup_of(&st, s.most_realizations());
    let prep = prepare(&setup, &obs, &s, &st.library).unwrap();
    let run = analyze(&prep, obs, 300).unwrap();
    let picked: Vec<FollowUp> = menu(&st, &setup, &run)
        .unwrap()
        .into_iter()
        .filter(|f| f.from_group == "FREE" && f.kind == FollowUpKind::Mechanism)
        .collect();
    assert_eq!(picked.len(), 1);
    let ds = DesignSettings { specimens: 3, replicates: 20, draws: 50, target: 0.8 };
    let reused = design(&run, &setup, picked.clone(), &ds, 300, &quiet).unwrap();
    let mut hidden = run.clone();
    hidden.grids = Default::default();
    hidden.baseline = vec![];
    let ran = design(&hidden, &setup, picked, &ds, 300, &quiet).unwrap();
    assert_eq!(reused.runs, 0);
    assert!(ran.runs > 0, "{}", ran.runs);
    assert_eq!(reused.ranked[0].chances, ran.ranked[0].chances);
    assert_eq!(reused.reported, ran.reported);
    assert!(reused.ranked[0].at_budget.alone_by_truth.iter().any(|&p| p > 0.0) || ran.ranked[0].at_budget.right > 0.0);
}

/// The follow-up campaign's analysis, prepared after the first campaign's
/// (`prepare_after`), reads every run of the first campaign's walls that it would make
/// the same way from it, and runs the rest: the same baseline, grids, null pool and
/// surrogate library as a preparation that runs everything, bit for bit. With the same
/// walls (a follow-up of more specimens or other readings) nothing is run again; with a
/// new group, the first campaign's baseline and null pool are read, and a grid node is
/// read only where its effect is the same: an effect carries the mean course height of the
/// study's walls (its length parameters scale with it), which a third group moves in its
/// last bits, so here every grid is run again (and a run of `edge_rounding` at a radius
/// one ulp off moves the displacements in their fifth digit: read, it would be wrong).
///
/// The smallest case that still has every kind of run: one realization per group for the
/// grids, the baseline and the null pool (the grids' neutral node is the baseline's first
/// realization either way), the two effects on 1-interval grids (each the node taken from
/// the baseline and one node run), and a template of 2 specimens per group (it sets only
/// which observations are prepared). The claim is about which runs are read and which are
/// made, bit for bit, which does not depend on how many realizations or grid nodes each
/// stage has: every stage of the three preparations still runs, and every run is compared.
#[test]
fn a_follow_up_prepared_after_the_first_campaign_runs_only_what_it_would_run_differently() {
    let (st, mut s) = small_test_bed(1, &["initial_lean", "edge_rounding"], false);
    (s.realizations, s.extension_realizations, s.null_realizations) = (1, 1, 1);
    let obs = data_set(&st, 0x5eed_da7a, 300, 2, Edit::Lean(1.5), NOISE, &[5.0, 10.0], s.sigma);
    let setup = setup_of(&st, s.most_realizations());
    let first = prepare(&setup, &obs, &s, &st.library).unwrap();
    let total = |p: &drystone::discrepancy::Prepared| p.forward_runs.iter().map(|r| r.runs).sum::<usize>();
    let same = |a: &drystone::discrepancy::Prepared, b: &drystone::discrepancy::Prepared| {
        assert_eq!(a.baseline.json(), b.baseline.json());
        assert_eq!(a.null_pool.json(), b.null_pool.json());
        assert_eq!(a.grids.len(), b.grids.len());
        for (name, nodes) in b.grids.iter() {
            let ours = &a.grids[name];
            assert_eq!(nodes.len(), ours.len(), "{name}");
            for ((x, o), (y, p)) in nodes.iter().zip(ours) {
                assert_eq!(x, y);
                assert_eq!(o.as_ref().map(|o| o.1.json()), p.as_ref().map(|p| p.1.json()), "{name} at {x:?}");
            }
        }
        assert_eq!(format!("{:?}", a.library), format!("{:?}", b.library));
    };
    // The same walls, as the design writes the follow-up's study and the study reads them
    // back (other files, the same descriptions): nothing run again.
    let dir = std::env::temp_dir().join(format!("prepare-after-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let files = write_followup(&st, &more_free_walls(), &dir, 3, None).unwrap().unwrap();
    let written = Study::from_file(&files.study).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let again_setup = setup_of(&written, s.most_realizations());
    assert_ne!(again_setup.groups[0].wall.source, setup.groups[0].wall.source);
    let again = prepare_after(&again_setup, &obs, &s, &written.library, Some(&first), &quiet).unwrap();
    same(&again, &first);
    assert!(total(&first) > 0);
    assert_eq!(total(&again), 0);
    // A new group of the free walls (a group's name seeds its effects' draws).
    let mut fst = st.clone();
    let mut more = fst.groups[0].clone();
    more.name = "FREE_again".into();
    fst.groups.push(more);
    let setup2 = setup_of(&fst, s.most_realizations());
    let fresh = prepare(&setup2, &obs, &s, &fst.library).unwrap();
    let after = prepare_after(&setup2, &obs, &s, &fst.library, Some(&first), &quiet).unwrap();
    same(&after, &fresh);
    let stage = |p: &drystone::discrepancy::Prepared, k: usize| p.forward_runs[k].runs;
    // The baseline and the null pool of the first campaign's walls are read.
    for k in [0, 2] {
        assert_eq!(stage(&after, k), stage(&fresh, k) - stage(&first, k), "{:?}", after.forward_runs[k]);
    }
    // The grids are run again: their effects are not the first campaign's.
    assert_eq!(stage(&after, 1), stage(&fresh, 1));
}

/// Outcomes as JSON: equal strings are equal values bit for bit (shortest round-trip
/// digits), NaN included (written `null` on both sides).
trait Json {
    fn json(&self) -> String;
}

impl<T: serde::Serialize> Json for T {
    fn json(&self) -> String {
        serde_json::to_string(self).unwrap()
    }
}

/// The design's refit, with no follow-up yet, is the analysis's own leave-one-specimen-out
/// fit: from its tables of scores at the scan points (a sum and a minimum per fold), every
/// contender's held-out score per specimen of the first campaign is the one the analysis
/// computed by its scan and Brent polish (`fit::loso`), up to the polish (a fold's point
/// kept to 0.01 of the range on one axis, 0.05 on two). The analysis's scores are an
/// independent path: `fit::fit_folds` and argmin's Brent method on the surrogates.
#[test]
fn the_refit_without_a_follow_up_is_the_analysis_s_own_held_out_fit() {
    let (st, s) = small_test_bed(4, &["initial_lean", "edge_rounding", "kn_scale"], true);
    let obs = data_set(&st, 0x5eed_da7a, 310, 3, Edit::Round(0.004), NOISE, &[5.0, 10.0], s.sigma);
    let setup = setup_of(&st, s.most_realizations());
    let prep = prepare(&setup, &obs, &s, &st.library).unwrap();
    let run = analyze(&prep, obs, 310).unwrap();
    let (cs, truths) = contenders(&run);
    assert!(truths >= 1 && truths <= cs.len());
    let first = first_scores(&run, &cs);
    let mut compared = 0;
    for (c, f) in cs.iter().zip(&first) {
        let Some(f) = f else {
            assert_eq!(c.name, "baseline");
            continue;
        };
        if c.made.is_some() {
            // A pair the design built: its held-out scores are this refit's own.
            continue;
        }
        let (elpd, measures) = heldout(&f.pins, &f.all, &[], &[], 0);
        assert_eq!(elpd.len(), c.elpd.len());
        // Measured: at most 0.111 nats (kn_scale's specimen 1; 0.063 its specimen 0), the
        // others' at most 0.022.
        for (k, (a, b)) in elpd.iter().zip(&c.elpd).enumerate() {
            assert!((a - b).abs() <= 0.15, "{} specimen {k}: refit {a} against {b}", c.name);
        }
        for (a, b) in measures.iter().zip(&c.elpd_measures) {
            assert!((a - b).abs() <= 0.15, "{}: measures {a} against {b}", c.name);
        }
        compared += 1;
    }
    assert!(compared >= 2, "{cs:?}");
}

/// A plan whose best follow-up is three more walls of group FREE, read as before (made by
/// hand: writing the follow-up does not look at the probabilities).
fn more_free_walls() -> Plan {
    let chance = Chance {
        specimens: 3,
        alone: 0.5,
        alone_se: 0.0,
        weights_alone: 0.6,
        right: 0.9,
        alone_by_truth: vec![],
        blocked_by: vec![],
        data_blocked_by: vec![],
    };
    let followup = FollowUp {
        name: "3 more FREE walls".into(),
        kind: FollowUpKind::MoreSpecimens,
        group: "FREE".into(),
        from_group: "FREE".into(),
        observables: vec![Observable::CollapseAngle],
        new_group: None,
        new_spec: None,
        edit: WallEdit::default(),
    };
    Plan {
        contenders: vec![],
        truths: 0,
        inadequacy: vec![],
        transfer: vec![],
        alone_now: false,
        ranked: vec![RankedFollowUp {
            followup,
            chances: vec![chance.clone()],
            at_budget: chance,
            to_target: None,
            runs: 0,
            disagreement: vec![],
            menu_index: 0,
        }],
        settings: DesignSettings::default(),
        runs: 0,
        reported: None,
    }
}

/// The follow-up's `measured/` holds the first campaign's files the analysis read: the
/// files the study's `[measured]` table names, or, with `--measured DIR`, the directory's
/// (rows other than the table's; a file the directory lacks is written header-only, not
/// taken from the table), and the written follow-up study reads those rows.
#[test]
fn the_follow_up_copies_the_measured_files_the_analysis_read() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let walls = root.join("tests/discrepancy/walls");
    let tmp = std::env::temp_dir().join(format!("design-measured-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let write = |rel: &str, text: &str| {
        let p = tmp.join(rel);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, text).unwrap();
        p
    };
    let study_text = format!(
        "version = 1\nname = \"measured_source\"\nseed = 7\nrealizations = 2\nprotocol = \"tilt\"\n\n\
         [tilt]\nstep_deg = 1.0\nresolution_deg = 0.25\n\n\
         [[groups]]\nname = \"FREE\"\nwall = \"{}\"\n\n\
         [[groups]]\nname = \"HELD\"\nwall = \"{}\"\n\n\
         [measured]\ncollapse = \"table/tilting_table_collapse.csv\"\n\
         displacement = \"table/tilting_table_displacement.csv\"\n",
        walls.join("small_free.toml").display(),
        walls.join("small_restrained.toml").display()
    );
    let study = write("study/study.toml", &study_text);
    let table_collapse = "specimen,group,collapse_angle_deg\nT1,FREE,24.5\nT2,FREE,25.0\nT3,HELD,31.5\n";
    let table_displacement =
        "specimen,group,measure,tilt_deg,displacement_cm\nT1,FREE,mean_of_left_center_right,5,0.1\n";
    write("study/table/tilting_table_collapse.csv", table_collapse);
    write("study/table/tilting_table_displacement.csv", table_displacement);
    // The directory `--measured` names: other specimens and angles, a mechanism file and
    // no displacement file.
    let dir_collapse = "specimen,group,collapse_angle_deg\nD1,FREE,21.0\nD2,FREE,22.5\nD3,HELD,28.0\nD4,HELD,29.5\n";
    let dir_mechanism = "specimen,group,failure_height_fraction,failure_height_low,failure_height_high,kind,start,extent_fraction,source\n\
                         D1,FREE,0.5,0.25,0.75,toppling,end,,seen\n";
    write("lab/tilting_table_collapse.csv", dir_collapse);
    write("lab/tilting_table_mechanism.csv", dir_mechanism);
    let lab = tmp.join("lab");
    let st = Study::from_file(&study).unwrap();
    let plan = more_free_walls();
    let read = |p: &PathBuf| std::fs::read_to_string(p).unwrap();
    let specimens = |st: &Study| st.measured.collapse.iter().map(|c| c.specimen.clone()).collect::<Vec<_>>();

    // The study's own [measured] table.
    let own = write_followup(&st, &plan, &tmp.join("own"), 3, None).unwrap().unwrap();
    assert_eq!(read(&own.measured[0]), table_collapse);
    assert_eq!(read(&own.measured[1]), table_displacement);
    assert_eq!(read(&own.measured[2]).lines().count(), 1, "the study has no mechanism file: header only");
    let fst = Study::from_file(&own.study).unwrap();
    assert_eq!(specimens(&fst), ["T1", "T2", "T3"]);
    assert_eq!(fst.measured.displacement.len(), 1);

    // `--measured DIR`: the directory's rows, none of the table's.
    let from_dir = write_followup(&st, &plan, &tmp.join("dir"), 3, Some(&lab)).unwrap().unwrap();
    assert_eq!(read(&from_dir.measured[0]), dir_collapse);
    assert_eq!(read(&from_dir.measured[1]), "specimen,group,measure,tilt_deg,displacement_cm\n");
    assert_eq!(read(&from_dir.measured[2]), dir_mechanism);
    for f in &from_dir.measured {
        assert!(!read(f).contains("T1,"), "{}: a row of the study's table", f.display());
    }
    let fst = Study::from_file(&from_dir.study).unwrap();
    assert_eq!(specimens(&fst), ["D1", "D2", "D3", "D4"]);
    assert!(fst.measured.displacement.is_empty());
    assert_eq!(fst.measured.mechanism.len(), 1);
    assert_eq!(fst.measured.mechanism[0].specimen, "D1");
    // The templates and specimens do not depend on where the data came from.
    assert_eq!(own.specimens, from_dir.specimens);
    assert_eq!(read(&own.templates[0]), read(&from_dir.templates[0]));
    let _ = std::fs::remove_dir_all(&tmp);
}

/// `drystone design`'s own options out of range are refused before anything runs, exit
/// status 2, each naming its key and range; an unreadable measured directory names the
/// file.
#[test]
fn bad_design_options_are_refused_naming_the_key() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let study = root.join("tests/discrepancy/study.toml");
    let out = std::env::temp_dir().join(format!("drystone-design-bad-{}", std::process::id()));
    let cases: [(&[&str], &str); 6] = [
        (&["--specimens", "0"], "--specimens 0: must be in [1, 64]"),
        (&["--specimens", "65"], "--specimens 65: must be in [1, 64]"),
        (&["--target", "1"], "--target 1: must be in (0, 1)"),
        (&["--target", "0"], "--target 0: must be in (0, 1)"),
        (&["--replicates", "9"], "--replicates 9: must be in [10, 100000]"),
        (&["--measured", "/nonexistent-measured-dir"], "/nonexistent-measured-dir"),
    ];
    for (args, want) in cases {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_drystone"))
            .arg("design")
            .arg(&study)
            .arg("--out")
            .arg(&out)
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// Where no follow-up of the menu reaches the target within the most specimens its ladder
/// tries (`DesignSettings::ladder`), the report says the contenders are not told apart at
/// an affordable size; where one does, it does not.
#[test]
fn the_report_says_when_no_affordable_follow_up_separates_the_contenders() {
    let mut plan = more_free_walls();
    let md = drystone::discrepancy::design::markdown(&plan);
    assert!(md.contains("No follow-up of the menu names the cause alone"), "{md}");
    plan.ranked[0].to_target = Some(8);
    assert!(!drystone::discrepancy::design::markdown(&plan).contains("No follow-up of the menu"));
}

/// `drystone design --measured DIR` (and `discrepancy --measured DIR`) with a group the
/// study does not have names DIR's file and line, not the study file's `[measured]`
/// table, which was not read.
#[test]
fn measured_rows_of_a_foreign_group_are_refused_naming_the_directory_s_file() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let study = root.join("tests/discrepancy/study.toml");
    let tmp = std::env::temp_dir().join(format!("drystone-design-foreign-{}", std::process::id()));
    let lab = tmp.join("lab");
    std::fs::create_dir_all(&lab).unwrap();
    let csv = lab.join("tilting_table_collapse.csv");
    std::fs::write(&csv, "specimen,group,collapse_angle_deg\nD1,FREE,21.0\nD2,ALIEN,22.5\n").unwrap();
    for command in ["design", "discrepancy"] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_drystone"))
            .arg(command)
            .arg(&study)
            .arg("--measured")
            .arg(&lab)
            .args(["--out", tmp.join("out").to_str().unwrap()])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{command}: {err}");
        assert!(err.contains("ALIEN"), "{command}: {err}");
        assert!(err.contains(&format!("{} line 3", csv.display())), "{command}: DIR's file not named: {err}");
        assert!(!err.contains("[measured]"), "{command}: names the study's table: {err}");
    }
    let _ = std::fs::remove_dir_all(&tmp);
}
