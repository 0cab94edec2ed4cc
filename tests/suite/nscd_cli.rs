//! The non-smooth solver's options on the command line (`--nscd-*` on `tilt` and `shake`):
//! they reach the solver (the 13-box wall's bracket of its exact rigid limit t/H under the
//! velocity norm set by hand), out-of-range values are refused naming the key, and they
//! are refused without `--solver nscd`.

use std::path::Path;
use std::process::{Command, Output};

fn drystone(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_drystone"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .expect("runs drystone")
}

const WALL: &str = "data/layouts/rigid/running_bond_13.json";

#[test]
fn nscd_options_reach_the_solver_and_the_bracket_holds_t_over_h() {
    assert!(Path::new(env!("CARGO_MANIFEST_DIR")).join(WALL).exists());
    let out = drystone(&[
        "tilt",
        WALL,
        "--solver",
        "nscd",
        "--resolution-deg",
        "0.05",
        "--nscd-norm",
        "velocity",
        "--nscd-tolerance",
        "1e-7",
        "--nscd-max-iterations",
        "3000",
        "--json",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let (lo, up) = (v["last_stable_deg"].as_f64().unwrap(), v["first_unstable_deg"].as_f64().unwrap());
    let exact = (1.0f64 / 3.0).atan().to_degrees();
    assert!(lo <= exact && exact <= up && up - lo <= 0.05 + 1e-9, "[{lo}, {up}] against {exact}");
}

#[test]
fn nscd_options_out_of_range_or_without_the_solver_are_refused() {
    let out = drystone(&["tilt", WALL, "--solver", "nscd", "--nscd-quad-tolerance", "2"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("quad_tolerance"), "{err}");
    let out = drystone(&["tilt", WALL, "--nscd-norm", "quad"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("--solver nscd"), "{err}");
    let out = drystone(&["tilt", WALL, "--solver", "nscd", "--nscd-norm", "l2"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("adaptive, velocity or quad"), "{err}");
    let out = drystone(&[
        "shake",
        WALL,
        "--pulse",
        "one-sine",
        "--amplitude-g",
        "0.1",
        "--period-s",
        "0.5",
        "--nscd-max-iterations",
        "0",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("max_iterations"), "{err}");
}

/// `drystone tilt --solver nscd` (and `--by-hand`) says its work in nscd's words: time
/// steps of non-smooth contact dynamics and NSGS sweeps, not the penalty DEM's implicit
/// iterations and steps of dynamic relaxation.
#[test]
fn the_tilt_by_nscd_describes_its_work_in_its_own_words() {
    let stack = "tests/bad_inputs/stable_stack.json";
    for extra in [&[][..], &["--by-hand", "--hand-increment-deg", "10", "--hand-hold-s", "0.1"][..]] {
        let out = drystone(&[&["tilt", stack, "--solver", "nscd"][..], extra].concat());
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{extra:?}: {}", String::from_utf8_lossy(&out.stderr));
        let work = text.lines().find(|l| l.starts_with("work")).unwrap_or_else(|| panic!("no work line: {text}"));
        assert!(work.contains("time steps of non-smooth contact dynamics") && work.contains("NSGS sweeps"), "{work}");
        assert!(!work.contains("dynamic relaxation") && !work.contains("implicit"), "{extra:?}: {work}");
    }
    // The penalty DEM keeps its own.
    let out = drystone(&["tilt", stack, "--step-deg", "5", "--resolution-deg", "1"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("steps of dynamic relaxation"), "{text}");
}
