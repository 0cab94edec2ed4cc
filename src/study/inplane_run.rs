//! The in-plane study's run directory, by the study core's mechanism: the journal of
//! finished realizations (`journal.jsonl`, [`crate::ensemble::journal`]: every row synced as
//! it finishes, each line with the run's identity and its checksum), resume after a kill,
//! shards (`--shard K/N`, the items whose index ≡ K−1 mod N, [`Shard`]) and their merge, and
//! the manifest (`manifest.json`, [`Manifest`]: the drystone version and build, the seed, the
//! realizations, the shard and every input file with its SHA-256 and text), written last
//! over the set of outputs ([`super::outputs::write_set`]). A resumed or merged run writes
//! the outputs of an uninterrupted one, byte for byte, but the `wall_time_s` column and the
//! report's wall-clock time.

use super::inplane::{group_effects, load, realization, write_rows, InPlaneRow, InPlaneStudyError, InPlaneStudyRun};
use super::inplane::{read_loops, read_specimens, InPlaneStudySpec, Specimen};
use super::inplane_report::report;
use super::lock::DirLock;
use super::provenance::{self, InputRole};
use super::shards::{Manifest, RunMode};
use crate::ensemble::journal::{Journal, JournalError, JournalRow, FILE_NAME};
use crate::ensemble::{items_per_group, Item, Shard};
use crate::generator::Wall;
use crate::loading::inplane::InPlaneParams;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// What a study's runs and outputs read: its file checked, its measured specimens, its
/// groups' walls and effects.
pub(super) struct Prepared {
    /// The study file.
    pub spec: InPlaneStudySpec,
    /// The measured specimens (none without `[measured]`).
    pub specimens: Vec<Specimen>,
    /// Each group's wall.
    pub walls: Vec<Wall>,
    /// Each group's effects.
    pub effects: Vec<Vec<crate::effects::Effect>>,
}

impl Prepared {
    /// Reads the study `path` and everything its runs read.
    ///
    /// # Errors
    /// A bad study file, wall or measured file (named).
    pub fn read(path: &Path) -> Result<Prepared, InPlaneStudyError> {
        let spec = load(path)?;
        let base = path.parent().unwrap_or(Path::new("."));
        let specimens = match &spec.measured {
            Some(m) => {
                let mut s =
                    read_specimens(&base.join(&m.walls), m.envelopes.as_ref().map(|e| base.join(e)).as_deref())?;
                if let Some(c) = &m.curves {
                    read_loops(&mut s, &base.join(c))?;
                }
                s
            }
            None => Vec::new(),
        };
        for (g, group) in spec.groups.iter().enumerate() {
            if let Some(s) = group.specimens.iter().find(|s| !specimens.iter().any(|m| &m.unit == *s)) {
                return Err(InPlaneStudyError::Invalid {
                    path: path.to_owned(),
                    key: format!("groups[{g}].specimens"),
                    message: format!("{s} is not a unit of the measured file"),
                });
            }
        }
        let walls: Vec<Wall> =
            (0..spec.groups.len()).map(|g| super::inplane::group_wall(&spec, path, g)).collect::<Result<_, _>>()?;
        let effects: Vec<Vec<crate::effects::Effect>> =
            (0..spec.groups.len()).map(|g| group_effects(&spec, path, g, &walls[g])).collect::<Result<_, _>>()?;
        Ok(Prepared { spec, specimens, walls, effects })
    }

    /// Realizations per group.
    pub fn realizations(&self) -> Vec<u64> {
        self.spec.groups.iter().map(|g| g.realizations.unwrap_or(self.spec.realizations)).collect()
    }

    /// Realization `i` of group `g` (generator index `g · 10000 + i`).
    pub fn run_one(&self, g: usize, i: u64) -> InPlaneRow {
        let group = &self.spec.groups[g];
        let params =
            InPlaneParams { sigma0_mpa: group.sigma0_mpa, history: group.history, ..self.spec.in_plane.clone() };
        realization(&self.walls[g], &self.effects[g], self.spec.seed, g, i, group, &params, self.spec.solver)
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
        path: &Path,
        dir: &Path,
        rows: &mut [InPlaneRow],
        whole: bool,
        elapsed_s: f64,
    ) -> Result<String, InPlaneStudyError> {
        write_rows(&dir.join("realizations.csv"), rows)?;
        if !whole {
            return Ok(String::new());
        }
        for (g, group) in self.spec.groups.iter().enumerate() {
            if let Some(r) = rows.iter_mut().find(|r| r.group == group.name && r.status == "ok") {
                if r.drawing.is_none() {
                    r.drawing = self.run_one(g, r.realization).drawing;
                }
            }
        }
        let s = &self.spec;
        report(s, path, dir, rows, &self.specimens, &self.walls, &self.effects, s.solver, elapsed_s)
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

/// The input files of a study: the study file, its walls (with the distribution files they
/// name), its measured specimens' table.
fn inputs(prepared: &Prepared, path: &Path) -> Result<Vec<provenance::InputFile>, InPlaneStudyError> {
    let base = path.parent().unwrap_or(Path::new("."));
    let mut files = vec![(InputRole::Study, path.to_owned())];
    for (g, wall) in prepared.spec.groups.iter().zip(&prepared.walls) {
        let p = base.join(g.source());
        for d in wall.distributions() {
            if !d.source.as_os_str().is_empty() && d.source != p {
                files.push((InputRole::Distribution, d.source.clone()));
            }
        }
        files.extend(crate::survey::survey_files(&p).into_iter().map(|f| (InputRole::Wall, f)));
        if let Some(m) = g.import.as_ref().and_then(|i| i.materials.as_ref()).filter(|_| g.survey.is_some()) {
            files.push((InputRole::Materials, base.join(m)));
        }
    }
    if let Some(m) = &prepared.spec.measured {
        files.push((InputRole::Measured, base.join(&m.walls)));
    }
    provenance::record(&files).map_err(|(p, e)| InPlaneStudyError::File { path: p, message: e.to_string() })
}

/// The manifest of `items` rows of shard `shard` of the study.
fn manifest(prepared: &Prepared, path: &Path, shard: Shard, items: usize) -> Result<Manifest, InPlaneStudyError> {
    Ok(Manifest {
        drystone_version: provenance::VERSION.to_string(),
        build: provenance::BUILD.to_string(),
        study: path.to_owned(),
        seed: prepared.spec.seed,
        realizations: prepared.spec.realizations,
        shard: format!("{}/{}", shard.k + 1, shard.n),
        total_items: items_per_group(&prepared.realizations(), 1).len(),
        items,
        inputs: inputs(prepared, path)?,
        outputs: Vec::new(),
    })
}

/// The generator's index of an item (`g · 10000 + i`), the rows' `index`.
fn row_index(it: &Item) -> u64 {
    it.group as u64 * 10_000 + it.realization
}

/// Runs the study `path` into `out` (see the module doc) on the current rayon pool: the
/// whole study, a journal of another run or an unfinished one refused
/// ([`run_into`]).
///
/// # Errors
/// A bad study file, wall or measured file (named), an output that cannot be written.
pub fn run(path: &Path, out: &Path) -> Result<InPlaneStudyRun, InPlaneStudyError> {
    run_into(path, out, crate::ensemble::Shard::ALL, RunMode::default())
}

/// Runs shard `shard` of the study `path` into `dir`, as the core's run does
/// ([`super::run_into`]): the directory's lock, the journal checked whole before anything
/// runs (with `mode.resume` its rows kept and only the missing realizations run; without,
/// an unfinished journal of this run refused, a finished one started again; a journal of
/// another run or a damaged one refused, or replaced with `mode.force`), every new row
/// journaled as it finishes, then the outputs and the manifest as one set: for a shard its
/// rows alone, for the whole study every output.
///
/// # Errors
/// A bad study file, wall or measured file (named), a journal refused (naming its line and
/// field, or the difference of the runs), an output that cannot be written.
pub fn run_into(path: &Path, dir: &Path, shard: Shard, mode: RunMode) -> Result<InPlaneStudyRun, InPlaneStudyError> {
    let t0 = std::time::Instant::now();
    let prepared = Prepared::read(path)?;
    std::fs::create_dir_all(dir).map_err(|e| write_error(dir, &e))?;
    let _lock = DirLock::acquire(dir).map_err(|e| write_error(dir, &e))?;
    let items = shard.select(&items_per_group(&prepared.realizations(), 1));
    let header = manifest(&prepared, path, shard, 0)?;
    let run = header.identity();
    let journal_path = dir.join(FILE_NAME);
    let refuse = |message: String| write_error(&journal_path, &message);
    let fresh = || Journal::create(&journal_path, &run, &header).map(|j| (j, Vec::new()));
    let contents = match Journal::read_rows::<Manifest, InPlaneRow>(&journal_path) {
        Err(JournalError::Corrupt { .. }) if mode.force => None,
        Err(e @ JournalError::Corrupt { .. }) => {
            return Err(refuse(format!("{e}; delete the journal or give --force to start again")))
        }
        Err(e) => return Err(refuse(e.to_string())),
        Ok(c) => c,
    };
    let opened = match contents {
        None => fresh(),
        Some(c) if c.run != run => {
            if !mode.force {
                let d = c.header.difference(&header, "the journal", "this run").unwrap_or_else(|| {
                    format!("run identity {} in the journal, {run} in this run (shard {})", c.run, header.shard)
                });
                return Err(refuse(format!("was written by another run ({d}); give another --out, or --force")));
            }
            fresh()
        }
        Some(c) => {
            if let Some(r) = c.rows.iter().find(|r| !items.iter().any(|it| row_index(it) == r.index)) {
                return Err(refuse(format!("item {} is not an item of shard {}", r.index, header.shard)));
            }
            if mode.resume {
                Journal::resume(&journal_path, &run, c.complete_len).map(|j| (j, c.rows))
            } else if c.rows.is_empty() || c.rows.len() == items.len() || mode.force {
                fresh()
            } else {
                return Err(refuse(format!(
                    "holds {} of {} finished realization(s) of this run; continue it with --resume, or give \
                     --force to start again",
                    c.rows.len(),
                    items.len()
                )));
            }
        }
    };
    let (journal, done) = opened.map_err(|e| refuse(e.to_string()))?;
    let resumed = done.len();
    let todo: Vec<&Item> = items.iter().filter(|it| !done.iter().any(|r| r.index == row_index(it))).collect();
    let new: Vec<InPlaneRow> = todo
        .par_iter()
        .map(|it| {
            let row = prepared.run_one(it.group, it.realization);
            journal.append(&row).map(|()| row)
        })
        .collect::<Result<_, _>>()
        .map_err(|e| refuse(e.to_string()))?;
    let mut rows: Vec<InPlaneRow> = done.into_iter().chain(new).collect();
    rows.sort_by_key(|r| r.index);
    let header = Manifest { items: rows.len(), ..header };
    let report = write_set(&prepared, path, dir, &mut rows, header, shard.n == 1, t0)?;
    Ok(InPlaneStudyRun { rows, report, wall_time_s: t0.elapsed().as_secs_f64(), resumed })
}

/// The rows (and for the whole study every output) with their manifest, as one set.
fn write_set(
    prepared: &Prepared,
    path: &Path,
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
            prepared.write(path, staging, rows, whole, t0.elapsed().as_secs_f64()).map_err(Wrapped::Study)
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
    let path = first.study.clone();
    let prepared = Prepared::read(&path)?;
    let whole = manifest(&prepared, &path, Shard::ALL, 0)?;
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
    let report = write_set(&prepared, &path, out, &mut rows, manifest, true, t0)?;
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
