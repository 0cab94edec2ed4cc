//! Crushing of a joint's faces: the pressure is capped at the compressive strength `fc` of
//! the stone's edges, `q = min(Kn u, fc)`: the linear joint up to `u = fc / Kn`, then a
//! plastic plateau (elastic–perfectly plastic in compression; the no-tension interface of
//! the micro-models of dry-joint masonry with a compression cap, Lourenço & Rots 1997,
//! J. Eng. Mech. 123:660, and the toe crushing that rocking walls show in tests,
//! Vasconcelos & Lourenço 2009, J. Struct. Eng. 135:1269). The cap holds no memory: a
//! face unloaded from the plateau recovers elastically (a monotonic load path, as the
//! in-plane test's pushes, follows the plastic law exactly).
//!
//! A rocking wall's toe then bears the vertical force `N` on a stress block of width
//! `a = N / (fc t)`, so its rocking capacity drops from `N L / (2 H0)` to
//! `N (L − a) / (2 H0)`.

use super::{ClosureLaw, ClosureRangeError};
use serde::{Deserialize, Serialize};

/// Range of the compressive strength of a crushing law, Pa: from a soft limestone's edge to
/// the strongest granites.
pub const STRENGTH_RANGE_PA: (f64, f64) = (1e5, 5e8);

/// The crushing law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Crushing {
    /// Compressive strength of the faces `fc`, Pa (in [`STRENGTH_RANGE_PA`]).
    pub strength_pa: f64,
}

impl ClosureLaw for Crushing {
    const NAME: &'static str = "crushing";

    #[inline(always)]
    fn pressure(&self, kn: f64, u: f64) -> f64 {
        (kn * u).min(self.strength_pa)
    }

    fn tangent(&self, kn: f64, u: f64) -> f64 {
        if kn * u < self.strength_pa {
            kn
        } else {
            0.0
        }
    }

    fn stiffness_bound(&self, kn: f64) -> f64 {
        kn
    }

    fn energy_density(&self, kn: f64, u: f64) -> f64 {
        let uc = self.strength_pa / kn;
        if u <= uc {
            0.5 * kn * u * u
        } else {
            0.5 * self.strength_pa * uc + self.strength_pa * (u - uc)
        }
    }

    fn kink(&self, kn: f64) -> f64 {
        self.strength_pa / kn
    }

    fn check(&self, key: &str) -> Result<(), ClosureRangeError> {
        let (lo, hi) = STRENGTH_RANGE_PA;
        if self.strength_pa.is_finite() && (lo..=hi).contains(&self.strength_pa) {
            Ok(())
        } else {
            Err(ClosureRangeError {
                key: format!("{key}.{}.strength_pa", Self::NAME),
                value: self.strength_pa,
                range: STRENGTH_RANGE_PA,
            })
        }
    }

    /// The linear joint's closure under self-weight (a wall's own weight does not crush it;
    /// the settle check allows the plateau's closure beside it).
    fn closure_under(&self, elastic: f64) -> f64 {
        elastic
    }

    /// The weaker face.
    fn combine(&self, other: &Self) -> Self {
        Crushing { strength_pa: self.strength_pa.min(other.strength_pa) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pressure is the linear joint's up to fc / Kn and fc beyond; the energy is its
    /// integral (checked by the trapezoidal rule across the kink).
    #[test]
    fn the_plateau_caps_the_linear_joint_at_the_strength() {
        let c = Crushing { strength_pa: 5e6 };
        let kn = 2e10;
        assert_eq!(c.pressure(kn, 1e-4), 2e6);
        assert_eq!(c.pressure(kn, 1e-3), 5e6);
        assert_eq!(c.kink(kn), 2.5e-4);
        assert_eq!(c.tangent(kn, 1e-3), 0.0);
        let u = 6e-4;
        let n = 60_000;
        let h = u / n as f64;
        let trapezoid: f64 =
            (0..n).map(|i| 0.5 * h * (c.pressure(kn, i as f64 * h) + c.pressure(kn, (i + 1) as f64 * h))).sum();
        assert!((trapezoid - c.energy_density(kn, u)).abs() < 1e-6 * trapezoid);
        assert!(Crushing { strength_pa: 0.0 }.check("x").is_err());
    }
}
