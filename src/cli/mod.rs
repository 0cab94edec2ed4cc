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
pub mod discrepancy;
pub mod generate;
pub mod lateral;
pub mod study;
pub mod tilt;
pub mod verify;

/// A rayon pool of `threads` workers (all cores when `None`).
fn pool(threads: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    Ok(rayon::ThreadPoolBuilder::new().num_threads(threads.unwrap_or(0)).build()?)
}
