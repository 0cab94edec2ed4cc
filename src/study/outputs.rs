//! Output sets that cannot mix: the files of a run directory are written as one set.
//!
//! [`write_set`] writes every output (tables, summary, report, plots) into a fresh staging
//! directory `DIR/.drystone-staging/`, records the SHA-256 of each, then commits the set:
//! it removes `manifest.json` (the directory is then marked incomplete), removes the
//! outputs of the previous set that the new one lacks, renames every new output into
//! `DIR`, and writes `manifest.json`, with the list of outputs and their digests, last.
//!
//! Hence a directory with a `manifest.json` holds one complete set, and each output in it
//! has the digest the manifest records; a directory without one (a run killed while it
//! committed) holds no complete set, and the next run or `--resume` writes one.
//! [`verify`] checks a set against its manifest.

use super::lock::{DirLock, LockError};
use super::provenance::sha256_hex;
use crate::io::FileError;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The staging directory inside a run directory.
pub const STAGING: &str = ".drystone-staging";

/// The manifest, written last: the completion marker of a set.
pub const MANIFEST: &str = "manifest.json";

/// One output file of a set.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct OutputFile {
    /// File name in the run directory.
    pub path: String,
    /// SHA-256 of its bytes, lower-case hex.
    pub sha256: String,
}

/// Writes a set of outputs into `dir`: `write` fills the staging directory it is given,
/// `manifest` turns the list of outputs into the text of `manifest.json`, and the set is
/// committed (see the module documentation). `previous` are the outputs of the set in
/// `dir` before (from its manifest), removed unless the new set has them too.
///
/// # Errors
/// `write`'s error, or [`FileError`] naming the file.
pub fn write_set<E: From<FileError>, T>(
    dir: &Path,
    previous: &[OutputFile],
    write: impl FnOnce(&Path) -> Result<T, E>,
    manifest: impl FnOnce(Vec<OutputFile>) -> Result<String, E>,
) -> Result<T, E> {
    write_named_set(dir, SetNames::RUN, previous, write, manifest)
}

/// The staging directory and the manifest of a set: a run's ([`SetNames::RUN`]), or
/// another command's writing beside it in the same directory (`calibrate`,
/// `discrepancy`), whose set is committed and checked on its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SetNames {
    /// The staging directory inside the output directory.
    pub staging: &'static str,
    /// The manifest, written last.
    pub manifest: &'static str,
}

impl SetNames {
    /// A run's set: `STAGING`, `MANIFEST`.
    pub const RUN: SetNames = SetNames { staging: STAGING, manifest: MANIFEST };
}

/// `write_set` with the staging directory and manifest of `names`.
///
/// # Errors
/// `write`'s error, or [`FileError`] naming the file.
pub fn write_named_set<E: From<FileError>, T>(
    dir: &Path,
    names: SetNames,
    previous: &[OutputFile],
    write: impl FnOnce(&Path) -> Result<T, E>,
    manifest: impl FnOnce(Vec<OutputFile>) -> Result<String, E>,
) -> Result<T, E> {
    let staging = dir.join(names.staging);
    let _ = std::fs::remove_dir_all(&staging);
    std::fs::create_dir_all(&staging).map_err(FileError::at(&staging))?;
    let value = write(&staging)?;
    let outputs = digests(&staging)?;
    let text = manifest(outputs.clone())?;
    let marker = dir.join(names.manifest);
    match std::fs::remove_file(&marker) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(FileError::at(&marker)(e).into()),
        _ => crate::io::sync_dir(&marker),
    }
    for old in previous.iter().filter(|o| !outputs.iter().any(|n| n.path == o.path)) {
        if plain_name(&old.path) {
            let _ = std::fs::remove_file(dir.join(&old.path));
        }
    }
    for f in &outputs {
        let to = dir.join(&f.path);
        std::fs::rename(staging.join(&f.path), &to).map_err(FileError::at(&to))?;
    }
    crate::io::sync_dir(&marker);
    crate::io::replace_file(&marker, text.as_bytes())?;
    let _ = std::fs::remove_dir_all(&staging);
    Ok(value)
}

/// The manifest of a command's set written beside a run's (`calibrate`, `discrepancy`):
/// the command, the study, the drystone version and every output with its digest.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CommandManifest {
    /// The command (`calibrate`, `discrepancy`).
    pub command: String,
    /// The study's name.
    pub study: String,
    /// The drystone version that wrote the set.
    pub drystone_version: String,
    /// The outputs.
    pub outputs: Vec<OutputFile>,
}

/// An output directory held by this command: its lock (`DirLock`, one writer per
/// directory, taken before anything is computed, released when dropped) and its sets
/// written whole ([`write_named_set`]). Two commands on one `--out`: the second is
/// refused naming the first, and nothing of theirs is mixed.
#[derive(Debug)]
pub struct HeldDir {
    dir: PathBuf,
    _lock: DirLock,
}

impl HeldDir {
    /// Creates `dir` if needed and takes its lock without waiting.
    ///
    /// # Errors
    /// `LockError::Held` naming the directory and the process holding it, or
    /// `LockError::File` naming the file.
    pub fn acquire(dir: &Path) -> Result<HeldDir, LockError> {
        let lock = DirLock::acquire(dir)?;
        Ok(HeldDir { dir: dir.to_owned(), _lock: lock })
    }

    /// The directory.
    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// Writes one set of `command`'s outputs for `study`: `write` fills the staging
    /// directory it is given (plain files only), and the set is committed with the
    /// manifest of `names` ([`CommandManifest`]); the outputs of the command's previous
    /// set that the new one lacks are removed, nothing else in the directory is touched.
    ///
    /// # Errors
    /// `write`'s error, or [`FileError`] naming the file.
    pub fn write_set<E: From<FileError>, T>(
        &self,
        names: SetNames,
        command: &str,
        study: &str,
        write: impl FnOnce(&Path) -> Result<T, E>,
    ) -> Result<T, E> {
        let marker = self.dir.join(names.manifest);
        let previous = std::fs::read_to_string(&marker)
            .ok()
            .and_then(|t| serde_json::from_str::<CommandManifest>(&t).ok())
            .map(|m| m.outputs)
            .unwrap_or_default();
        write_named_set(&self.dir, names, &previous, write, |outputs| {
            let m = CommandManifest {
                command: command.into(),
                study: study.into(),
                drystone_version: env!("CARGO_PKG_VERSION").into(),
                outputs,
            };
            serde_json::to_string_pretty(&m)
                .map_err(|e| E::from(FileError::at(&marker)(std::io::Error::other(e.to_string()))))
        })
    }
}

/// A file name without a directory part (what an output path must be).
fn plain_name(p: &str) -> bool {
    let mut c = Path::new(p).components();
    matches!((c.next(), c.next()), (Some(std::path::Component::Normal(_)), None))
}

/// The files of `dir` (not its subdirectories) with their digests, by name.
fn digests(dir: &Path) -> Result<Vec<OutputFile>, FileError> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).map_err(FileError::at(dir))? {
        let e = e.map_err(FileError::at(dir))?;
        let p: PathBuf = e.path();
        if p.is_file() {
            let bytes = std::fs::read(&p).map_err(FileError::at(&p))?;
            out.push(OutputFile { path: e.file_name().to_string_lossy().into_owned(), sha256: sha256_hex(&bytes) });
        }
    }
    out.sort_by(|a, b| a.path.cmp(&b.path));
    Ok(out)
}

/// Checks that every output of a set in `dir` has the digest its manifest records.
///
/// # Errors
/// [`VerifyError`] naming the file: missing, or with another digest (the set was mixed
/// with another run's files, or altered).
pub fn verify(dir: &Path, outputs: &[OutputFile]) -> Result<(), VerifyError> {
    if outputs.is_empty() {
        return Err(VerifyError::Empty { manifest: dir.join(MANIFEST) });
    }
    for f in outputs {
        let p = dir.join(&f.path);
        let bytes = std::fs::read(&p).map_err(FileError::at(&p))?;
        let actual = sha256_hex(&bytes);
        if actual != f.sha256 {
            return Err(VerifyError::Digest { path: p, actual, recorded: f.sha256.clone() });
        }
    }
    Ok(())
}

/// An output set that is not the one its manifest records ([`verify`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VerifyError {
    /// The manifest lists no file.
    #[error("{}: the manifest records no outputs", manifest.display())]
    Empty {
        /// The manifest.
        manifest: PathBuf,
    },
    /// A listed file cannot be read (missing).
    #[error(transparent)]
    Read(#[from] FileError),
    /// A file whose digest differs from the manifest's.
    #[error("{}: sha256 {actual}, the manifest records {recorded} (the file is not the one its run wrote)", path.display())]
    Digest {
        /// The file.
        path: PathBuf,
        /// Its digest now.
        actual: String,
        /// The manifest's digest.
        recorded: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(dir: &Path, files: &[(&str, &str)], fail: bool) -> Result<(), FileError> {
        let previous: Vec<OutputFile> = std::fs::read_to_string(dir.join(MANIFEST))
            .ok()
            .map(|t| serde_json::from_str(&t).unwrap())
            .unwrap_or_default();
        write_set(
            dir,
            &previous,
            |staging| {
                for (name, text) in files {
                    std::fs::write(staging.join(name), text).map_err(FileError::at(staging))?;
                }
                Ok(())
            },
            |outputs| {
                if fail {
                    Err(FileError::at(dir)(std::io::Error::other("killed")))
                } else {
                    Ok(serde_json::to_string(&outputs).unwrap())
                }
            },
        )
    }

    fn outputs_of(dir: &Path) -> Vec<OutputFile> {
        serde_json::from_str(&std::fs::read_to_string(dir.join(MANIFEST)).unwrap()).unwrap()
    }

    #[test]
    fn a_set_is_whole_or_marked_incomplete_and_its_digests_are_checked() {
        let dir = std::env::temp_dir().join(format!("drystone-outputs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        set(&dir, &[("a.csv", "old a"), ("old.svg", "old plot")], false).unwrap();
        let old = outputs_of(&dir);
        assert_eq!(old.len(), 2);
        assert_eq!(old[0].sha256, sha256_hex(b"old a"));
        verify(&dir, &old).unwrap();
        // Stopped before its commit: the old set stands.
        assert!(set(&dir, &[("a.csv", "new a")], true).is_err());
        assert_eq!(std::fs::read_to_string(dir.join("a.csv")).unwrap(), "old a");
        verify(&dir, &outputs_of(&dir)).unwrap();
        // Stopped in its commit (a file cannot be renamed): no manifest, the set is marked
        // incomplete.
        std::fs::create_dir_all(dir.join("b.csv").join("x")).unwrap();
        assert!(set(&dir, &[("a.csv", "new a"), ("b.csv", "new b")], false).is_err());
        assert!(!dir.join(MANIFEST).exists());
        std::fs::remove_dir_all(dir.join("b.csv")).unwrap();
        // A whole new set: the old plot it lacks is removed; a file altered afterwards is
        // named.
        std::fs::write(dir.join(MANIFEST), serde_json::to_string(&old).unwrap()).unwrap();
        set(&dir, &[("a.csv", "new a")], false).unwrap();
        assert!(!dir.join("old.svg").exists());
        std::fs::write(dir.join("a.csv"), "altered").unwrap();
        let e = verify(&dir, &outputs_of(&dir)).unwrap_err().to_string();
        assert!(e.contains("a.csv: sha256") && e.contains("the file is not the one its run wrote"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
