//! The hyperbolic closure of rough rock joints (Bandis, Lumsden & Barton 1983, Int. J. Rock
//! Mech. Min. Sci. 20:249, Eq. 4; Goodman 1976): `q = Kni u / (1 − u / Vm)`, soft (`Kni`)
//! at low stress and stiffening without bound as the closure approaches the maximum
//! closure `Vm`. Past `u = 0.8 Vm` ([`HYPERBOLIC_CAP`]) the law continues along its tangent
//! (stiffness `25 Kni`), which bounds the tangent stiffness and so the critical time step.

use super::{check_length, ClosureLaw, ClosureRangeError};
use serde::{Deserialize, Serialize};

/// The closure ratio `u / Vm` past which the hyperbolic law continues along its tangent.
pub const HYPERBOLIC_CAP: f64 = 0.8;

/// The hyperbolic law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hyperbolic {
    /// Maximum closure Vm, m (> 0, in [`super::CLOSURE_RANGE_M`]).
    pub max_closure_m: f64,
}

impl ClosureLaw for Hyperbolic {
    const NAME: &'static str = "hyperbolic";

    #[inline(always)]
    fn pressure(&self, kni: f64, u: f64) -> f64 {
        let vm = self.max_closure_m;
        if u <= 0.0 {
            return kni * u;
        }
        let uc = HYPERBOLIC_CAP * vm;
        if u <= uc {
            kni * u / (1.0 - u / vm)
        } else {
            let qc = kni * uc / (1.0 - HYPERBOLIC_CAP);
            let kc = kni / ((1.0 - HYPERBOLIC_CAP) * (1.0 - HYPERBOLIC_CAP));
            qc + kc * (u - uc)
        }
    }

    fn tangent(&self, kni: f64, u: f64) -> f64 {
        let r = (u / self.max_closure_m).min(HYPERBOLIC_CAP);
        kni / ((1.0 - r) * (1.0 - r))
    }

    fn stiffness_bound(&self, kni: f64) -> f64 {
        kni / ((1.0 - HYPERBOLIC_CAP) * (1.0 - HYPERBOLIC_CAP))
    }

    fn energy_density(&self, kni: f64, u: f64) -> f64 {
        let vm = self.max_closure_m;
        let uc = HYPERBOLIC_CAP * vm;
        let w = |s: f64| kni * vm * (-s - vm * (1.0 - s / vm).ln());
        if u <= uc {
            w(u)
        } else {
            let (qc, kc) = (self.pressure(kni, uc), self.stiffness_bound(kni));
            w(uc) + qc * (u - uc) + 0.5 * kc * (u - uc) * (u - uc)
        }
    }

    fn kink(&self, _kn: f64) -> f64 {
        HYPERBOLIC_CAP * self.max_closure_m
    }

    fn check(&self, key: &str) -> Result<(), ClosureRangeError> {
        check_length(format!("{key}.{}.max_closure_m", Self::NAME), self.max_closure_m)
    }

    /// At most the maximum closure, whatever the load.
    fn closure_under(&self, _elastic: f64) -> f64 {
        self.max_closure_m
    }

    /// The mean maximum closure.
    fn combine(&self, other: &Self) -> Self {
        Hyperbolic { max_closure_m: 0.5 * (self.max_closure_m + other.max_closure_m) }
    }
}
