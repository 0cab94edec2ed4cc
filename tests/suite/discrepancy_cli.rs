//! `drystone discrepancy` and `drystone synthesize` on bad input: a clear message naming the
//! file, key, group or effect, exit status 2, no panic.

use crate::common;

use common::Scratch;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn drystone(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_drystone")).args(args).current_dir(root()).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!err.contains("panicked"), "{err}");
    (out.status.code().unwrap_or(-1), err)
}

fn study() -> String {
    root().join("tests/discrepancy/study.toml").display().to_string()
}

#[test]
fn an_unknown_effect_is_named_with_the_known_ones() {
    let (code, err) = drystone(&["synthesize", &study(), "--effect", "lean=1", "--seed", "1"]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown effect `lean`") && err.contains("initial_lean"), "{err}");
}

#[test]
fn a_parameter_out_of_its_range_is_named_with_the_range() {
    let (code, err) = drystone(&["synthesize", &study(), "--effect", "seating_gap=0.01", "--seed", "1"]);
    assert_eq!(code, 2);
    assert!(err.contains("max_gap_m = 0.01") && err.contains("[0, 0.003] m"), "{err}");
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join(name), text).unwrap();
}

#[test]
fn measured_data_of_a_group_the_study_lacks_is_refused() {
    let dir = Scratch::new("disc-group");
    write(&dir, "tilting_table_collapse.csv", "specimen,group,collapse_angle_deg\nX1,XYZ,20\n");
    let (code, err) = drystone(&["discrepancy", &study(), "--measured", &dir.display().to_string()]);
    assert_eq!(code, 2);
    assert!(err.contains("group `XYZ`") && err.contains("FREE, HELD"), "{err}");
}

#[test]
fn an_empty_data_file_is_refused() {
    let dir = Scratch::new("disc-empty");
    write(&dir, "tilting_table_collapse.csv", "specimen,group,collapse_angle_deg\n");
    let (code, err) = drystone(&["discrepancy", &study(), "--measured", &dir.display().to_string()]);
    assert_eq!(code, 2);
    assert!(err.contains("no observation"), "{err}");
}

#[test]
fn unknown_keys_and_effects_of_the_discrepancy_table_are_named() {
    let dir = Scratch::new("disc-table");
    let text = std::fs::read_to_string(root().join("tests/discrepancy/study.toml")).unwrap();
    let walls = root().join("tests/discrepancy/walls");
    let base = text.replace("walls/", &format!("{}/", walls.display()));
    let (head, _) = base.split_once("[discrepancy]").unwrap();
    for (table, expect) in [
        ("[discrepancy]\nrealisations = 3\n", "realisations"),
        ("[discrepancy]\neffects = [\"lean\"]\n", "lean"),
        ("[discrepancy]\nnull_replicates = 2\n", "null_replicates"),
    ] {
        write(&dir, "s.toml", &format!("{head}{table}"));
        let (code, err) = drystone(&["discrepancy", &dir.join("s.toml").display().to_string()]);
        assert_eq!(code, 2, "{table}");
        assert!(err.contains(expect) && err.contains("s.toml"), "{table}: {err}");
    }
}

/// The small walls' study with measured collapse angles and one calibration step, written
/// into `dir` (its walls by absolute path).
fn study_with_data(dir: &Path) -> String {
    let text = std::fs::read_to_string(root().join("tests/discrepancy/study.toml")).unwrap();
    let walls = root().join("tests/discrepancy/walls");
    let mut rows = String::from("specimen,group,collapse_angle_deg\n");
    for (i, (free, held)) in [(26.0, 33.5), (25.5, 34.0), (26.5, 33.0)].into_iter().enumerate() {
        rows += &format!("F{i},FREE,{free}\nH{i},HELD,{held}\n");
    }
    write(dir, "collapse.csv", &rows);
    let study = text.replace("walls/", &format!("{}/", walls.display()))
        + "\n[measured]\ncollapse = \"collapse.csv\"\n\n[[calibrate]]\ngroup = \"FREE\"\nparameter = \"friction_deg\"\nlower = 30.0\nupper = 31.0\n";
    write(dir, "s.toml", &study);
    dir.join("s.toml").display().to_string()
}

/// `discrepancy` and `calibrate` hold their output directory as `run` does: while one
/// analysis runs, a second one, a calibration and a run on the same `--out` are refused
/// naming the holder (its process id and command line), and nothing is written there;
/// after it is killed, the directory holds no output of it (its set was never committed)
/// and a calibration writes its own set whole (`calibration-manifest.json` with the digest
/// of each file).
#[test]
fn discrepancy_and_calibrate_hold_their_output_directory_and_write_whole_sets() {
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let scratch = Scratch::created("discrepancy-lock");
    let st = study_with_data(&scratch);
    let out = scratch.join("out");
    let o = out.to_str().unwrap();
    let mut first = Command::new(env!("CARGO_BIN_EXE_drystone"))
        .args(["discrepancy", &st, "--threads", "1", "--out", o])
        .current_dir(root())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("drystone starts");
    let lock = out.join(".drystone.lock");
    let t0 = Instant::now();
    while std::fs::read_to_string(&lock).map_or(true, |t| t.is_empty()) {
        assert!(t0.elapsed() < Duration::from_secs(60), "no lock within 60 s");
        assert!(first.try_wait().unwrap().is_none(), "the analysis ended before the test could race it");
        std::thread::sleep(Duration::from_millis(5));
    }
    let holder = format!("{}: in use by another drystone process (pid {}: ", out.display(), first.id());
    for args in [
        vec!["discrepancy", st.as_str(), "--threads", "1", "--out", o],
        vec!["calibrate", st.as_str(), "--out", o],
        vec!["run", st.as_str(), "--realizations", "1", "--out", o],
    ] {
        let (code, err) = drystone(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(&holder), "{args:?}: {err}");
    }
    assert!(first.try_wait().unwrap().is_none(), "the analysis ran through the race");
    first.kill().expect("SIGKILL");
    first.wait().unwrap();
    let names = |d: &Path| {
        let mut v: Vec<String> =
            std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    };
    assert_eq!(names(&out), [".drystone.lock"], "nothing written but the lock");
    let (code, err) = drystone(&["calibrate", &st, "--threads", "1", "--out", o]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(names(&out), [".drystone.lock", "calibration-manifest.json", "calibration.json", "calibration.md"]);
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("calibration-manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["command"], "calibrate");
    let outputs: Vec<drystone::study::OutputFile> = serde_json::from_value(manifest["outputs"].clone()).unwrap();
    let listed: Vec<&str> = outputs.iter().map(|f| f.path.as_str()).collect();
    assert_eq!(listed, ["calibration.json", "calibration.md"]);
    drystone::study::verify_outputs(&out, &outputs).unwrap();
    assert!(err.contains("calibrate: step 1/1 (FREE): friction_deg in 30.0° .. 31.0°"), "{err}");
}

/// A run store that cannot be made is refused before anything runs, naming its directory,
/// by both commands that take one.
#[test]
fn a_run_store_that_cannot_be_made_is_named() {
    let scratch = Scratch::created("run-store-bad");
    let st = study_with_data(&scratch);
    write(&scratch, "plain_file", "x");
    let bad = scratch.join("plain_file").join("runs");
    let out = scratch.join("out");
    for command in ["discrepancy", "design"] {
        let (code, err) =
            drystone(&[command, &st, "--run-store", &bad.display().to_string(), "--out", &out.display().to_string()]);
        assert_eq!(code, 2, "{command}: {err}");
        assert!(err.contains("run store") && err.contains("plain_file"), "{command}: {err}");
        assert!(!out.join("discrepancy.md").exists(), "{command}: nothing written");
    }
}

/// An in-plane study reads its specimens from `[measured] walls`: `--measured` and
/// `--measured-sets`, which replace a study's data by the tilting table's files, are
/// refused naming the study file and where its data come from, before anything is run or
/// written; without them the same study is read (a missing `[measured]` named by its key).
#[test]
fn an_in_plane_study_refuses_the_tilting_tables_measured_files_naming_its_own() {
    let dir = Scratch::new("disc-inplane-measured");
    let wall = root().join("studies/walls/granite_vasconcelos.toml");
    let walls = root().join("data/inplane_granite/walls.csv");
    let text = format!(
        "version = 1\nname = \"ip\"\nseed = 7\nrealizations = 1\nprotocol = \"in_plane\"\n\n[in_plane]\n\
         shear_span_m = 1.325\ndrift_pct = 0.5\n\n[[groups]]\nname = \"G\"\nwall = \"{}\"\nsigma0_mpa = 0.5\n",
        wall.display()
    );
    let measured = format!("specimens = [\"WS.100\"]\n\n[measured]\nwalls = \"{}\"\n", walls.display());
    write(&dir, "ip.toml", &format!("{text}{measured}"));
    write(&dir, "bare.toml", &text);
    let study = dir.join("ip.toml").display().to_string();
    let out = dir.join("out");
    let data = dir.display().to_string();
    for flag in ["--measured", "--measured-sets"] {
        let (code, err) = drystone(&["discrepancy", &study, flag, &data, "--out", &out.display().to_string()]);
        assert_eq!(code, 2, "{flag}: {err}");
        for part in [study.as_str(), "--measured and --measured-sets", "[measured] walls"] {
            assert!(err.contains(part), "{flag}: {part:?} not in {err}");
        }
        assert!(!out.exists(), "{flag}: {} written", out.display());
    }
    let bare = dir.join("bare.toml").display().to_string();
    let (code, err) = drystone(&["discrepancy", &bare, "--out", &out.display().to_string()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&bare) && err.contains("measured: the analysis needs the measured specimens"), "{err}");
    assert!(!out.exists(), "{} written", out.display());
}
