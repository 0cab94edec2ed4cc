//! Files written whole and file errors that name the file: the one way drystone writes a
//! result file, below every layer that writes one ([`crate::ensemble`]'s journal, [`crate::io`]'s
//! tables, the study's outputs).
//!
//! Result files are replaced whole ([`replace_file`], [`replace_file_with`]): written under a
//! temporary name in the same directory, synced to disk, then renamed over the old file. A
//! reader (or a crash) sees the old file or the new one, never a part of one. Every error
//! names the file and gives the system's reason, e.g. `out/x/realizations.parquet: No space
//! left on device (os error 28)`.

use std::io::Write as _;
use std::path::{Path, PathBuf};

/// A file that could not be written or read: the file and the system's reason.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {source}")]
pub struct FileError {
    /// The file.
    pub path: PathBuf,
    /// The cause (e.g. `No space left on device`).
    pub source: std::io::Error,
}

impl FileError {
    /// A closure that wraps an I/O error of `path`.
    pub fn at(path: &Path) -> impl Fn(std::io::Error) -> FileError + '_ {
        move |source| FileError { path: path.to_owned(), source }
    }
}

/// SHA-256 of `bytes`, lower-case hex (the digests of the journal's lines, of a study's
/// inputs and outputs, and the run store's keys).
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    sha2::Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// The temporary name `path` is written under before [`replace_file`] renames it:
/// `.NAME.tmp` in the same directory.
pub fn temporary_name(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp"))
}

/// Writes `bytes` to `path` whole: into [`temporary_name`], synced, then renamed over
/// `path` (see the module documentation).
///
/// # Errors
/// [`FileError`] naming `path` (the temporary file is removed).
pub fn replace_file(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    replace_file_with(path, |tmp| {
        let mut f = std::fs::File::create(tmp).map_err(FileError::at(path))?;
        f.write_all(bytes).map_err(FileError::at(path))
    })
}

/// As [`replace_file`] for a writer that takes a path (e.g. a plot): `write` writes the
/// temporary file, which is then synced and renamed over `path`.
///
/// # Errors
/// `write`'s error, or [`FileError`] naming `path`; the temporary file is removed.
pub fn replace_file_with<E: From<FileError>>(path: &Path, write: impl FnOnce(&Path) -> Result<(), E>) -> Result<(), E> {
    let tmp = temporary_name(path);
    let done = write(&tmp).and_then(|()| {
        let sync = std::fs::File::open(&tmp).and_then(|f| f.sync_all());
        sync.and_then(|()| std::fs::rename(&tmp, path)).map_err(|e| E::from(FileError::at(path)(e)))
    });
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    } else {
        sync_dir(path);
    }
    done
}

/// Syncs the directory of `path` so that a rename in it is on disk (best effort: not every
/// file system or platform can open a directory).
pub fn sync_dir(path: &Path) {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn a_replaced_file_is_whole_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("drystone-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.csv");
        replace_file(&p, b"old").unwrap();
        replace_file(&p, b"new").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        assert!(!temporary_name(&p).exists());
        let failed: Result<(), FileError> = replace_file_with(&p, |tmp| {
            std::fs::write(tmp, b"half").map_err(FileError::at(tmp))?;
            Err(FileError::at(tmp)(std::io::Error::other("disk gone")))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"new", "a failed write keeps the old file");
        assert!(!temporary_name(&p).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_full_disk_is_reported_with_the_file() {
        // /dev/full fails every write with ENOSPC (Linux).
        let full = Path::new("/dev/full");
        if !full.exists() {
            return;
        }
        let mut f = std::fs::OpenOptions::new().write(true).open(full).unwrap();
        let e = f.write_all(&[0u8; 8192]).and_then(|()| f.flush()).map_err(FileError::at(full)).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("/dev/full: No space left on device"), "{msg}");
    }
}
