//! The vertical compression test's column group of a realization's row
//! ([`CompressionColumns`], [`super::row::RealizationRow::compression`]): the wall's vertical
//! modulus (the database's `Epc`), the secants of the cycles' loading branches, the residual
//! settlements, the compressive strength's bracket and the force–shortening curve
//! ([`crate::loading::compression::CompressionResult`]). Stresses and moduli in MPa,
//! settlements and shortenings in mm; NaN where a reading does not exist (no raise, no
//! strength reached, a failed run).

use super::exact;
use serde::{Deserialize, Serialize};

/// The compression test's readings of one realization.
/// [`CompressionColumns::default`] has every reading NaN and no series: what a run that gave
/// nothing reports.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompressionColumns {
    /// The wall's vertical modulus, MPa: the secant of the first loading branch.
    #[serde(with = "exact::one")]
    pub compression_modulus_mpa: f64,
    /// The secant of each cycle's loading branch, MPa (the first the modulus).
    #[serde(with = "exact::vec")]
    pub loading_secants_mpa: Vec<f64>,
    /// The residual settlement after each cycle's unloading, mm.
    #[serde(with = "exact::vec")]
    pub residual_settlements_mm: Vec<f64>,
    /// The compressive strength's bracket: the raise's last stress in equilibrium, MPa (NaN:
    /// no raise, or none lost equilibrium).
    #[serde(with = "exact::one")]
    pub strength_low_mpa: f64,
    /// The raise's first stress without equilibrium, MPa (NaN as `strength_low_mpa`).
    #[serde(with = "exact::one")]
    pub strength_high_mpa: f64,
    /// Static solves of the history without equilibrium.
    pub compression_unconverged: u64,
    /// The force–shortening curve's stresses, MPa.
    #[serde(with = "exact::vec")]
    pub curve_stress_mpa: Vec<f64>,
    /// The force–shortening curve's shortenings, mm.
    #[serde(with = "exact::vec")]
    pub curve_shortening_mm: Vec<f64>,
}

impl Default for CompressionColumns {
    fn default() -> Self {
        CompressionColumns {
            compression_modulus_mpa: f64::NAN,
            loading_secants_mpa: Vec::new(),
            residual_settlements_mm: Vec::new(),
            strength_low_mpa: f64::NAN,
            strength_high_mpa: f64::NAN,
            compression_unconverged: 0,
            curve_stress_mpa: Vec::new(),
            curve_shortening_mm: Vec::new(),
        }
    }
}
