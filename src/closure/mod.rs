//! Normal closure laws of joints: the normal pressure `q(u)` (Pa, compression positive) of
//! a joint as a function of its closure `u` (m, positive when the two faces overlap,
//! `u = −gap`), for a joint of normal stiffness `Kn` (the initial stiffness `Kni` of a
//! nonlinear law), Pa/m.
//!
//! One law per file, each a [`ClosureLaw`]: [`Linear`] (the Winkler joint of 3DEC and of the
//! source paper), [`Hyperbolic`] (Bandis, Lumsden & Barton 1983) and [`Seating`] (uneven
//! beds) and [`Crushing`] (faces crushing at their strength). [`Closure`] is the choice a
//! layout file makes — `"linear"` (default), `{"hyperbolic": {"max_closure_m": V}}`,
//! `{"seating": {"max_gap_m": G}}`, `{"crushing": {"strength_pa": F}}` — read into it
//! directly, and what the DEM's normal kernel (`dem::contact::law::normal`) integrates over
//! a sub-contact.
//!
//! # Adding a law
//!
//! 1. A file in this folder with the law's struct (its parameters, with their units in
//!    their serde keys) and its [`ClosureLaw`] implementation, with the law's source.
//! 2. A variant of [`Closure`] and its arm in the `each_law!` dispatch beside it (and, for
//!    a law of one length parameter, in [`Closure::with_length`], which the discrepancy
//!    effects' `closure` steps name it by).
//! 3. Its line in `dem::contact::law::contract::representative_laws`, which runs the
//!    joint-law contract over it (the list fails to compile until the variant is in it).
//!
//! A law that is linear in tension (`q = Kn u` for `u < 0`, used while a joint carries
//! tension) is the rule: every law here is.

mod crushing;
mod hyperbolic;
mod linear;
mod seating;

pub use crushing::{Crushing, STRENGTH_RANGE_PA};
pub use hyperbolic::{Hyperbolic, HYPERBOLIC_CAP, WINDOW_TANGENT_RATIO};
pub use linear::Linear;
pub use seating::Seating;

use serde::{Deserialize, Serialize};

/// Range of a closure law's length parameter (a hyperbolic law's maximum closure Vm, a
/// seating law's largest initial gap), m: from a polished joint to the roughest rubble beds.
pub const CLOSURE_RANGE_M: (f64, f64) = (1e-6, 0.05);

/// A parameter of a closure law out of its range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{key} = {value:e} must be in [{:e}, {:e}]", range.0, range.1)]
pub struct ClosureRangeError {
    /// The key, `{prefix}.{law}.{parameter}`.
    pub key: String,
    /// The value given.
    pub value: f64,
    /// The range allowed.
    pub range: (f64, f64),
}

/// A normal closure law: its pressure, tangent and energy as functions of the closure, and
/// what the rest of drystone needs to know of it.
pub trait ClosureLaw {
    /// The law's name in files (`"hyperbolic"`).
    const NAME: &'static str;

    /// Pressure at closure `u` (m), Pa, compression positive; `u ≤ 0` gives the tensile
    /// branch `kn u`.
    fn pressure(&self, kn: f64, u: f64) -> f64;

    /// Tangent stiffness `dq/du` at closure `u > 0` (m), Pa/m (the consistent tangent of the
    /// implicit increments).
    fn tangent(&self, kn: f64, u: f64) -> f64;

    /// Largest tangent stiffness the law reaches, Pa/m: the stiffness the critical time step
    /// must be taken from.
    fn stiffness_bound(&self, kn: f64) -> f64;

    /// A window of the closure over which the tangent stays bounded below the law's
    /// [`ClosureLaw::stiffness_bound`], for a sub-contact whose largest nodal closure is
    /// `u` (m): `Some((cap, k))` where every closure up to `cap` (m, `> u`; infinite once
    /// the window reaches the law's own bound) has a tangent of at most `k` (Pa/m). The
    /// time step is then taken from `k` until a node passes `cap`, which the contact pass
    /// watches. `None` (the default): the law's tangent is bounded by a constant of the
    /// order of `kn` and the step takes the bound itself.
    fn tangent_window(&self, _kn: f64, _u: f64) -> Option<(f64, f64)> {
        None
    }

    /// Strain energy per unit area at closure `u > 0`, `∫₀ᵘ q ds`, J/m².
    fn energy_density(&self, kn: f64, u: f64) -> f64;

    /// The closure (m) where the pressure has a kink for a joint of stiffness `kn` (Pa/m;
    /// `f64::INFINITY`: none); the quadrature over a sub-contact splits there.
    fn kink(&self, kn: f64) -> f64;

    /// Checks the law's parameters; `key` names the `closure` key they sit under.
    ///
    /// # Errors
    /// [`ClosureRangeError`] naming `{key}.{NAME}.{parameter}`.
    fn check(&self, key: &str) -> Result<(), ClosureRangeError>;

    /// The largest closure (m) the law can show under the self-weight of a wall whose
    /// linear joint of the same `kn` closes by `elastic` (m): the settle check's allowance.
    fn closure_under(&self, elastic: f64) -> f64;

    /// The law of a joint between two materials that both have this law.
    fn combine(&self, other: &Self) -> Self;
}

/// Checks `value` against [`CLOSURE_RANGE_M`] under `key`.
pub(crate) fn check_length(key: String, value: f64) -> Result<(), ClosureRangeError> {
    let (lo, hi) = CLOSURE_RANGE_M;
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(ClosureRangeError { key, value, range: CLOSURE_RANGE_M })
    }
}

/// The normal closure law of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[non_exhaustive]
pub enum Closure {
    /// [`Linear`]: `q = Kn u`.
    #[default]
    Linear,
    /// [`Hyperbolic`]: `q = Kni u / (1 − u / Vm)`.
    Hyperbolic(Hyperbolic),
    /// [`Seating`]: initial gaps uniform in `[0, g₀]` that close under load.
    Seating(Seating),
    /// [`Crushing`]: `q = min(Kn u, fc)`, the faces crushing at their strength.
    Crushing(Crushing),
}

/// `$body` with `$l` bound to the law of `$c` (one arm per variant of [`Closure`]).
macro_rules! each_law {
    ($c:expr, $l:ident => $body:expr) => {
        match $c {
            Closure::Linear => {
                let $l = &Linear;
                $body
            }
            Closure::Hyperbolic($l) => $body,
            Closure::Seating($l) => $body,
            Closure::Crushing($l) => $body,
        }
    };
}

impl Closure {
    /// The law named `name` in files whose one length parameter (m; a hyperbolic law's
    /// maximum closure Vm, a seating law's largest initial gap g₀) is `v`; `None` for a
    /// name that is not such a law. What an effect's `closure` step sets.
    pub fn with_length(name: &str, v: f64) -> Option<Closure> {
        Closure::length_laws(v).into_iter().find(|c| c.name() == name)
    }

    /// The names of the laws [`Closure::with_length`] knows.
    pub fn length_law_names() -> Vec<&'static str> {
        Closure::length_laws(0.0).iter().map(Closure::name).collect()
    }

    /// Every law of one length parameter, at `v` (m).
    fn length_laws(v: f64) -> [Closure; 2] {
        [Closure::Hyperbolic(Hyperbolic { max_closure_m: v }), Closure::Seating(Seating { max_gap_m: v })]
    }

    /// The linear law.
    pub fn is_linear(&self) -> bool {
        *self == Closure::Linear
    }

    /// The law's name in files.
    pub fn name(&self) -> &'static str {
        fn name_of<L: ClosureLaw>(_: &L) -> &'static str {
            L::NAME
        }
        each_law!(self, l => name_of(l))
    }

    /// See [`ClosureLaw::pressure`].
    #[inline(always)]
    pub fn pressure(&self, kn: f64, u: f64) -> f64 {
        each_law!(self, l => l.pressure(kn, u))
    }

    /// See [`ClosureLaw::tangent`]; `kn` for `u ≤ 0` (the tensile branch).
    #[inline(always)]
    pub fn tangent(&self, kn: f64, u: f64) -> f64 {
        if u <= 0.0 {
            return kn;
        }
        each_law!(self, l => l.tangent(kn, u))
    }

    /// See [`ClosureLaw::stiffness_bound`].
    pub fn stiffness_bound(&self, kn: f64) -> f64 {
        each_law!(self, l => l.stiffness_bound(kn))
    }

    /// See [`ClosureLaw::tangent_window`].
    pub fn tangent_window(&self, kn: f64, u: f64) -> Option<(f64, f64)> {
        each_law!(self, l => l.tangent_window(kn, u))
    }

    /// Whether the law has a [`ClosureLaw::tangent_window`] (a tangent that grows far
    /// past `kn` with the closure).
    pub fn is_windowed(&self) -> bool {
        self.tangent_window(1.0, 0.0).is_some()
    }

    /// See [`ClosureLaw::energy_density`]; `kn u² / 2` for `u ≤ 0` (the tensile branch).
    pub fn energy_density(&self, kn: f64, u: f64) -> f64 {
        if u <= 0.0 {
            return 0.5 * kn * u * u;
        }
        each_law!(self, l => l.energy_density(kn, u))
    }

    /// See [`ClosureLaw::kink`].
    pub fn kink(&self, kn: f64) -> f64 {
        each_law!(self, l => l.kink(kn))
    }

    /// Checks the law's parameters and returns it; `key` names the `closure` key.
    ///
    /// # Errors
    /// See [`ClosureLaw::check`].
    pub fn check(self, key: &str) -> Result<Closure, ClosureRangeError> {
        each_law!(&self, l => l.check(key))?;
        Ok(self)
    }

    /// See [`ClosureLaw::closure_under`].
    pub fn closure_under(&self, elastic: f64) -> f64 {
        each_law!(self, l => l.closure_under(elastic))
    }

    /// The law of a joint between a material with this law and one with `other`: the
    /// combination of the two when they are the same law ([`ClosureLaw::combine`]), this
    /// law otherwise.
    pub fn combine(&self, other: &Closure) -> Closure {
        match (self, other) {
            (Closure::Hyperbolic(a), Closure::Hyperbolic(b)) => Closure::Hyperbolic(a.combine(b)),
            (Closure::Seating(a), Closure::Seating(b)) => Closure::Seating(a.combine(b)),
            (Closure::Crushing(a), Closure::Crushing(b)) => Closure::Crushing(a.combine(b)),
            (c, _) => *c,
        }
    }
}
