//! Shared helpers of the integration tests.

use std::ffi::OsStr;
use std::ops::Deref;
use std::path::{Path, PathBuf};

/// A scratch directory under the system temporary directory, named after the test and the
/// process (`drystone-NAME-PID`), empty when made and removed with everything in it when
/// dropped, also when the test panics. The directory itself is not created: the commands
/// under test create their output directories.
pub struct Scratch(PathBuf);

impl Scratch {
    /// A fresh (absent) scratch path for `name`.
    pub fn new(name: &str) -> Scratch {
        let d = std::env::temp_dir().join(format!("drystone-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        Scratch(d)
    }

    /// As [`Scratch::new`], and the directory created.
    #[allow(dead_code)] // not every test file that includes this module makes one
    pub fn created(name: &str) -> Scratch {
        let s = Scratch::new(name);
        std::fs::create_dir_all(&s.0).unwrap_or_else(|e| panic!("{}: {e}", s.0.display()));
        s
    }
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<OsStr> for Scratch {
    fn as_ref(&self) -> &OsStr {
        self.0.as_os_str()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Asserts that two tilting-table runs of one layout reach the same result: collapse angles
/// within `bracket_deg` of each other, and the displacements of every stable increment up
/// to 80 % of the collapse angle (where the response is nearly linear; nearer collapse the
/// equilibrium itself is ill-conditioned) equal to within 2 % of the largest (both runs are
/// equilibria to the same unbalanced-force tolerance). Returns that tilt limit, degrees.
#[allow(dead_code)]
pub fn assert_same_tilt_result(
    a: &drystone::loading::tilt::TiltResult,
    b: &drystone::loading::tilt::TiltResult,
    bracket_deg: f64,
) -> f64 {
    assert!(
        (a.collapse_angle_deg() - b.collapse_angle_deg()).abs() <= bracket_deg + 1e-9,
        "collapse angles {} and {}",
        a.collapse_angle_deg(),
        b.collapse_angle_deg()
    );
    let limit = 0.8 * b.collapse_angle_deg();
    let stable = |r: &drystone::loading::tilt::TiltResult| {
        r.increments
            .iter()
            .filter(|i| i.stable && i.alpha_deg <= limit)
            .map(|i| (i.alpha_deg, i.displacement_m.clone()))
            .collect::<Vec<_>>()
    };
    let (da, db) = (stable(a), stable(b));
    assert_eq!(da.len(), db.len());
    let largest = db.iter().flat_map(|(_, d)| d.iter().map(|v| v.abs())).fold(0.0, f64::max);
    assert!(largest > 0.0);
    for ((alpha, xa), (beta, xb)) in da.iter().zip(&db) {
        assert_eq!(alpha, beta);
        for (x, y) in xa.iter().zip(xb) {
            assert!((x - y).abs() <= 0.02 * largest, "at {alpha}°: {x} vs {y} m (largest {largest} m)");
        }
    }
    limit
}

/// The property tests' random-number seed: fixed (20210917), so that a test run is the
/// same run on every machine and a failure reproduces; `DRYSTONE_PROPTEST_SEED=N` for
/// another fixed seed, `DRYSTONE_PROPTEST_SEED=random` for a fresh one per run (a soak,
/// with `DRYSTONE_PROPTEST_CASES`).
pub fn proptest_seed() -> proptest::test_runner::RngSeed {
    use proptest::test_runner::RngSeed;
    match std::env::var("DRYSTONE_PROPTEST_SEED").ok().as_deref() {
        Some("random") => RngSeed::Random,
        Some(s) => s.parse().map(RngSeed::Fixed).unwrap_or(RngSeed::Fixed(20210917)),
        None => RngSeed::Fixed(20210917),
    }
}

/// Runs the whole study of the file `path` into `out` by the study core, as `drystone run`
/// does (its journal, outputs and manifest); the error as text.
pub fn run_study_file(path: &Path, out: &Path) -> Result<drystone::study::StudyRun, String> {
    run_study_shard(path, out, drystone::ensemble::Shard::ALL, drystone::study::RunMode::default())
}

/// As [`run_study_file`], for shard `shard` of the study, its journal treated as `mode` says.
pub fn run_study_shard(
    path: &Path,
    out: &Path,
    shard: drystone::ensemble::Shard,
    mode: drystone::study::RunMode,
) -> Result<drystone::study::StudyRun, String> {
    let study = drystone::study::Study::from_file(path).map_err(|e| e.to_string())?;
    drystone::study::run_into(&study, path, shard, out, mode).map_err(|e| e.to_string())
}

/// The in-plane test's readings of a row of an in-plane study.
pub fn in_plane(r: &drystone::ensemble::row::RealizationRow) -> &drystone::ensemble::row::InPlaneColumns {
    r.in_plane.as_deref().expect("a row of an in-plane study holds the in-plane columns")
}
