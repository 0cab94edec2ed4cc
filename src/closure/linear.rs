//! The linear (Winkler) joint: `q = Kn u` (3DEC's linear joint, Itasca 3DEC manual; the
//! source paper's Eq. 2, Santa-Cruz et al. 2021).

use super::{ClosureLaw, ClosureRangeError};

/// The linear law; no parameter (`Kn` is the joint's).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Linear;

impl ClosureLaw for Linear {
    const NAME: &'static str = "linear";

    #[inline(always)]
    fn pressure(&self, kn: f64, u: f64) -> f64 {
        kn * u
    }

    fn tangent(&self, kn: f64, _u: f64) -> f64 {
        kn
    }

    fn stiffness_bound(&self, kn: f64) -> f64 {
        kn
    }

    fn energy_density(&self, kn: f64, u: f64) -> f64 {
        0.5 * kn * u * u
    }

    fn kink(&self, _kn: f64) -> f64 {
        f64::INFINITY
    }

    fn check(&self, _key: &str) -> Result<(), ClosureRangeError> {
        Ok(())
    }

    fn closure_under(&self, elastic: f64) -> f64 {
        elastic
    }

    fn combine(&self, _other: &Self) -> Self {
        Linear
    }
}
