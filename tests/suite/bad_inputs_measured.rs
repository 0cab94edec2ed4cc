//! The corpus of bad measured data in `tests/bad_inputs/measured/`: one file per class of
//! impossible or ambiguous data, each refused with a message that names the file, the
//! line and the column, exit status 2 and nothing run. `collapse.csv` and
//! `displacement.csv` are good; a case named `collapse_*` or `displacement_*` replaces one of
//! them in a small study of the SBL wall (tilt step 0.5°).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common;

fn corpus(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs/measured").join(name)
}

/// A study in `dir` of the SBL wall measured by `collapse` and `displacement` (corpus
/// files).
fn study(dir: &Path, collapse: &str, displacement: &str) -> PathBuf {
    let wall = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/walls/sbl.toml");
    let text = format!(
        "version = 1\nname = \"measured\"\nseed = 1\nrealizations = 1\n[tilt]\nstep_deg = 0.5\n\
         [[groups]]\nname = \"SBL\"\nwall = {:?}\n[measured]\ncollapse = {:?}\ndisplacement = {:?}\n",
        wall.display().to_string(),
        corpus(collapse).display().to_string(),
        corpus(displacement).display().to_string()
    );
    let p = dir.join(format!("{collapse}-{displacement}.toml"));
    std::fs::write(&p, text).unwrap();
    p
}

fn drystone(args: &[&dyn AsRef<std::ffi::OsStr>]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_drystone")).args(args).output().expect("drystone runs")
}

#[test]
fn every_bad_measured_file_is_refused_naming_file_line_and_column() {
    let s = common::Scratch::created("bad-measured");
    let cases = [
        ("collapse_angle_negative.csv", "line 3, column collapse_angle_deg: -5 is not in (0, 90) degrees"),
        ("collapse_angle_95.csv", "line 3, column collapse_angle_deg: 95 is not in (0, 90) degrees"),
        ("collapse_duplicate_specimen.csv", "line 5, column specimen: specimen SBL1 has a collapse angle on line 2"),
        ("collapse_missing_field.csv", "line 3, column -: 2 fields, the header has 3"),
        ("displacement_tilt_negative.csv", "line 3, column tilt_deg: -2 is not in [0, 90) degrees"),
        ("displacement_tilt_1000.csv", "line 3, column tilt_deg: 1000 is not in [0, 90) degrees"),
        ("displacement_1e300.csv", "line 5, column displacement_cm: 1e300 is not a displacement within ±1000 cm"),
        ("displacement_nan.csv", "line 5, column displacement_cm: NaN is not a displacement"),
        ("displacement_taller_than_wall.csv", "line 5, column displacement_cm: 50 cm is more than the height of the group's wall (37.5 cm)"),
        ("displacement_beyond_collapse.csv", "line 3, column tilt_deg: a displacement of specimen SBL1 at 14 degrees, beyond its collapse angle of 13.5 degrees (line 2 of"),
        ("displacement_off_grid.csv", "line 3, column tilt_deg: 5.3 degrees is not a tilt the study observes: not a multiple of its [tilt] step_deg = 0.5"),
        ("displacement_duplicate.csv", "line 8, column specimen: specimen SBL2 has a mean_of_left_center_right at 10 degrees on line 5 already"),
        ("displacement_two_groups.csv", "line 7, column group: specimen SBL3 is in group SBR here and in group SBL on line 6"),
        ("displacement_unknown_measure.csv", "line 4, column measure: unknown measure `mean_of_left_centre_right`"),
    ];
    for (case, fragment) in cases {
        let p = if case.starts_with("collapse") {
            study(&s, case, "displacement.csv")
        } else {
            study(&s, "collapse.csv", case)
        };
        let out = s.join(case);
        let o = drystone(&[&"run", &p, &"--out", &out]);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(2), "{case}: {err}");
        assert!(
            err.contains(&format!("{}: {fragment}", corpus(case).display())),
            "{case}: expected {fragment:?} in {err}"
        );
        assert!(!out.exists(), "{case}: nothing is written");
    }
}

#[test]
fn a_held_out_score_needs_two_specimens_per_group() {
    let s = common::Scratch::created("bad-measured-one");
    let p = study(&s, "collapse_single_specimen.csv", "displacement.csv");
    // The displacement file holds SBL2 and SBL3 too: the single specimen is only in a
    // collapse-only study.
    let text = std::fs::read_to_string(&p).unwrap();
    let one = text.lines().filter(|l| !l.starts_with("displacement")).collect::<Vec<_>>().join("\n");
    std::fs::write(&p, one).unwrap();
    let o = drystone(&[&"discrepancy", &p, &"--out", &s.join("out")]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{err}");
    let fragment = format!(
        "{}: line 2, column specimen: group SBL has a single specimen (SBL1); a held-out score needs at least two specimens per group",
        corpus("collapse_single_specimen.csv").display()
    );
    assert!(err.contains(&fragment), "{err}");
}

#[test]
fn the_good_files_load_and_repeated_effects_are_refused() {
    let s = common::Scratch::created("bad-measured-good");
    let p = study(&s, "collapse.csv", "displacement.csv");
    let st = drystone::study::Study::from_file(&p).unwrap();
    assert_eq!(st.measured.collapse.len(), 3);
    assert_eq!(st.measured.displacement[5].line, 7);
    let o = drystone(&[
        &"synthesize",
        &p,
        &"--effect",
        &"kn_scale=0.5,kn_scale=0.7",
        &"--seed",
        &"1",
        &"--out",
        &s.join("syn"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--effect: kn_scale is given twice"), "{err}");
    let o = drystone(&[&"synthesize", &p, &"--specimens", &"10000", &"--seed", &"1", &"--out", &s.join("syn")]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--specimens 10000: 10000 simulations of walls of up to about"), "{err}");
    assert!(!s.join("syn").exists());
}
