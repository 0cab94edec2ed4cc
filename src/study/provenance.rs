//! Provenance: the files a study was resolved from, each with its SHA-256 and its text.
//!
//! A study reads its own file, the wall description of each group, the named distribution
//! files those walls use, and its measured data. [`InputFile`] records each one by its path
//! relative to the deepest directory that holds them all (`/`-separated, so the record
//! does not depend on where the tree sits or on the working directory), the SHA-256 of
//! its bytes (lower-case hex) and its text. The manifest of a run directory and the header
//! of its journal carry the list: a resumed run and `drystone merge` compare it file by
//! file, and merge rebuilds the study from the stored texts ([`materialize`]), so it needs
//! neither the study file nor its walls where they were.

use crate::files::FileError;
use serde::{Deserialize, Serialize};
use std::path::{Component, Path, PathBuf};

/// The drystone version of this build (`CARGO_PKG_VERSION`).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The exact build: `VERSION+src.DIGEST`, DIGEST the first 16 hex digits of a SHA-256 over
/// the crate's sources (`src/`), `Cargo.toml`, `Cargo.lock` and `build.rs`, computed by
/// `build.rs` when the crate is compiled. Manifests and journals record it; a journal is
/// continued only by the build that started it.
pub const BUILD: &str = env!("DRYSTONE_BUILD");

/// What an input file is to the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InputRole {
    /// The study file.
    Study,
    /// A wall description of a group.
    Wall,
    /// A named distribution file a wall uses.
    Distribution,
    /// A measured-data file.
    Measured,
    /// An effect definition file.
    Effect,
    /// A ground-motion record of a shaking study.
    Record,
    /// The materials file of a surveyed group (`[groups.import] materials`).
    Materials,
}

impl InputRole {
    /// The role in messages: `study file`, `wall file`, …
    pub fn describe(self) -> &'static str {
        match self {
            InputRole::Study => "study file",
            InputRole::Wall => "wall file",
            InputRole::Distribution => "distribution file",
            InputRole::Measured => "measured-data file",
            InputRole::Effect => "effect file",
            InputRole::Record => "ground-motion record",
            InputRole::Materials => "materials file",
        }
    }
}

/// One input file of a study.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputFile {
    /// What it is.
    pub role: InputRole,
    /// Path relative to the deepest directory holding every input, `/`-separated.
    pub path: String,
    /// SHA-256 of the bytes, lower-case hex.
    pub sha256: String,
    /// The contents (UTF-8; any invalid byte replaced, which the hash then shows).
    pub text: String,
}

pub use crate::files::sha256_hex;

/// The input files `(role, path)` read and recorded, in the order given with duplicates
/// removed (a distribution shared by two walls is one input).
///
/// Each path is recorded as the study reaches it ([`lexical`]: made absolute, `.` and `..`
/// taken from the path's own text, symbolic links not followed), so the stored tree lays
/// out the files as the study file's relative paths name them, and a study rebuilt from it
/// ([`materialize`]) finds each one where it names it, even when a wall or measured folder
/// is a link to another place.
///
/// # Errors
/// The file that cannot be read or located, with the reason.
pub fn record(files: &[(InputRole, PathBuf)]) -> Result<Vec<InputFile>, (PathBuf, std::io::Error)> {
    let mut seen: Vec<PathBuf> = Vec::new();
    let mut read: Vec<(InputRole, PathBuf, Vec<u8>)> = Vec::new();
    for (role, p) in files {
        let at = lexical(p).map_err(|e| (p.clone(), e))?;
        if seen.contains(&at) {
            continue;
        }
        let bytes = std::fs::read(p).map_err(|e| (p.clone(), e))?;
        seen.push(at.clone());
        read.push((*role, at, bytes));
    }
    let root = common_dir(read.iter().map(|(_, p, _)| p.as_path()));
    Ok(read
        .into_iter()
        .map(|(role, p, bytes)| InputFile {
            role,
            path: relative(&p, &root),
            sha256: sha256_hex(&bytes),
            text: String::from_utf8_lossy(&bytes).into_owned(),
        })
        .collect())
}

/// `p` made absolute against the working directory, its `.` and `..` components taken
/// from the path's text (`a/b/../c` is `a/c`), symbolic links not resolved: the place the
/// study's relative paths name, which a tree rebuilt without links reproduces.
///
/// # Errors
/// The working directory cannot be read.
fn lexical(p: &Path) -> std::io::Result<PathBuf> {
    let mut out = PathBuf::new();
    for c in std::path::absolute(p)?.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    Ok(out)
}

/// The deepest directory that holds every path (absolute paths of files).
fn common_dir<'a>(paths: impl Iterator<Item = &'a Path>) -> PathBuf {
    let mut root: Option<PathBuf> = None;
    for p in paths {
        let dir = p.parent().unwrap_or(Path::new("/")).to_path_buf();
        root = Some(match root {
            None => dir,
            Some(r) => r.components().zip(dir.components()).take_while(|(a, b)| a == b).map(|(a, _)| a).collect(),
        });
    }
    root.unwrap_or_default()
}

/// `path` below `root`, `/`-separated.
fn relative(path: &Path, root: &Path) -> String {
    let rest = path.strip_prefix(root).unwrap_or(path);
    rest.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/")
}

/// Writes the inputs under `dir` at their relative paths and returns the path of the study
/// file among them.
///
/// # Errors
/// [`MaterializeError`] naming the input or the file that could not be written.
pub fn materialize(inputs: &[InputFile], dir: &Path) -> Result<PathBuf, MaterializeError> {
    let mut study = None;
    for f in inputs {
        let rel = Path::new(&f.path);
        let safe = rel.components().all(|c| matches!(c, Component::Normal(_)));
        if !safe || f.path.is_empty() {
            return Err(MaterializeError::Path(f.path.clone()));
        }
        if sha256_hex(f.text.as_bytes()) != f.sha256 {
            return Err(MaterializeError::Digest {
                role: f.role.describe(),
                path: f.path.clone(),
                sha256: f.sha256.clone(),
            });
        }
        let p = dir.join(rel);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(FileError::at(parent))?;
        }
        std::fs::write(&p, &f.text).map_err(FileError::at(&p))?;
        if f.role == InputRole::Study {
            study = Some(p);
        }
    }
    place_distributions(inputs, dir)?;
    study.ok_or(MaterializeError::NoStudy)
}

/// Why a manifest's stored inputs cannot be written back (`materialize`).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MaterializeError {
    /// A stored path that is not plain and relative (it could write outside the directory).
    #[error("stored input path {0:?} is not a plain relative path")]
    Path(String),
    /// A stored text whose digest is not the one recorded beside it.
    #[error("stored {role} {path} does not match its sha256 {sha256}")]
    Digest {
        /// What the input is (`study file`, `wall file`, ...).
        role: &'static str,
        /// Its stored path.
        path: String,
        /// The digest recorded.
        sha256: String,
    },
    /// No study file among the inputs.
    #[error("no study file among the stored inputs")]
    NoStudy,
    /// Writing a file.
    #[error(transparent)]
    File(#[from] FileError),
}

/// Makes every stored distribution file findable from every stored wall by the lookup of
/// [`DistributionSource::default_for`](crate::generator::DistributionSource::default_for)
/// (the first `distributions` directory beside the wall or above it) without the working
/// directory: a distribution the run found in the working directory's `distributions/` is
/// written into that first directory under `dir` (made at `dir/distributions` if there is
/// none), unless a file of its name is there already. The lookup then never leaves `dir`.
fn place_distributions(inputs: &[InputFile], dir: &Path) -> Result<(), FileError> {
    let dists: Vec<&InputFile> = inputs.iter().filter(|f| f.role == InputRole::Distribution).collect();
    for wall in inputs.iter().filter(|f| f.role == InputRole::Wall) {
        let mut cur = dir.join(&wall.path);
        let mut found = None;
        while cur.pop() && cur.starts_with(dir) {
            if cur.join("distributions").is_dir() {
                found = Some(cur.join("distributions"));
                break;
            }
        }
        let target = found.unwrap_or_else(|| dir.join("distributions"));
        for d in &dists {
            let Some(name) = Path::new(&d.path).file_name() else { continue };
            let p = target.join(name);
            if !p.exists() {
                std::fs::create_dir_all(&target).map_err(FileError::at(&target))?;
                std::fs::write(&p, &d.text).map_err(FileError::at(&p))?;
            }
        }
    }
    Ok(())
}

/// As [`first_difference`], with distribution files compared by file name and hash, and
/// the other files by their paths below the deepest directory that holds them all (where
/// a distribution is found depends on the directory a study is run from, and with it the
/// directory every path is relative to; which file it is, its hash says).
pub fn first_difference_by_content(x: &[InputFile], y: &[InputFile], a: &str, b: &str) -> Option<String> {
    let normal = |v: &[InputFile]| -> Vec<InputFile> {
        let dirs = v.iter().filter(|f| f.role != InputRole::Distribution).map(|f| Path::new(&f.path));
        let root = common_dir(dirs);
        v.iter()
            .map(|f| {
                let path = match f.role {
                    InputRole::Distribution => f.path.rsplit('/').next().unwrap_or(&f.path).to_string(),
                    _ => relative(Path::new(&f.path), &root),
                };
                InputFile { path, ..f.clone() }
            })
            .collect()
    };
    first_difference(&normal(x), &normal(y), a, b)
}

/// The first difference between two lists of inputs, in words: a file in one list and not
/// in the other, or a file whose hash differs. `a` and `b` name the two sides.
pub fn first_difference(x: &[InputFile], y: &[InputFile], a: &str, b: &str) -> Option<String> {
    for f in x {
        match y.iter().find(|g| g.role == f.role && g.path == f.path) {
            None => return Some(format!("the {} {} is an input of {a} but not of {b}", f.role.describe(), f.path)),
            Some(g) if g.sha256 != f.sha256 => {
                return Some(format!(
                    "the {} {} differs: sha256 {} in {a}, {} in {b}",
                    f.role.describe(),
                    f.path,
                    f.sha256,
                    g.sha256
                ))
            }
            Some(_) => {}
        }
    }
    y.iter()
        .find(|g| !x.iter().any(|f| f.role == g.role && f.path == g.path))
        .map(|g| format!("the {} {} is an input of {b} but not of {a}", g.role.describe(), g.path))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_of_known_text() {
        assert_eq!(sha256_hex(b"abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    }

    #[test]
    fn paths_are_relative_to_the_deepest_common_directory() {
        let paths =
            [Path::new("/a/b/studies/s.toml"), Path::new("/a/b/studies/walls/w.toml"), Path::new("/a/b/d/x.toml")];
        let root = common_dir(paths.iter().copied());
        assert_eq!(root, Path::new("/a/b"));
        assert_eq!(relative(paths[1], &root), "studies/walls/w.toml");
    }

    #[test]
    fn differences_name_the_file_and_both_hashes() {
        let f = |path: &str, text: &str| InputFile {
            role: InputRole::Wall,
            path: path.into(),
            sha256: sha256_hex(text.as_bytes()),
            text: text.into(),
        };
        let x = vec![f("w.toml", "a")];
        assert_eq!(first_difference(&x, &x, "A", "B"), None);
        let d = first_difference(&x, &[f("w.toml", "b")], "A", "B").unwrap();
        assert!(d.starts_with("the wall file w.toml differs: sha256 ca978112"), "{d}");
        let d = first_difference(&x, &[], "A", "B").unwrap();
        assert_eq!(d, "the wall file w.toml is an input of A but not of B");
        let bad = vec![InputFile { path: "../x".into(), ..f("x", "a") }];
        assert!(materialize(&bad, Path::new("/nonexistent")).unwrap_err().to_string().contains("plain relative path"));
    }
}
