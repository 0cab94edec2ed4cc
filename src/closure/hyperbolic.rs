//! The hyperbolic closure of rough rock joints (Bandis, Lumsden & Barton 1983, Int. J. Rock
//! Mech. Min. Sci. 20:249, Eq. 4; Goodman 1976): `q = Kni u / (1 − u / Vm)`, soft (`Kni`)
//! at low stress and stiffening without bound as the closure approaches the maximum
//! closure `Vm`. Past `u = 0.8 Vm` ([`HYPERBOLIC_CAP`]) the law continues along its tangent
//! (stiffness `25 Kni`), which bounds the tangent stiffness and so the critical time step.
//!
//! The tangent `Kni / (1 − u/Vm)²` is 25 times its initial value only at the cap; a joint
//! under the stresses of a wall works far below it (0.2 Vm under 0.5 MPa for the granite
//! walls' sawn beds, a tangent of 1.6 Kni). [`ClosureLaw::tangent_window`] gives the time
//! step a window in which the tangent at most doubles ([`WINDOW_TANGENT_RATIO`]), so that
//! the step follows the tangent and not the cap.

use super::{check_length, ClosureLaw, ClosureRangeError};
use serde::{Deserialize, Serialize};

/// The closure ratio `u / Vm` past which the hyperbolic law continues along its tangent.
pub const HYPERBOLIC_CAP: f64 = 0.8;

/// How much the tangent may grow within a [`ClosureLaw::tangent_window`] of the
/// hyperbolic law: the window from a closure `u` ends where `Kni / (1 − u/Vm)²` is this
/// many times its value at `u` (at `max(u, 0)`: an open or tensile node starts from `Kni`).
pub const WINDOW_TANGENT_RATIO: f64 = 2.0;

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

    /// From `r = max(u, 0)/Vm`, the window ends at `r_hi = 1 − (1 − r)/√2`, where the
    /// tangent has doubled; once `r_hi` reaches the cap the window is the whole law and
    /// its bound `25 Kni`.
    fn tangent_window(&self, kni: f64, u: f64) -> Option<(f64, f64)> {
        let vm = self.max_closure_m;
        let r = (u.max(0.0) / vm).min(HYPERBOLIC_CAP);
        let r_hi = 1.0 - (1.0 - r) / WINDOW_TANGENT_RATIO.sqrt();
        if r_hi >= HYPERBOLIC_CAP {
            return Some((f64::INFINITY, self.stiffness_bound(kni)));
        }
        Some((r_hi * vm, kni / ((1.0 - r_hi) * (1.0 - r_hi))))
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
