//! The one entry point that generates a realization of a wall: a wall description's
//! courses ([`super::realization`]) or a surveyed wall's trace ([`super::traced`]).

use super::realization::GeneratedWall;
use super::wall::Wall;
use super::GeneratorError;

/// Generates realization `realization` of `wall` from the master seed `seed`.
///
/// ```
/// use drystone::generator::{generate, Wall};
/// use std::path::Path;
///
/// // The source paper's CBL wall: cobblestones 0.2 m long in running bond, 9 courses of
/// // 0.375 m / 9 on a trapezoidal section 1.5 m long.
/// let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
/// let wall = Wall::from_file(&dir.join("studies/walls/cbl.toml"))?;
/// let a = generate(&wall, 20210917, 3)?;
/// // Seeded: a realization is the same layout bit for bit, alone or in a batch.
/// let same = generate(&wall, 20210917, 3)?;
/// assert_eq!(serde_json::to_string(&a.layout)?, serde_json::to_string(&same.layout)?);
/// let layout = a.check()?; // checked as `drystone tilt` checks a layout file
/// let top = layout.blocks.iter().flat_map(|b| b.shape.vertices.iter().map(|v| v.z)).fold(0.0, f64::max);
/// assert!((top - 0.375).abs() < 1e-9, "{top}");
/// // Running bond with half overlap: 7 or 8 whole or cut stones per course.
/// let (stones, wedges) = a.counts();
/// assert!((9 * 7..=9 * 9).contains(&stones) && wedges == 0, "{stones} {wedges}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`GeneratorError::Infeasible`] if this realization cannot be built (far too steep dips
/// for the course heights, or head-joint gaps wider than the blocks); for a surveyed wall
/// ([`Wall::traced`]), the errors of [`super::traced::generate`].
pub fn generate(wall: &Wall, seed: u64, realization: u64) -> Result<GeneratedWall, GeneratorError> {
    match &wall.traced {
        Some(t) => super::traced::generate(wall, t, seed, realization).map(|(g, _)| g),
        None => super::realization::generate_described(wall, seed, realization),
    }
}

/// Generates realizations `range` of `wall` in parallel (rayon); element j is
/// `generate(wall, seed, range.start + j)`, identical to generating it alone.
pub fn generate_batch(
    wall: &Wall,
    seed: u64,
    range: std::ops::Range<u64>,
) -> Vec<Result<GeneratedWall, GeneratorError>> {
    use rayon::prelude::*;
    range.into_par_iter().map(|i| generate(wall, seed, i)).collect()
}
