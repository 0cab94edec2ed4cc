//! Sizes: what a study asks for (work items, blocks per layout, memory), estimated from the
//! study and wall files before anything is allocated, and the limits beyond which a study
//! is refused.
//!
//! | quantity | limit | why |
//! | --- | --- | --- |
//! | sweep points (product of the `[sweep]` value counts) | [`MAX_SWEEP_POINTS`] | each point is a wall resolved, a row of `summary.csv` and a panel of the report |
//! | work items (Σ over groups of realizations × sweep points) | [`MAX_ITEMS`] | each finished item is a row held in memory until the tables are written |
//! | blocks of one layout (estimated from the wall description) | [`MAX_BLOCKS`] | each block of a running simulation takes memory on its thread |
//!
//! Memory is estimated as [`BYTES_PER_ROW`] per work item plus, on each thread,
//! [`BYTES_PER_BLOCK`] per block of the largest layout. `drystone run` also refuses a study
//! whose estimate exceeds the memory of the machine.

use crate::generator::{Arrangement, Wall};
use std::collections::BTreeMap;

/// Most sweep points a study may have.
pub const MAX_SWEEP_POINTS: u64 = 10_000;
/// Most work items a study may have.
pub const MAX_ITEMS: u64 = 1_000_000;
/// Most blocks the layout of a wall may have (estimated by [`estimated_blocks`]).
pub const MAX_BLOCKS: f64 = 100_000.0;
/// Memory of one result row (the row, its per-increment series, its share of the tables),
/// bytes.
pub const BYTES_PER_ROW: f64 = 4096.0;
/// Memory of one block in a running simulation (its layout, body, contacts and their
/// history), bytes: about twice what the tilting table of the SBL wall uses.
pub const BYTES_PER_BLOCK: f64 = 32_768.0;

/// The number of blocks a layout of `wall` has at most, roughly (an upper estimate, not a
/// count): courses `round(H / h̄) + 1` (h̄ the mean course height) times stones per course
/// `ceil(L / l̄) + 2` (l̄ the mean block length), and for an irregular wall up to two
/// wedge gaps per stone, each cut into `ceil(l_max / w̄)` wedges (w̄ the mean wedge length,
/// at least the shortest wedge kept; one wedge per gap without a wedge length law).
/// A double-faced section (`[section] leaves = 2`) cuts each of them into two leaves and,
/// with a hearting, `ceil(l_max / hearting_stone_m)` hearting pieces (one without
/// `hearting_stone_m`). Infinite when a mean is not a positive number.
pub fn estimated_blocks(wall: &Wall) -> f64 {
    let per = |total: f64, mean: f64| if mean > 0.0 && mean.is_finite() { total / mean } else { f64::INFINITY };
    let lbar = wall.block_length.mean();
    let courses = per(wall.height, wall.course_height.mean()).round().max(1.0) + 1.0;
    let stones = courses * (per(wall.length, lbar).ceil() + 2.0);
    let cuts = match &wall.section {
        crate::generator::Section::Single => 1.0,
        crate::generator::Section::Double { leaf_width: None, .. } => 2.0,
        crate::generator::Section::Double { leaf_width: Some(_), hearting_stone, .. } => {
            2.0 + hearting_stone.map_or(1.0, |h| per(wall.block_length.practical_max(), h).ceil().max(1.0))
        }
    };
    cuts * match &wall.arrangement {
        Arrangement::Irregular(ir) => {
            let shortest = ir.min_wedge_length.max(1e-6 * lbar);
            let per_gap = ir
                .wedge_length
                .as_ref()
                .map_or(1.0, |d| per(wall.block_length.practical_max(), d.mean().max(shortest)).ceil().max(1.0));
            stones * (1.0 + 2.0 * per_gap)
        }
        _ => stones,
    }
}

/// The number of points of a `[sweep]` table (the product of its value counts; 1 without
/// a sweep), computed without building the grid.
pub fn sweep_points(sweep: &BTreeMap<String, Vec<toml::Value>>) -> f64 {
    sweep.values().map(|v| v.len() as f64).product()
}

/// A memory size in the binary unit that suits it, e.g. `3.1 GiB`.
pub fn human_bytes(bytes: f64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut v = bytes;
    let mut i = 0;
    while v >= 1024.0 && i + 1 < units.len() {
        v /= 1024.0;
        i += 1;
    }
    if v >= 1024.0 {
        format!("{bytes:.1e} B")
    } else {
        format!("{v:.1} {}", units[i])
    }
}

/// A count for a message: the integer when it is one of reasonable size, else `1.2e9`.
pub fn count(v: f64) -> String {
    if v.is_finite() && v < 1e15 && v.fract() == 0.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.2e}")
    }
}

/// The memory of this machine, bytes (`MemTotal` of `/proc/meminfo`); `None` where that
/// cannot be read.
pub fn machine_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// A value for a message: as written for ordinary magnitudes, in scientific notation
/// beyond (`1e300`, `1e-9`).
pub fn compact(v: f64) -> String {
    if v == 0.0 || (1e-4..1e7).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Processor time of one tilting-table simulation per block of its layout as
/// [`estimated_blocks`] counts them, seconds: 0.001–0.002 s measured with `drystone
/// synthesize` on `studies/tilting_table.toml` and `tests/discrepancy/study.toml` (x86-64,
/// one core per simulation), doubled; a planning figure, not a bound.
pub const SECONDS_PER_BLOCK: f64 = 0.004;

/// The estimated processor time of `simulations` tilting-table runs of layouts of about
/// `blocks` blocks each (estimated by [`estimated_blocks`]), seconds.
pub fn simulation_seconds(simulations: f64, blocks: f64) -> f64 {
    simulations * blocks * SECONDS_PER_BLOCK
}

/// A duration for a message: `40 s`, `12 min`, `3.5 h`, `2.1 days`.
pub fn human_seconds(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 172_800.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.1e} days", s / 86_400.0)
    }
}

/// What a study asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SizeEstimate {
    /// Work items.
    pub items: f64,
    /// Blocks of the largest layout (estimated).
    pub largest_layout_blocks: f64,
}

impl SizeEstimate {
    /// Memory of a run on `threads` threads, bytes: the rows of every item and one
    /// simulation of the largest layout per thread.
    pub fn memory_bytes(&self, threads: usize) -> f64 {
        self.items * BYTES_PER_ROW + threads as f64 * self.largest_layout_blocks * BYTES_PER_BLOCK
    }
}

/// Checks the number of work items of groups with `realizations` each (per sweep point)
/// over `points` sweep points. `key` names where the count came from.
///
/// # Errors
/// [`SizeError::Items`] with the estimate and the limit.
pub fn check_items(realizations: &[u64], points: f64) -> Result<(), SizeError> {
    let total: f64 = realizations.iter().map(|&r| r as f64).sum::<f64>() * points;
    if total <= MAX_ITEMS as f64 {
        return Ok(());
    }
    let how = if realizations.windows(2).all(|w| w[0] == w[1]) {
        format!("{} realizations × {} group(s) × {} sweep point(s)", realizations[0], realizations.len(), count(points))
    } else {
        let sum: u64 = realizations.iter().fold(0u64, |a, &r| a.saturating_add(r));
        format!("{sum} realizations over the groups × {} sweep point(s)", count(points))
    };
    Err(SizeError::Items { how, items: total })
}

/// Checks the estimated blocks of one wall's layout.
///
/// # Errors
/// [`SizeError::Blocks`] with the estimate, the wall values it comes from, and the limit.
pub fn check_blocks(wall: &Wall) -> Result<(), SizeError> {
    let blocks = estimated_blocks(wall);
    if blocks <= MAX_BLOCKS {
        return Ok(());
    }
    Err(SizeError::Blocks {
        blocks,
        length_m: wall.length,
        height_m: wall.height,
        course_height_m: wall.course_height.mean(),
        block_length_m: wall.block_length.mean(),
    })
}

/// A study or wall over drystone's size limits (`MAX_ITEMS`, [`MAX_BLOCKS`]), refused
/// before any memory is taken.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SizeError {
    /// More work items than `MAX_ITEMS`.
    #[error(
        "{how} = {} work items (about {} of result rows in memory); the limit is {MAX_ITEMS} work items per study",
        count(*items),
        human_bytes(*items * BYTES_PER_ROW)
    )]
    Items {
        /// How the count arises (realizations × groups × sweep points).
        how: String,
        /// The number of work items.
        items: f64,
    },
    /// A layout of more blocks than [`MAX_BLOCKS`].
    #[error(
        "the layout would have about {} blocks (geometry.length_m = {}, geometry.height_m = {}, mean courses.height_m = {}, mean blocks.length_m = {}), about {} per simulation; the limit is {} blocks per layout",
        count(blocks.ceil()),
        compact(*length_m),
        compact(*height_m),
        compact(*course_height_m),
        compact(*block_length_m),
        human_bytes(*blocks * BYTES_PER_BLOCK),
        MAX_BLOCKS
    )]
    Blocks {
        /// The estimated number of blocks.
        blocks: f64,
        /// `geometry.length_m`, m.
        length_m: f64,
        /// `geometry.height_m`, m.
        height_m: f64,
        /// The mean of `courses.height_m`, m.
        course_height_m: f64,
        /// The mean of `blocks.length_m`, m.
        block_length_m: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall(length: f64, course: f64, kind: &str) -> Wall {
        crate::generator::test_wall(&format!(
            "version = 1\n[geometry]\nlength_m = {length:e}\nheight_m = 0.375\nbase_width_m = 0.15\ntop_width_m = 0.08\n\
             [arrangement]\nkind = \"{kind}\"\n[courses]\nheight_m = {course:e}\n\
             [blocks]\nlength_m = 0.1\n"
        ))
    }

    #[test]
    fn the_block_estimate_bounds_the_generated_count_and_refuses_huge_walls() {
        for kind in ["continuous", "discontinuous"] {
            let w = wall(1.5, 0.05, kind);
            let g = crate::generator::generate(&w, 1, 0).unwrap();
            let n = g.layout.blocks.len() as f64;
            let e = estimated_blocks(&w);
            assert!(e >= n && e <= 3.0 * n, "{kind}: estimate {e}, generated {n}");
            assert!(check_blocks(&w).is_ok());
        }
        let err = check_blocks(&wall(1e300, 0.05, "continuous")).unwrap_err().to_string();
        assert!(err.contains("geometry.length_m = 1e300") && err.contains("limit is 100000"), "{err}");
        assert!(check_blocks(&wall(10_000.0, 0.05, "continuous")).is_err());
        let err = check_blocks(&wall(1.5, 1e-6, "continuous")).unwrap_err().to_string();
        assert!(err.contains("courses.height_m = 1e-6"), "{err}");
    }

    #[test]
    fn item_counts_beyond_the_limit_are_refused_with_the_estimate() {
        assert!(check_items(&[12, 12, 12], 4.0).is_ok());
        let err = check_items(&[1_000_000_000; 3], 1.0).unwrap_err().to_string();
        assert!(
            err.starts_with("1000000000 realizations × 3 group(s) × 1 sweep point(s) = 3000000000 work items"),
            "{err}"
        );
        assert!(err.contains("TiB"), "{err}");
        let err = check_items(&[1, u64::MAX], 2.0).unwrap_err().to_string();
        assert!(err.contains("realizations over the groups"), "{err}");
        assert_eq!(human_bytes(3.0 * 1024.0 * 1024.0 * 1024.0), "3.0 GiB");
        assert_eq!(count(64_000.0), "64000");
    }
}
