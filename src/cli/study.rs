//! `drystone run`, `calibrate` and `merge`: studies, suites, calibrations and shards.

use super::pool;
use anyhow::{bail, Result};
use drystone::ensemble::Shard;
use drystone::study::calibrate::{calibrate as calibrate_steps, write_calibration};
use drystone::study::run::run_study;
use drystone::study::shards::{read_shards, write_outputs};
use drystone::study::suite::{is_suite, run_suite, Suite};
use drystone::study::Study;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `run`: a suite, or one study (or one shard of it).
pub fn run(
    study: &Path,
    out: Option<PathBuf>,
    threads: Option<usize>,
    shard: Option<&str>,
    realizations: Option<u64>,
    full: bool,
) -> Result<ExitCode> {
    if is_suite(study) {
        if shard.is_some() || realizations.is_some() {
            bail!("{}: --shard and --realizations apply to single studies; a suite takes --full", study.display());
        }
        return suite(study, out, threads, full);
    }
    if full {
        bail!("{}: --full applies to suites only", study.display());
    }
    let st = load(study, realizations)?;
    let shard = shard.map_or(Ok(Shard::ALL), Shard::parse)?;
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&st.name));
    let pool = pool(threads)?;
    let t0 = std::time::Instant::now();
    let rows = pool.install(|| run_study(&st, shard));
    let elapsed = t0.elapsed().as_secs_f64();
    let text = write_outputs(&st, study, shard, &rows, &dir)?;
    let failed = rows.iter().filter(|r| !r.status.is_ok()).count();
    out!(
        "study {}: {} realizations ({} failed) on {} threads in {:.1} s -> {}",
        st.name,
        rows.len(),
        failed,
        pool.current_num_threads(),
        elapsed,
        dir.display()
    );
    if let Some(t) = text {
        out!("{t}");
        out!("report: {}", dir.join("report.md").display());
    } else {
        out!("shard written; join the shards with `drystone merge --out DIR SHARD_DIRS...`");
    }
    Ok(ExitCode::SUCCESS)
}

/// A study file with `--realizations` applied.
fn load(study: &Path, realizations: Option<u64>) -> Result<Study> {
    load_with(Study::from_file(study)?, realizations)
}

/// A study with `--realizations` applied.
fn load_with(mut st: Study, realizations: Option<u64>) -> Result<Study> {
    if let Some(n) = realizations {
        if n == 0 {
            bail!("--realizations must be at least 1");
        }
        st.realizations = n;
    }
    Ok(st)
}

fn suite(path: &Path, out: Option<PathBuf>, threads: Option<usize>, full: bool) -> Result<ExitCode> {
    let suite = Suite::from_file(path, full)?;
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&suite.name));
    let pool = pool(threads)?;
    let t0 = std::time::Instant::now();
    let report = pool.install(|| run_suite(&suite, &dir, |line| out!("{line}")))?;
    out!(
        "suite {}: {} studies on {} threads in {:.1} s -> {}",
        suite.name,
        suite.studies.len(),
        pool.current_num_threads(),
        t0.elapsed().as_secs_f64(),
        report.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// `calibrate`: the study's `[[calibrate]]` steps.
pub fn calibrate(
    study: &Path,
    out: Option<PathBuf>,
    threads: Option<usize>,
    realizations: Option<u64>,
) -> Result<ExitCode> {
    let st = Study::from_file(study)?;
    if st.calibrate.is_empty() {
        bail!("{}: no [[calibrate]] steps", study.display());
    }
    let st = load_with(st, realizations)?;
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&st.name));
    let pool = pool(threads)?;
    let t0 = std::time::Instant::now();
    let results = pool
        .install(|| calibrate_steps(&st, &st.calibrate))
        .map_err(|m| anyhow::anyhow!("{}: {m}", study.display()))?;
    let md = write_calibration(&st, &results, &dir)?;
    out!("{md}");
    out!(
        "calibration {}: {} steps on {} threads in {:.1} s -> {}",
        st.name,
        results.len(),
        pool.current_num_threads(),
        t0.elapsed().as_secs_f64(),
        dir.join("calibration.md").display()
    );
    Ok(ExitCode::SUCCESS)
}

/// `merge`: shard directories into what an unsharded run writes.
pub fn merge(out: &Path, shards: &[PathBuf]) -> Result<ExitCode> {
    let (manifest, rows) = read_shards(shards)?;
    let mut st = Study::from_file(&manifest.study)?;
    st.realizations = manifest.realizations;
    let text = write_outputs(&st, &manifest.study, Shard::ALL, &rows, out)?;
    out!("merged {} shards, {} realizations -> {}", shards.len(), rows.len(), out.display());
    if let Some(t) = text {
        out!("{t}");
    }
    Ok(ExitCode::SUCCESS)
}
