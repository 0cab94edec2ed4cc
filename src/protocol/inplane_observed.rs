//! What an in-plane run gives to compare with measured data ([`InPlaneObserved`], a part of
//! [`super::Observed`]; made by [`super::Observed::of_in_plane`]).

use crate::loading::inplane::MechanismKind;
use serde::Serialize;

/// What an in-plane run gives to compare with measured data: the measures of the first
/// direction loaded (+x) and the mode read from the blocks (`loading::inplane`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct InPlaneObserved {
    /// The peak horizontal force, kN.
    pub peak_force_kn: f64,
    /// The drift at the peak, %.
    pub drift_at_peak_pct: f64,
    /// The initial stiffness, the secant at 15 % of the peak, kN/mm.
    pub initial_stiffness_kn_per_mm: f64,
    /// The mechanism's mode (`none`: no joint moved past the threshold).
    pub mode: MechanismKind,
}
