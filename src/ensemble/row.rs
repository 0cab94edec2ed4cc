//! The record of one realization: what `realizations.parquet` / `.csv` hold, one row each.
//!
//! A row also serializes (serde) with every number exact: finite values as JSON numbers
//! (shortest round-trip form), the others as text (`NaN`, `inf`, `-inf`, or the bit
//! pattern `0x…` of a NaN other than the usual one). The journal of a run relies on it: a
//! row read back is the row written, bit for bit.

use serde::{Deserialize, Serialize};

pub use super::compression_columns::CompressionColumns;
pub use super::exact;
pub use super::inplane_columns::InPlaneColumns;

/// Outcome of one realization.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Ran to collapse.
    Collapsed,
    /// Stood up to the largest tilt tried (or, for a lateral load, reached equilibrium; for
    /// the in-plane test, ran its whole history: its readings are in [`InPlaneColumns`]).
    Stood,
    /// The generated layout did not reach equilibrium under gravity at α = 0.
    NoInitialEquilibrium,
    /// The state became non-finite.
    BlewUp,
    /// The layout could not be generated or did not pass the layout checks.
    LayoutFailed,
    /// The protocol refused the realization's parameters for its wall before running it (a
    /// parameter out of range once the wall's dimensions are known, such as a shear span
    /// below its top or a stress that closes its joints past the contacts' reach, or a
    /// wall the rig cannot be laid on), with the refusal in the row's error.
    Refused,
    /// The run ended, but a block was shed from the wall on the way (the in-plane test: its
    /// excursion from its course passed a quarter of its smallest extent,
    /// [`crate::loading::excursion::SHED_SHARE`]), with the block in the row's error: its
    /// readings are in the row, but they are no wall's, and the statistics leave them out.
    ShedBlock,
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
            Status::Refused => "refused",
            Status::ShedBlock => "shed_block",
        }
    }

    /// Parses [`Status::as_str`].
    pub fn parse(s: &str) -> Option<Status> {
        [
            Status::Collapsed,
            Status::Stood,
            Status::NoInitialEquilibrium,
            Status::BlewUp,
            Status::LayoutFailed,
            Status::Refused,
            Status::ShedBlock,
        ]
        .into_iter()
        .find(|v| v.as_str() == s)
    }

    /// The status of a run that ended in an error: `no_initial_equilibrium` if the layout did
    /// not stand as given, `refused` if the protocol refused its parameters for the wall
    /// before running, else `blew_up`.
    pub fn of_failure(does_not_stand: bool, refused: bool) -> Status {
        match (does_not_stand, refused) {
            (true, _) => Status::NoInitialEquilibrium,
            (false, true) => Status::Refused,
            (false, false) => Status::BlewUp,
        }
    }

    /// A result usable in the statistics.
    pub fn is_ok(&self) -> bool {
        matches!(self, Status::Collapsed | Status::Stood)
    }
}

/// One realization's results: the columns every protocol has (identification, status,
/// solver effort), then each protocol's own ([`CollapseColumns`], [`TiltColumns`],
/// [`LateralColumns`], [`ShakeColumns`], [`PushoverColumns`], [`InPlaneColumns`], [`CompressionColumns`]), empty where the protocol does not fill them.
/// Angles in degrees, displacements in cm (report units), times in s.
///
/// The protocol groups serialize flat (their fields are columns of the row, as in the
/// tables), except the shaking table's and the in-plane test's, which nest under `shake`
/// and `in_plane`.
/// [`RealizationRow::default`] is a row with no result yet: status `layout_failed`,
/// every number zero or empty.
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
    /// The collapse and its mechanism (tilting table, limit analysis; the collapse reason
    /// of a lateral load).
    #[serde(flatten)]
    pub collapse: CollapseColumns,
    /// The tilting table's displacement curves.
    #[serde(flatten)]
    pub tilt: TiltColumns,
    /// The static lateral load's displacements.
    #[serde(flatten)]
    pub lateral: LateralColumns,
    /// Shaking table: the motion, its level and what the wall did (empty for the other
    /// protocols).
    #[serde(default)]
    pub shake: ShakeColumns,
    /// The collapse load multiplier of the lateral pressure (`[lateral] pushover = true`);
    /// empty otherwise, and then absent from the tables.
    #[serde(flatten)]
    pub pushover: PushoverColumns,
    /// The in-plane shear–compression test's readings (`protocol = "in_plane"`); `None` for
    /// the other protocols (and then absent from the journal and the tables).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub in_plane: Option<Box<InPlaneColumns>>,
    /// The vertical compression test's readings (`protocol = "compression"`); `None` for
    /// the other protocols (and then absent from the journal and the tables).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compression: Option<Box<CompressionColumns>>,
    /// Dynamic-relaxation steps (engine steps).
    pub steps: u64,
    /// Iterations of the implicit relaxation (tilting table; 0 for the lateral load).
    #[serde(default)]
    pub iterations: u64,
    /// Time step, s.
    #[serde(with = "exact::one")]
    pub dt_s: f64,
    /// Wall-clock time, s (the only non-deterministic column).
    #[serde(with = "exact::one")]
    pub wall_time_s: f64,
}

impl Default for RealizationRow {
    fn default() -> RealizationRow {
        RealizationRow {
            index: 0,
            study: String::new(),
            group: String::new(),
            point: 0,
            sweep: String::new(),
            seed: 0,
            realization: 0,
            status: Status::LayoutFailed,
            error: String::new(),
            blocks: 0,
            collapse: CollapseColumns::default(),
            tilt: TiltColumns::default(),
            lateral: LateralColumns::default(),
            shake: ShakeColumns::default(),
            pushover: PushoverColumns::default(),
            in_plane: None,
            compression: None,
            steps: 0,
            iterations: 0,
            dt_s: 0.0,
            wall_time_s: 0.0,
        }
    }
}

/// The collapse columns of a row: the tilting table's collapse angle and mechanism
/// ([`crate::loading::tilt::TiltResult`]), the limit analysis's collapse angle, the
/// reason a lateral load collapsed. Empty (`None`, `""`, 0) where the protocol has none.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CollapseColumns {
    /// Collapse angle α_max (last stable tilt), degrees.
    #[serde(with = "exact::opt")]
    pub collapse_angle_deg: Option<f64>,
    /// First unstable tilt, degrees.
    #[serde(with = "exact::opt")]
    pub first_unstable_deg: Option<f64>,
    /// Why the first unstable tilt failed.
    pub collapse_reason: String,
    /// Mechanism kind (`sliding`, `toppling`, `mixed`, `none`).
    pub mechanism: String,
    /// Governing joint.
    pub joint: String,
    /// Number of blocks that moved at collapse.
    pub moving_blocks: u64,
    /// The lowest bed joint of the moving part as a fraction of the wall's height (0: the
    /// table joint; [`crate::loading::mechanism::MechanismReading`]); `None` without a
    /// mechanism.
    #[serde(default, with = "exact::opt")]
    pub failure_height_fraction: Option<f64>,
    /// The failure's kind as a person reads it (`toppling`, `sliding`, `bending`, `mixed`;
    /// empty without a mechanism).
    #[serde(default)]
    pub mechanism_kind: String,
    /// Where along the wall it started (`end`, `centre`, `uniform`; empty without a
    /// mechanism).
    #[serde(default)]
    pub mechanism_start: String,
    /// The share of the wall's length the moving blocks span, in [0, 1]; `None` without a
    /// mechanism.
    #[serde(default, with = "exact::opt")]
    pub mechanism_extent: Option<f64>,
}

/// The tilting table's curves: the top displacements at each stable increment (empty for
/// the other protocols). The three points are the default [`crate::loading::TopMonitor`]s.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TiltColumns {
    /// Tilt of each stable increment, degrees.
    #[serde(with = "exact::vec")]
    pub tilt_deg: Vec<f64>,
    /// Out-of-plane displacement of the top-left point at each stable increment, cm.
    #[serde(with = "exact::vec")]
    pub disp_top_left_cm: Vec<f64>,
    /// Same, top-centre point.
    #[serde(with = "exact::vec")]
    pub disp_top_centre_cm: Vec<f64>,
    /// Same, top-right point.
    #[serde(with = "exact::vec")]
    pub disp_top_right_cm: Vec<f64>,
}

/// The static lateral load's columns ([`crate::loading::lateral::LateralResult`]); `None`
/// for the other protocols and for a wall that collapsed under the load.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct LateralColumns {
    /// Out-of-plane (y) displacement of the top-left point at equilibrium, cm (positive in
    /// the direction of the load).
    #[serde(with = "exact::opt")]
    pub lateral_disp_left_cm: Option<f64>,
    /// Same, top-centre point.
    #[serde(with = "exact::opt")]
    pub lateral_disp_centre_cm: Option<f64>,
    /// Same, top-right point.
    #[serde(with = "exact::opt")]
    pub lateral_disp_right_cm: Option<f64>,
    /// Top displacement (largest |displacement| of left, centre, right), cm.
    #[serde(with = "exact::opt")]
    pub lateral_disp_max_cm: Option<f64>,
    /// Drift, top displacement / H (dimensionless).
    #[serde(with = "exact::opt")]
    pub lateral_drift: Option<f64>,
}

/// The collapse load multiplier λ of the lateral pressure, a study with `[lateral] pushover
/// = true` ([`crate::loading::lateral::LateralParams::pushover`]): by the DEM pushover
/// ([`crate::loading::lateral_pushover`]) and by limit analysis of the same layout. `None`
/// where not run (and then the columns are left out of the tables and of the journal, so
/// that the rows of other studies have the columns they always have).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PushoverColumns {
    /// The pushover by a method that steps (the penalty DEM, or nscd: the column keeps
    /// its `_dem` name from before nscd ran it): the largest λ found stable (the collapse
    /// load multiplier).
    #[serde(default, skip_serializing_if = "Option::is_none", with = "exact::opt")]
    pub load_multiplier_dem: Option<f64>,
    /// The pushover by a method that steps (the penalty DEM or nscd): the smallest λ found
    /// unstable (`None`: stood to the largest λ tried).
    #[serde(default, skip_serializing_if = "Option::is_none", with = "exact::opt")]
    pub load_multiplier_dem_unstable: Option<f64>,
    /// Limit analysis (rigid blocks, `crate::limit::limit_lateral`): the collapse λ.
    #[serde(default, skip_serializing_if = "Option::is_none", with = "exact::opt")]
    pub load_multiplier_limit: Option<f64>,
}

impl PushoverColumns {
    /// Whether any of the columns holds a value.
    pub fn any(&self) -> bool {
        self.load_multiplier_dem.is_some()
            || self.load_multiplier_dem_unstable.is_some()
            || self.load_multiplier_limit.is_some()
    }
}

/// The shaking-table columns of a row ([`crate::loading::shake::ShakeResult`]); empty
/// (`""`, `None`) for the tilting table and the lateral load. Whether the wall overturned
/// is the row's status: `collapsed` (a block fell) or `stood`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ShakeColumns {
    /// The ground motion's name (a record's file stem, `kt_SEED_I` for a generated motion,
    /// `one-sine_…` for a pulse).
    pub motion: String,
    /// The PGA the motion was scaled to, g.
    #[serde(with = "exact::opt")]
    pub pga_g: Option<f64>,
    /// When the first block fell, s from the start of the motion (`None` if none did).
    #[serde(with = "exact::opt")]
    pub collapse_time_s: Option<f64>,
    /// The largest |rotation about x| (out-of-plane rocking) of any block, degrees.
    #[serde(with = "exact::opt")]
    pub max_rotation_deg: Option<f64>,
    /// The largest drift (top y displacement relative to the table / H), –.
    #[serde(with = "exact::opt")]
    pub max_drift: Option<f64>,
    /// The drift at the end of the run, –.
    #[serde(with = "exact::opt")]
    pub residual_drift: Option<f64>,
    /// Blocks fallen at the end of the run.
    pub blocks_fallen: Option<u64>,
    /// Steps whose natural-map residual is above the solver's `natural_tolerance`,
    /// settling included (`nscd`; `None` for `penalty`).
    pub unconverged_steps: Option<u64>,
    /// The largest natural-map residual of a step, settling included (`nscd`; `None` for
    /// `penalty`), dimensionless.
    #[serde(with = "exact::opt")]
    pub max_natural_residual: Option<f64>,
}

/// A displacement measure of the top of the wall.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Measure {
    /// The mean of the left, centre and right top points (the paper's free walls).
    #[default]
    MeanOfLeftCenterRight,
    /// The centre minus the mean of the two ends (the paper's restrained walls).
    CenterMinusMeanOfEnds,
}

impl Measure {
    /// Every measure.
    pub const ALL: [Measure; 2] = [Measure::MeanOfLeftCenterRight, Measure::CenterMinusMeanOfEnds];

    /// The name used in the measured-data files.
    pub fn name(self) -> &'static str {
        match self {
            Measure::MeanOfLeftCenterRight => "mean_of_left_center_right",
            Measure::CenterMinusMeanOfEnds => "center_minus_mean_of_ends",
        }
    }

    /// The measure of a name.
    pub fn from_name(name: &str) -> Option<Measure> {
        Measure::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The measure from the left, centre and right top displacements (any unit).
    pub fn of(self, left: f64, centre: f64, right: f64) -> f64 {
        match self {
            Measure::MeanOfLeftCenterRight => (left + centre + right) / 3.0,
            Measure::CenterMinusMeanOfEnds => centre - 0.5 * (left + right),
        }
    }
}

impl std::fmt::Display for Measure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl RealizationRow {
    /// A row for a realization that produced no result.
    pub fn failed(base: RealizationRow, status: Status, error: String) -> RealizationRow {
        RealizationRow { status, error, ..base }
    }

    fn at_tilt(&self, v: &[f64], tilt: f64) -> Option<f64> {
        self.tilt.tilt_deg.iter().position(|t| (t - tilt).abs() < 1e-9).map(|i| v[i])
    }

    /// Mean of the left, centre and right top displacements at a tilt, cm (the paper's SBL
    /// measure, Table 3); `None` if that tilt was not a stable increment.
    pub fn disp_mean_at(&self, tilt: f64) -> Option<f64> {
        let l = self.at_tilt(&self.tilt.disp_top_left_cm, tilt)?;
        let c = self.at_tilt(&self.tilt.disp_top_centre_cm, tilt)?;
        let r = self.at_tilt(&self.tilt.disp_top_right_cm, tilt)?;
        Some((l + c + r) / 3.0)
    }

    /// Centre minus the mean of the two ends at a tilt, cm (the paper's SBR measure).
    pub fn disp_centre_rel_at(&self, tilt: f64) -> Option<f64> {
        let l = self.at_tilt(&self.tilt.disp_top_left_cm, tilt)?;
        let c = self.at_tilt(&self.tilt.disp_top_centre_cm, tilt)?;
        let r = self.at_tilt(&self.tilt.disp_top_right_cm, tilt)?;
        Some(c - 0.5 * (l + r))
    }

    /// A displacement measure at a tilt, cm; `None` if that tilt was not a stable
    /// increment.
    pub fn disp_measure_at(&self, measure: Measure, tilt: f64) -> Option<f64> {
        match measure {
            Measure::MeanOfLeftCenterRight => self.disp_mean_at(tilt),
            Measure::CenterMinusMeanOfEnds => self.disp_centre_rel_at(tilt),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(values: &[f64]) -> RealizationRow {
        RealizationRow {
            index: 3,
            study: "s".into(),
            group: "g".into(),
            point: 1,
            sweep: "kn_pa_per_m=1".into(),
            seed: u64::MAX,
            realization: 2,
            status: Status::Collapsed,
            error: String::new(),
            blocks: 9,
            collapse: CollapseColumns {
                collapse_angle_deg: Some(values[0]),
                first_unstable_deg: None,
                collapse_reason: "total_displacement".into(),
                mechanism: "mixed".into(),
                joint: "b1-b2".into(),
                moving_blocks: 4,
                failure_height_fraction: Some(values[2]),
                mechanism_kind: "bending".into(),
                mechanism_start: "centre".into(),
                mechanism_extent: None,
            },
            tilt: TiltColumns {
                tilt_deg: values.to_vec(),
                disp_top_left_cm: values.iter().rev().copied().collect(),
                disp_top_centre_cm: vec![],
                disp_top_right_cm: vec![f64::NAN],
            },
            lateral: LateralColumns {
                lateral_disp_left_cm: Some(values[values.len() - 1]),
                lateral_disp_centre_cm: None,
                lateral_disp_right_cm: Some(f64::NEG_INFINITY),
                lateral_disp_max_cm: Some(-0.0),
                lateral_drift: None,
            },
            shake: ShakeColumns {
                motion: "kt_1_0".into(),
                pga_g: Some(values[3]),
                collapse_time_s: None,
                max_rotation_deg: Some(values[4]),
                max_drift: Some(values[6]),
                residual_drift: Some(values[7]),
                blocks_fallen: Some(3),
                unconverged_steps: Some(7),
                max_natural_residual: Some(values[5]),
            },
            pushover: PushoverColumns {
                load_multiplier_dem: Some(values[8]),
                load_multiplier_dem_unstable: None,
                load_multiplier_limit: Some(values[9]),
            },
            in_plane: None,
            compression: None,
            steps: 77,
            iterations: 5,
            dt_s: values[1],
            wall_time_s: 0.25,
        }
    }

    fn bits(r: &RealizationRow) -> Vec<u64> {
        let mut v: Vec<f64> = vec![
            r.collapse.collapse_angle_deg.unwrap(),
            r.dt_s,
            r.wall_time_s,
            r.collapse.failure_height_fraction.unwrap(),
        ];
        v.extend(&r.tilt.tilt_deg);
        v.extend(&r.tilt.disp_top_left_cm);
        v.extend(&r.tilt.disp_top_right_cm);
        v.extend(
            [r.lateral.lateral_disp_left_cm, r.lateral.lateral_disp_right_cm, r.lateral.lateral_disp_max_cm]
                .map(Option::unwrap),
        );
        let s = &r.shake;
        v.extend([s.pga_g, s.max_rotation_deg, s.max_drift, s.residual_drift].map(Option::unwrap));
        v.extend([r.pushover.load_multiplier_dem, r.pushover.load_multiplier_limit].map(Option::unwrap));
        assert!(r.pushover.load_multiplier_dem_unstable.is_none());
        v.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn a_row_survives_json_bit_for_bit() {
        let mut values = vec![
            0.1 + 0.2,
            -0.0,
            f64::MIN_POSITIVE / 3.0,
            f64::MAX,
            1e300,
            20.0,
            f64::NAN,
            -f64::NAN,
            f64::from_bits(0x7ff0_0000_0000_0001),
            f64::INFINITY,
        ];
        // Pseudo-random bit patterns (a fixed LCG).
        let mut x = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..200 {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            values.push(f64::from_bits(x));
        }
        let r = row(&values);
        let text = serde_json::to_string(&r).unwrap();
        assert!(!text.contains('\n'));
        let back: RealizationRow = serde_json::from_str(&text).unwrap();
        assert_eq!(bits(&back), bits(&r));
        assert_eq!(serde_json::to_string(&back).unwrap(), text);
        assert!(serde_json::from_str::<RealizationRow>(&text.replace("\"-inf\"", "\"minus\"")).is_err());
    }

    /// A row without a pushover writes no pushover key (the journal lines of the other
    /// studies keep their keys), and reads back without one.
    #[test]
    fn a_row_without_a_pushover_has_no_pushover_keys() {
        let r = RealizationRow { pushover: PushoverColumns::default(), ..row(&[1.0; 10]) };
        let text = serde_json::to_string(&r).unwrap();
        assert!(!text.contains("load_multiplier"), "{text}");
        let back: RealizationRow = serde_json::from_str(&text).unwrap();
        assert!(!back.pushover.any());
    }
}
