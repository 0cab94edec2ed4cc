//! The run store: forward runs kept on disk, so that every command and process that runs
//! the same realization of the same model reads it instead of running it again
//! (`drystone discrepancy`, then `drystone design` on the same study, then the analysis of
//! both campaigns on the follow-up study it writes; the parts of a design column).
//!
//! A run is stored under the SHA-256 of everything [`super::run_one`] reads
//! ([`super::Setup::run_key`]): the build (`drystone --version`: its version and the
//! digest of its sources, so a run made by another build is never read), the group's name
//! (it seeds the effects' draws), its walls as
//! [`Wall::same_walls`](crate::generator::Wall::same_walls) compares them (the files they
//! were read from aside), its end restraints, course height, own effects and loading
//! protocol, the setup's master seed, solver and protocol, the realization, and the model's
//! effects. Each is written out by its `Debug` form, whose floats are the shortest text
//! that reads back as the same bits, so two inputs that differ in any bit have different
//! keys.
//!
//! An outcome is stored only if it reads back the same to the bit (its `Debug` form
//! compared before and after the JSON round trip): a run with a NaN reading (a monitor
//! the layout lacks) or an infinite one is run again each time, never read changed. A file
//! is written whole to a temporary name and renamed, so a reader sees a complete record or
//! none, and processes that share the directory need no lock; an unreadable record is a
//! miss. Runs read from the store are the same bit for bit as runs made again
//! (`tests/suite/run_store.rs`).
//!
//! Each record carries the key it was stored under, and a record is read only under that
//! key: a record found in another key's file (files moved or swapped by hand, a copy
//! gone wrong) is a miss, run again, with a warning on stderr naming the file; a record
//! without its key (written before records carried it) is a miss, made again. A run that
//! cannot be written (a directory that cannot be written, a full disk) is not kept: the
//! first such failure is warned of on stderr, naming the directory and the error, and
//! [`RunStore::summary`] says when nothing could be kept.

use super::outcome::Outcome;
use crate::protocol::{InPlaneReading, Observed};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// A directory of forward runs ([module docs](self)). Shared by the setups of one command
/// through an `Arc` (`Setup::store`); counts the runs it gave and took.
#[derive(Debug)]
pub struct RunStore {
    dir: PathBuf,
    read: AtomicUsize,
    written: AtomicUsize,
    /// Runs that could not be written, and the first error.
    unwritten: AtomicUsize,
    first_write_error: Mutex<Option<String>>,
}

/// A run store's directory that cannot be made or written.
#[derive(Debug, thiserror::Error)]
#[error("run store {}: {source}", dir.display())]
pub struct StoreError {
    /// The directory.
    pub dir: PathBuf,
    /// Why.
    pub source: std::io::Error,
}

/// One stored run: the key it was stored under, the outcome and the in-plane rig reading it
/// is read again from ([`Observed::rig_reading`], not part of the outcome's JSON).
#[derive(Serialize, Deserialize)]
struct Record {
    /// The key ([`super::Setup::run_key`]); `None` in a record written before records
    /// carried it (a miss).
    #[serde(default)]
    key: Option<String>,
    observed: Observed,
    rig: Option<InPlaneReading>,
    error: Option<String>,
}

impl Record {
    fn of(key: &str, o: &Outcome) -> Record {
        Record {
            key: Some(key.to_string()),
            observed: o.observed.clone(),
            rig: o.observed.rig_reading.as_deref().cloned(),
            error: o.error.clone(),
        }
    }

    fn outcome(self) -> Outcome {
        let mut observed = self.observed;
        observed.rig_reading = self.rig.map(Arc::new);
        Outcome { observed, error: self.error }
    }
}

impl RunStore {
    /// The store in `dir`, made if it does not exist.
    ///
    /// # Errors
    /// [`StoreError`] naming `dir` if it cannot be made or is not a directory.
    pub fn open(dir: impl Into<PathBuf>) -> Result<RunStore, StoreError> {
        let dir = dir.into();
        std::fs::create_dir_all(&dir).map_err(|source| StoreError { dir: dir.clone(), source })?;
        Ok(RunStore {
            dir,
            read: AtomicUsize::new(0),
            written: AtomicUsize::new(0),
            unwritten: AtomicUsize::new(0),
            first_write_error: Mutex::new(None),
        })
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Runs read from the store so far.
    pub fn reads(&self) -> usize {
        self.read.load(Ordering::Relaxed)
    }

    /// Runs written to the store so far.
    pub fn writes(&self) -> usize {
        self.written.load(Ordering::Relaxed)
    }

    /// Runs that could not be written so far (the directory not writable, a full disk),
    /// and the first write's error; `None` when every write succeeded. A run left out
    /// because it would not read back exactly is not a failure.
    pub fn write_failures(&self) -> Option<(usize, String)> {
        let n = self.unwritten.load(Ordering::Relaxed);
        let first = self.first_write_error.lock().ok()?.clone()?;
        Some((n, first))
    }

    /// The line a command prints of its store: runs read and kept, and, when runs could not
    /// be written, a warning naming the directory, the number not kept and the first error
    /// (`nothing could be kept` when no write succeeded).
    pub fn summary(&self) -> String {
        let line = format!("run store {}: {} run(s) read, {} kept", self.dir.display(), self.reads(), self.writes());
        match self.write_failures() {
            None => line,
            Some((n, e)) if self.writes() == 0 => format!(
                "{line}\nwarning: run store {}: nothing could be kept, {n} run(s) not written: {e}",
                self.dir.display()
            ),
            Some((n, e)) => {
                format!("{line}\nwarning: run store {}: {n} run(s) not written: {e}", self.dir.display())
            }
        }
    }

    fn path(&self, key: &str) -> PathBuf {
        self.dir.join(&key[..2]).join(format!("{key}.json"))
    }

    /// The stored run under `key` ([`super::Setup::run_key`]), if there is a complete one
    /// stored under that key; a record that does not read, or that holds no key or
    /// another key (warned of on stderr, naming the file), is a miss.
    pub fn get(&self, key: &str) -> Option<Outcome> {
        let path = self.path(key);
        let text = std::fs::read(&path).ok()?;
        let record: Record = serde_json::from_slice(&text).ok()?;
        match &record.key {
            Some(k) if k == key => {}
            Some(other) => {
                eprintln!(
                    "warning: run store {}: the record holds the run of key {other}, not of the key it is filed \
                     under: not read, the run is made again",
                    path.display()
                );
                return None;
            }
            None => return None,
        }
        self.read.fetch_add(1, Ordering::Relaxed);
        Some(record.outcome())
    }

    /// Stores `outcome` under `key` ([`super::Setup::run_key`]) if it reads back the same to the
    /// bit; returns whether it did. A run that cannot be stored (a NaN or infinite reading,
    /// a full disk) is left out, and made again when asked for; the first write that fails
    /// is warned of on stderr, naming the directory and the error
    /// ([`RunStore::write_failures`]).
    pub fn put(&self, key: &str, outcome: &Outcome) -> bool {
        let Ok(text) = serde_json::to_vec(&Record::of(key, outcome)) else { return false };
        let same = serde_json::from_slice::<Record>(&text)
            .is_ok_and(|r| format!("{:?}", r.outcome()) == format!("{outcome:?}"));
        if !same {
            return false;
        }
        let path = self.path(key);
        // Written whole (`files::replace_file`); two writers of one key write the same bytes.
        let written = match path.parent() {
            Some(d) => std::fs::create_dir_all(d)
                .map_err(|e| format!("{}: {e}", d.display()))
                .and_then(|()| crate::files::replace_file(&path, &text).map_err(|e| e.to_string())),
            None => Err(format!("{}: no directory", path.display())),
        };
        match written {
            Ok(()) => {
                self.written.fetch_add(1, Ordering::Relaxed);
                true
            }
            Err(e) => {
                self.failed_write(e);
                false
            }
        }
    }

    /// Counts a write that failed with `error`; the first is warned of on stderr.
    fn failed_write(&self, error: String) {
        self.unwritten.fetch_add(1, Ordering::Relaxed);
        let Ok(mut first) = self.first_write_error.lock() else { return };
        if first.is_none() {
            eprintln!(
                "warning: run store {}: a run could not be kept ({error}); runs not kept are made again when asked for",
                self.dir.display()
            );
            *first = Some(error);
        }
    }
}
