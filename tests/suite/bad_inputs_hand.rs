//! Hostile inputs to the tilting table rolled by hand (`drystone tilt --by-hand`) and to
//! the discrepancy settings' `also_effects`: each case is refused with exit status 2 and a
//! message naming the flag or key at fault, never a panic and never a run that goes on
//! for hours. `CORPUS_CASES` counts them (docs/discrepancy.md, "The table rolled by hand").

use std::path::PathBuf;
use std::process::Command;

/// The number of cases of this corpus.
const CORPUS_CASES: usize = 22;

fn layout(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs").join(name).to_str().unwrap().to_string()
}

fn tilt(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_drystone")).arg("tilt").args(args).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn refused(case: &str, (code, _, err): (i32, String, String), fragments: &[&str], count: &mut usize) {
    assert_eq!(code, 2, "{case}: exit {code}, {err}");
    for f in fragments {
        assert!(err.contains(f), "{case}: {f:?} not in {err}");
    }
    assert!(!err.contains("panicked"), "{case}: {err}");
    *count += 1;
}

#[test]
fn hostile_inputs_to_the_table_rolled_by_hand_are_refused_by_name() {
    let stack = layout("stable_stack.json");
    let mut count = 0;
    let nscd = ["--solver", "nscd", "--by-hand"];
    let with = |extra: &[&str]| -> Vec<String> {
        let mut v = vec![stack.clone()];
        v.extend(nscd.iter().map(|s| s.to_string()));
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let run = |v: Vec<String>| tilt(&v.iter().map(String::as_str).collect::<Vec<_>>());
    // Without --solver the message does not say the user named the penalty DEM.
    let bare = tilt(&[&stack, "--by-hand"]);
    assert!(!bare.2.contains("solver penalty"), "--by-hand without --solver: {}", bare.2);
    refused("--by-hand with the penalty solver", bare, &["--by-hand", "--solver nscd"], &mut count);
    refused(
        "a hand option without --by-hand",
        tilt(&[&stack, "--solver", "nscd", "--hand-hold-s", "2"]),
        &["--by-hand"],
        &mut count,
    );
    for (flag, value, fragment) in [
        ("--hand-increment-deg", "0", "--hand-increment-deg"),
        ("--hand-increment-deg", "90", "--hand-increment-deg"),
        ("--hand-rate-deg-s", "-1", "--hand-rate-deg-s"),
        ("--hand-rate-deg-s", "NaN", "--hand-rate-deg-s"),
        ("--hand-ramp-s", "0", "--hand-ramp-s"),
        ("--hand-ramp-s", "5", "--hand-ramp-s"),
        ("--hand-hold-s", "-0.5", "--hand-hold-s"),
        ("--hand-hold-s", "inf", "--hand-hold-s"),
        ("--table-axis-depth-m", "-1", "--table-axis-depth-m"),
    ] {
        refused(&format!("{flag} {value}"), run(with(&[flag, value])), &[fragment], &mut count);
    }
    // A run of about 1e8 steps (increments of 0.5° rolled at 0.5°/s and held 600 s each) is
    // refused before it starts, with the bound; a stop of 2 ms at the 1 ms step is not
    // resolved.
    refused(
        "increments of 0.5° held 600 s",
        run(with(&["--hand-increment-deg", "0.5", "--hand-rate-deg-s", "0.5", "--hand-hold-s", "600"])),
        &["--hand-hold-s", "2e7"],
        &mut count,
    );
    refused(
        "a roll at 1e-6 °/s",
        run(with(&["--hand-rate-deg-s", "1e-6", "--hand-ramp-s", "0.1"])),
        &["--hand-rate-deg-s", "2e7"],
        &mut count,
    );
    refused(
        "a stop of two steps",
        run(with(&["--hand-ramp-s", "0.002"])),
        &["--hand-ramp-s", "5 time steps"],
        &mut count,
    );
    // A wall that does not stand is refused with the tilting table's message.
    refused(
        "the leaning block",
        tilt(&[&layout("leaning_block.json"), "--solver", "nscd", "--by-hand"]),
        &["does not stand as given", "block leaning moved"],
        &mut count,
    );
    // The options of a step of motion (the shaking table's) are refused by name by the
    // tilting table and the table rolled by hand, whose release trials do not read them.
    for (flag, value) in
        [("--nscd-step-solver", "nsgs"), ("--nscd-natural-tolerance", "1e-6"), ("--nscd-rest", "solve")]
    {
        refused(
            &format!("{flag} with --by-hand"),
            run(with(&[flag, value])),
            &[flag, "table rolled by hand", "drystone shake"],
            &mut count,
        );
        refused(
            &format!("{flag} with the tilt by nscd"),
            tilt(&[&stack, "--solver", "nscd", flag, value]),
            &[flag, "tilting table", "drystone shake"],
            &mut count,
        );
    }
    // A valid control runs.
    let (code, out, err) = run(with(&["--hand-increment-deg", "10", "--hand-hold-s", "0.1"]));
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("table rolled by hand"), "{out}");
    // An unknown name in `also_effects` is refused naming it.
    let dir = std::env::temp_dir().join(format!("drystone-bad-hand-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("study.toml");
    let mut text =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/tilting_table.toml")).unwrap();
    text = text.replace("also_effects = [\"table_kick\"]", "also_effects = [\"table_kik\"]");
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies");
    text = text.replace("\"walls/", &format!("\"{}/walls/", src.display()));
    text = text.replace("\"../data/", &format!("\"{}/../data/", src.display()));
    std::fs::write(&study, text).unwrap();
    let out =
        Command::new(env!("CARGO_BIN_EXE_drystone")).args(["discrepancy", study.to_str().unwrap()]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    refused(
        "also_effects naming no effect",
        (out.status.code().unwrap_or(-1), String::new(), err),
        &["table_kik"],
        &mut count,
    );
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(count, CORPUS_CASES);
}
