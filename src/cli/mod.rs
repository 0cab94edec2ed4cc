//! The work of each subcommand: read the inputs, call the library, print the result.

/// `println!` that ends the program quietly when stdout is closed (e.g. piped into `head`)
/// instead of panicking.
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        if writeln!(std::io::stdout(), $($t)*).is_err() {
            std::process::exit(0);
        }
    }};
}

pub mod bench;
pub mod compression;
pub mod design;
pub mod discrepancy;
pub mod generate;
pub mod import;
pub mod inplane;
pub mod lateral;
pub mod limit;
pub mod shake;
pub mod solver;
pub mod study;
pub mod tilt;
pub mod verify;

/// The worker threads of a command that runs realizations in parallel.
#[derive(clap::Args)]
pub struct Workers {
    /// Worker threads: 0 or absent means all cores; more than the cores available is
    /// reduced to that number. The results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// The number of worker threads for `--threads`: absent or 0 means every core available
/// to the process; more than that is reduced to it (with a warning), since a simulation
/// is single-threaded and extra threads would only share the cores and add memory. The
/// results never depend on it.
fn thread_count(threads: Option<usize>) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    match threads {
        None | Some(0) => cores,
        Some(n) if n > cores => {
            eprintln!("warning: --threads {n} is more than the {cores} core(s) available; using {cores}");
            cores
        }
        Some(n) => n,
    }
}

/// A rayon pool of [`thread_count`] workers.
fn pool(threads: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    Ok(rayon::ThreadPoolBuilder::new().num_threads(thread_count(threads)).build()?)
}

/// Checks before a run that an output file can be written where it is asked: its folder
/// exists (a run is not spent on an output it cannot write).
///
/// # Errors
/// Naming the file and its folder.
pub fn check_writable(path: &std::path::Path) -> anyhow::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => std::path::Path::new("."),
    };
    if !dir.is_dir() {
        anyhow::bail!("cannot write {}: its folder {} does not exist", path.display(), dir.display());
    }
    if path.is_dir() {
        anyhow::bail!("cannot write {}: it is a folder", path.display());
    }
    Ok(())
}

/// Reads and checks a layout file; an error of its contents names the file (read and parse
/// errors name it already).
pub fn read_layout(path: &std::path::Path) -> anyhow::Result<drystone::layout::Layout> {
    use drystone::layout::{Layout, LayoutError};
    Layout::from_file(path).map_err(|e| match e {
        LayoutError::Io { .. } | LayoutError::Parse { .. } => anyhow::Error::from(e),
        other => anyhow::Error::from(other).context(format!("layout file {}", path.display())),
    })
}
