//! The in-plane shear–compression test's column group of a realization's row
//! ([`InPlaneColumns`], [`super::row::RealizationRow::in_plane`]): the readings of its
//! force–drift curve in each direction (the envelope's robust readings among them, as the
//! measured files define them), the mechanism, limit analysis's peak beside it, the curve
//! itself for the figures, and, not serialized, the poses its mechanism figure draws.
//! Forces in kN, drifts in % of the measuring height, stiffnesses in kN/mm; NaN where a
//! reading does not exist (the − direction of a monotonic run, a failed run).

use super::exact;
use crate::loading::inplane::InPlaneMechanism;
#[cfg(doc)]
use crate::loading::inplane::InPlaneResult;
#[cfg(doc)]
use crate::loading::inplane_loops::{loop_damping_ratio, LOOP_MIN_DRIFT_PCT};
use crate::math::Vec3;
use serde::{Deserialize, Serialize};

/// The poses of the blocks (position, rotation vector) at the mechanism's reading and the
/// mechanism: what the report's mechanism figure draws.
pub type InPlaneDrawing = (Vec<(Vec3, Vec3)>, InPlaneMechanism);

/// The in-plane test's readings of one realization ([`crate::loading::inplane::InPlaneResult`],
/// with limit analysis's [`crate::limit::inplane::limit_in_plane`]).
/// [`InPlaneColumns::default`] has every reading NaN, no text, no curve: what a run that
/// gave nothing reports.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InPlaneColumns {
    /// The peak horizontal force in the + direction, kN.
    #[serde(with = "exact::one")]
    pub peak_pos_kn: f64,
    /// The drift at the + peak, %.
    #[serde(with = "exact::one")]
    pub drift_at_peak_pos_pct: f64,
    /// The ultimate drift in the + direction, %.
    #[serde(with = "exact::one")]
    pub ultimate_drift_pos_pct: f64,
    /// The initial stiffness in the + direction, kN/mm.
    #[serde(with = "exact::one")]
    pub stiffness_pos_kn_per_mm: f64,
    /// The peak horizontal force in the − direction, kN (NaN for a monotonic run).
    #[serde(with = "exact::one")]
    pub peak_neg_kn: f64,
    /// The drift at the − peak, % (NaN for a monotonic run).
    #[serde(with = "exact::one")]
    pub drift_at_peak_neg_pct: f64,
    /// The ultimate drift in the − direction, % (NaN for a monotonic run).
    #[serde(with = "exact::one")]
    pub ultimate_drift_neg_pct: f64,
    /// The initial stiffness in the − direction, kN/mm (NaN for a monotonic run).
    #[serde(with = "exact::one")]
    pub stiffness_neg_kn_per_mm: f64,
    /// The mechanism's kind (its name in the in-plane test's vocabulary; the `mechanism`
    /// column of the in-plane `realizations.csv`).
    pub in_plane_mechanism: String,
    /// The database's failure type of the mechanism (1 rocking, 0.5 mixed, 0 shear).
    #[serde(with = "exact::one")]
    pub failure_type: f64,
    /// The share of the crack's motion that is opening, in [0, 1].
    #[serde(with = "exact::one")]
    pub opening_share: f64,
    /// Limit analysis's peak force, kN (run beside the study's method on the same layout).
    #[serde(with = "exact::one")]
    pub limit_peak_kn: f64,
    /// Limit analysis's mechanism (empty if it failed).
    pub limit_mechanism: String,
    /// The rigid rocking capacity N_total L / (2 H0), kN.
    #[serde(with = "exact::one")]
    pub rocking_kn: f64,
    /// The equivalent viscous damping ratio of its loops (the cycles of at least
    /// [`LOOP_MIN_DRIFT_PCT`] % drift, [`loop_damping_ratio`]); NaN for a monotonic run.
    #[serde(with = "exact::one")]
    pub damping_ratio: f64,
    /// The envelope's force at 0.25 % drift, +, kN.
    #[serde(with = "exact::one")]
    pub force_at_0_25_pos_kn: f64,
    /// The envelope's force at 0.5 % drift, +, kN.
    #[serde(with = "exact::one")]
    pub force_at_0_5_pos_kn: f64,
    /// The envelope's force at 1 % drift, +, kN.
    #[serde(with = "exact::one")]
    pub force_at_1_pos_kn: f64,
    /// The envelope's force at 2 % drift, +, kN.
    #[serde(with = "exact::one")]
    pub force_at_2_pos_kn: f64,
    /// The drift at 80 % of the peak, +, %.
    #[serde(with = "exact::one")]
    pub drift_at_80_pos_pct: f64,
    /// The drift at 95 % of the peak, +, %.
    #[serde(with = "exact::one")]
    pub drift_at_95_pos_pct: f64,
    /// The plateau's slope past 95 % of the peak, +, kN per % drift.
    #[serde(with = "exact::one")]
    pub plateau_slope_pos_kn_per_pct: f64,
    /// The envelope's force at 0.25 % drift, −, kN.
    #[serde(with = "exact::one")]
    pub force_at_0_25_neg_kn: f64,
    /// The envelope's force at 0.5 % drift, −, kN.
    #[serde(with = "exact::one")]
    pub force_at_0_5_neg_kn: f64,
    /// The envelope's force at 1 % drift, −, kN.
    #[serde(with = "exact::one")]
    pub force_at_1_neg_kn: f64,
    /// The envelope's force at 2 % drift, −, kN.
    #[serde(with = "exact::one")]
    pub force_at_2_neg_kn: f64,
    /// The drift at 80 % of the peak, −, %.
    #[serde(with = "exact::one")]
    pub drift_at_80_neg_pct: f64,
    /// The drift at 95 % of the peak, −, %.
    #[serde(with = "exact::one")]
    pub drift_at_95_neg_pct: f64,
    /// The plateau's slope past 95 % of the peak, −, kN per % drift.
    #[serde(with = "exact::one")]
    pub plateau_slope_neg_kn_per_pct: f64,
    /// The wall's vertical modulus read in the vertical loading phase, MPa (the
    /// database's `Epc`; [`InPlaneResult::wall_vertical_modulus_mpa`]).
    #[serde(with = "exact::one")]
    pub vertical_modulus_mpa: f64,
    /// The largest excursion of a block from its course over the history, mm
    /// ([`InPlaneResult::largest_block_excursion_mm`]).
    #[serde(with = "exact::one")]
    pub largest_block_excursion_mm: f64,
    /// The block of `largest_block_excursion_mm`.
    pub excursion_block: String,
    /// The widening of the most widened course at the history's end, mm
    /// ([`InPlaneResult::course_widening_mm`]).
    #[serde(with = "exact::one")]
    pub course_widening_mm: f64,
    /// Static solves that did not reach equilibrium.
    pub unconverged: u64,
    /// The force–drift curve's drifts, % (in the journal and `realizations.parquet`, for
    /// the figures of a resumed or merged run; not in `realizations.csv`).
    #[serde(with = "exact::vec")]
    pub curve_drift_pct: Vec<f64>,
    /// The curve's forces, kN, one per drift.
    #[serde(with = "exact::vec")]
    pub curve_force_kn: Vec<f64>,
    /// The poses at the mechanism's reading and the mechanism, for the report's drawing;
    /// kept by the run that computed them only (not journaled: drawn again from the
    /// realization for a resumed or merged run, the same bits).
    #[serde(skip)]
    pub drawing: Option<Box<InPlaneDrawing>>,
}

impl Default for InPlaneColumns {
    fn default() -> InPlaneColumns {
        InPlaneColumns {
            peak_pos_kn: f64::NAN,
            drift_at_peak_pos_pct: f64::NAN,
            ultimate_drift_pos_pct: f64::NAN,
            stiffness_pos_kn_per_mm: f64::NAN,
            peak_neg_kn: f64::NAN,
            drift_at_peak_neg_pct: f64::NAN,
            ultimate_drift_neg_pct: f64::NAN,
            stiffness_neg_kn_per_mm: f64::NAN,
            in_plane_mechanism: String::new(),
            failure_type: f64::NAN,
            opening_share: f64::NAN,
            limit_peak_kn: f64::NAN,
            limit_mechanism: String::new(),
            rocking_kn: f64::NAN,
            damping_ratio: f64::NAN,
            force_at_0_25_pos_kn: f64::NAN,
            force_at_0_5_pos_kn: f64::NAN,
            force_at_1_pos_kn: f64::NAN,
            force_at_2_pos_kn: f64::NAN,
            drift_at_80_pos_pct: f64::NAN,
            drift_at_95_pos_pct: f64::NAN,
            plateau_slope_pos_kn_per_pct: f64::NAN,
            force_at_0_25_neg_kn: f64::NAN,
            force_at_0_5_neg_kn: f64::NAN,
            force_at_1_neg_kn: f64::NAN,
            force_at_2_neg_kn: f64::NAN,
            drift_at_80_neg_pct: f64::NAN,
            drift_at_95_neg_pct: f64::NAN,
            plateau_slope_neg_kn_per_pct: f64::NAN,
            vertical_modulus_mpa: f64::NAN,
            largest_block_excursion_mm: f64::NAN,
            excursion_block: String::new(),
            course_widening_mm: f64::NAN,
            unconverged: 0,
            curve_drift_pct: Vec::new(),
            curve_force_kn: Vec::new(),
            drawing: None,
        }
    }
}

impl InPlaneColumns {
    /// The force–drift curve: (drift %, force kN) pairs.
    pub fn curve(&self) -> Vec<(f64, f64)> {
        self.curve_drift_pct.iter().copied().zip(self.curve_force_kn.iter().copied()).collect()
    }
}
