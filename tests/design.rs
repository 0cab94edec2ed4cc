//! `drystone design` end to end on the test bed's small walls: an analysis of data the
//! engine did not make (`tests/realwalls`), the menu of follow-ups, the preposterior
//! ranking, and the best follow-up written as a study whose files the product reads.
//! Small ensembles and few simulated follow-ups: the outcome is not the point, the plumbing
//! and the files are (the ranking itself is tested on constructed ties in
//! `src/discrepancy/design/tests.rs`).

mod realwalls;

use drystone::discrepancy::design::{design, DesignSettings, FollowUpKind};
use drystone::discrepancy::{analyze, prepare, quiet, report_json, report_markdown};
use drystone::io::table::{read_measured_collapse, read_measured_displacement, read_measured_mechanism};
use drystone::study::discrepancy::setup_of;
use drystone::study::followup::{menu, write_followup};
use drystone::study::Study;
use realwalls::{data_set, Edit, Noise};
use std::path::PathBuf;

const NOISE: Noise =
    Noise { angle_deg: 0.4, displacement_cm: 0.01, angle_reading_deg: 0.25, displacement_reading_cm: 0.01 };

#[test]
fn the_best_follow_up_is_written_as_a_study_whose_templates_the_readers_read() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let st = Study::from_file(&root.join("tests/discrepancy/study.toml")).unwrap();
    let mut s = st.discrepancy.clone();
    (s.realizations, s.extension_realizations, s.null_realizations) = (2, 3, 3);
    (s.grid_points, s.null_replicates, s.check_replicates, s.bootstrap) = (2, 20, 20, 100);
    s.effects = vec!["initial_lean".into(), "edge_rounding".into()];
    (s.scatter, s.confirm) = (false, false);
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
    assert!(plan.contenders.len() >= 2 && (plan.contenders.iter().map(|c| c.prior).sum::<f64>() - 1.0).abs() < 1e-9);
    for w in plan.ranked.windows(2) {
        assert!(w[0].at_budget.alone >= w[1].at_budget.alone, "ranked best first");
    }
    for r in &plan.ranked {
        assert!((0.0..=1.0).contains(&r.at_budget.alone) && r.at_budget.alone <= r.at_budget.right + 1e-12);
        // Naming alone asks the weights' criterion and the tie check's two tests.
        assert!(r.at_budget.alone <= r.at_budget.weights_alone + 1e-12);
        // The surrogates answer for more specimens of a group; the others need runs.
        assert_eq!(r.followup.kind == FollowUpKind::MoreSpecimens, r.runs == 0 && r.followup.new_group.is_none());
    }
    // The report's section and the JSON's `followup`, only when designed.
    assert!(!report_markdown(&run, "t").contains("The next experiment"));
    assert!(report_json(&run).get("followup").is_none());
    run.followup = Some(plan.clone());
    assert!(report_markdown(&run, "t").contains("## The next experiment"));
    assert!(report_json(&run)["followup"]["ranked"].as_array().is_some_and(|a| a.len() == 3));

    // Write the follow-up the tall walls would be (whatever ranked first) and the best one.
    let dir = std::env::temp_dir().join(format!("design-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut tall = plan.clone();
    tall.ranked.sort_by_key(|r| r.followup.kind != FollowUpKind::Height);
    let files = write_followup(&st, &tall, &dir.join("tall"), 4).unwrap().unwrap();
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
    let best = write_followup(&st, &plan, &dir.join("best"), 3).unwrap().unwrap();
    assert!(Study::from_file(&best.study).is_ok());
    let _ = std::fs::remove_dir_all(&dir);
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
