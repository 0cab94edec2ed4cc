//! Observed failure mechanisms (`[measured] mechanism = "..."`): the good corpus file reads
//! with every field that may be missing missing somewhere, the paper's transcription reads
//! as the text says, and every bad file in `tests/bad_inputs/measured/mechanism_*.csv` is
//! refused naming the file, the line and the column (through the study, so that the
//! checks against the study and the other measured files run too; one case through the
//! command line for its exit status).

use drystone::io::table::read_measured_mechanism;
use drystone::loading::mechanism::{FailureKind, FailureStart};
use drystone::study::Study;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common;

fn corpus(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs/measured").join(name)
}

/// A study in `dir` of the SBL wall measured by the corpus' good collapse and displacement
/// files and the mechanism file `mechanism`.
fn study(dir: &Path, mechanism: &str) -> PathBuf {
    let wall = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/walls/sbl.toml");
    let text = format!(
        "version = 1\nname = \"measured\"\nseed = 1\nrealizations = 1\n[tilt]\nstep_deg = 0.5\n\
         [[groups]]\nname = \"SBL\"\nwall = {:?}\n[measured]\ncollapse = {:?}\ndisplacement = {:?}\nmechanism = {:?}\n",
        wall.display().to_string(),
        corpus("collapse.csv").display().to_string(),
        corpus("displacement.csv").display().to_string(),
        corpus(mechanism).display().to_string()
    );
    let p = dir.join(format!("{mechanism}.toml"));
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn the_good_file_reads_with_missing_fields_missing() {
    let m = read_measured_mechanism(&corpus("mechanism.csv")).unwrap();
    assert_eq!(m.len(), 3);
    assert_eq!(
        (m[0].failure_height, m[0].kind, m[0].start, m[0].extent),
        (None, None, Some(FailureStart::Random), Some(1.0))
    );
    assert_eq!(m[1].failure_height, Some((0.4, 0.3, 0.5)));
    assert_eq!((m[1].kind, m[1].start), (Some(FailureKind::Toppling), Some(FailureStart::End)));
    assert_eq!(m[1].source, "a, quoted \"sentence\"");
    assert_eq!((m[2].failure_height, m[2].kind, m[2].start, m[2].extent, m[2].line), (None, None, None, None, 4));
    let s = common::Scratch::created("mechanism-good");
    let st = Study::from_file(&study(&s, "mechanism.csv")).unwrap();
    assert_eq!(st.measured.mechanism, m);
}

/// The paper's transcription, against its text (§2.2): the three CBL walls topple with the
/// upper 60 % moving, SBL starts in a random section, SBR bends from its centre.
#[test]
fn the_paper_s_mechanisms_are_its_words() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/paper/tilting_table_mechanism.csv");
    let m = read_measured_mechanism(&p).unwrap();
    assert_eq!(m.len(), 9);
    for r in &m {
        match r.group.as_str() {
            "CBL" => {
                let (v, lo, hi) = r.failure_height.unwrap();
                assert!((v - (1.0 - 0.6)).abs() < 1e-12 && lo < v && v < hi, "{r:?}");
                assert_eq!((r.kind, r.start), (Some(FailureKind::Toppling), None));
                assert!(r.source.contains("toppling of the 60% upper section"));
            }
            "SBL" => {
                assert_eq!((r.failure_height, r.kind, r.start), (None, None, Some(FailureStart::Random)));
                assert!(r.source.contains("started in a random section"));
            }
            "SBR" => {
                assert_eq!(
                    (r.failure_height, r.kind, r.start),
                    (None, Some(FailureKind::Bending), Some(FailureStart::Centre))
                );
                assert!(r.source.contains("started in the central section"));
            }
            g => panic!("unexpected group {g}"),
        }
    }
    // The main job reads it.
    let st = Study::from_file(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/tilting_table.toml")).unwrap();
    assert_eq!(st.measured.mechanism.len(), 9);
}

#[test]
fn every_bad_mechanism_file_is_refused_naming_file_line_and_column() {
    let s = common::Scratch::created("mechanism-bad");
    let cases = [
        (
            "mechanism_height_1.2.csv",
            "line 3, column failure_height_fraction: 1.2 is not a fraction of the wall height in [0, 1]",
        ),
        (
            "mechanism_height_outside_interval.csv",
            "line 2, column failure_height_fraction: 0.6 is not within its reading interval [0.3, 0.5]",
        ),
        (
            "mechanism_height_without_low.csv",
            "line 3, column failure_height_low: empty: a failure height needs its reading interval",
        ),
        (
            "mechanism_unknown_kind.csv",
            "line 4, column kind: unknown kind `overturning` (known: toppling, sliding, bending, mixed)",
        ),
        (
            "mechanism_unknown_start.csv",
            "line 2, column start: unknown start `left` (known: end, centre, uniform, random)",
        ),
        ("mechanism_extent_0.csv", "line 2, column extent_fraction: 0 is not in (0, 1]"),
        ("mechanism_duplicate.csv", "line 3, column specimen: specimen SBL1 has a mechanism on line 2 already"),
        (
            "mechanism_unknown_specimen.csv",
            "line 3, column specimen: unknown specimen SBL7: not in the collapse or displacement data",
        ),
        ("mechanism_unknown_group.csv", "line 3, column group: group CBL is not a group of the study (groups: SBL)"),
    ];
    for (case, fragment) in cases {
        let err = Study::from_file(&study(&s, case)).map(|_| ()).unwrap_err().to_string();
        assert!(
            err.contains(&format!("{}: {fragment}", corpus(case).display())),
            "{case}: expected {fragment:?} in {err}"
        );
    }
    // Through the command line: exit status 2, nothing written.
    let out = s.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_drystone"))
        .args([
            std::ffi::OsStr::new("run"),
            study(&s, "mechanism_unknown_kind.csv").as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("column kind: unknown kind `overturning`"));
    assert!(!out.exists());
}
