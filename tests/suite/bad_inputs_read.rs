//! Hostile studies refused when they are read: every value the command line refuses
//! (`drystone tilt --by-hand`, `drystone tilt --solver limit`, the rope, the section
//! sizes) is refused by `drystone run` before any realization runs, with exit status 2
//! and a message naming the file, the key and the value; never a column of `blew_up`
//! rows. `CORPUS_CASES` counts them.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The number of cases of this corpus.
const CORPUS_CASES: usize = 19;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A study of `body` (its tables after `protocol`) on `wall` (a path under the crate
/// root), written to `dir/name.toml`.
fn study(dir: &Path, name: &str, wall: &str, body: &str) -> PathBuf {
    let text = format!(
        "version = 1\nname = \"{name}\"\nseed = 7\nrealizations = 2\nprotocol = \"tilt\"\n{body}\n\n[[groups]]\nname = \"G\"\nwall = \"{}\"\n",
        root().join(wall).display()
    );
    let p = dir.join(format!("{name}.toml"));
    std::fs::write(&p, text).unwrap();
    p
}

/// Runs `drystone run study --out dir/out-NAME`; the exit status and stderr.
fn run(study: &Path, dir: &Path) -> (i32, String, PathBuf) {
    let out = dir.join(format!("out-{}", study.file_stem().unwrap().to_str().unwrap()));
    let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
        .args(["run", study.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    (o.status.code().unwrap_or(-1), String::from_utf8_lossy(&o.stderr).into_owned(), out)
}

fn refused(case: &str, study: &Path, dir: &Path, fragments: &[&str], count: &mut usize) {
    let (code, err, out) = run(study, dir);
    assert_eq!(code, 2, "{case}: exit {code}, {err}");
    for f in fragments {
        assert!(err.contains(f), "{case}: {f:?} not in {err}");
    }
    assert!(err.contains(study.file_name().unwrap().to_str().unwrap()), "{case}: the file is named: {err}");
    assert!(!err.contains("panicked"), "{case}: {err}");
    // Nothing ran: no journal of realizations.
    let journal = out.join("journal.jsonl");
    let rows = std::fs::read_to_string(&journal).map(|t| t.lines().count()).unwrap_or(0);
    assert_eq!(rows, 0, "{case}: {rows} realizations ran");
    *count += 1;
}

/// A block 0.09 × 0.3 × 0.4 m (y, z, x) on the table, its base held, with one rope of
/// the given values at mid-length over its height.
fn rope_block(values: &str) -> String {
    format!(
        r#"{{"version": 1, "name": "block held by a rope", "materials": [{{"name": "m", "density_kg_per_m3": 2200,
        "kn_pa_per_m": 1e9, "ks_pa_per_m": 5e8, "friction_deg": 30}}], "table": {{"material": "m"}},
        "blocks": [{{"id": "b0", "material": "m", "vertices": [[0,-0.045,0],[0.4,-0.045,0],[0.4,0.045,0],[0,0.045,0],
        [0,-0.045,0.3],[0.4,-0.045,0.3],[0.4,0.045,0.3],[0,0.045,0.3]]}}],
        "restraints": {{"base_sliding": "held", "ropes": [{{"x_m": 0.2, "band_m": [0.0, 0.3], {values}}}]}}}}"#
    )
}

const TINY: &str = "tests/studies/walls/tiny_running_bond.toml";
const RESTRAINED: &str = "tests/discrepancy/walls/small_restrained.toml";

#[test]
fn values_the_command_line_refuses_are_refused_when_a_study_is_read() {
    let dir = std::env::temp_dir().join(format!("drystone-bad-read-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut count = 0;
    let nscd = "[solver]\nkind = \"nscd\"\n";
    // The hand-rolled table: a run of about 1e8 steps, a stop of 2 ms (two steps of the
    // default 1 ms), a stop under 5 steps of a longer `dt_s`.
    let s = study(
        &dir,
        "hold_600",
        TINY,
        &format!("{nscd}\n[tilt]\nby_hand = {{ increment_deg = 0.5, rate_deg_per_s = 0.5, hold_s = 600.0 }}"),
    );
    refused("increments of 0.5° held 600 s", &s, &dir, &["tilt.by_hand.hold_s", "600", "2e7"], &mut count);
    let s = study(&dir, "ramp_2ms", TINY, &format!("{nscd}\n[tilt]\nby_hand = {{ ramp_s = 0.002 }}"));
    refused("a stop of 2 ms", &s, &dir, &["tilt.by_hand.ramp_s", "0.002", "5 time steps"], &mut count);
    let s = study(
        &dir,
        "ramp_under_5_steps",
        TINY,
        "[solver]\nkind = \"nscd\"\nnscd = { dt_s = 0.01 }\n\n[tilt]\nby_hand = { ramp_s = 0.04 }",
    );
    refused("a stop of 4 steps of dt_s", &s, &dir, &["tilt.by_hand.ramp_s", "0.04", "5 time steps"], &mut count);
    // Limit analysis of a wall held by ropes, refused as `drystone tilt --solver limit` does.
    let s = study(
        &dir,
        "limit_end_rope",
        RESTRAINED,
        "[solver]\nkind = \"limit\"\n\n[effects]\nend_rope = { pretension_n = 300.0, axial_stiffness_n = 6.0e4 }",
    );
    refused("limit analysis with end_rope", &s, &dir, &["effects.end_rope", "rope restraint"], &mut count);
    // `table_kick` (the quasi-static equivalent of the stops' kicks) with the table rolled by
    // hand (which runs the kicks and does not read it): refused by name, not dropped.
    let s = study(
        &dir,
        "hand_table_kick",
        TINY,
        &format!(
            "{nscd}\n[tilt]\nby_hand = {{ increment_deg = 10.0 }}\n\n[effects]\ntable_kick = {{ overshoot_deg = 1.0 }}"
        ),
    );
    refused("table_kick with by_hand", &s, &dir, &["effects.table_kick", "by_hand"], &mut count);
    // An effect on the in-plane rig's vertical load in a tilting-table study, which has no
    // such rig: refused by name, not run as the plain wall.
    let s = study(&dir, "tilt_jack_tilt", TINY, "[effects]\njack_tilt = { inverse_length_per_m = 0.5 }");
    refused("jack_tilt on the tilting table", &s, &dir, &["effects.jack_tilt", "in_plane"], &mut count);
    // The discrepancy settings: an unknown name under the list that gives it, a σ of 1e300.
    let s = study(&dir, "also_unknown", TINY, "[discrepancy]\nalso_effects = [\"table_kik\"]");
    refused("also_effects naming no effect", &s, &dir, &["discrepancy.also_effects[0]", "table_kik"], &mut count);
    let s = study(&dir, "sigma_1e300", TINY, "[discrepancy]\nsigma = { angle_deg = 1e300 }");
    refused("sigma.angle_deg = 1e300", &s, &dir, &["sigma.angle_deg", "1e300"], &mut count);
    // A reading's share on each neighbouring joint of 0.6 (more than the joint read keeps).
    let s = study(&dir, "neighbour_joint", TINY, "[discrepancy]\nreading = { neighbour_joint = 0.6 }");
    refused("reading.neighbour_joint = 0.6", &s, &dir, &["reading.neighbour_joint", "0.6", "[0, 1/3)"], &mut count);
    // 0.4 on each neighbour leaves the joint read 0.2: a reading at the failing joint would
    // score worse than one a course off. Refused with the range that keeps it highest.
    let s = study(&dir, "neighbour_joint_04", TINY, "[discrepancy]\nreading = { neighbour_joint = 0.4 }");
    refused(
        "reading.neighbour_joint = 0.4",
        &s,
        &dir,
        &["reading.neighbour_joint", "0.4", "[0, 1/3)", "a course off"],
        &mut count,
    );
    // Flags named by themselves, values with a minus sign included.
    let stack = root().join("tests/bad_inputs/stable_stack.json");
    let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
        .arg("tilt")
        .arg(&stack)
        .args(["--solver", "nscd", "--by-hand", "--hand-increment-deg", "1e-300"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--hand-increment-deg") && !err.contains("--hand-ramp-s"), "{err}");
    count += 1;
    for (flag, value) in [("--specimens", "-1"), ("--target", "-0.5")] {
        let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
            .arg("design")
            .arg(root().join("studies/tilting_table.toml"))
            .args([flag, value, "--out"])
            .arg(dir.join("design"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {err}");
        assert!(err.contains(flag) && err.contains(value), "{flag} {value}: {err}");
        assert!(!err.contains("unexpected argument") && !err.contains("discrepancy.design"), "{err}");
        count += 1;
    }
    // Rope values in range that would blow the run up: refused by the rope's key.
    for (name, rope, key, value) in [
        (
            "rope_span_1e-200",
            r#""pretension_n": 300, "axial_stiffness_n": 6e4, "span_m": 1e-200"#,
            "restraints.ropes[0].span_m",
            "1e-200",
        ),
        (
            "rope_wrap_9cm_1e6",
            r#""pretension_n": 1e6, "axial_stiffness_n": 6e4, "span_m": 0.1, "wrap_depth_m": 0.09"#,
            "restraints.ropes[0].wrap_depth_m",
            "0.09",
        ),
    ] {
        let layout = dir.join(format!("{name}.json"));
        std::fs::write(&layout, rope_block(rope)).unwrap();
        for solver in ["penalty", "nscd"] {
            let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
                .args(["tilt", layout.to_str().unwrap(), "--solver", solver])
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&o.stderr).into_owned();
            assert_eq!(o.status.code(), Some(2), "{name} {solver}: {err}");
            assert!(err.contains(key) && err.contains(value), "{name} {solver}: {err}");
            assert!(!err.contains("blew up"), "{name} {solver}: {err}");
        }
        count += 1;
    }
    // Section sizes below the thinnest piece: refused by name by `generate` and when a
    // study is read, never a layout grown past memory or called a generator bug.
    let tiny = std::fs::read_to_string(root().join(TINY)).unwrap();
    for (name, section, key, value) in [
        ("leaf_1e-9", "leaf_width_m = 1e-9", "section.leaf_width_m", "0.000000001"),
        ("leaf_1e-4", "leaf_width_m = 1e-4", "section.leaf_width_m", "0.0001"),
        ("hearting_1e-9", "leaf_width_m = 0.02\nhearting_stone_m = 1e-9", "section.hearting_stone_m", "0.000000001"),
    ] {
        let wall = dir.join(format!("{name}.toml"));
        std::fs::write(&wall, format!("{tiny}\n[section]\nleaves = 2\n{section}\n")).unwrap();
        let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
            .args(["generate", wall.to_str().unwrap(), "--seed", "1", "--out"])
            .arg(dir.join(format!("{name}.json")))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(2), "generate {name}: {err}");
        assert!(err.contains(key) && err.contains(value), "generate {name}: {err}");
        assert!(!err.contains("generator bug"), "{name}: {err}");
        if name == "hearting_1e-9" {
            let text = format!(
                "version = 1\nname = \"{name}\"\nseed = 7\nrealizations = 2\nprotocol = \"tilt\"\n\n[[groups]]\nname = \"G\"\nwall = \"{}\"\n",
                wall.display()
            );
            let s = dir.join(format!("study_{name}.toml"));
            std::fs::write(&s, text).unwrap();
            refused("a study of hearting pieces of 1e-9 m", &s, &dir, &[key, value], &mut count);
        }
        count += 1;
    }
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(count, CORPUS_CASES);
}

/// Inputs a study accepts but does not use are named in a warning on stderr and in the
/// report's "Warnings": `end_rope` on a wall without end restraints, `[tilt] step_deg`
/// with the table rolled by hand, `discrepancy.also_effects` beside `discrepancy.effects`,
/// a `[solver.penalty]` key with `kind = "nscd"` (as a `[solver.nscd]` key with the
/// penalty DEM), a `[solver.nscd]` key of a step of motion in a tilting study (its
/// release trials do not read it); `drystone discrepancy` and `design` print them too.
#[test]
fn inputs_accepted_but_ignored_are_warned_of_by_key() {
    let dir = std::env::temp_dir().join(format!("drystone-ignored-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let s = study(
        &dir,
        "ignored",
        TINY,
        "[solver]\nkind = \"nscd\"\n\n[solver.penalty]\nmax_steps = 1000\n\n[solver.nscd]\nnatural_tolerance = 1e-5\n\n[tilt]\nstep_deg = 1.0\nby_hand = { increment_deg = 10.0, rate_deg_per_s = 10.0, hold_s = 0.1 }\n\n\
         [effects]\nend_rope = { pretension_n = 300.0, axial_stiffness_n = 6.0e4 }\n\n\
         [discrepancy]\neffects = [\"end_rope\"]\nalso_effects = [\"table_kick\"]",
    );
    let (code, err, out) = run(&s, &dir);
    assert_eq!(code, 0, "{err}");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let warnings = report.split("## Warnings").nth(1).unwrap_or_else(|| panic!("no Warnings section: {report}"));
    for key in [
        "effects.end_rope",
        "tilt.step_deg",
        "discrepancy.also_effects",
        "discrepancy: table_kick",
        "solver.penalty.max_steps",
        "solver.nscd.natural_tolerance",
    ] {
        assert!(err.lines().any(|l| l.starts_with("warning:") && l.contains(key)), "{key} not warned on stderr: {err}");
        assert!(warnings.contains(key), "{key} not in the report's Warnings");
    }
    // `drystone discrepancy` and `design` read the same study and warn the same (before
    // they refuse a study without measured data).
    for command in ["discrepancy", "design"] {
        let o = Command::new(env!("CARGO_BIN_EXE_drystone")).arg(command).arg(&s).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.lines().any(|l| l.starts_with("warning: solver.penalty.max_steps is not read")),
            "{command}: {err}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `drystone tilt --by-hand` names every penalty or quasi-static option it does not read.
#[test]
fn options_the_table_rolled_by_hand_does_not_read_are_warned_of() {
    let stack = root().join("tests/bad_inputs/stable_stack.json");
    let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
        .arg("tilt")
        .arg(&stack)
        .args(["--solver", "nscd", "--by-hand", "--hand-increment-deg", "10", "--hand-hold-s", "0.1"])
        .args(["--step-deg", "1", "--resolution-deg", "0.5", "--max-steps", "1000", "--damping", "0.5"])
        .args(["--density-scaling", "off", "--timestep-safety", "0.5", "--no-predictor"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(0), "{err}");
    // A start or stop that pushes the top at hundreds of g is run, with the plausibility
    // warning the shaking table gives above 5 g.
    let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
        .arg("tilt")
        .arg(&stack)
        .args(["--solver", "nscd", "--by-hand", "--hand-increment-deg", "10", "--hand-hold-s", "0.1"])
        .args(["--table-axis-depth-m", "100", "--hand-ramp-s", "0.005", "--hand-rate-deg-s", "10"])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(e.lines().any(|l| l.starts_with("warning:") && l.contains("implausible") && l.contains("5 g")), "{e}");
    for flag in [
        "--step-deg",
        "--resolution-deg",
        "--max-steps",
        "--damping",
        "--density-scaling",
        "--timestep-safety",
        "--no-predictor",
    ] {
        assert!(err.lines().any(|l| l.starts_with(&format!("warning: {flag} "))), "{flag}: {err}");
    }
}
