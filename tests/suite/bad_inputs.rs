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

/// `drystone in-plane --quarter-increments 1000000` (a million static solves a quarter
/// cycle) is refused at once, naming the flag and its limit, instead of running on with its
/// history's memory growing. The child is killed after 60 s: a run that does not stop is a
/// failure, not a hang of the suite.
#[test]
fn in_plane_quarter_increments_past_the_limit_are_refused_naming_the_flag() {
    let dir = std::env::temp_dir().join(format!("drystone-quarter-increments-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let layout = dir.join("block.json");
    let v = |x: f64, y: f64, z: f64| format!("[{x},{y},{z}]");
    let vertices: Vec<String> = [0.0, 1.2]
        .iter()
        .flat_map(|&z| [(0.0, -0.1), (1.0, -0.1), (1.0, 0.1), (0.0, 0.1)].map(|(x, y)| v(x, y, z)))
        .collect();
    std::fs::write(
        &layout,
        format!(
            r#"{{"version": 1, "name": "one block", "materials": [{{"name": "m", "density_kg_per_m3": 2200,
            "kn_pa_per_m": 1e10, "ks_pa_per_m": 4e9, "friction_deg": 45}}], "table": {{"material": "m"}},
            "blocks": [{{"id": "wall", "material": "m", "vertices": [{}]}}]}}"#,
            vertices.join(",")
        ),
    )
    .unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_drystone"))
        .args(["in-plane", layout.to_str().unwrap(), "--sigma0-mpa", "0.5", "--shear-span-m", "1.325"])
        .args(["--cyclic", "--quarter-increments", "1000000"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if t0.elapsed().as_secs() > 60 {
            let _ = child.kill();
            let _ = child.wait();
            panic!("--quarter-increments 1000000 still running after 60 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(2), "{err}");
    assert!(err.contains("--quarter-increments = 1000000 must be at most 1000"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
