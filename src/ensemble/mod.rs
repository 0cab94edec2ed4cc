//! Ensembles: the work items of a study (group × sweep point × realization), run in
//! parallel with rayon, journaled as they finish ([`journal`]), sharded across machines,
//! merged back.
//!
//! # Determinism
//!
//! Every item is a pure function of the study and its index: its layout is drawn from
//! `rng_for(seed, realization, Purpose::Layout)` (the same realization index at every sweep
//! point and in every group: common random numbers), and its simulation is serial. Results
//! are put back in index order whatever order the items ran in, and every reduction over
//! them is serial and ordered. Hence: the same rows bit for bit on 1 or N threads,
//! realization i the same alone or inside the ensemble, and shards that merge into exactly
//! the unsharded run.

pub mod compression_columns;
pub mod exact;
pub mod inplane_columns;
pub mod journal;
pub mod row;

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::io::IsTerminal;
use thiserror::Error;

/// One unit of work.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Item {
    /// Global index in the study (group-major, then sweep point, then realization).
    pub index: usize,
    /// Group index.
    pub group: usize,
    /// Sweep point index.
    pub point: usize,
    /// Realization index (the RNG stream of the layout).
    pub realization: u64,
}

/// All items of a study, in index order, with `realizations[g]` realizations per sweep point
/// in group `g` (length: the number of groups).
pub fn items_per_group(realizations: &[u64], points: usize) -> Vec<Item> {
    let mut v = Vec::new();
    for (g, &n) in realizations.iter().enumerate() {
        for p in 0..points {
            for r in 0..n {
                v.push(Item { index: v.len(), group: g, point: p, realization: r });
            }
        }
    }
    v
}

/// A shard `k` of `n` (0-based `k < n`): the items whose index ≡ k (mod n). Round-robin
/// balances groups whose cost differs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This shard, 0-based.
    pub k: usize,
    /// Number of shards.
    pub n: usize,
}

/// A shard text that is not `K/N` with 1 ≤ K ≤ N.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("shard {text:?}: {reason}")]
pub struct ShardError {
    /// The text given.
    pub text: String,
    /// What is wrong.
    pub reason: &'static str,
}

impl Shard {
    /// The whole study.
    pub const ALL: Shard = Shard { k: 0, n: 1 };

    /// Parses `K/N` with 1 ≤ K ≤ N (1-based on the command line, as a Slurm array index
    /// plus one).
    ///
    /// # Errors
    /// [`ShardError`] naming the bad text.
    pub fn parse(text: &str) -> Result<Shard, ShardError> {
        let error = |reason: &'static str| ShardError { text: text.to_owned(), reason };
        let (k, n) = text.split_once('/').ok_or_else(|| error("expected K/N, e.g. 1/4"))?;
        let k: usize = k.trim().parse().map_err(|_| error("K is not a number"))?;
        let n: usize = n.trim().parse().map_err(|_| error("N is not a number"))?;
        if n == 0 || k == 0 || k > n {
            return Err(error("need 1 <= K <= N"));
        }
        Ok(Shard { k: k - 1, n })
    }

    /// Keeps this shard's items.
    pub fn select(&self, items: &[Item]) -> Vec<Item> {
        items.iter().filter(|it| it.index % self.n == self.k).copied().collect()
    }
}

/// Runs `f` on every work unit in parallel (rayon, on the current pool) and returns the
/// results in the order of `work`. Units are taken by decreasing `cost` (one estimate per
/// unit, any unit of measure; ties in order): each free worker takes the costliest unit
/// left (greedy longest-processing-time list scheduling), so a few expensive units do not
/// leave a thread idle at the end. Every unit being a pure function of itself, the results
/// do not depend on the costs or on the number of threads. Shows a progress bar on a
/// terminal (stderr); elsewhere (a batch log) a line `LABEL: K/N done, T elapsed` at most
/// every [`PROGRESS_LINE_INTERVAL_S`] seconds, and a last line if any was printed, so that
/// a short run stays silent and a long one shows it advances.
///
/// # Panics
/// If `cost` does not have one entry per unit.
pub fn run_scheduled<T: Sync, R: Send, F: Fn(&T) -> R + Sync + Send>(
    work: &[T],
    cost: &[f64],
    label: &str,
    f: F,
) -> Vec<R> {
    assert_eq!(work.len(), cost.len(), "one cost per work unit");
    let mut order: Vec<usize> = (0..work.len()).collect();
    order.sort_by(|&a, &b| cost[b].total_cmp(&cost[a]).then(a.cmp(&b)));
    let terminal = std::io::stderr().is_terminal();
    let lines = (!terminal).then(|| Lines::new(label, work.len()));
    let bar = if terminal {
        let b = ProgressBar::new(work.len() as u64);
        b.set_style(
            ProgressStyle::with_template("{msg} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta})")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b.set_message(label.to_string());
        Some(b)
    } else {
        None
    };
    // par_bridge pulls from the sequential iterator as workers become free: a shared queue
    // in cost order.
    let mut done: Vec<(usize, R)> = order
        .into_iter()
        .par_bridge()
        .map(|k| {
            let r = f(&work[k]);
            if let Some(b) = &bar {
                b.inc(1);
            }
            if let Some(l) = &lines {
                l.one_done();
            }
            (k, r)
        })
        .collect();
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if let Some(l) = lines {
        l.finish();
    }
    done.sort_by_key(|(k, _)| *k);
    done.into_iter().map(|(_, r)| r).collect()
}

/// Least interval between two progress lines of [`run_scheduled`] off a terminal, s.
pub const PROGRESS_LINE_INTERVAL_S: f64 = 20.0;

/// The progress lines of [`run_scheduled`] when stderr is not a terminal.
struct Lines {
    label: String,
    total: usize,
    start: std::time::Instant,
    /// Units done, time of the last line (`None`: no line yet).
    state: std::sync::Mutex<(usize, Option<std::time::Instant>)>,
}

impl Lines {
    fn new(label: &str, total: usize) -> Lines {
        Lines {
            label: label.to_owned(),
            total,
            start: std::time::Instant::now(),
            state: std::sync::Mutex::new((0, None)),
        }
    }

    fn line(&self, done: usize) {
        let elapsed = self.start.elapsed().as_secs_f64();
        eprintln!("{}: {done}/{} done, {elapsed:.0} s elapsed", self.label, self.total);
    }

    fn one_done(&self) {
        let Ok(mut st) = self.state.lock() else { return };
        st.0 += 1;
        let since = st.1.unwrap_or(self.start).elapsed().as_secs_f64();
        if since >= PROGRESS_LINE_INTERVAL_S && st.0 < self.total {
            self.line(st.0);
            st.1 = Some(std::time::Instant::now());
        }
    }

    fn finish(self) {
        let Ok(st) = self.state.lock() else { return };
        if st.1.is_some() {
            self.line(st.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn items(groups: usize, points: usize, realizations: u64) -> Vec<Item> {
        items_per_group(&vec![realizations; groups], points)
    }

    #[test]
    fn scheduled_run_returns_results_in_item_order() {
        let all = items(2, 3, 4);
        let cost: Vec<f64> = all.iter().map(|it| ((it.index * 7) % 5) as f64).collect();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let out = pool.install(|| run_scheduled(&all, &cost, "t", |it| it.index * 10 + it.group));
        let expect: Vec<usize> = all.iter().map(|it| it.index * 10 + it.group).collect();
        assert_eq!(out, expect);
    }

    #[test]
    fn shards_partition_the_items() {
        let all = items(3, 2, 5);
        assert_eq!(all.len(), 30);
        let mut seen: Vec<usize> = Vec::new();
        for k in 1..=4 {
            let s = Shard::parse(&format!("{k}/4")).unwrap();
            seen.extend(s.select(&all).iter().map(|i| i.index));
        }
        seen.sort();
        assert_eq!(seen, (0..30).collect::<Vec<_>>());
        assert!(Shard::parse("0/4").is_err());
        assert!(Shard::parse("5/4").is_err());
        assert!(Shard::parse("x").is_err());
    }

    #[test]
    fn results_come_back_in_item_order_on_any_pool() {
        let all = items(2, 3, 7);
        for threads in [1, 2, 4] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let out = pool.install(|| run_scheduled(&all, &vec![0.0; all.len()], "t", |it| it.index * 10 + it.group));
            assert_eq!(out, all.iter().map(|it| it.index * 10 + it.group).collect::<Vec<_>>());
        }
    }
}
