//! `drystone run`, `calibrate` and `merge`: studies, suites, calibrations and shards.

use super::{pool, thread_count};
use anyhow::{bail, Result};
use drystone::ensemble::Shard;
use drystone::study::calibrate::{calibrate_with, write_calibration, OUTPUT_SET as CALIBRATION_SET};
use drystone::study::write_vtk_realizations;
use drystone::study::HeldDir;
use drystone::study::Study;
use drystone::study::{check_writable, merge as merge_shards, run_into, RunMode};
use drystone::study::{human_bytes, machine_memory};
use drystone::study::{is_suite, run_suite_with, Suite};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Exit status of a run in which every realization failed (the outputs are written all
/// the same).
pub const ALL_FAILED: u8 = 3;

/// Options of `drystone run`.
#[derive(clap::Args)]
pub struct RunArgs {
    /// Study file (TOML).
    study: PathBuf,
    /// Output directory, checked writable before anything runs. Default: out/<study name>.
    #[arg(long)]
    out: Option<PathBuf>,
    #[command(flatten)]
    workers: super::Workers,
    /// Run only shard K of N (1-based, e.g. 3/8 for a job array); merge with `drystone merge`.
    #[arg(long)]
    shard: Option<String>,
    /// Realizations per group and sweep point, overriding the study file.
    #[arg(long)]
    realizations: Option<u64>,
    /// For a suite (e.g. studies/paper.toml): run every study at its own full size
    /// instead of the suite's reduced default.
    #[arg(long)]
    full: bool,
    /// Continue the run whose journal is in --out: skip the realizations it holds, run
    /// the rest. Refused if the journal is of another run (drystone build, seed, study,
    /// wall, distribution or measured files, realizations, shard) or has a damaged line;
    /// without a journal, starts afresh. Without --resume, a journal of an unfinished
    /// run in --out is refused.
    #[arg(long)]
    resume: bool,
    /// Replace a journal in --out that would be refused (another run's, a damaged one,
    /// or an unfinished one without --resume): its finished realizations are lost.
    #[arg(long)]
    force: bool,
    /// Also write the ParaView time series of these realizations (e.g. 0,3) of every
    /// group and sweep point into DIR/vtk/ (each is run again with the recording on;
    /// the rows do not change).
    #[arg(long, value_name = "I,J,...", value_delimiter = ',')]
    vtk_realizations: Vec<u64>,
}

/// Options of `drystone calibrate`.
#[derive(clap::Args)]
pub struct CalibrateArgs {
    /// Study file (TOML) with [[calibrate]] steps.
    study: PathBuf,
    /// Output directory. Default: out/<study name>.
    #[arg(long)]
    out: Option<PathBuf>,
    #[command(flatten)]
    workers: super::Workers,
    /// Realizations per evaluation, overriding the study file.
    #[arg(long)]
    realizations: Option<u64>,
}

/// Options of `drystone merge`.
#[derive(clap::Args)]
pub struct MergeArgs {
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
    /// Shard directories.
    #[arg(required = true)]
    shards: Vec<PathBuf>,
}

/// `run`: a suite, or one study (or one shard of it).
pub fn run(a: RunArgs) -> Result<ExitCode> {
    let study = a.study.as_path();
    if is_suite(study) {
        if a.shard.is_some() || a.realizations.is_some() {
            bail!("{}: --shard and --realizations apply to single studies; a suite takes --full", study.display());
        }
        if !a.vtk_realizations.is_empty() {
            bail!("{}: --vtk-realizations applies to single studies", study.display());
        }
        return suite(study, a.out, a.workers.threads, a.full, RunMode { resume: a.resume, force: a.force });
    }
    if a.full {
        bail!("{}: --full applies to suites only", study.display());
    }
    let st = load(study, a.realizations)?;
    let shard = a.shard.as_deref().map_or(Ok(Shard::ALL), Shard::parse)?;
    let dir = a.out.unwrap_or_else(|| PathBuf::from("out").join(&st.name));
    let threads = thread_count(a.workers.threads);
    check_memory(&st, threads)?;
    let pool = pool(Some(threads))?;
    for w in st.warnings() {
        eprintln!("warning: {w}");
    }
    let t0 = std::time::Instant::now();
    let run = pool.install(|| run_into(&st, study, shard, &dir, RunMode { resume: a.resume, force: a.force }))?;
    let elapsed = t0.elapsed().as_secs_f64();
    if !a.vtk_realizations.is_empty() {
        let files = pool.install(|| write_vtk_realizations(&st, shard, &dir, &a.vtk_realizations))?;
        out!(
            "ParaView series of realizations {:?}: {} written under {}",
            a.vtk_realizations,
            files.len(),
            dir.join("vtk").display()
        );
    }
    let failed = run.rows.iter().filter(|r| !r.status.is_ok()).count();
    let resumed = if run.resumed > 0 { format!(", {} from the journal", run.resumed) } else { String::new() };
    out!(
        "study {}: {} realizations ({} failed{}) on {} threads in {:.1} s -> {}",
        st.name,
        run.rows.len(),
        failed,
        resumed,
        pool.current_num_threads(),
        elapsed,
        dir.display()
    );
    if let Some(t) = run.text {
        out!("{t}");
        out!("report: {}", dir.join("report.md").display());
    } else {
        out!("shard written; join the shards with `drystone merge --out DIR SHARD_DIRS...`");
    }
    Ok(failures(run.rows.len(), failed))
}

/// The exit status for `failed` of `total` realizations: success, with a warning on
/// stderr when some failed; [`ALL_FAILED`] when all did.
fn failures(total: usize, failed: usize) -> ExitCode {
    if failed == 0 {
        ExitCode::SUCCESS
    } else if failed < total {
        eprintln!(
            "warning: {failed} of {total} realizations failed; their rows give the status and the error (realizations.csv), the statistics use the others"
        );
        ExitCode::SUCCESS
    } else {
        eprintln!("error: every realization ({total}) failed; see the status and error columns of realizations.csv");
        ExitCode::from(ALL_FAILED)
    }
}

/// Refuses a study whose memory estimate on `threads` threads exceeds this machine's
/// memory.
fn check_memory(st: &Study, threads: usize) -> Result<()> {
    let size = st.size();
    let need = size.memory_bytes(threads);
    if let Some(have) = machine_memory() {
        if need > have {
            bail!(
                "study {}: {} work items and layouts of up to about {:.0} blocks on {threads} thread(s) need about {} of memory; this machine has {} (fewer --threads or --realizations, or a smaller sweep)",
                st.name,
                size.items,
                size.largest_layout_blocks,
                human_bytes(need),
                human_bytes(have)
            );
        }
    }
    Ok(())
}

/// A study file with `--realizations` applied.
fn load(study: &Path, realizations: Option<u64>) -> Result<Study> {
    load_with(Study::from_file(study)?, realizations)
}

/// A study with `--realizations` applied, its size checked.
fn load_with(mut st: Study, realizations: Option<u64>) -> Result<Study> {
    if let Some(n) = realizations {
        if n == 0 {
            bail!("--realizations must be at least 1");
        }
        st.realizations = n;
        if let Err(reason) = st.check_items() {
            bail!("--realizations {n}: {}: {reason}", st.path.display());
        }
    }
    Ok(st)
}

fn suite(path: &Path, out: Option<PathBuf>, threads: Option<usize>, full: bool, mode: RunMode) -> Result<ExitCode> {
    let suite = Suite::from_file(path, full)?;
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&suite.name));
    let threads = thread_count(threads);
    for (_, _, st) in &suite.studies {
        check_memory(st, threads)?;
    }
    let pool = pool(Some(threads))?;
    let t0 = std::time::Instant::now();
    let done = pool.install(|| run_suite_with(&suite, &dir, mode, |line| out!("{line}")))?;
    out!(
        "suite {}: {} studies on {} threads in {:.1} s -> {}",
        suite.name,
        suite.studies.len(),
        pool.current_num_threads(),
        t0.elapsed().as_secs_f64(),
        done.report.display()
    );
    Ok(failures(done.realizations, done.failed))
}

/// `calibrate`: the study's `[[calibrate]]` steps.
pub fn calibrate(a: CalibrateArgs) -> Result<ExitCode> {
    let CalibrateArgs { study, out, workers, realizations } = a;
    let (study, threads) = (study.as_path(), workers.threads);
    let st = Study::from_file(study)?;
    if st.calibrate.is_empty() {
        bail!("{}: no [[calibrate]] steps", study.display());
    }
    let st = load_with(st, realizations)?;
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&st.name));
    // The directory is held from here to the end: a second command on it is refused.
    let held = HeldDir::acquire(&dir)?;
    check_writable(&dir)?;
    let progress = super::discrepancy::progress_lines("calibrate");
    let setup = drystone::study::discrepancy::setup_of(&st, 1);
    for i in drystone::discrepancy::inert_effects(&setup, &[]) {
        progress(&format!("warning: {i}"));
    }
    let pool = pool(threads)?;
    let t0 = std::time::Instant::now();
    let results = pool
        .install(|| calibrate_with(&st, &st.calibrate, &progress))
        .map_err(|m| anyhow::anyhow!("{}: {m}", study.display()))?;
    let md =
        held.write_set(CALIBRATION_SET, "calibrate", &st.name, |staging| write_calibration(&st, &results, staging))?;
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
pub fn merge(a: MergeArgs) -> Result<ExitCode> {
    let (out, shards) = (a.out.as_path(), a.shards.as_slice());
    let merged = merge_shards(shards, out)?;
    let failed = merged.rows.iter().filter(|r| !r.status.is_ok()).count();
    out!(
        "merged {} shards, {} realizations (seed {}) -> {}",
        shards.len(),
        merged.rows.len(),
        merged.study.seed,
        out.display()
    );
    if let Some(t) = merged.text {
        out!("{t}");
    }
    Ok(failures(merged.rows.len(), failed))
}
