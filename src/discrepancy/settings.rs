//! The settings of a discrepancy analysis (`[discrepancy]` in a study) and their ranges.

use super::observations;
use super::predictive::Reading;
use super::DiscrepancyError;
use serde::{Deserialize, Serialize};

/// The largest share of a failure-height reading on each neighbouring joint, exclusive
/// ([`super::predictive::Reading::neighbour_joint`]): the joint read keeps `1 − 2d`, which
/// stays above each neighbour's `d` only below 1/3.
pub const NEIGHBOUR_JOINT_MAX: f64 = 1.0 / 3.0;

/// Settings of a discrepancy analysis. Defaults in brackets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Realizations per group at every node of the surrogates' grids \[2\]: the models
    /// share their layouts (common random numbers), so the nodes differ by the effect and
    /// not by the sampling; the predictive carries the few realizations (Student-t), and
    /// the two best candidates are re-run and scored with `extension_realizations`.
    pub realizations: u64,
    /// Realizations per group of the baseline's and of a confirmed candidate's full run
    /// \[9\] (the first `realizations` of the baseline are the grids' neutral node).
    pub extension_realizations: u64,
    /// Realizations per group on independent layouts (a master seed of their own) for the
    /// null data and the posterior predictive check \[9\].
    pub null_realizations: u64,
    /// Grid intervals per parameter axis of a one-parameter effect \[4\]: nodes at
    /// `x = 0, 1/G, …, 1`, the node nearest the neutral value taken from the baseline.
    pub grid_points: usize,
    /// Nodes per axis of a two-parameter effect \[3\], corners included.
    pub grid_points_2d: usize,
    /// Null data sets of the margin calibration \[200\] (all set the margins; the
    /// false-alarm rate is measured by cross-fitting their two halves).
    pub null_replicates: usize,
    /// Data sets of the posterior predictive check \[200\].
    pub check_replicates: usize,
    /// Bootstrap resamples of the specimens for the gain's interval \[2000\].
    pub bootstrap: usize,
    /// The effects searched, by name \[every built-in and every effect file of the
    /// study\].
    pub effects: Vec<String>,
    /// Effects searched beside the default ones when `effects` is empty, by name \[none\]:
    /// the built-ins searched only by name ([`crate::effects::NAMED_ONLY_EFFECTS`], e.g.
    /// `table_kick` for a table rolled by hand) or effect files. Ignored when `effects`
    /// lists the search.
    pub also_effects: Vec<String>,
    /// Rank the specimen-scatter hypothesis beside the mechanisms \[true\].
    pub scatter: bool,
    /// Re-run the two best candidates as full ensembles at their fitted parameters and
    /// score them by those runs \[true\]; off, the surrogate's scores stand (for power
    /// studies; the report says so).
    pub confirm: bool,
    /// Measurement standard deviations.
    pub sigma: observations::MeasurementSigma,
    /// Reading resolutions of the measured values.
    pub reading: Reading,
    /// Where the observations' σ came from when a study's reader set them from the data
    /// (one sentence per family; the report prints them); empty when every σ is the
    /// setting's. Not a key of the file.
    #[serde(skip)]
    pub sigma_notes: Vec<String>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            realizations: 2,
            extension_realizations: 9,
            null_realizations: 9,
            grid_points: 4,
            grid_points_2d: 3,
            null_replicates: 200,
            check_replicates: 200,
            bootstrap: 2000,
            effects: vec![],
            also_effects: vec![],
            scatter: true,
            confirm: true,
            sigma: observations::MeasurementSigma::default(),
            reading: Reading::default(),
            sigma_notes: vec![],
        }
    }
}

impl Settings {
    /// The settings of `drystone discrepancy --thorough`: twice the realizations of the
    /// grids, of the full runs and of the independent layouts, and finer grids (at least 6
    /// intervals per axis, 4 nodes per axis of a two-parameter effect). About three times
    /// the cost.
    pub fn thorough(&mut self) {
        self.realizations *= 2;
        self.extension_realizations *= 2;
        self.null_realizations *= 2;
        self.grid_points = self.grid_points.max(6);
        self.grid_points_2d = self.grid_points_2d.max(4);
    }

    /// The most realizations any of its runs takes per group (grids, full runs, independent
    /// layouts): what a [`simulate::Setup`](super::Setup) for the analysis must allow.
    pub fn most_realizations(&self) -> u64 {
        self.realizations.max(self.extension_realizations).max(self.null_realizations)
    }

    /// Checks ranges.
    ///
    /// # Errors
    /// [`DiscrepancyError::Setting`] naming the key.
    pub fn validate(&self) -> Result<(), DiscrepancyError> {
        let bad = |key, value: String, reason| Err(DiscrepancyError::Setting { key, value, reason });
        // The counts: (key, value, lowest, highest, the range as the error states it).
        for (key, v, lo, hi, range) in [
            ("realizations", self.realizations, 1, 10_000, "must be in [1, 10000]"),
            ("extension_realizations", self.extension_realizations, 1, 10_000, "must be in [1, 10000]"),
            ("grid_points", self.grid_points as u64, 1, 20, "must be in [1, 20]"),
            ("grid_points_2d", self.grid_points_2d as u64, 2, 10, "must be in [2, 10]"),
            ("null_replicates", self.null_replicates as u64, 20, 100_000, "must be in [20, 100000]"),
            ("bootstrap", self.bootstrap as u64, 100, 1_000_000, "must be in [100, 1000000]"),
            ("null_realizations", self.null_realizations, 1, 10_000, "must be in [1, 10000]"),
            ("check_replicates", self.check_replicates as u64, 20, 100_000, "must be in [20, 100000]"),
        ] {
            if !(lo..=hi).contains(&v) {
                return bad(key, v.to_string(), range);
            }
        }
        if !(self.reading.misreading.is_finite() && (0.0..0.5).contains(&self.reading.misreading)) {
            return bad("reading.misreading", self.reading.misreading.to_string(), "must be in [0, 0.5)");
        }
        // The joint read keeps 1 − 2d of a reading, each neighbour d: below 1/3 the
        // failing joint's share is the largest, so that a reading at it scores better than
        // one a course off.
        let d = self.reading.neighbour_joint;
        if !(d.is_finite() && (0.0..NEIGHBOUR_JOINT_MAX).contains(&d)) {
            return bad(
                "reading.neighbour_joint",
                d.to_string(),
                "must be in [0, 1/3): the joint read keeps 1 − 2 d of a reading and each neighbour d, so from \
                 1/3 up a reading at the failing joint would score no better than one a course off",
            );
        }
        for (key, v) in [
            ("reading.angle_deg", self.reading.angle_deg),
            ("reading.displacement_cm", self.reading.displacement_cm),
            ("reading.force_kn", self.reading.force_kn),
            ("reading.drift_pct", self.reading.drift_pct),
            ("reading.stiffness_kn_per_mm", self.reading.stiffness_kn_per_mm),
            ("reading.asymmetry_kn", self.reading.asymmetry_kn),
        ] {
            if !(v.is_finite() && (0.0..=10.0).contains(&v)) {
                return bad(key, v.to_string(), "must be in [0, 10] (0: exact readings)");
            }
        }
        let v = self.reading.modulus_mpa;
        if !(v.is_finite() && (0.0..=1e3).contains(&v)) {
            return bad("reading.modulus_mpa", v.to_string(), "must be in [0, 1000] MPa (0: exact readings)");
        }
        // The measurement σ divides every residual: positive, finite and of the scale of a
        // reading (the angle and the displacement as `reading`, a failure height as a
        // fraction of the wall's height).
        for (key, v, hi, range) in [
            ("sigma.angle_deg", self.sigma.angle_deg, 10.0, "must be in (0, 10] degrees"),
            ("sigma.displacement_cm", self.sigma.displacement_cm, 10.0, "must be in (0, 10] cm"),
            ("sigma.failure_height", self.sigma.failure_height, 1.0, "must be in (0, 1] (a fraction of the height)"),
            ("sigma.force_kn", self.sigma.force_kn, 1e4, "must be in (0, 10000] kN"),
            ("sigma.drift_pct", self.sigma.drift_pct, 50.0, "must be in (0, 50] %"),
            ("sigma.stiffness_kn_per_mm", self.sigma.stiffness_kn_per_mm, 1e4, "must be in (0, 10000] kN/mm"),
            ("sigma.modulus_mpa", self.sigma.modulus_mpa, 1e5, "must be in (0, 100000] MPa"),
            ("sigma.asymmetry_kn", self.sigma.asymmetry_kn, 1e4, "must be in (0, 10000] kN"),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= hi) {
                return bad(key, v.to_string(), range);
            }
        }
        let mut seen = std::collections::BTreeSet::new();
        for e in &self.effects {
            if !seen.insert(e) {
                return bad("effects", e.clone(), "an effect is listed twice");
            }
        }
        let mut seen = std::collections::BTreeSet::new();
        for e in &self.also_effects {
            if !seen.insert(e) {
                return bad("also_effects", e.clone(), "an effect is listed twice");
            }
        }
        Ok(())
    }
}
