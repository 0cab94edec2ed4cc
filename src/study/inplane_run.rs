//! The in-plane study's run directory, by the study core's mechanism: the journal of
//! finished realizations (`journal.jsonl`, [`crate::ensemble::journal`]: every row synced as
//! it finishes, each line with the run's identity and its checksum), resume after a kill,
//! shards (`--shard K/N`, the items whose index ≡ K−1 mod N, [`Shard`]) and their merge, and
//! the manifest (`manifest.json`, [`Manifest`]: the drystone version and build, the seed, the
//! realizations, the shard and every input file with its SHA-256 and text), written last
//! over the set of outputs ([`super::outputs::write_set`]). A resumed or merged run writes
//! the outputs of an uninterrupted one, byte for byte, but the `wall_time_s` column and the
//! report's wall-clock time.

use super::inplane::{realization, write_rows, InPlaneRow, InPlaneStudyError, InPlaneStudyRun};
use super::inplane_report::report;
use super::inplane_spec::InPlaneStudy;
use super::lock::DirLock;
use super::provenance::{self, InputRole};
use super::shards::{open_journal, Manifest, OutputError, RunMode};
use super::Study;
use crate::ensemble::journal::{Journal, JournalRow, FILE_NAME};
use crate::ensemble::{items_per_group, Item, Shard};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// An in-plane study as its run reads it: the study (read by the core,
/// [`Study::from_file`]) and its in-plane test.
pub(super) struct Prepared<'a> {
    /// The study: its groups' walls and effects, seed, realizations, solver and inputs.
    pub study: &'a Study,
    /// Its in-plane test: the parameters, each group's values, the measured specimens.
    pub test: &'a InPlaneStudy,
}

impl<'a> Prepared<'a> {
    /// The in-plane study `study`.
    ///
    /// # Errors
    /// [`InPlaneStudyError::Invalid`] at `protocol` for a study of another protocol.
    pub fn of(study: &'a Study) -> Result<Prepared<'a>, InPlaneStudyError> {
        let test = study.protocol.in_plane().ok_or_else(|| InPlaneStudyError::Invalid {
            path: study.path.clone(),
            key: "protocol".into(),
            message: format!("{:?}: this run is the in-plane test's (protocol = \"in_plane\")", study.protocol.name()),
        })?;
        Ok(Prepared { study, test })
    }

    /// Realizations per group.
    pub fn realizations(&self) -> Vec<u64> {
        (0..self.study.groups.len()).map(|g| self.study.group_realizations(g)).collect()
    }

    /// Realization `i` of group `g` (generator index `g · 10000 + i`).
    pub fn run_one(&self, g: usize, i: u64) -> InPlaneRow {
        let group = &self.study.groups[g];
        let (wall, params) = (&group.walls[0], self.test.params_of(g));
        realization(wall, &group.effects, self.study.seed, g, i, &group.name, &params, self.study.solver)
    }

    /// Writes the rows (`realizations.csv`) into `dir`, and with `whole` (every item of the
    /// study, not a shard's) the statistics, the comparison, the figures and the report;
    /// returns the report's text. A group's first row that lacks its drawing (read back
    /// from a journal, which does not keep it) is drawn again from its realization, the
    /// same bits.
    ///
    /// # Errors
    /// An output that cannot be written.
    pub fn write(
        &self,
        dir: &Path,
        rows: &mut [InPlaneRow],
        whole: bool,
        elapsed_s: f64,
    ) -> Result<String, InPlaneStudyError> {
        write_rows(&dir.join("realizations.csv"), rows)?;
        if !whole {
            return Ok(String::new());
        }
        for (g, group) in self.study.groups.iter().enumerate() {
            if let Some(r) = rows.iter_mut().find(|r| r.group == group.name && r.status == "ok") {
                if r.drawing.is_none() {
                    r.drawing = self.run_one(g, r.realization).drawing;
                }
            }
        }
        report(self.study, self.test, dir, rows, elapsed_s)
    }
}

impl JournalRow for InPlaneRow {
    fn item_index(&self) -> u64 {
        self.index
    }
}

fn write_error(p: &Path, e: &dyn std::fmt::Display) -> InPlaneStudyError {
    InPlaneStudyError::Write(format!("{}: {e}", p.display()))
}

/// The generator's index of an item (`g · 10000 + i`), the rows' `index`.
fn row_index(it: &Item) -> u64 {
    it.group as u64 * 10_000 + it.realization
}

/// Runs the study file `path` into `out` (see the module doc) on the current rayon pool:
/// the whole study, a journal of another run or an unfinished one refused
/// ([`run_into`]).
///
/// # Errors
/// A bad study file, wall or measured file (named), an output that cannot be written.
pub fn run(path: &Path, out: &Path) -> Result<InPlaneStudyRun, InPlaneStudyError> {
    run_into(path, out, crate::ensemble::Shard::ALL, RunMode::default())
}

/// Runs shard `shard` of the study file `path` into `dir` ([`run_study_into`] of the study
/// the core reads, [`Study::from_file`]).
///
/// # Errors
/// As [`run_study_into`]; a bad study file, wall or measured file (named).
pub fn run_into(path: &Path, dir: &Path, shard: Shard, mode: RunMode) -> Result<InPlaneStudyRun, InPlaneStudyError> {
    run_study_into(&Study::from_file(path)?, dir, shard, mode)
}

/// Runs shard `shard` of the in-plane study `study` into `dir`, as the core's run does
/// ([`super::run_into`]): the directory's lock, the journal checked whole before anything
/// runs (with `mode.resume` its rows kept and only the missing realizations run; without,
/// an unfinished journal of this run refused, a finished one started again; a journal of
/// another run or a damaged one refused, or replaced with `mode.force`), every new row
/// journaled as it finishes, then the outputs and the manifest as one set: for a shard its
/// rows alone, for the whole study every output.
///
/// # Errors
/// A study of another protocol (at `protocol`), a journal refused (naming its line and
/// field, or the difference of the runs), an output that cannot be written.
pub fn run_study_into(
    study: &Study,
    dir: &Path,
    shard: Shard,
    mode: RunMode,
) -> Result<InPlaneStudyRun, InPlaneStudyError> {
    let t0 = std::time::Instant::now();
    let prepared = Prepared::of(study)?;
    std::fs::create_dir_all(dir).map_err(|e| write_error(dir, &e))?;
    let _lock = DirLock::acquire(dir).map_err(|e| write_error(dir, &e))?;
    let items = shard.select(&items_per_group(&prepared.realizations(), 1));
    let header = Manifest::new(study, &study.path, shard, 0);
    let journal_path = dir.join(FILE_NAME);
    let check =
        |rows: &[InPlaneRow], _: &[usize]| match rows.iter().find(|r| !items.iter().any(|it| row_index(it) == r.index))
        {
            Some(r) => Err(OutputError::File {
                path: journal_path.clone(),
                message: format!("item {} is not an item of shard {}", r.index, header.shard),
            }),
            None => Ok(()),
        };
    let (journal, done) = open_journal(&journal_path, &header, items.len(), mode, check)?;
    let resumed = done.len();
    let todo: Vec<&Item> = items.iter().filter(|it| !done.iter().any(|r| r.index == row_index(it))).collect();
    let new: Vec<InPlaneRow> = todo
        .par_iter()
        .map(|it| {
            let row = prepared.run_one(it.group, it.realization);
            journal.append(&row).map(|()| row)
        })
        .collect::<Result<_, _>>()
        .map_err(|e| write_error(&journal_path, &e))?;
    let mut rows: Vec<InPlaneRow> = done.into_iter().chain(new).collect();
    rows.sort_by_key(|r| r.index);
    let header = Manifest { items: rows.len(), ..header };
    let report = write_set(&prepared, dir, &mut rows, header, shard.n == 1, t0)?;
    Ok(InPlaneStudyRun { rows, report, wall_time_s: t0.elapsed().as_secs_f64(), resumed })
}

/// The rows (and for the whole study every output) with their manifest, as one set.
fn write_set(
    prepared: &Prepared,
    dir: &Path,
    rows: &mut [InPlaneRow],
    mut manifest: Manifest,
    whole: bool,
    t0: std::time::Instant,
) -> Result<String, InPlaneStudyError> {
    let marker = dir.join(super::outputs::MANIFEST);
    let previous = std::fs::read_to_string(&marker)
        .ok()
        .and_then(|t| serde_json::from_str::<Manifest>(&t).ok())
        .map(|m| m.outputs)
        .unwrap_or_default();
    super::outputs::write_set(
        dir,
        &previous,
        |staging| -> Result<String, Wrapped> {
            prepared.write(staging, rows, whole, t0.elapsed().as_secs_f64()).map_err(Wrapped::Study)
        },
        |outputs| {
            manifest.outputs = outputs;
            serde_json::to_string_pretty(&manifest).map_err(|e| Wrapped::Study(write_error(&marker, &e)))
        },
    )
    .map_err(Wrapped::into_error)
}

/// The study's error or a file's, as the set writer gives them.
enum Wrapped {
    Study(InPlaneStudyError),
    File(crate::io::FileError),
}

impl From<crate::io::FileError> for Wrapped {
    fn from(e: crate::io::FileError) -> Wrapped {
        Wrapped::File(e)
    }
}

impl Wrapped {
    fn into_error(self) -> InPlaneStudyError {
        match self {
            Wrapped::Study(e) => e,
            Wrapped::File(e) => InPlaneStudyError::Write(e.to_string()),
        }
    }
}

/// Merges the shard directories `dirs` of an in-plane study into `out`: every shard of one
/// run (the same manifest but its shard, each of the `N` shards once), each journal checked
/// as a resume checks it, the study read again from the file the manifests name, which must
/// still be the one the shards ran (every input file's SHA-256 the manifests', else
/// refused naming the file); then the outputs of the whole study, as an unsharded run
/// writes them.
///
/// # Errors
/// A shard missing, repeated or of another run (naming the field), an input changed since,
/// an output that cannot be written.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<InPlaneStudyRun, InPlaneStudyError> {
    let t0 = std::time::Instant::now();
    let merge_error = |m: String| InPlaneStudyError::Write(format!("merge: {m}"));
    let mut shards: Vec<(Manifest, Vec<InPlaneRow>, PathBuf)> = Vec::new();
    for d in dirs {
        let path = d.join(FILE_NAME);
        let c = Journal::read_rows::<Manifest, InPlaneRow>(&path)
            .map_err(|e| write_error(&path, &e))?
            .ok_or_else(|| merge_error(format!("{}: no journal", d.display())))?;
        if c.run != c.header.identity() {
            return Err(write_error(&path, &"its lines are not of the run its header names"));
        }
        shards.push((c.header, c.rows, d.clone()));
    }
    let Some(first) = shards.first().map(|(m, ..)| m.clone()) else {
        return Err(merge_error("no shard directory given".into()));
    };
    let n: usize = first.shard.split_once('/').and_then(|(_, n)| n.parse().ok()).unwrap_or(0);
    for (m, _, d) in &shards[1..] {
        if let Some(diff) = first.difference(m, &dirs[0].display().to_string(), &d.display().to_string()) {
            return Err(merge_error(diff));
        }
    }
    for k in 1..=n {
        let count = shards.iter().filter(|(m, ..)| m.shard == format!("{k}/{n}")).count();
        if count != 1 {
            return Err(merge_error(format!("shard {k}/{n} is given {count} times (each of the {n} once)")));
        }
    }
    if shards.len() != n {
        return Err(merge_error(format!("{} directories for {n} shards", shards.len())));
    }
    // The study the shards ran, with their realizations (`--realizations`).
    let mut study = Study::from_file(&first.study)?;
    study.realizations = first.realizations;
    let prepared = Prepared::of(&study)?;
    let whole = Manifest::new(&study, &study.path, Shard::ALL, 0);
    if let Some(d) = provenance::first_difference(&first.inputs, &whole.inputs, "the shards", "the study now") {
        return Err(merge_error(format!("the study's inputs changed since the shards ran: {d}")));
    }
    let mut rows: Vec<InPlaneRow> = Vec::new();
    for (m, r, d) in shards {
        let k: usize = m.shard.split_once('/').and_then(|(k, _)| k.parse().ok()).unwrap_or(0);
        let items = Shard { k: k.saturating_sub(1), n }.select(&items_per_group(&prepared.realizations(), 1));
        if r.len() != items.len() || r.iter().any(|x| !items.iter().any(|it| row_index(it) == x.index)) {
            return Err(merge_error(format!(
                "{}: {} of the {} realizations of shard {} (run it to its end, --resume)",
                d.display(),
                r.len(),
                items.len(),
                m.shard
            )));
        }
        rows.extend(r);
    }
    rows.sort_by_key(|r| r.index);
    std::fs::create_dir_all(out).map_err(|e| write_error(out, &e))?;
    let _lock = DirLock::acquire(out).map_err(|e| write_error(out, &e))?;
    let manifest = Manifest { items: rows.len(), build: first.build.clone(), ..whole };
    let report = write_set(&prepared, out, &mut rows, manifest, true, t0)?;
    Ok(InPlaneStudyRun { rows, report, wall_time_s: t0.elapsed().as_secs_f64(), resumed: 0 })
}

/// Whether the shard directory `dir` holds an in-plane study's run (its journal's header
/// names a study file of `protocol = "in_plane"`, as stored).
pub fn is_in_plane_shard(dir: &Path) -> bool {
    let text = std::fs::read_to_string(dir.join(super::outputs::MANIFEST)).unwrap_or_default();
    let Ok(m) = serde_json::from_str::<Manifest>(&text) else {
        return false;
    };
    m.inputs.iter().filter(|f| f.role == InputRole::Study).any(|f| {
        f.text.parse::<toml::Table>().ok().and_then(|t| t.get("protocol").and_then(|p| p.as_str()).map(String::from))
            == Some("in_plane".to_string())
    })
}
