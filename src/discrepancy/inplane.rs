//! The in-plane shear–compression test's observables: its measures of the first direction
//! loaded ([`InPlaneQuantity`], as the Stone Masonry Database defines them) and its modes
//! ([`IN_PLANE_MODES`]), and how a run's [`InPlaneObserved`] gives their values. The
//! measured values are its database's (`study::inplane_discrepancy`).

use crate::loading::inplane::MechanismKind as InPlaneMode;
use crate::protocol::InPlaneObserved;
use serde::Serialize;

/// A measure of the in-plane shear–compression test (`loading::inplane`'s per-direction
/// outputs, as the Stone Masonry Database defines them, Vanin et al. 2017).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InPlaneQuantity {
    /// The peak horizontal force, kN.
    PeakForce,
    /// The drift at the peak force, %.
    DriftAtPeak,
    /// The initial stiffness, the secant at 15 % of the peak, kN/mm.
    InitialStiffness,
    /// The wall's vertical modulus from the vertical loading phase, MPa (the database's
    /// `Epc`): the reading of the joints' normal compliance that the horizontal measures
    /// mix with the rocking.
    VerticalModulus,
    /// The ± asymmetry of the peak, kN: the peak pushed towards −x less that towards +x,
    /// each a magnitude (the database's `Vmax_neg − Vmax_pos` of a cyclic specimen; the
    /// model's by the mirror image of its push, [`crate::protocol::InPlaneReading::negative_peak_kn`]):
    /// the reading of what in the rig is not symmetric (a leaning or eccentric vertical
    /// load), which the peak of one direction mixes with the wall's strength.
    PeakAsymmetry,
}

impl InPlaneQuantity {
    /// Every measure, in report order.
    pub const ALL: [InPlaneQuantity; 5] = [
        InPlaneQuantity::PeakForce,
        InPlaneQuantity::DriftAtPeak,
        InPlaneQuantity::InitialStiffness,
        InPlaneQuantity::VerticalModulus,
        InPlaneQuantity::PeakAsymmetry,
    ];

    /// Its name: `peak_force_kn`, `drift_at_peak_pct`, `initial_stiffness_kn_per_mm`,
    /// `wall_vertical_modulus_mpa`, `peak_asymmetry_kn`.
    pub fn name(self) -> &'static str {
        match self {
            InPlaneQuantity::PeakForce => "peak_force_kn",
            InPlaneQuantity::DriftAtPeak => "drift_at_peak_pct",
            InPlaneQuantity::InitialStiffness => "initial_stiffness_kn_per_mm",
            InPlaneQuantity::VerticalModulus => "wall_vertical_modulus_mpa",
            InPlaneQuantity::PeakAsymmetry => "peak_asymmetry_kn",
        }
    }

    /// Its unit.
    pub fn unit(self) -> &'static str {
        match self {
            InPlaneQuantity::PeakForce => "kN",
            InPlaneQuantity::DriftAtPeak => "%",
            InPlaneQuantity::InitialStiffness => "kN/mm",
            InPlaneQuantity::VerticalModulus => "MPa",
            InPlaneQuantity::PeakAsymmetry => "kN",
        }
    }
}

/// The in-plane modes a realization is read as (`InPlaneMode::None`, no mechanism, is not
/// one: such a run gives no mode).
pub const IN_PLANE_MODES: [InPlaneMode; 4] =
    [InPlaneMode::Rocking, InPlaneMode::Sliding, InPlaneMode::Diagonal, InPlaneMode::Mixed];

impl InPlaneQuantity {
    /// Its value in a run's measures; `None` where the run did not give it (not finite).
    pub fn of(self, m: &InPlaneObserved) -> Option<f64> {
        let v = match self {
            InPlaneQuantity::PeakForce => m.peak_force_kn,
            InPlaneQuantity::DriftAtPeak => m.drift_at_peak_pct,
            InPlaneQuantity::InitialStiffness => m.initial_stiffness_kn_per_mm,
            InPlaneQuantity::VerticalModulus => m.wall_vertical_modulus_mpa,
            InPlaneQuantity::PeakAsymmetry => m.peak_asymmetry_kn,
        };
        v.is_finite().then_some(v)
    }
}

/// Whether a run's mechanism was of `mode` (1 or 0); `None` for a run with no mechanism.
pub fn mode_value(mode: InPlaneMode, m: &InPlaneObserved) -> Option<f64> {
    (m.mode != InPlaneMode::None).then_some(f64::from(u8::from(m.mode == mode)))
}
