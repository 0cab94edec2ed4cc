//! The record of one realization: what `realizations.parquet` / `.csv` hold, one row each.

use serde::{Deserialize, Serialize};

/// Outcome of one realization.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Ran to collapse.
    Collapsed,
    /// Stood up to the largest tilt tried (or, for a lateral load, reached equilibrium).
    Stood,
    /// The generated layout did not reach equilibrium under gravity at α = 0.
    NoInitialEquilibrium,
    /// The state became non-finite.
    BlewUp,
    /// The layout could not be generated or did not pass the layout checks.
    LayoutFailed,
}

impl Status {
    /// The snake_case name used in the tables.
    pub fn as_str(&self) -> &'static str {
        match self {
            Status::Collapsed => "collapsed",
            Status::Stood => "stood",
            Status::NoInitialEquilibrium => "no_initial_equilibrium",
            Status::BlewUp => "blew_up",
            Status::LayoutFailed => "layout_failed",
        }
    }

    /// Parses [`Status::as_str`].
    pub fn parse(s: &str) -> Option<Status> {
        [Status::Collapsed, Status::Stood, Status::NoInitialEquilibrium, Status::BlewUp, Status::LayoutFailed]
            .into_iter()
            .find(|v| v.as_str() == s)
    }

    /// A result usable in the statistics.
    pub fn is_ok(&self) -> bool {
        matches!(self, Status::Collapsed | Status::Stood)
    }
}

/// One realization's results. Angles in degrees, displacements in cm (report units), times
/// in s.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RealizationRow {
    /// Global item index in the study.
    pub index: u64,
    /// Study name.
    pub study: String,
    /// Group name.
    pub group: String,
    /// Sweep point index.
    pub point: u64,
    /// Sweep values of the point, `key=value` joined by `;` (empty without a sweep).
    pub sweep: String,
    /// Master seed.
    pub seed: u64,
    /// Realization index.
    pub realization: u64,
    /// Outcome.
    pub status: Status,
    /// Error message for failed realizations (empty otherwise).
    pub error: String,
    /// Number of blocks of the layout.
    pub blocks: u64,
    /// Collapse angle α_max (last stable tilt), degrees.
    pub collapse_angle_deg: Option<f64>,
    /// First unstable tilt, degrees.
    pub first_unstable_deg: Option<f64>,
    /// Why the first unstable tilt failed.
    pub collapse_reason: String,
    /// Mechanism kind (`sliding`, `toppling`, `mixed`, `none`).
    pub mechanism: String,
    /// Governing joint.
    pub joint: String,
    /// Number of blocks that moved at collapse.
    pub moving_blocks: u64,
    /// Tilt of each stable increment, degrees.
    pub tilt_deg: Vec<f64>,
    /// Out-of-plane displacement of the top-left point at each stable increment, cm.
    pub disp_top_left_cm: Vec<f64>,
    /// Same, top-centre point.
    pub disp_top_centre_cm: Vec<f64>,
    /// Same, top-right point.
    pub disp_top_right_cm: Vec<f64>,
    /// Static lateral load: out-of-plane (y) displacement of the top-left point at
    /// equilibrium, cm (positive in the direction of the load).
    pub lateral_disp_left_cm: Option<f64>,
    /// Same, top-centre point.
    pub lateral_disp_centre_cm: Option<f64>,
    /// Same, top-right point.
    pub lateral_disp_right_cm: Option<f64>,
    /// Static lateral load: top displacement (largest |displacement| of left, centre,
    /// right), cm.
    pub lateral_disp_max_cm: Option<f64>,
    /// Static lateral load: drift, top displacement / H (dimensionless).
    pub lateral_drift: Option<f64>,
    /// Engine steps.
    pub steps: u64,
    /// Time step, s.
    pub dt_s: f64,
    /// Wall-clock time, s (the only non-deterministic column).
    pub wall_time_s: f64,
}

impl RealizationRow {
    /// A row for a realization that produced no result.
    pub fn failed(base: RealizationRow, status: Status, error: String) -> RealizationRow {
        RealizationRow { status, error, ..base }
    }

    fn at_tilt(&self, v: &[f64], tilt: f64) -> Option<f64> {
        self.tilt_deg.iter().position(|t| (t - tilt).abs() < 1e-9).map(|i| v[i])
    }

    /// Mean of the left, centre and right top displacements at a tilt, cm (the paper's SBL
    /// measure, Table 3); `None` if that tilt was not a stable increment.
    pub fn disp_mean_at(&self, tilt: f64) -> Option<f64> {
        let l = self.at_tilt(&self.disp_top_left_cm, tilt)?;
        let c = self.at_tilt(&self.disp_top_centre_cm, tilt)?;
        let r = self.at_tilt(&self.disp_top_right_cm, tilt)?;
        Some((l + c + r) / 3.0)
    }

    /// Centre minus the mean of the two ends at a tilt, cm (the paper's SBR measure).
    pub fn disp_centre_rel_at(&self, tilt: f64) -> Option<f64> {
        let l = self.at_tilt(&self.disp_top_left_cm, tilt)?;
        let c = self.at_tilt(&self.disp_top_centre_cm, tilt)?;
        let r = self.at_tilt(&self.disp_top_right_cm, tilt)?;
        Some(c - 0.5 * (l + r))
    }

    /// A measure by its name in the measured data (`mean_of_left_center_right`,
    /// `center_minus_mean_of_ends`).
    pub fn disp_measure_at(&self, measure: &str, tilt: f64) -> Option<f64> {
        match measure {
            "mean_of_left_center_right" => self.disp_mean_at(tilt),
            "center_minus_mean_of_ends" => self.disp_centre_rel_at(tilt),
            _ => None,
        }
    }
}
