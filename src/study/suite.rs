//! Suites: several studies run one after the other into one report (`studies/paper.toml`).
//!
//! ```toml
//! version = 1
//! name = "paper"
//! description = "..."
//!
//! [[studies]]
//! study = "joint_arrangement.toml"   # relative to this file
//! realizations = 10                  # the reduced default size; --full uses the study's own
//!
//! [[studies]]
//! study = "calibration.toml"
//! realizations = 1
//! calibrate = true                   # run its [[calibrate]] steps instead of the ensemble
//! ```
//!
//! `drystone run SUITE.toml [--full] [--out DIR]` writes each study's outputs into
//! `DIR/<study name>/` and one `DIR/report.md` that holds every study's report (headings one
//! level down, figure links into the study's directory) and the calibration.

use super::calibrate::{self, write_calibration, CalibrateError};
use super::shards::{check_writable, run_into, OutputError, RunMode};
use super::{Study, StudyError};
use crate::ensemble::Shard;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A suite file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuiteSpec {
    /// Must be 1.
    pub version: u32,
    /// Suite name (the default output directory `out/<name>`).
    pub name: String,
    /// Free text, first in the report.
    #[serde(default)]
    pub description: String,
    /// The studies, in the order they run.
    pub studies: Vec<SuiteEntry>,
}

/// One study of a suite.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuiteEntry {
    /// Study file, relative to the suite file.
    pub study: PathBuf,
    /// Realizations per group and point at the reduced (default) size; the study's own
    /// count with `--full`.
    #[serde(default)]
    pub realizations: Option<u64>,
    /// Run the study's `[[calibrate]]` steps instead of its ensemble.
    #[serde(default)]
    pub calibrate: bool,
}

/// True when a TOML file is a suite (it has a top-level `studies` array) rather than a
/// study.
pub fn is_suite(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .is_some_and(|t| t.get("studies").is_some_and(|v| v.is_array()))
}

/// A checked suite: its studies resolved.
#[derive(Debug, Clone)]
pub struct Suite {
    /// Name.
    pub name: String,
    /// Description.
    pub description: String,
    /// Studies with their entry.
    pub studies: Vec<(SuiteEntry, PathBuf, Study)>,
}

impl Suite {
    /// Reads a suite and resolves every study in it; `full` keeps each study's own
    /// realizations, otherwise the entry's reduced count applies.
    ///
    /// # Errors
    /// The first bad file, named.
    pub fn from_file(path: &Path, full: bool) -> Result<Suite, StudyError> {
        let text = std::fs::read_to_string(path).map_err(|source| StudyError::Io { path: path.to_owned(), source })?;
        let spec: SuiteSpec =
            toml::from_str(&text).map_err(|e| StudyError::Parse { path: path.to_owned(), message: e.to_string() })?;
        let invalid =
            |key: &str, reason: String| StudyError::Invalid { path: path.to_owned(), key: key.into(), reason };
        if spec.version != 1 {
            return Err(invalid("version", format!("this drystone reads suite version 1, got {}", spec.version)));
        }
        super::checks::check_name(&spec.name).map_err(|r| invalid("name", r.to_string()))?;
        if spec.studies.is_empty() {
            return Err(invalid("studies", "at least one study is needed".into()));
        }
        let dir = path.parent().unwrap_or(Path::new("."));
        let mut studies = Vec::new();
        let mut names = std::collections::BTreeSet::new();
        for (i, e) in spec.studies.iter().enumerate() {
            let p = dir.join(&e.study);
            let mut st = Study::from_file(&p)?;
            if !names.insert(st.name.clone()) {
                return Err(invalid(&format!("studies[{i}]"), format!("study name {:?} appears twice", st.name)));
            }
            if e.calibrate && st.calibrate.is_empty() {
                return Err(invalid(
                    &format!("studies[{i}].calibrate"),
                    format!("{} has no [[calibrate]] steps", p.display()),
                ));
            }
            if let Some(n) = e.realizations {
                if n == 0 {
                    return Err(invalid(&format!("studies[{i}].realizations"), "must be at least 1".into()));
                }
                if !full {
                    st.realizations = n;
                    st.check_items().map_err(|r| invalid(&format!("studies[{i}].realizations"), r.to_string()))?;
                }
            }
            studies.push((e.clone(), p, st));
        }
        Ok(Suite { name: spec.name, description: spec.description, studies })
    }
}

/// Errors of running a suite.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SuiteError {
    /// A study's outputs.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A calibration that could not run.
    #[error("{path}: {source}")]
    Calibrate {
        /// The study file.
        path: PathBuf,
        /// What went wrong.
        source: CalibrateError,
    },
    /// Writing a calibration's outputs.
    #[error(transparent)]
    Calibration(CalibrateError),
    /// A file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

/// What [`run_suite`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct SuiteOutcome {
    /// The combined report.
    pub report: PathBuf,
    /// Realizations run (or resumed) over the ensembles of the suite.
    pub realizations: usize,
    /// How many of them failed.
    pub failed: usize,
}

/// Runs every study of a suite on the current rayon pool and writes the outputs and the
/// combined report into `dir`; returns the report. `progress` is called with a line per
/// finished study. See [`run_suite_with`].
///
/// # Errors
/// [`SuiteError`] naming the study or file.
pub fn run_suite(suite: &Suite, dir: &Path, progress: impl FnMut(&str)) -> Result<PathBuf, SuiteError> {
    run_suite_with(suite, dir, RunMode::default(), progress).map(|o| o.report)
}

/// As [`run_suite`], each ensemble with its journal in `DIR/<study name>/` (continued or
/// replaced as `mode` says, see [`run_into`]); `DIR` is locked
/// (`DirLock`) and every output directory is checked writable
/// first.
///
/// # Errors
/// [`SuiteError`] naming the study or file.
pub fn run_suite_with(
    suite: &Suite,
    dir: &Path,
    mode: RunMode,
    mut progress: impl FnMut(&str),
) -> Result<SuiteOutcome, SuiteError> {
    let _lock = super::lock::DirLock::acquire(dir).map_err(OutputError::from)?;
    for (_, _, st) in &suite.studies {
        check_writable(&dir.join(&st.name))?;
    }
    let (mut realizations, mut failed) = (0, 0);
    let mut md = String::new();
    let _ = writeln!(md, "# Suite `{}`\n", suite.name);
    if !suite.description.is_empty() {
        let _ = writeln!(md, "{}\n", suite.description.trim());
    }
    let _ = writeln!(md, "| study | realizations per group and point | wall time [s] | outputs |");
    let _ = writeln!(md, "| --- | --- | --- | --- |");
    let mut body = String::new();
    for (entry, path, st) in &suite.studies {
        let sub = dir.join(&st.name);
        let t0 = std::time::Instant::now();
        let text = if entry.calibrate {
            let results = calibrate::calibrate(st, &st.calibrate)
                .map_err(|source| SuiteError::Calibrate { path: path.clone(), source })?;
            write_calibration(st, &results, &sub).map_err(SuiteError::Calibration)?
        } else {
            let run = run_into(st, path, Shard::ALL, &sub, mode)?;
            realizations += run.rows.len();
            failed += run.rows.iter().filter(|r| !r.status.is_ok()).count();
            let p = sub.join("report.md");
            std::fs::read_to_string(&p).map_err(|source| SuiteError::Io { path: p, source })?
        };
        let secs = t0.elapsed().as_secs_f64();
        let _ = writeln!(md, "| `{}` | {} | {:.1} | `{}/` |", st.name, st.realizations, secs, st.name);
        body.push_str(&demote(&text, &st.name));
        body.push('\n');
        progress(&format!("{}: {:.1} s -> {}", st.name, secs, sub.display()));
    }
    let _ = writeln!(md, "\nWall times are the only numbers here that change from run to run.\n");
    md.push_str(&body);
    let p = dir.join("report.md");
    crate::io::replace_file(&p, md.as_bytes()).map_err(|e| SuiteError::Io { path: e.path, source: e.source })?;
    Ok(SuiteOutcome { report: p, realizations, failed })
}

/// A study report inside the suite report: headings one level down, relative links to
/// SVG and CSV files prefixed with the study's directory.
fn demote(text: &str, sub: &str) -> String {
    text.lines()
        .map(|l| {
            let l = if l.starts_with('#') { format!("#{l}") } else { l.to_string() };
            l.replace("](", &format!("]({sub}/"))
                .replace(&format!("]({sub}/http"), "](http")
                .replace("Data: `", &format!("Data: `{sub}/"))
        })
        .collect::<Vec<_>>()
        .join("\n")
}
