//! The corpus of hostile inputs to the shaking table, ground-motion files, limit analysis
//! and the pushover (`tests/bad_inputs/motion/` and the layouts of `tests/bad_inputs/`):
//! each case is a command or a study with its expected refusal (exit status 2 and a
//! fragment naming the flag, key, file, line or block) or warning; the valid controls next
//! to them still run. `CORPUS_CASES` counts the cases (docs/shake.md, "Refused inputs").

use drystone::ground::{read_record, read_record_with, ColumnMap};
use drystone::study::Study;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The number of cases of this corpus (every refusal and warning asserted below).
const CORPUS_CASES: usize = 61;

fn layout(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs").join(name)
}

fn motion(name: &str) -> PathBuf {
    layout("motion").join(name)
}

/// Runs `drystone ARGS...`; returns the exit code, the standard output and the standard
/// error.
fn drystone(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_drystone")).args(args).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `drystone shake LAYOUT ARGS...` with a short tail (only the verdict matters).
fn shake(layout_file: &str, args: &[&str]) -> (i32, String, String) {
    let l = layout(layout_file);
    let mut all = vec!["shake", l.to_str().unwrap()];
    if !args.contains(&"--tail-s") {
        all.extend_from_slice(&["--tail-s", "0.2"]);
    }
    all.extend_from_slice(args);
    drystone(&all)
}

fn refused(case: &str, (code, _, err): (i32, String, String), fragments: &[&str], count: &mut usize) {
    assert_eq!(code, 2, "{case}: exit {code}, {err}");
    for f in fragments {
        assert!(err.contains(f), "{case}: {f:?} not in {err}");
    }
    assert!(!err.contains("panicked"), "{case}: {err}");
    *count += 1;
}

const PULSE: [&str; 6] = ["--pulse", "one-sine", "--amplitude-g", "0.1", "--period-s", "0.2"];

fn with_pulse<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v: Vec<&str> = PULSE.to_vec();
    v.extend_from_slice(extra);
    v
}

/// Walls that do not stand as given are refused by every protocol with the tilting table's
/// message (which block, and how far it moved), before any load.
fn walls_that_do_not_stand(count: &mut usize) {
    for solver in ["nscd", "penalty"] {
        let s = ["--solver", solver];
        refused(
            "leaning block, zero amplitude",
            shake(
                "leaning_block.json",
                &[&["--pulse", "one-sine", "--amplitude-g", "0", "--period-s", "0.2"], &s[..]].concat(),
            ),
            &["does not stand as given", "block leaning moved"],
            count,
        );
        refused(
            "block 0.1 m above the table",
            shake("lifted_block.json", &[&PULSE[..], &s[..]].concat()),
            &["does not stand as given", "block lifted touches nothing"],
            count,
        );
        refused(
            "a block floating above the wall",
            shake("floating_block.json", &[&PULSE[..], &s[..]].concat()),
            &["block floater touches nothing"],
            count,
        );
        refused(
            "overhanging top block",
            shake("overhanging_top_block.json", &[&PULSE[..], &s[..]].concat()),
            &["does not stand as given", "block top moved"],
            count,
        );
    }
    let leaning = layout("leaning_block.json");
    let svg = std::env::temp_dir().join(format!("drystone-bad-motion-{}.svg", std::process::id()));
    let (code, out, err) = drystone(&["limit", leaning.to_str().unwrap(), "--svg", svg.to_str().unwrap()]);
    // The leaning block: centroid 0.05 m beyond its base edge at 0.1 m height, λ = −0.5.
    refused(
        "limit of the leaning block",
        (code, out, err.clone()),
        &["does not stand as given", "-0.5000", "leaning"],
        count,
    );
    assert!(!svg.exists(), "no mechanism is drawn for a wall that does not stand");
    refused(
        "lateral pushover (penalty) of the leaning block",
        drystone(&["lateral", leaning.to_str().unwrap(), "--pushover"]),
        &["does not stand as given", "block leaning moved"],
        count,
    );
    let (code, out, err) = drystone(&["lateral", leaning.to_str().unwrap(), "--solver", "nscd"]);
    assert!(!err.contains("damping"), "the rigid pushover asks for no damping: {err}");
    refused("lateral pushover (nscd) of the leaning block", (code, out, err), &["block leaning moved"], count);
}

/// Record files mean what their columns say.
fn columns(count: &mut usize) {
    let l = "stable_stack.json";
    let rec = |f: &str| motion(f).to_str().unwrap().to_string();
    let two = rec("two_horizontal.csv");
    refused(
        "two horizontal columns",
        shake(l, &["--record", &two]),
        &["two_horizontal.csv", "line 1", "2 horizontal acceleration columns", "--columns"],
        count,
    );
    let grav = rec("vertical_with_gravity.csv");
    refused(
        "vertical channel averaging -1 g",
        shake(l, &["--record", &grav]),
        &[
            "vertical_with_gravity.csv",
            "\"vert_g\" averages -1.000 g",
            "contains gravity",
            "--columns time=time_s,h=accel_g",
        ],
        count,
    );
    let minus2 = rec("vertical_minus_2g.csv");
    refused("vertical channel of -2 g", shake(l, &["--record", &minus2]), &["averages -2.000 g"], count);
    let twov = rec("two_vertical.csv");
    refused("two vertical columns", shake(l, &["--record", &twov]), &["2 vertical columns"], count);
    let three = rec("three_axes.csv");
    refused("three axes without a mapping", shake(l, &["--record", &three]), &["the header must be `time_s`"], count);
    refused(
        "a mapped column that is not there",
        shake(l, &["--record", &three, "--columns", "time=t,h=acc_q_g"]),
        &["--columns h=acc_q_g: no such column", "acc_x_g"],
        count,
    );
    refused(
        "a mapping without h",
        shake(l, &["--record", &three, "--columns", "time=t,v=acc_z_g"]),
        &["--columns", "h=COLUMN"],
        count,
    );
    refused(
        "a mapping for an AT2 record",
        shake(l, &["--record", &rec("coarse.AT2"), "--columns", "h=accel_g"]),
        &["coarse.AT2", "column mapping does not apply"],
        count,
    );
    // The mapping reads what it names: h = acc_x_g, v = acc_z_g (independent of the file's order).
    let map: ColumnMap = "time=t,h=acc_x_g,v=acc_z_g".parse().unwrap();
    let m = read_record_with(&motion("three_axes.csv"), Some(&map)).unwrap();
    assert_eq!(m.horizontal_g, vec![0.0, 0.1, 0.0]);
    assert_eq!(m.vertical_g, Some(vec![0.0, 0.02, 0.0]));
    // The command line says whether a vertical component was applied, in text and JSON.
    let (code, out, err) = shake(l, &["--record", &three, "--columns", "time=t,h=acc_x_g,v=acc_z_g"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("vertical          applied (peak 0.020 g)"), "{out}");
    let (code, out, err) = shake(l, &["--record", &two, "--columns", "h=accel_h2_g", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["vertical_applied"], false);
    assert!((v["pga_g"].as_f64().unwrap() - 0.2).abs() < 1e-12, "the second column was taken: {out}");
}

/// Every size has a limit before it is allocated or run.
fn sizes(count: &mut usize) {
    let l = "stable_stack.json";
    let rec = |f: &str| motion(f).to_str().unwrap().to_string();
    refused(
        "two samples 1e-12 s apart",
        shake(l, &["--record", &rec("gap_1e-12.csv")]),
        &["gap_1e-12.csv", "smallest interval is 1e-12 s", "1.000e12 samples", "8.0 TB"],
        count,
    );
    refused("AT2 DT = 1e9", shake(l, &["--record", &rec("dt_1e9.AT2")]), &["dt_1e9.AT2", "line 4", "2.000e9 s"], count);
    refused(
        "AT2 NPTS = 1e11",
        shake(l, &["--record", &rec("npts_1e11.AT2")]),
        &["npts_1e11.AT2", "line 4", "NPTS"],
        count,
    );
    refused(
        "a CSV of 1e9 s",
        shake(l, &["--record", &rec("long_uniform.csv")]),
        &["long_uniform.csv", "1.000e9 s"],
        count,
    );
    refused("--tail-s 1e9", shake(l, &with_pulse(&["--tail-s", "1e9"])), &["tail_s = 1000000000", "3600"], count);
    refused("--duration-s 1e9", shake(l, &with_pulse(&["--duration-s", "1e9"])), &["duration_s = 1000000000"], count);
    refused(
        "--period-s 1e6",
        shake(l, &["--pulse", "one-sine", "--amplitude-g", "0.1", "--period-s", "1e6"]),
        &["--period-s 1000000", "1.000e6 s"],
        count,
    );
    refused(
        "--dt-s 1e-12",
        shake(l, &with_pulse(&["--dt-s", "1e-12"])),
        &["--dt-s", "2.000e11 samples", "1.6 TB"],
        count,
    );
    refused(
        "a record at --dt-s 1e-9",
        shake(l, &["--record", &rec("coarse.AT2"), "--dt-s", "1e-9"]),
        &["too long", "steps of 1.000e-9 s", "limit is 1e8 steps"],
        count,
    );
}

/// Motions the solver cannot resolve, implausible PGAs and messages that name the real cause.
fn resolution_and_messages(count: &mut usize) {
    let l = "stable_stack.json";
    let rec = |f: &str| motion(f).to_str().unwrap().to_string();
    refused(
        "a pulse of two steps",
        shake(l, &["--pulse", "one-sine", "--amplitude-g", "5", "--period-s", "0.002"]),
        &["--period-s 0.002", "2.0 steps", "--period-s >= 1e-2"],
        count,
    );
    refused(
        "--scale-pga-g on an all-zero record",
        shake(l, &["--record", &rec("all_zero.csv"), "--scale-pga-g", "0.5"]),
        &["--scale-pga-g 0.5", "PGA 0"],
        count,
    );
    let (code, _, err) = shake(l, &["--record", &rec("coarse.AT2")]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning: ") && err.contains("sampled every 0.2 s"), "{err}");
    *count += 1;
    let (code, _, err) = shake(l, &["--pulse", "one-sine", "--amplitude-g", "1e6", "--period-s", "0.2"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning: PGA 1.000e6 g is implausible"), "{err}");
    *count += 1;
    let (code, _, err) = shake(l, &PULSE);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("warning"), "a plausible pulse runs without a warning: {err}");
    // A duration past the motion's end simulates the motion only: said, not silent.
    let (code, _, err) = shake(l, &with_pulse(&["--duration-s", "100"]));
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning: --duration-s 100 is longer than the motion"), "{err}");
    *count += 1;
    // A --vtk path that cannot hold the series (an existing file) is refused before the run.
    let scratch = std::env::temp_dir().join(format!("drystone-vtk-file-{}", std::process::id()));
    std::fs::write(&scratch, "not a directory").unwrap();
    let started = std::time::Instant::now();
    let (code, out, err) = shake(l, &with_pulse(&["--tail-s", "30", "--vtk", scratch.to_str().unwrap()]));
    assert!(started.elapsed().as_secs_f64() < 20.0 && out.is_empty(), "the run went ahead: {out}");
    refused("--vtk at a file", (code, out, err), &["--vtk", "cannot be written"], count);
    let _ = std::fs::remove_file(&scratch);
    // A record saved with a UTF-8 byte-order mark (as spreadsheets save CSV) reads.
    let bom = std::env::temp_dir().join(format!("drystone-bom-{}.csv", std::process::id()));
    std::fs::write(&bom, "\u{feff}time_s,accel_g\n0,0\n0.01,0.1\n0.02,0\n").unwrap();
    let (code, _, err) = shake(l, &["--record", bom.to_str().unwrap()]);
    assert_eq!(code, 0, "a record with a byte-order mark: {err}");
    assert!(!err.contains("coarser than the record"), "{err}");
    *count += 1;
    // Settings of a step of motion that cost more than they save run with a warning naming
    // the flag: a natural-map tolerance below the rounding floor, an iteration cap that
    // sends the capped steps to the cone programs.
    for (flag, value) in [("--nscd-natural-tolerance", "1e-12"), ("--nscd-max-iterations", "20")] {
        let (code, _, err) = shake(l, &with_pulse(&["--tail-s", "0", flag, value]));
        assert_eq!(code, 0, "{err}");
        assert!(err.contains(&format!("warning: {flag} = {value}")), "{flag} {value}: {err}");
        *count += 1;
    }
    // A solver step coarser than the record's sampling runs on the record's mean over each
    // step, with a warning naming both.
    let (code, _, err) = shake(l, &["--record", bom.to_str().unwrap(), "--dt-s", "0.02"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("--dt-s 0.02 s is coarser than the record's sampling 0.01 s"), "{err}");
    *count += 1;
    let _ = std::fs::remove_file(&bom);
    refused(
        "--solver penalty --dt-s 0",
        shake(l, &with_pulse(&["--solver", "penalty", "--dt-s", "0"])),
        &["--dt-s must be > 0"],
        count,
    );
    refused("--duration-s -1", shake(l, &with_pulse(&["--duration-s", "-1"])), &["duration_s = -1"], count);
    refused("--tail-s -1", shake(l, &with_pulse(&["--tail-s", "-1"])), &["tail_s = -1"], count);
    refused(
        "--amplitude-g beside --record",
        shake(l, &["--record", &rec("coarse.AT2"), "--amplitude-g", "0.3"]),
        &["--amplitude-g", "--scale-pga-g"],
        count,
    );
    let stack = layout(l);
    let s = stack.to_str().unwrap();
    for solver in [&["--pushover"][..], &["--solver", "nscd"][..]] {
        let mut a = vec!["lateral", s, "--pressure-base-pa", "0", "--pressure-top-pa", "0"];
        a.extend_from_slice(solver);
        refused("pushover of zero pressure", drystone(&a), &["pressure_base_pa = 0", "both are 0"], count);
    }
    // A wedge whose front face slopes 79° from vertical: no face takes the pressure.
    let wedge = layout("wedge_no_exposed_face.json");
    for solver in [&["--pushover"][..], &["--solver", "nscd"][..]] {
        let mut a = vec!["lateral", wedge.to_str().unwrap()];
        a.extend_from_slice(solver);
        refused(
            "pushover of a pressure on no exposed face",
            drystone(&a),
            &["pressure_base_pa = 1000", "resolves to no force", "0 loaded faces"],
            count,
        );
    }
    // The rigid check allows no joint closure: its message gives no tolerance of 0 m.
    let leaning = layout("leaning_block.json");
    let (code, out, err) = drystone(&["lateral", leaning.to_str().unwrap(), "--solver", "nscd"]);
    assert!(!err.contains("0.000e0"), "no zero tolerance in the rigid message: {err}");
    refused("rigid check of the leaning block", (code, out, err), &["rigid contacts", "did not come to rest"], count);
    refused(
        "lateral --pressure-base-pa -5",
        drystone(&["lateral", s, "--pressure-base-pa", "-5"]),
        &["pressure_base_pa = -5"],
        count,
    );
}

/// A shaking study of the rigid block of 0.2 × 0.1 × 0.5 m with the given `[shake]` lines.
fn study(dir: &Path, shake: &str) -> PathBuf {
    let wall = "version = 1\nname = \"block\"\n[geometry]\nlength_m = 0.2\nheight_m = 0.5\nbase_width_m = 0.1\n\
                top_width_m = 0.1\nbatter = \"symmetric\"\n[arrangement]\nkind = \"continuous\"\n[courses]\n\
                height_m = 0.5\n[blocks]\nlength_m = 0.2\nmaterial = \"stone\"\n[[materials]]\nname = \"stone\"\n\
                density_kg_per_m3 = 2000.0\nkn_pa_per_m = 1.0e9\nks_pa_per_m = 5.0e8\nfriction_deg = 60.0\n\
                cohesion_pa = 0.0\ntensile_strength_pa = 0.0\n[restraints]\nbase = \"free\"\nends = { kind = \"free\" }\n";
    std::fs::write(dir.join("block.toml"), wall).unwrap();
    for f in ["two_horizontal.csv", "vertical_with_gravity.csv", "three_axes.csv"] {
        std::fs::copy(motion(f), dir.join(f)).unwrap();
    }
    let text = format!(
        "version = 1\nname = \"block_shake\"\nseed = 5\nrealizations = 1\nprotocol = \"shake\"\n[solver]\n\
         kind = \"nscd\"\n[shake]\n{shake}\n[[groups]]\nname = \"block\"\nwall = \"block.toml\"\n"
    );
    let path = dir.join("study.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// The same rules in studies, naming the key.
fn studies(count: &mut usize) {
    let dir = std::env::temp_dir().join(format!("drystone-bad-motion-study-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let err = |shake: &str| Study::from_file(&study(&dir, shake)).unwrap_err().to_string();
    let cases: [(&str, &[&str]); 9] = [
        (
            "pga_g = [0.2]\nrecords = [\"two_horizontal.csv\"]",
            &["shake.records[0]", "2 horizontal acceleration columns"],
        ),
        ("pga_g = [0.2]\nrecords = [\"vertical_with_gravity.csv\"]", &["shake.records[0]", "contains gravity"]),
        (
            "pga_g = [0.2]\nrecords = [\"three_axes.csv\"]\ncolumns = { h = \"acc_q_g\" }",
            &["shake.records[0]", "no such column"],
        ),
        ("pga_g = [0.2]\nstochastic = { count = 1, duration_s = 1e9 }", &["shake.stochastic.duration_s", "3600"]),
        ("pga_g = [0.2]\nstochastic = { count = 1, dt_s = 1e-9 }", &["shake.stochastic.dt_s", "2e7 samples"]),
        (
            "pga_g = [0.2, 0.4]\npulses = [{ kind = \"one-sine\", amplitude_g = 5.0, period_s = 0.002 }]",
            &["shake.pulses[0]", "period_s = 0.002", "too few to resolve"],
        ),
        (
            "pga_g = [0.2]\npulses = [{ kind = \"one-sine\", amplitude_g = 1.0, period_s = 0.5 }]\ntail_s = 1e9",
            &["shake.tail_s", "3600"],
        ),
        (
            "pga_g = [0.2]\npulses = [{ kind = \"one-sine\", amplitude_g = 1.0, period_s = 1e6 }]",
            &["shake.pulses[0]", "period_s = 1000000", "3600 s"],
        ),
        (
            "pga_g = [1e300]\npulses = [{ kind = \"one-sine\", amplitude_g = 1.0, period_s = 0.5 }]",
            &["shake.pga_g", "at most 100 g", "1e300"],
        ),
    ];
    for (shake, fragments) in cases {
        let text = err(shake);
        for f in fragments {
            assert!(text.contains(f), "{shake}: {f:?} not in {text}");
        }
        *count += 1;
    }
    // Limit analysis in a study: a realization built 20° out of plumb (its centroid beyond
    // its base: tan 20° · 0.25 m = 0.091 m > 0.05 m) gives a failed row with the message,
    // as a tilting-table row does, not a negative capacity.
    let effect = "version = 1\nname = \"big_lean\"\ndescription = \"built far out of plumb\"\n[[parameters]]\n\
                  name = \"lean_deg\"\nunit = \"deg\"\nmin = 0.0\nmax = 30.0\nscale = \"linear\"\nneutral = 0.0\n\
                  [[steps]]\nkind = \"lean\"\nparameter = \"lean_deg\"\n";
    std::fs::write(dir.join("big_lean.toml"), effect).unwrap();
    let text = "version = 1\nname = \"lean\"\nseed = 5\nrealizations = 1\neffect_files = [\"big_lean.toml\"]\n\
                protocol = \"tilt\"\n[solver]\nkind = \"limit\"\n[[groups]]\nname = \"block\"\nwall = \"block.toml\"\n\
                effects = { big_lean = { lean_deg = 20.0 } }\n";
    std::fs::write(dir.join("lean.toml"), text).unwrap();
    let rows =
        drystone::study::run_study(&Study::from_file(&dir.join("lean.toml")).unwrap(), drystone::ensemble::Shard::ALL);
    assert_eq!(rows[0].status.as_str(), "no_initial_equilibrium", "{:?}", rows[0]);
    assert!(rows[0].error.contains("does not stand as given") && rows[0].error.contains("-0.16"), "{}", rows[0].error);
    assert_eq!(rows[0].collapse.collapse_angle_deg, None);
    *count += 1;
    // A penalty study whose step count (the penalty step of realization 0, from its masses
    // and stiffnesses: about 8e-6 s at penalty_step_fraction 0.01) passes 1e8 is refused
    // before the run, with the estimate.
    let path = study(
        &dir,
        "pga_g = [0.2]\npulses = [{ kind = \"one-sine\", amplitude_g = 1.0, period_s = 0.5 }]\ntail_s = 3000\n\
         penalty_step_fraction = 0.01",
    );
    let text = std::fs::read_to_string(&path).unwrap().replace("kind = \"nscd\"", "kind = \"penalty\"");
    std::fs::write(&path, text).unwrap();
    let e = Study::from_file(&path).unwrap_err().to_string();
    for f in ["by the penalty solver", "realization 0", "too long", "the limit is 1e8 steps"] {
        assert!(e.contains(f), "{f:?} not in {e}");
    }
    *count += 1;
    // A shaking study warns once per motion about a coarse record and a PGA above 5 g, on
    // stderr and in the report.
    std::fs::copy(motion("coarse.AT2"), dir.join("coarse.AT2")).unwrap();
    let path = study(&dir, "pga_g = [0.2, 6.0]\nrecords = [\"coarse.AT2\"]\ntail_s = 0.2");
    let out = dir.join("out");
    let (code, _, err) = drystone(&["run", path.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    for w in ["motion coarse is sampled every 0.2 s", "motion coarse is scaled to PGA 6.000e0 g, implausible"] {
        assert_eq!(err.matches(w).count(), 1, "{w:?} once in {err}");
        assert!(report.contains(w), "{w:?} not in the report");
        *count += 1;
    }
    // A plausible study warns about nothing.
    let path = study(&dir, "pga_g = [0.2]\npulses = [{ kind = \"one-sine\", amplitude_g = 1.0, period_s = 0.5 }]");
    assert!(Study::from_file(&path).unwrap().protocol.shake().unwrap().warnings().is_empty());
    // A mapping in the study reads the record it names.
    let ok = Study::from_file(&study(
        &dir,
        "pga_g = [0.2]\nrecords = [\"two_horizontal.csv\"]\ncolumns = { h = \"accel_h1_g\" }",
    ));
    assert!(ok.is_ok(), "{:?}", ok.err());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_hostile_motion_input_is_refused_or_warned_about() {
    let mut count = 0;
    walls_that_do_not_stand(&mut count);
    columns(&mut count);
    sizes(&mut count);
    resolution_and_messages(&mut count);
    studies(&mut count);
    assert_eq!(count, CORPUS_CASES, "update CORPUS_CASES and docs/shake.md");
}

/// Valid records read as before: one horizontal column, or one horizontal and one
/// vertical column named so, in either order.
#[test]
fn valid_column_layouts_still_read() {
    let dir = std::env::temp_dir().join(format!("drystone-good-motion-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        ("a.csv", "time_s,accel_g\n0,0.1\n0.01,-0.2\n", None),
        ("b.csv", "time_s,accel_g,vert_g\n0,0.1,0.05\n0.01,-0.2,0\n", Some(vec![0.05, 0.0])),
        ("c.tsv", "time_s\tup_g\taccel_g\n0\t0.05\t0.1\n0.01\t0\t-0.2\n", Some(vec![0.05, 0.0])),
        ("d.csv", "time_s,acc_ew_g,acc_ud_g\n0,0.1,0.05\n0.01,-0.2,0\n", Some(vec![0.05, 0.0])),
    ];
    for (name, text, vertical) in cases {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let m = read_record(&p).unwrap();
        assert_eq!(m.horizontal_g, vec![0.1, -0.2], "{name}");
        assert_eq!(m.vertical_g, vertical, "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
