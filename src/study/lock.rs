//! One writer per output directory: an OS advisory lock (`flock` on Unix, `LockFileEx` on
//! Windows, through `fs4`) on the file `.drystone.lock` in the directory, taken before
//! anything else is written there and held until the command ends. The operating system
//! releases it when the process ends, however it ends (a crash or `kill -9` leaves no
//! stale lock). The holder writes its process id and command line into the file, so that
//! a second command refused names it. The file stays in the directory.

use crate::io::FileError;
use fs4::{FileExt, TryLockError};
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The file name of the lock in an output directory.
pub const FILE_NAME: &str = ".drystone.lock";

/// Errors of taking the lock.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LockError {
    /// The lock file cannot be created or locked.
    #[error(transparent)]
    File(#[from] FileError),
    /// Another process holds the directory.
    #[error("{dir}: in use by another drystone process ({holder}); wait until it ends, or give another --out")]
    Held {
        /// The directory.
        dir: PathBuf,
        /// What the holder wrote about itself (`pid N: drystone run …`).
        holder: String,
    },
}

/// The lock of an output directory, released when dropped.
#[derive(Debug)]
pub struct DirLock {
    file: File,
}

impl DirLock {
    /// Creates `dir` if needed and takes its lock without waiting.
    ///
    /// # Errors
    /// [`LockError::Held`] naming the directory and the holder (its process id and command
    /// line) when another process holds it; [`LockError::File`] naming the file when it
    /// cannot be created or locked.
    pub fn acquire(dir: &Path) -> Result<DirLock, LockError> {
        std::fs::create_dir_all(dir).map_err(FileError::at(dir))?;
        let path = dir.join(FILE_NAME);
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(FileError::at(&path))?;
        match FileExt::try_lock(&file) {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let mut text = String::new();
                let _ = file.read_to_string(&mut text);
                let holder = text.trim();
                let holder = if holder.is_empty() { "it has not yet written its name" } else { holder };
                return Err(LockError::Held { dir: dir.to_owned(), holder: holder.to_string() });
            }
            Err(TryLockError::Error(e)) => return Err(FileError::at(&path)(e).into()),
        }
        let me = format!("pid {}: {}", std::process::id(), std::env::args().collect::<Vec<_>>().join(" "));
        let written = file.set_len(0).and_then(|()| file.rewind()).and_then(|()| file.write_all(me.as_bytes()));
        written.and_then(|()| file.sync_data()).map_err(FileError::at(&path))?;
        Ok(DirLock { file })
    }
}

impl Drop for DirLock {
    fn drop(&mut self) {
        let _ = FileExt::unlock(&self.file);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_on_a_directory_is_refused_naming_the_holder_until_the_first_is_dropped() {
        let dir = std::env::temp_dir().join(format!("drystone-lock-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let first = DirLock::acquire(&dir).unwrap();
        // flock locks belong to the open file: a second open in this process conflicts as
        // one in another process would.
        let e = DirLock::acquire(&dir).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!(
                "{}: in use by another drystone process (pid {}: ",
                dir.display(),
                std::process::id()
            )),
            "{e}"
        );
        drop(first);
        let again = DirLock::acquire(&dir).unwrap();
        assert!(dir.join(FILE_NAME).is_file());
        drop(again);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
