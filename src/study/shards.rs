//! The run directory: the journal of finished items, the realization tables and a
//! manifest, and for a complete run the summary, report and plots. A study may run in
//! shards (`--shard K/N`, e.g. on a job array), each writing its own directory;
//! [`read_shards`] joins them back into the rows of the unsharded run and [`merge`] writes
//! what the unsharded run writes.
//!
//! # What a run directory guarantees
//!
//! - One writer: every command that writes the directory holds its lock
//!   ([`lock`](super::lock)) from before its first write to its end.
//! - `journal.jsonl` ([`crate::ensemble::journal`]) gets every finished item at
//!   once, synced, each line with the run's identity ([`Manifest::identity`]) and its own
//!   checksum: a crash loses no finished item. [`run_into`] with `resume` checks every line
//!   and row before running anything, runs only the items the journal lacks, and the
//!   outputs are byte for byte those of a run that was never interrupted, except the
//!   `wall_time_s` column.
//! - The tables, the summary, the report and the plots are one set
//!   ([`super::outputs`]): staged, moved in, and completed by `manifest.json`,
//!   written last with the SHA-256 of every output.
//! - The manifest records the drystone version and build, the master seed, the
//!   realizations, the shard, and every input file (study, walls, distributions, measured
//!   data) with its SHA-256 and its text ([`super::provenance`]). A resume and
//!   a merge refuse what disagrees on any of them, naming the field and both values; merge
//!   rebuilds the study from the stored texts, not from the study file, and checks every
//!   row against its items.

use super::lock::{DirLock, LockError};
use super::outputs::{self, OutputFile};
use super::provenance::{self, InputFile, InputRole};
use super::report::{write_report, ReportError};
use super::run::run_study_with;
use super::Study;
use crate::ensemble::journal::{self, Journal, JournalError, JournalRow};
use crate::ensemble::row::RealizationRow;
use crate::ensemble::Shard;
use crate::io::{table, FileError};
use std::path::{Path, PathBuf};

/// What a run directory holds besides its tables: its provenance, and enough to merge
/// shards.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    /// The drystone version that wrote its rows (`CARGO_PKG_VERSION`).
    #[serde(default)]
    pub drystone_version: String,
    /// The exact build that wrote its rows ([`provenance::BUILD`]: version and source
    /// digest).
    #[serde(default)]
    pub build: String,
    /// The study file as given on the command line.
    pub study: PathBuf,
    /// The master seed of the rows.
    #[serde(default)]
    pub seed: u64,
    /// Realizations per group and point actually run.
    pub realizations: u64,
    /// This shard, 1-based `K/N` (`1/1` for a whole run).
    pub shard: String,
    /// Items of the whole study.
    pub total_items: usize,
    /// Items in this directory.
    pub items: usize,
    /// The input files of the study with their SHA-256 and text.
    #[serde(default)]
    pub inputs: Vec<InputFile>,
    /// The outputs of the set this manifest completes, with their SHA-256
    /// (`super::outputs`); empty in a journal header.
    #[serde(default)]
    pub outputs: Vec<OutputFile>,
}

impl Manifest {
    /// The manifest of `items` rows of a shard of a study.
    pub fn new(study: &Study, study_arg: &Path, shard: Shard, items: usize) -> Manifest {
        Manifest {
            drystone_version: provenance::VERSION.to_string(),
            build: provenance::BUILD.to_string(),
            study: study_arg.to_owned(),
            seed: study.seed,
            realizations: study.realizations,
            shard: format!("{}/{}", shard.k + 1, shard.n),
            total_items: study.items().len(),
            items,
            inputs: study.inputs.clone(),
            outputs: Vec::new(),
        }
    }

    /// The number of shards `N` of `K/N`.
    fn shard_count(&self) -> &str {
        self.shard.split_once('/').map_or("", |(_, n)| n)
    }

    /// The identity of the run: the SHA-256 (hex) of what makes its rows (the drystone
    /// version and build, the seed, the realizations, the shard `K/N`, the item count and
    /// every input file by role, path and hash); the study path as typed and the item
    /// count of this directory are not part of it. Every line of the run's journal carries
    /// it.
    pub fn identity(&self) -> String {
        let inputs: Vec<(InputRole, &str, &str)> =
            self.inputs.iter().map(|f| (f.role, f.path.as_str(), f.sha256.as_str())).collect();
        let id = serde_json::json!({
            "drystone_version": self.drystone_version,
            "build": self.build,
            "seed": self.seed,
            "realizations": self.realizations,
            "shard": self.shard,
            "total_items": self.total_items,
            "inputs": inputs,
        });
        provenance::sha256_hex(id.to_string().as_bytes())
    }

    /// The first field on which two runs disagree (everything but the study path, the
    /// shard index and the item count), as `field: VALUE in a, VALUE in b`.
    pub fn difference(&self, other: &Manifest, a: &str, b: &str) -> Option<String> {
        let fields = [
            ("drystone version", self.drystone_version.clone(), other.drystone_version.clone()),
            ("drystone build", self.build.clone(), other.build.clone()),
            ("seed", self.seed.to_string(), other.seed.to_string()),
            ("realizations", self.realizations.to_string(), other.realizations.to_string()),
            ("total items", self.total_items.to_string(), other.total_items.to_string()),
            ("number of shards", self.shard_count().to_string(), other.shard_count().to_string()),
        ];
        for (name, x, y) in fields {
            if x != y {
                return Some(format!("{name}: {x} in {a}, {y} in {b}"));
            }
        }
        provenance::first_difference(&self.inputs, &other.inputs, a, b)
    }
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
    /// The journal.
    #[error(transparent)]
    Journal(#[from] JournalError),
    /// A file.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Another process writes the directory.
    #[error(transparent)]
    Lock(#[from] LockError),
    /// Shards that do not fit together.
    #[error("merge: {0}")]
    Merge(String),
    /// The caller stopped the run ([`run_into_observed`]); the journal keeps every
    /// finished item.
    #[error("interrupted: the finished realizations are kept in {journal} (resume to continue)")]
    Interrupted {
        /// The run's journal.
        journal: PathBuf,
    },
}

impl From<FileError> for OutputError {
    fn from(e: FileError) -> Self {
        OutputError::File { path: e.path, message: e.source.to_string() }
    }
}

/// Creates `dir` if needed and checks that a file can be written in it (before anything is
/// computed).
///
/// # Errors
/// [`OutputError::File`] naming the directory or the file.
pub fn check_writable(dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(FileError::at(dir))?;
    let probe = dir.join(".drystone-write-test");
    std::fs::write(&probe, b"").map_err(FileError::at(&probe))?;
    std::fs::remove_file(&probe).map_err(FileError::at(&probe))?;
    Ok(())
}

/// Writes a run's outputs into `dir` (created if needed): the tables and the manifest, and,
/// for a complete run, `summary.csv`, `report.md` and the plots, as one set
/// (`outputs::write_set`: staged, then committed with `manifest.json`, which records the
/// digest of every output, written last). Returns the comparison text for a complete run.
///
/// # Errors
/// [`OutputError`] naming the file; [`OutputError::Merge`] if a row was made with another
/// seed than the study's (the report prints the study's seed as the seed of its rows).
pub fn write_outputs(
    study: &Study,
    study_arg: &Path,
    shard: Shard,
    rows: &[RealizationRow],
    dir: &Path,
) -> Result<Option<String>, OutputError> {
    write_outputs_by(study, study_arg, shard, rows, dir, None)
}

/// As [`write_outputs`], with the drystone version, build and inputs of the manifest
/// `made_by` (the shards' run, for a merge) instead of this build's and the study's.
fn write_outputs_by(
    study: &Study,
    study_arg: &Path,
    shard: Shard,
    rows: &[RealizationRow],
    dir: &Path,
    made_by: Option<&Manifest>,
) -> Result<Option<String>, OutputError> {
    if let Some(r) = rows.iter().find(|r| r.seed != study.seed) {
        return Err(OutputError::Merge(format!(
            "item {} was run with seed {}, the study has seed {}",
            r.index, r.seed, study.seed
        )));
    }
    std::fs::create_dir_all(dir).map_err(FileError::at(dir))?;
    let previous = read_manifest(dir).map(|m| m.outputs).unwrap_or_default();
    let mut manifest = Manifest::new(study, study_arg, shard, rows.len());
    if let Some(m) = made_by {
        manifest.drystone_version = m.drystone_version.clone();
        manifest.build = m.build.clone();
        manifest.inputs = m.inputs.clone();
    }
    let path = dir.join(outputs::MANIFEST);
    outputs::write_set(
        dir,
        &previous,
        |staging| -> Result<Option<String>, OutputError> {
            study.protocol.write_rows(study, rows, staging)?;
            Ok(if shard.n == 1 { Some(write_report(study, rows, staging)?) } else { None })
        },
        |outputs| {
            manifest.outputs = outputs;
            serde_json::to_string_pretty(&manifest).map_err(|e| OutputError::File { path, message: e.to_string() })
        },
    )
}

/// How [`run_into`] treats a journal already in the directory.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RunMode {
    /// Continue the journal of this run: keep its rows, run the missing items
    /// (`--resume`).
    pub resume: bool,
    /// Replace a journal that cannot be continued (another run's, a damaged one, or an
    /// unfinished one without `resume`) instead of refusing it (`--force`): its rows are
    /// lost.
    pub force: bool,
}

/// What [`run_into`] did.
#[derive(Debug, Clone)]
pub struct StudyRun {
    /// Every row of the shard, in item order.
    pub rows: Vec<RealizationRow>,
    /// How many of them came from the journal of an earlier run.
    pub resumed: usize,
    /// The comparison text of a complete run (see [`write_outputs`]).
    pub text: Option<String>,
}

/// Runs a shard of a study into `dir` with its journal: checks that `dir` is writable,
/// takes the directory's lock (`DirLock`: one writer per directory), opens the journal
/// (continuing it with `resume`), runs the items not yet finished on the
/// current rayon pool, each row journaled as soon as it is computed, and writes the
/// outputs.
///
/// The journal is read and checked whole before anything is computed: every line must
/// carry its checksum and the identity of this run ([`Manifest::identity`]), and every row
/// must be an item of this shard with this study's name, seed, group, sweep point and
/// realization. With `resume`, its rows are kept and only the missing items run. Without
/// `resume`, a journal of this run with every item finished (or none) is started again; an
/// unfinished one is refused (its finished items would be lost). A journal of another run
/// or a damaged one is refused in both cases, naming the journal, the line and the field.
/// With `force`, a journal that would be refused is replaced instead. A journal is never
/// replaced or cut by another command while this one runs: the lock refuses it.
///
/// # Errors
/// [`OutputError`] naming the file, or the difference with the journal.
pub fn run_into(
    study: &Study,
    study_arg: &Path,
    shard: Shard,
    dir: &Path,
    mode: RunMode,
) -> Result<StudyRun, OutputError> {
    run_into_observed(study, study_arg, shard, dir, mode, &|_| true)
}

/// As [`run_into`], handing every new row to `observe` (from the worker thread that
/// computed it) as soon as it is journaled: a progress report, and a way to stop. When
/// `observe` returns false, no further item starts, the items already running finish and
/// are journaled, and the run ends with [`OutputError::Interrupted`] without writing the
/// tables: the journal keeps every finished item, and `resume` continues it. An `observe`
/// that always returns true makes this [`run_into`], row for row.
///
/// # Errors
/// As [`run_into`]; [`OutputError::Interrupted`] when `observe` stopped the run.
pub fn run_into_observed(
    study: &Study,
    study_arg: &Path,
    shard: Shard,
    dir: &Path,
    mode: RunMode,
    observe: &(dyn Fn(&RealizationRow) -> bool + Sync),
) -> Result<StudyRun, OutputError> {
    let _lock = DirLock::acquire(dir)?;
    check_writable(dir)?;
    let path = dir.join(journal::FILE_NAME);
    let header = Manifest::new(study, study_arg, shard, 0);
    let wanted = shard.select(&study.items()).len();
    let check = |rows: &[RealizationRow], lines: &[usize]| {
        check_rows(study, shard, rows, |i| (path.clone(), format!("line {}", lines[i])), "journal")
    };
    let (journal, done) = open_journal(&path, &header, wanted, mode, check)?;
    let resumed = done.len();
    let rows = run_study_with(study, shard, done, |row| {
        journal.append(row)?;
        if observe(row) {
            Ok(())
        } else {
            Err(OutputError::Interrupted { journal: path.clone() })
        }
    })?;
    let text = write_outputs(study, study_arg, shard, &rows, dir)?;
    Ok(StudyRun { rows, resumed, text })
}

/// The journal `path` of a run whose manifest is `header` and which has `wanted` items,
/// opened as `mode` says, with the rows it keeps: the journal read and checked whole (its
/// rows by `check`, given each row's line) before anything runs; with `mode.resume` its
/// rows kept; without, an unfinished journal of this run refused, a finished one (or an
/// empty one) started again; a journal of another run or a damaged one refused, or replaced
/// with `mode.force`. Every study's run opens its journal here, whatever its rows.
///
/// # Errors
/// [`OutputError::File`] naming the journal and, for a damaged line, the line and field;
/// for a journal of another run, the difference of the runs.
pub(super) fn open_journal<R: JournalRow>(
    path: &Path,
    header: &Manifest,
    wanted: usize,
    mode: RunMode,
    check: impl Fn(&[R], &[usize]) -> Result<(), OutputError>,
) -> Result<(Journal, Vec<R>), OutputError> {
    let run = header.identity();
    let refuse = |message: String| OutputError::File { path: path.to_owned(), message };
    let fresh = || Ok::<_, OutputError>((Journal::create(path, &run, header)?, Vec::new()));
    let contents = match Journal::read_rows::<Manifest, R>(path) {
        Err(JournalError::Corrupt { .. }) if mode.force => None,
        Err(JournalError::Corrupt { line, field, message, .. }) => {
            return Err(refuse(format!(
                "line {line}: {field}: {message}; delete the journal or give --force to start again"
            )))
        }
        other => other?,
    };
    match contents {
        None => fresh(),
        Some(c) if c.run != run => {
            if mode.force {
                fresh()
            } else {
                let d = c.header.difference(header, "the journal", "this run").unwrap_or_else(|| {
                    format!("run identity {} in the journal, {run} in this run (shard {})", c.run, header.shard)
                });
                Err(refuse(format!("was written by another run ({d}); give another --out, or --force to replace it")))
            }
        }
        Some(c) => match check(&c.rows, &c.lines).map(|()| c.rows) {
            Err(_) if mode.force => fresh(),
            Err(e) => Err(e),
            Ok(done) if mode.resume => Ok((Journal::resume(path, &run, c.complete_len)?, done)),
            Ok(done) if done.is_empty() || done.len() == wanted || mode.force => fresh(),
            Ok(done) => Err(refuse(format!(
                "holds {} of {wanted} finished realization(s) of this run; continue it with --resume, or give \
                 --force to start again",
                done.len()
            ))),
        },
    }
}

/// Rows checked against the items of a shard of the study: each one an item of the shard
/// with the study's name and seed and the item's group, sweep point and realization. `at`
/// places row `i` (the file and, e.g., `line 4`) and `source` names where the rows come
/// from in the message (`journal`, `shard`).
///
/// # Errors
/// [`OutputError::File`] naming the file, the place and the field with both values.
fn check_rows(
    study: &Study,
    shard: Shard,
    rows: &[RealizationRow],
    at: impl Fn(usize) -> (PathBuf, String),
    source: &str,
) -> Result<(), OutputError> {
    let items = study.items();
    for (i, r) in rows.iter().enumerate() {
        let refuse = |field: &str, theirs: String, ours: String| {
            let (path, place) = at(i);
            OutputError::File {
                path,
                message: format!("{place}: {field}: {theirs} in the {source}, {ours} in this run (item {})", r.index),
            }
        };
        let it = match items.get(r.index as usize) {
            Some(it) if shard.select(std::slice::from_ref(it)).len() == 1 => it,
            _ => {
                let n = format!("shard {}/{} of {} items", shard.k + 1, shard.n, items.len());
                return Err(refuse("index", format!("item {}", r.index), format!("no such item in {n}")));
            }
        };
        let group = &study.groups[it.group].name;
        let sweep = super::point_label(&study.points[it.point]);
        let fields = [
            ("study", r.study.clone(), study.name.clone()),
            ("seed", r.seed.to_string(), study.seed.to_string()),
            ("group", r.group.clone(), group.clone()),
            ("point", r.point.to_string(), it.point.to_string()),
            ("realization", r.realization.to_string(), it.realization.to_string()),
            ("sweep", format!("{:?}", r.sweep), format!("{sweep:?}")),
        ];
        if let Some((field, theirs, ours)) = fields.into_iter().find(|(_, a, b)| a != b) {
            return Err(refuse(field, theirs, ours));
        }
    }
    Ok(())
}

fn read_manifest(dir: &Path) -> Result<Manifest, OutputError> {
    let path = dir.join("manifest.json");
    let text = std::fs::read_to_string(&path).map_err(FileError::at(&path))?;
    serde_json::from_str(&text).map_err(|e| OutputError::File { path, message: e.to_string() })
}

/// Reads shard directories, checks that they are the shards of one run (the same drystone
/// version and build, seed, realizations, number of shards and input files, by hash), that
/// each one's outputs have the digests its manifest records (a table swapped in from
/// another run is refused) and that they cover every item exactly once, and returns the
/// manifest of the first and the rows in item order.
///
/// # Errors
/// [`OutputError::Merge`] naming what does not fit: the field and both values.
pub fn read_shards(dirs: &[PathBuf]) -> Result<(Manifest, Vec<RealizationRow>), OutputError> {
    read_shards_with_origin(dirs).map(|(m, rows, _)| (m, rows))
}

/// As [`read_shards`], with the shard directory of each row. Each shard's outputs must
/// have the digests its manifest records.
#[allow(clippy::type_complexity)]
fn read_shards_with_origin(dirs: &[PathBuf]) -> Result<(Manifest, Vec<RealizationRow>, Vec<PathBuf>), OutputError> {
    let mut first: Option<Manifest> = None;
    let mut rows = Vec::new();
    for d in dirs {
        let m = read_manifest(d)?;
        outputs::verify(d, &m.outputs).map_err(|e| OutputError::Merge(format!("{}: {e}", d.display())))?;
        if let Some(f) = &first {
            if let Some(diff) = f.difference(&m, &dirs[0].display().to_string(), &d.display().to_string()) {
                return Err(OutputError::Merge(format!("the shards are not of one run: {diff}")));
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
        if let Some(r) = part.iter().find(|r| r.seed != m.seed) {
            return Err(OutputError::Merge(format!(
                "{}: item {} has seed {}, the manifest seed {}",
                d.display(),
                r.index,
                r.seed,
                m.seed
            )));
        }
        rows.extend(part.into_iter().map(|r| (r, d.clone())));
    }
    let first = first.ok_or_else(|| OutputError::Merge("no shard directories given".into()))?;
    rows.sort_by_key(|(r, _)| r.index);
    let (rows, origin): (Vec<RealizationRow>, Vec<PathBuf>) = rows.into_iter().unzip();
    // A missing item names its shard: item i is in shard (i mod N) + 1 of N.
    let n_shards: Option<usize> = first.shard.split_once('/').and_then(|(_, n)| n.parse().ok()).filter(|n| *n > 0);
    let present: std::collections::BTreeSet<u64> = rows.iter().map(|r| r.index).collect();
    if let Some(n) = n_shards {
        let missing: Vec<String> = (0..n)
            .filter(|k| (*k..first.total_items).step_by(n).next().is_some_and(|i| !present.contains(&(i as u64))))
            .map(|k| format!("{}/{n}", k + 1))
            .collect();
        if !missing.is_empty() {
            return Err(OutputError::Merge(format!(
                "{} {} missing: {} in none of the directories given (run it, e.g. with `drystone run STUDY --shard {} --resume --out DIR`, then merge again)",
                if missing.len() == 1 { "shard" } else { "shards" },
                missing.join(", "),
                if missing.len() == 1 { "its items are" } else { "their items are" },
                missing[0]
            )));
        }
    }
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
    Ok((first, rows, origin))
}

/// What [`merge`] wrote.
#[derive(Debug, Clone)]
pub struct Merged {
    /// The study, rebuilt from the inputs stored in the manifests.
    pub study: Study,
    /// Every row, in item order.
    pub rows: Vec<RealizationRow>,
    /// The comparison text (see [`write_outputs`]).
    pub text: Option<String>,
}

/// Merges shard directories into `out` (under its lock, `DirLock`): [`read_shards`]; the
/// study rebuilt from the input files stored in the manifest (written under `out/.inputs/`
/// while it resolves, then removed: the study file need not exist any more, nor be where
/// it was); every row checked against the rebuilt study's items (study name, seed, group,
/// sweep point, realization); then [`write_outputs`] as for the unsharded run, its manifest
/// with the shards' drystone version and build.
///
/// # Errors
/// [`OutputError`] naming the shard, field or file.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Merged, OutputError> {
    let _lock = DirLock::acquire(out)?;
    // The merged outputs would replace a shard's own (its manifest and rows) as they are
    // read: the output folder is none of the shards.
    let same = |d: &Path| match (std::fs::canonicalize(d), std::fs::canonicalize(out)) {
        (Ok(a), Ok(b)) => a == b,
        _ => d == out,
    };
    if let Some(d) = dirs.iter().find(|d| same(d)) {
        return Err(OutputError::Merge(format!(
            "--out {} is one of the shards to merge ({}): write the merged study to another folder",
            out.display(),
            d.display()
        )));
    }
    check_writable(out)?;
    let (manifest, rows, origin) = read_shards_with_origin(dirs)?;
    if manifest.inputs.is_empty() {
        return Err(OutputError::Merge(format!(
            "{}: the manifest stores no input files (written by drystone {}); run the shards again",
            dirs[0].display(),
            if manifest.drystone_version.is_empty() { "before 0.1.0" } else { &manifest.drystone_version }
        )));
    }
    let scratch = out.join(".inputs");
    let _ = std::fs::remove_dir_all(&scratch);
    let rebuilt = rebuild(&manifest, &scratch);
    let _ = std::fs::remove_dir_all(&scratch);
    let study = rebuilt?;
    let at = |i: usize| (origin[i].join("realizations.parquet"), format!("row of item {}", rows[i].index));
    check_rows(&study, Shard::ALL, &rows, at, "shard")?;
    let text = write_outputs_by(&study, &manifest.study, Shard::ALL, &rows, out, Some(&manifest))?;
    Ok(Merged { study, rows, text })
}

/// The study of a manifest, resolved from its stored inputs written under `scratch`, with
/// the manifest's realizations; its inputs must be the stored ones.
fn rebuild(manifest: &Manifest, scratch: &Path) -> Result<Study, OutputError> {
    let merge_error = |m: String| OutputError::Merge(m);
    let path = provenance::materialize(&manifest.inputs, scratch).map_err(|e| merge_error(e.to_string()))?;
    let mut study = Study::from_file(&path).map_err(|e| merge_error(format!("the stored study: {e}")))?;
    study.realizations = manifest.realizations;
    let d =
        provenance::first_difference_by_content(&manifest.inputs, &study.inputs, "the manifest", "the rebuilt study");
    if let Some(d) = d {
        return Err(merge_error(format!("the stored inputs do not rebuild the study: {d}")));
    }
    // The study file as the shards ran it (the rebuilt one's folder is removed): what a
    // report names, and where the in-plane report finds its crack maps.
    study.path.clone_from(&manifest.study);
    Ok(study)
}
