//! The size of a resolved study ([`Study::size`]) and its check against the limits of
//! [`super::size`].

use super::size::{check_items, estimated_blocks, SizeError, SizeEstimate};
use super::Study;

impl Study {
    /// The size of the study as it stands (after any `--realizations`).
    pub fn size(&self) -> SizeEstimate {
        let blocks = self.groups.iter().flat_map(|g| g.walls.iter()).map(estimated_blocks).fold(0.0, f64::max);
        let counts: Vec<u64> = (0..self.groups.len()).map(|g| self.group_realizations(g)).collect();
        let items = counts.iter().map(|&r| r as f64).sum::<f64>() * self.points.len() as f64;
        SizeEstimate { items, largest_layout_blocks: blocks }
    }

    /// Checks the number of work items against `MAX_ITEMS` (after the realizations were
    /// changed, e.g. by `--realizations`).
    ///
    /// # Errors
    /// [`SizeError::Items`] with the estimate and the limit.
    pub fn check_items(&self) -> Result<(), SizeError> {
        let counts: Vec<u64> = (0..self.groups.len()).map(|g| self.group_realizations(g)).collect();
        check_items(&counts, self.points.len() as f64)
    }
}
