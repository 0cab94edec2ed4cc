//! Seating of an uneven bed: initial gaps spread uniformly over `[0, g₀]` (the seating of
//! hand-placed stones; the homogenised form of a uniform asperity-height distribution,
//! Greenwood & Williamson 1966). The share of the area in contact at closure `u` is
//! `min(u/g₀, 1)`, so `q = Kn u² / (2 g₀)` while the gaps close and `q = Kn (u − g₀/2)` once
//! all are closed: soft at first, the linear joint after seating.

use super::{check_length, ClosureLaw, ClosureRangeError};
use serde::{Deserialize, Serialize};

/// The seating law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Seating {
    /// Largest initial gap g₀, m (> 0, in [`super::CLOSURE_RANGE_M`]).
    pub max_gap_m: f64,
}

impl ClosureLaw for Seating {
    const NAME: &'static str = "seating";

    #[inline(always)]
    fn pressure(&self, kn: f64, u: f64) -> f64 {
        let g = self.max_gap_m;
        if u <= 0.0 {
            kn * u
        } else if u <= g {
            kn * u * u / (2.0 * g)
        } else {
            kn * (u - 0.5 * g)
        }
    }

    fn tangent(&self, kn: f64, u: f64) -> f64 {
        kn * (u / self.max_gap_m).min(1.0)
    }

    fn stiffness_bound(&self, kn: f64) -> f64 {
        kn
    }

    fn energy_density(&self, kn: f64, u: f64) -> f64 {
        let g = self.max_gap_m;
        if u <= g {
            kn * u * u * u / (6.0 * g)
        } else {
            kn * (g * g / 6.0 + 0.5 * (u * u - g * g) - 0.5 * g * (u - g))
        }
    }

    fn kink(&self, _kn: f64) -> f64 {
        self.max_gap_m
    }

    fn check(&self, key: &str) -> Result<(), ClosureRangeError> {
        check_length(format!("{key}.{}.max_gap_m", Self::NAME), self.max_gap_m)
    }

    /// The largest gap closes, then the linear joint.
    fn closure_under(&self, elastic: f64) -> f64 {
        self.max_gap_m + elastic
    }

    /// The first material's gaps (the joint's law is the first material's, as for
    /// different laws).
    fn combine(&self, _other: &Self) -> Self {
        *self
    }
}
