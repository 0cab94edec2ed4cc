//! The corpus of bad layouts in `tests/bad_inputs/`, one per class of input that once ran
//! to a silently wrong answer, a crash or a blow-up: `drystone tilt` on each, with its exit
//! status and a fragment of its message. A valid but demanding input (a many-faceted block)
//! must run, and a static run without damping is refused up front instead of blowing up.

use std::path::PathBuf;
use std::process::Command;

fn corpus(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs").join(name)
}

/// Runs `drystone tilt FILE ARGS...` (coarse steps: only the verdict matters); returns the
/// exit code and the standard error.
fn tilt(name: &str, args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_drystone"))
        .arg("tilt")
        .arg(corpus(name))
        .args(["--step-deg", "2", "--resolution-deg", "1"])
        .args(args)
        .output()
        .unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn every_bad_layout_is_refused_with_its_reason() {
    let cases = [
        ("non_convex_block.json", "block ell is not convex"),
        ("monitor_in_millimetres.json", "monitors[tip].point"),
        ("density_1e-300.json", "materials[m].density_kg_per_m3 = 1e-300"),
        ("joints_too_soft.json", "materials[m].kn_pa_per_m"),
        ("overhanging_top_block.json", "does not stand as given: block top moved"),
        ("floating_block.json", "block floater touches nothing"),
        ("unknown_key.json", "unknown field `colour`"),
        ("infinite_stiffness.json", "number out of range"),
        ("all_blocks_fixed.json", "blocks = 2 blocks, every one fixed: no free block"),
    ];
    for (file, fragment) in cases {
        let (code, err) = tilt(file, &[]);
        assert_eq!(code, 2, "{file}: exit {code}, {err}");
        assert!(err.contains(fragment), "{file}: expected {fragment:?} in {err:?}");
        assert!(err.contains(file), "{file}: the message does not name the file: {err:?}");
        assert!(!err.contains("panicked"), "{file}: {err}");
    }
}

#[test]
fn demanding_valid_inputs_run_or_say_why() {
    // A near-sphere of 219 vertices on the table.
    let (code, err) = tilt("near_sphere.json", &[]);
    assert_eq!(code, 0, "{err}");
    // Without damping dynamic relaxation cannot settle (and the undamped explicit scheme
    // with contacts opening and closing can blow up): refused up front, naming the key.
    for file in ["stable_stack.json", "../../data/layouts/single_block.json"] {
        let (code, err) = tilt(file, &["--damping", "0"]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("damping = 0 is out of range"), "{err}");
        assert!(!err.contains("non-finite"), "{err}");
    }
    let (code, err) = tilt("stable_stack.json", &[]);
    assert_eq!(code, 0, "{err}");
}

/// A tolerance below what rounding lets relaxation reach is named as such: the layout
/// stands, and the message says so with the tolerance it can reach; a layout that does not
/// stand keeps its own message.
#[test]
fn an_unreachable_tolerance_is_named_not_blamed_on_the_layout() {
    let (code, err) = tilt("stable_stack.json", &["--tolerance", "1e-15", "--max-steps", "20000"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("the layout stands, but the tolerance 1e-15 is below"), "{err}");
    assert!(err.contains("give a tolerance of at least"), "{err}");
    assert!(!err.contains("does not stand"), "{err}");
    let (code, err) = tilt("overhanging_top_block.json", &["--tolerance", "1e-15", "--max-steps", "20000"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("does not stand"), "{err}");
}
