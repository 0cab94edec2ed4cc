//! The outcome of one forward run ([`Outcome`]): what the model's run of one realization
//! gave to compare with measured data, and why it failed, if it did.

use super::observations::Observable;
use crate::protocol::Observed;
use serde::Serialize;

/// The outcome of one realization of one model: what its run gave to compare with
/// measured data ([`Observed`], empty for a failed run) and why it failed, if it did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Outcome {
    /// The run's observables: collapse angle and bracket, stable tilts, top displacements,
    /// the mechanism's reading (`Observed::collapse_deg` is `None` under the lateral load).
    #[serde(flatten)]
    pub observed: Observed,
    /// Why the run failed, if it did.
    pub error: Option<String>,
}

impl Outcome {
    /// A failed run: no observables, and why.
    pub(super) fn failed(error: String) -> Outcome {
        Outcome { observed: Observed::default(), error: Some(error) }
    }

    /// The collapse angle as the middle of its bracket (last stable, first unstable),
    /// degrees: the unbiased point value of an angle known to lie in the bracket.
    pub fn collapse_mid_deg(&self) -> Option<f64> {
        Observable::CollapseAngle.of(&self.observed)
    }

    /// The value of an observable ([`Observable::of`]); `None` for a failed run.
    pub fn value(&self, obs: &Observable) -> Option<f64> {
        self.error.is_none().then_some(())?;
        obs.of(&self.observed)
    }
}
