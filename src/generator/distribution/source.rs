//! Where named distributions are found: the directories searched for `NAME.toml` (inline
//! definitions of a wall file come first, in the wall's resolution), and the rule for names.

use std::path::{Path, PathBuf};

/// Where named distributions are looked up: inline definitions first, then
/// `DIR/NAME.toml` in each directory in order.
#[derive(Debug, Clone, Default)]
pub struct DistributionSource {
    /// Directories searched for `NAME.toml`, in order.
    pub dirs: Vec<PathBuf>,
}

impl DistributionSource {
    /// A source searching one directory.
    pub fn dir(dir: impl Into<PathBuf>) -> Self {
        DistributionSource { dirs: vec![dir.into()] }
    }

    /// The default source for a wall file: the first directory called `distributions` found
    /// next to the wall file or in one of its ancestors, then `./distributions`.
    pub fn default_for(wall_file: &Path) -> Self {
        let mut dirs = Vec::new();
        let start = wall_file.parent().map(Path::to_path_buf).unwrap_or_default();
        let start = if start.as_os_str().is_empty() { PathBuf::from(".") } else { start };
        let mut cur = std::fs::canonicalize(&start).unwrap_or(start);
        loop {
            let cand = cur.join("distributions");
            if cand.is_dir() {
                dirs.push(cand);
                break;
            }
            if !cur.pop() {
                break;
            }
        }
        let cwd = PathBuf::from("distributions");
        if cwd.is_dir() && !dirs.iter().any(|d| std::fs::canonicalize(&cwd).ok().as_ref() == Some(d)) {
            dirs.push(cwd);
        }
        DistributionSource { dirs }
    }

    /// Names available in the directories (sorted), for error messages.
    pub fn available(&self) -> Vec<String> {
        let mut names = std::collections::BTreeSet::new();
        for d in &self.dirs {
            if let Ok(rd) = std::fs::read_dir(d) {
                for e in rd.flatten() {
                    let p = e.path();
                    if p.extension().and_then(|s| s.to_str()) == Some("toml") {
                        if let Some(s) = p.file_stem().and_then(|s| s.to_str()) {
                            names.insert(s.to_string());
                        }
                    }
                }
            }
        }
        names.into_iter().collect()
    }

    /// Finds the file of `name`, if any.
    pub fn find(&self, name: &str) -> Option<PathBuf> {
        self.dirs.iter().map(|d| d.join(format!("{name}.toml"))).find(|p| p.is_file())
    }
}

/// True for a valid distribution name: `[A-Za-z0-9_-]+`.
pub fn valid_name(name: &str) -> bool {
    !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}
