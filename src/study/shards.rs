//! The run directory: the realization tables and a manifest, and for a complete run the
//! summary, report and plots. A study may run in shards (`--shard K/N`, e.g. on a job
//! array), each writing its own directory; [`read_shards`] joins them back into the rows of
//! the unsharded run.

use super::report::{write_report, ReportError};
use super::Study;
use crate::ensemble::row::RealizationRow;
use crate::ensemble::Shard;
use crate::io::table;
use std::path::{Path, PathBuf};

/// What a run directory holds besides its tables: enough to merge shards.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    /// The study file as given on the command line.
    pub study: PathBuf,
    /// Realizations per group and point actually run.
    pub realizations: u64,
    /// This shard, 1-based `K/N` (`1/1` for a whole run).
    pub shard: String,
    /// Items of the whole study.
    pub total_items: usize,
    /// Items in this directory.
    pub items: usize,
}

/// Errors of writing a run's outputs or merging shards.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// A table.
    #[error(transparent)]
    Table(#[from] table::TableError),
    /// The report.
    #[error(transparent)]
    Report(#[from] ReportError),
    /// A file.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Shards that do not fit together.
    #[error("merge: {0}")]
    Merge(String),
}

fn write_manifest(dir: &Path, m: &Manifest) -> Result<(), OutputError> {
    let path = dir.join("manifest.json");
    let text = serde_json::to_string_pretty(m)
        .map_err(|e| OutputError::File { path: path.clone(), message: e.to_string() })?;
    std::fs::write(&path, text).map_err(|e| OutputError::File { path, message: e.to_string() })
}

/// Writes a run's outputs into `dir` (created if needed): the tables and the manifest, and,
/// for a complete run, `summary.csv`, `report.md` and the plots. Returns the comparison
/// text for a complete run.
///
/// # Errors
/// [`OutputError`] naming the file.
pub fn write_outputs(
    study: &Study,
    study_arg: &Path,
    shard: Shard,
    rows: &[RealizationRow],
    dir: &Path,
) -> Result<Option<String>, OutputError> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::File { path: dir.to_owned(), message: e.to_string() })?;
    table::write_realizations(rows, dir)?;
    write_manifest(
        dir,
        &Manifest {
            study: study_arg.to_owned(),
            realizations: study.realizations,
            shard: format!("{}/{}", shard.k + 1, shard.n),
            total_items: study.items().len(),
            items: rows.len(),
        },
    )?;
    if shard.n == 1 {
        Ok(Some(write_report(study, rows, dir)?))
    } else {
        Ok(None)
    }
}

/// Reads shard directories, checks that they are the shards of one run and cover every
/// item exactly once, and returns the manifest of the first and the rows in item order.
///
/// # Errors
/// [`OutputError::Merge`] naming what does not fit.
pub fn read_shards(dirs: &[PathBuf]) -> Result<(Manifest, Vec<RealizationRow>), OutputError> {
    let mut first: Option<Manifest> = None;
    let mut rows = Vec::new();
    for d in dirs {
        let mpath = d.join("manifest.json");
        let text = std::fs::read_to_string(&mpath)
            .map_err(|e| OutputError::File { path: mpath.clone(), message: e.to_string() })?;
        let m: Manifest = serde_json::from_str(&text)
            .map_err(|e| OutputError::File { path: mpath.clone(), message: e.to_string() })?;
        if let Some(f) = &first {
            if f.study != m.study || f.realizations != m.realizations || f.total_items != m.total_items {
                return Err(OutputError::Merge(format!(
                    "{} is from another run than {}",
                    d.display(),
                    dirs[0].display()
                )));
            }
        } else {
            first = Some(m.clone());
        }
        let part = table::read_realizations(&d.join("realizations.parquet"))?;
        if part.len() != m.items {
            return Err(OutputError::Merge(format!(
                "{}: manifest says {} items, table has {}",
                d.display(),
                m.items,
                part.len()
            )));
        }
        rows.extend(part);
    }
    let first = first.ok_or_else(|| OutputError::Merge("no shard directories given".into()))?;
    rows.sort_by_key(|r| r.index);
    for (i, r) in rows.iter().enumerate() {
        if r.index as usize != i {
            return Err(OutputError::Merge(format!(
                "item {} is {} (the shards must cover items 0..{} exactly once)",
                i,
                if (r.index as usize) < i { "duplicated" } else { "missing" },
                first.total_items
            )));
        }
    }
    if rows.len() != first.total_items {
        return Err(OutputError::Merge(format!("{} of {} items present", rows.len(), first.total_items)));
    }
    Ok((first, rows))
}
