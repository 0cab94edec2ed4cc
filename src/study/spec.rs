//! The study file as written: serde types, strict (`deny_unknown_fields`), `version = 1`.
//! [`StudySpec::resolve`](crate::study::StudySpec::resolve) checks it into a
//! [`Study`](crate::study::Study).

use super::calibrate::CalibrateSpec;
use super::paper::PaperStudy;
use super::StudyError;
use crate::dem::SolverParams;
use crate::loading::lateral::LateralParams;
use crate::loading::tilt::TiltParams;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The loading protocol.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProtocolKind {
    /// The tilting table to collapse.
    #[default]
    Tilt,
    /// The static lateral (trapezoidal pressure) load, solved to equilibrium.
    Lateral,
}

/// Raw study file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    /// Must be 1.
    pub version: u32,
    /// Study name.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// Master seed.
    pub seed: u64,
    /// Realizations per group and sweep point (≥ 1).
    pub realizations: u64,
    /// Protocol. Default `tilt`.
    #[serde(default)]
    pub protocol: ProtocolKind,
    /// Tilting-table parameters.
    #[serde(default)]
    pub tilt: TiltParams,
    /// Static lateral load parameters (protocol `lateral`).
    #[serde(default)]
    pub lateral: LateralParams,
    /// Solver parameters.
    #[serde(default)]
    pub solver: SolverParams,
    /// Groups (≥ 1).
    pub groups: Vec<GroupSpec>,
    /// Sweep: key → values; every combination is a point (keys in sorted order, the last
    /// varying fastest). Keys: [`SweepKey`](super::SweepKey).
    #[serde(default)]
    pub sweep: BTreeMap<String, Vec<toml::Value>>,
    /// Measured data.
    #[serde(default)]
    pub measured: Option<MeasuredSpec>,
    /// Which of the source paper's studies this reproduces: adds its comparison to the
    /// report (see [`paper`](super::paper)).
    #[serde(default)]
    pub paper: Option<PaperStudy>,
    /// Calibration steps (`drystone calibrate`; see [`calibrate`](super::calibrate)).
    #[serde(default)]
    pub calibrate: Vec<CalibrateSpec>,
}

/// A group of realizations: one wall description.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupSpec {
    /// Group name.
    pub name: String,
    /// Wall description file, relative to the study file.
    pub wall: PathBuf,
    /// Group name in the measured data. Default: `name`.
    #[serde(default)]
    pub measured_group: Option<String>,
    /// Fixed overrides of this group (same keys as the sweep).
    #[serde(default)]
    pub overrides: BTreeMap<String, toml::Value>,
    /// Realizations of this group per sweep point, overriding the study's `realizations`
    /// (and the `--realizations` of the command line): e.g. 1 for a wall without random
    /// input (continuous or running-bond joints, no scatter).
    #[serde(default)]
    pub realizations: Option<u64>,
}

/// Measured data files, relative to the study file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeasuredSpec {
    /// Collapse angles: `specimen, group, collapse_angle_deg`.
    #[serde(default)]
    pub collapse: Option<PathBuf>,
    /// Displacements: `specimen, group, measure, tilt_deg, displacement_cm`.
    #[serde(default)]
    pub displacement: Option<PathBuf>,
    /// The paper's own DEM collapse angles (Table 7): `model, ends, phi_deg, kn_pa_per_m,
    /// collapse_angle_deg`.
    #[serde(default)]
    pub paper_dem: Option<PathBuf>,
}

impl StudySpec {
    /// Reads a study file.
    ///
    /// # Errors
    /// [`StudyError::Io`], [`StudyError::Parse`].
    pub fn from_file(path: &Path) -> Result<Self, StudyError> {
        let text = std::fs::read_to_string(path).map_err(|source| StudyError::Io { path: path.to_owned(), source })?;
        toml::from_str(&text).map_err(|e| StudyError::Parse { path: path.to_owned(), message: e.to_string() })
    }
}
