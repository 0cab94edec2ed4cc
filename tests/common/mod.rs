//! Shared helpers of the integration tests.

use std::ffi::OsStr;
use std::ops::Deref;
use std::path::{Path, PathBuf};

/// A scratch directory under the system temporary directory, named after the test and the
/// process (`drystone-NAME-PID`), empty when made and removed with everything in it when
/// dropped, also when the test panics. The directory itself is not created: the commands
/// under test create their output directories.
pub struct Scratch(PathBuf);

impl Scratch {
    /// A fresh (absent) scratch path for `name`.
    pub fn new(name: &str) -> Scratch {
        let d = std::env::temp_dir().join(format!("drystone-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        Scratch(d)
    }

    /// As [`Scratch::new`], and the directory created.
    #[allow(dead_code)] // not every test file that includes this module makes one
    pub fn created(name: &str) -> Scratch {
        let s = Scratch::new(name);
        std::fs::create_dir_all(&s.0).unwrap_or_else(|e| panic!("{}: {e}", s.0.display()));
        s
    }
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<OsStr> for Scratch {
    fn as_ref(&self) -> &OsStr {
        self.0.as_os_str()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
