//! The one place that seeds random number generators.
//!
//! Every random draw in drystone comes from [`rng_for`]: a `ChaCha8Rng` seeded with the
//! study's master seed and set to a stream derived from the realization index and a named
//! purpose. Realization `i` therefore draws the same numbers whether it runs alone, inside a
//! batch, on any thread or any machine (rand's `examples/rayon-monte-carlo.rs` pattern).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// What a random stream is used for. Each purpose gets its own stream, so adding draws for
/// one purpose never shifts the numbers of another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Purpose {
    /// Block layout geometry (course heights, block lengths, dips, wedges).
    Layout,
    /// Scatter of material or joint properties.
    Material,
    /// Bootstrap resampling in the statistics.
    Bootstrap,
    /// Model-discrepancy analysis (synthetic data, measurement noise, bootstrap of the
    /// held-out error, null replicates).
    Discrepancy,
    /// The random per-realization forms of the model-discrepancy effects.
    Effect,
    /// Stochastic ground motions (`ground::stochastic`), per motion index.
    GroundMotion,
    /// The Bayesian bootstrap of the model-discrepancy analysis's model weights.
    Weights,
    /// The design's re-estimate of the follow-up it chose: simulated follow-ups drawn
    /// on streams disjoint from the [`Purpose::Discrepancy`] streams that ranked the menu,
    /// so the probability reported is not the maximum of the ranking's estimates (the
    /// optimizer's curse, Smith & Winkler 2006, *Management Science* 52, 311–322).
    DesignReport,
    /// A surveyed wall's tracing tolerance drawn per realization (`generator::traced`).
    Survey,
    /// The seating of each block's bed drawn per realization (`[scatter]
    /// bed_seating_gap_m` of a wall description, `generator::realization`): a stream of
    /// its own, so that switching it on or off changes no other drawn number.
    Seating,
}

impl Purpose {
    fn code(self) -> u64 {
        match self {
            Purpose::Layout => 1,
            Purpose::Material => 2,
            Purpose::Bootstrap => 3,
            Purpose::Discrepancy => 4,
            Purpose::Effect => 5,
            Purpose::GroundMotion => 6,
            Purpose::Weights => 7,
            Purpose::DesignReport => 8,
            Purpose::Survey => 9,
            Purpose::Seating => 10,
        }
    }
}

/// The generator for `(master seed, realization, purpose)`.
///
/// The stream number is `realization × 16 + purpose code`, so up to 2⁶⁰ realizations have
/// disjoint streams for every purpose.
pub fn rng_for(master: u64, realization: u64, purpose: Purpose) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(master);
    rng.set_stream(realization.wrapping_mul(16).wrapping_add(purpose.code()));
    rng
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::RngExt;

    #[test]
    fn streams_are_distinct_and_repeatable() {
        let a: u64 = rng_for(7, 0, Purpose::Layout).random();
        let b: u64 = rng_for(7, 0, Purpose::Layout).random();
        let c: u64 = rng_for(7, 1, Purpose::Layout).random();
        let d: u64 = rng_for(7, 0, Purpose::Material).random();
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_ne!(a, d);
    }
}
