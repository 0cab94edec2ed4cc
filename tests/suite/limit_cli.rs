//! Limit analysis's options on the command line (`--limit-*` on `tilt`, `lateral` and
//! `limit`): they reach the analysis (the associative answer only is marked so), out-of-range
//! values are refused naming the key, and they are refused with another solver, which would
//! ignore them.

use std::process::{Command, Output};

fn drystone(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_drystone"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .expect("runs drystone")
}

const WALL: &str = "data/layouts/rigid/running_bond_13.json";

fn governing(args: &[&str]) -> String {
    let out = drystone(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    v["governing"].as_str().expect("governing").to_string()
}

#[test]
fn limit_options_reach_the_analysis_from_every_command() {
    // The 13-box wall tips (t/H): its mechanism does not slide, so no correction runs and
    // both answers are associative; `--limit-max-iterations` within range is accepted.
    assert_eq!(governing(&["limit", WALL, "--json", "--limit-max-iterations", "5"]), "associative");
    assert_eq!(governing(&["tilt", WALL, "--solver", "limit", "--limit-associative", "--json"]), "associative");
    assert_eq!(
        governing(&["lateral", WALL, "--solver", "limit", "--limit-tolerance", "1e-6", "--json"]),
        "associative"
    );
}

#[test]
fn limit_options_out_of_range_or_without_the_solver_are_refused() {
    // Above 1, and so small that λ's change per iteration would meet the tolerance before
    // λ settles.
    for bad in ["1.5", "1e-12"] {
        let out = drystone(&["tilt", WALL, "--solver", "limit", "--limit-relaxation", bad]);
        assert!(!out.status.success(), "{bad}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("relaxation") && err.contains("[0.1, 1]"), "{bad}: {err}");
    }
    for cmd in ["tilt", "lateral"] {
        let out = drystone(&[cmd, WALL, "--limit-associative"]);
        assert!(!out.status.success(), "{cmd}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--solver limit"), "{cmd}: {err}");
    }
}
