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

use super::outcome::Outcome;
use crate::protocol::{InPlaneReading, Observed};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// A directory of forward runs ([module docs](self)). Shared by the setups of one command
/// through an `Arc` (`Setup::store`); counts the runs it gave and took.
#[derive(Debug)]
pub struct RunStore {
    dir: PathBuf,
    read: AtomicUsize,
    written: AtomicUsize,
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

/// One stored run: the outcome and the in-plane rig reading it is read again from
/// ([`Observed::rig_reading`], not part of the outcome's JSON).
#[derive(Serialize, Deserialize)]
struct Record {
    observed: Observed,
    rig: Option<InPlaneReading>,
    error: Option<String>,
}

impl Record {
    fn of(o: &Outcome) -> Record {
        Record { observed: o.observed.clone(), rig: o.observed.rig_reading.as_deref().cloned(), error: o.error.clone() }
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
        Ok(RunStore { dir, read: AtomicUsize::new(0), written: AtomicUsize::new(0) })
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

    fn path(&self, key: &str) -> PathBuf {
        self.dir.join(&key[..2]).join(format!("{key}.json"))
    }

    /// The stored run under `key` ([`super::Setup::run_key`]), if there is a complete one; a
    /// record that does not read is a miss.
    pub fn get(&self, key: &str) -> Option<Outcome> {
        let text = std::fs::read(self.path(key)).ok()?;
        let record: Record = serde_json::from_slice(&text).ok()?;
        self.read.fetch_add(1, Ordering::Relaxed);
        Some(record.outcome())
    }

    /// Stores `outcome` under `key` ([`super::Setup::run_key`]) if it reads back the same to the
    /// bit; returns whether it did. A run that cannot be stored (a NaN or infinite reading,
    /// a full disk) is left out, and made again when asked for.
    pub fn put(&self, key: &str, outcome: &Outcome) -> bool {
        let Ok(text) = serde_json::to_vec(&Record::of(outcome)) else { return false };
        let same = serde_json::from_slice::<Record>(&text)
            .is_ok_and(|r| format!("{:?}", r.outcome()) == format!("{outcome:?}"));
        if !same {
            return false;
        }
        let path = self.path(key);
        // Written whole (`files::replace_file`); two writers of one key write the same bytes.
        let written = path.parent().is_some_and(|d| std::fs::create_dir_all(d).is_ok())
            && crate::files::replace_file(&path, &text).is_ok();
        if written {
            self.written.fetch_add(1, Ordering::Relaxed);
        }
        written
    }
}
