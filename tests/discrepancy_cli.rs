//! `drystone discrepancy` and `drystone synthesize` on bad input: a clear message naming the
//! file, key, group or effect, exit status 2, no panic.

mod common;

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
