//! Study files: which walls, how many realizations, the master seed, the protocol, a sweep
//! over parameters (a cartesian grid) and the measured data to compare with.
//!
//! A study is TOML, strict, `version = 1`, read into a raw [`StudySpec`] and resolved into a
//! checked [`Study`] (every wall generated from its description with the sweep's overrides,
//! every measured file read) before anything runs:
//!
//! ```toml
//! version = 1
//! name = "tilting_table"
//! seed = 2021
//! realizations = 16          # per group and sweep point
//! protocol = "tilt"          # the tilting table, or "lateral" (static pressure)
//!
//! [tilt]                     # optional, TiltParams (degrees)
//! step_deg = 0.5
//!
//! [lateral]                  # optional, LateralParams (protocol "lateral"; Pa)
//! pressure_base_pa = 1000.0
//! pressure_top_pa = 500.0
//!
//! [solver]                   # optional, SolverParams
//! damping = 0.8
//!
//! [[groups]]
//! name = "SBL"
//! wall = "walls/sbl.toml"    # path relative to this file
//! measured_group = "SBL"     # optional, default: the group name
//!
//! [sweep]                    # optional: every combination is a sweep point
//! kn_pa_per_m = [2.5e7, 5.0e7]
//! friction_deg = [30, 40]
//!
//! [measured]                 # optional, paths relative to this file
//! collapse = "../data/paper/tilting_table_collapse.csv"
//! displacement = "../data/paper/tilting_table_displacement.csv"
//! ```
//!
//! Sweep (and per-group `overrides`) keys act on the wall description:
//!
//! | key | effect | unit |
//! | --- | --- | --- |
//! | `kn_pa_per_m` | Kn of every material; Ks follows at the material's own Ks/Kn unless `ks_over_kn` is set | Pa/m |
//! | `ks_over_kn` | Ks = ratio × Kn for every material | – |
//! | `friction_deg` | φ of every material | degrees |
//! | `cohesion_pa` | cohesion of every material | Pa |
//! | `length_m` | wall length L | m |
//! | `arrangement` | `continuous`, `discontinuous` or `irregular` | – |
//! | `ends` | `free`, or `rigid` (every block within the wall's end zone, or [`DEFAULT_END_ZONE_M`] if it has none, held in y) | – |
//!
//! A group may fix its own `realizations` (e.g. 1 for a wall without random input).

pub mod calibrate;
pub mod discrepancy;
pub mod paper;
pub mod report;
pub mod run;
pub mod suite;
pub mod summary;

use crate::dem::SolverParams;
use crate::generator::distribution::DistributionSource;
use crate::generator::spec::{ArrangementKind, WallSpec};
use crate::generator::Wall;
use crate::io::table::{self, MeasuredCollapse, MeasuredDisplacement, TableError};
use crate::loading::lateral::LateralParams;
use crate::loading::tilt::TiltParams;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Study errors, each naming the file and the key at fault.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum StudyError {
    /// The file could not be read.
    #[error("cannot read study file {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Not valid study TOML (syntax, unknown key, wrong type, missing key).
    #[error("study file {path}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// serde's message.
        message: String,
    },
    /// A value is out of range.
    #[error("study file {path}: {key}: {reason}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The key.
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// A wall description of a group failed.
    #[error("study file {path}: group {group}: {source}")]
    Wall {
        /// The study file.
        path: PathBuf,
        /// The group.
        group: String,
        /// The generator's error.
        source: Box<crate::generator::GeneratorError>,
    },
    /// A measured-data file failed.
    #[error("study file {path}: measured data: {source}")]
    Measured {
        /// The study file.
        path: PathBuf,
        /// The table error.
        source: TableError,
    },
}

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
    /// varying fastest).
    #[serde(default)]
    pub sweep: BTreeMap<String, Vec<toml::Value>>,
    /// Measured data.
    #[serde(default)]
    pub measured: Option<MeasuredSpec>,
    /// Which of the source paper's studies this reproduces: adds its comparison to the
    /// report (see [`paper`]).
    #[serde(default)]
    pub paper: Option<paper::PaperStudy>,
    /// Calibration steps (`drystone calibrate`; see [`calibrate`]).
    #[serde(default)]
    pub calibrate: Vec<calibrate::CalibrateSpec>,
    /// Model-discrepancy settings (`drystone discrepancy`; see
    /// [`crate::discrepancy::Settings`]).
    #[serde(default)]
    pub discrepancy: Option<crate::discrepancy::Settings>,
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

/// A sweep value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SweepValue {
    /// A number.
    Number(f64),
    /// Text (e.g. an arrangement).
    Text(String),
}

impl std::fmt::Display for SweepValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SweepValue::Number(v) => write!(f, "{v}"),
            SweepValue::Text(s) => write!(f, "{s}"),
        }
    }
}

/// A point of the sweep: (key, value) in key order.
pub type SweepPoint = Vec<(String, SweepValue)>;

/// Label of a point: `key=value;key=value` (empty without a sweep).
pub fn point_label(p: &SweepPoint) -> String {
    p.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(";")
}

/// A checked group.
#[derive(Debug, Clone)]
pub struct Group {
    /// Name.
    pub name: String,
    /// Group name in the measured data.
    pub measured_group: String,
    /// The wall description file.
    pub wall_path: PathBuf,
    /// The resolved wall at each sweep point.
    pub walls: Vec<Wall>,
    /// Own number of realizations per sweep point, if the group fixes it.
    pub realizations: Option<u64>,
    /// The group's wall description with its overrides applied (before any sweep point).
    pub spec: WallSpec,
}

/// Measured data of a study.
#[derive(Debug, Clone, Default)]
pub struct Measured {
    /// Collapse angles.
    pub collapse: Vec<MeasuredCollapse>,
    /// Displacements.
    pub displacement: Vec<MeasuredDisplacement>,
    /// The paper's DEM collapse angles (Table 7).
    pub paper_dem: Vec<table::PaperDemAngle>,
}

/// A checked study.
#[derive(Debug, Clone)]
pub struct Study {
    /// Name.
    pub name: String,
    /// Description.
    pub description: String,
    /// The study file.
    pub path: PathBuf,
    /// Master seed.
    pub seed: u64,
    /// Realizations per group and point.
    pub realizations: u64,
    /// Protocol.
    pub protocol: ProtocolKind,
    /// Tilting-table parameters.
    pub tilt: TiltParams,
    /// Static lateral load parameters.
    pub lateral: LateralParams,
    /// Solver parameters.
    pub solver: SolverParams,
    /// Groups.
    pub groups: Vec<Group>,
    /// Sweep points (one empty point without a sweep).
    pub points: Vec<SweepPoint>,
    /// Measured data.
    pub measured: Measured,
    /// The paper's study reproduced, if any.
    pub paper: Option<paper::PaperStudy>,
    /// Calibration steps.
    pub calibrate: Vec<calibrate::CalibrateSpec>,
    /// Model-discrepancy settings (defaults where the file has no `[discrepancy]`).
    pub discrepancy: crate::discrepancy::Settings,
}

const SWEEP_KEYS: [&str; 7] =
    ["kn_pa_per_m", "ks_over_kn", "friction_deg", "cohesion_pa", "length_m", "arrangement", "ends"];

/// End zone given to a wall made `rigid` by the `ends` key when it has none, m: the
/// paper's SBR ropes sat 0.05 m from each end.
pub const DEFAULT_END_ZONE_M: f64 = 0.05;

fn to_value(v: &toml::Value) -> Option<SweepValue> {
    match v {
        toml::Value::Integer(i) => Some(SweepValue::Number(*i as f64)),
        toml::Value::Float(f) => Some(SweepValue::Number(*f)),
        toml::Value::String(s) => Some(SweepValue::Text(s.clone())),
        _ => None,
    }
}

/// Applies one override to a wall description.
fn apply(spec: &mut WallSpec, key: &str, value: &SweepValue) -> Result<(), String> {
    let num = || match value {
        SweepValue::Number(v) if v.is_finite() => Ok(*v),
        other => Err(format!("expects a finite number, got {other}")),
    };
    match key {
        "kn_pa_per_m" => {
            let kn = num()?;
            if kn <= 0.0 {
                return Err(format!("must be > 0, got {kn}"));
            }
            for m in &mut spec.materials {
                let ratio = m.ks_pa_per_m / m.kn_pa_per_m;
                m.kn_pa_per_m = kn;
                m.ks_pa_per_m = kn * ratio;
            }
        }
        "ks_over_kn" => {
            let r = num()?;
            if r <= 0.0 {
                return Err(format!("must be > 0, got {r}"));
            }
            for m in &mut spec.materials {
                m.ks_pa_per_m = m.kn_pa_per_m * r;
            }
        }
        "friction_deg" => {
            let p = num()?;
            for m in &mut spec.materials {
                m.friction_deg = p;
            }
        }
        "cohesion_pa" => {
            let c = num()?;
            for m in &mut spec.materials {
                m.cohesion_pa = c;
            }
        }
        "length_m" => spec.geometry.length_m = num()?,
        "ends" => match value {
            SweepValue::Text(s) if s == "free" => {
                spec.restraints.ends = crate::generator::spec::EndsSpec::default();
            }
            SweepValue::Text(s) if s == "rigid" => {
                let e = &mut spec.restraints.ends;
                e.kind = crate::generator::spec::EndKind::Rigid;
                e.zone_m = Some(e.zone_m.unwrap_or(DEFAULT_END_ZONE_M));
                e.stiffness_n_per_m = None;
            }
            other => return Err(format!("expects free or rigid, got {other}")),
        },
        "arrangement" => {
            let kind = match value {
                SweepValue::Text(s) if s == "continuous" => ArrangementKind::Continuous,
                SweepValue::Text(s) if s == "discontinuous" => ArrangementKind::Discontinuous,
                SweepValue::Text(s) if s == "irregular" => ArrangementKind::Irregular,
                other => return Err(format!("expects continuous, discontinuous or irregular, got {other}")),
            };
            spec.arrangement.kind = kind;
        }
        _ => return Err(format!("unknown key; known keys: {}", SWEEP_KEYS.join(", "))),
    }
    Ok(())
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

    /// Checks the study and resolves every wall and measured file.
    ///
    /// # Errors
    /// The first problem found, naming the file and key.
    pub fn resolve(&self, path: &Path) -> Result<Study, StudyError> {
        let invalid =
            |key: &str, reason: String| StudyError::Invalid { path: path.to_owned(), key: key.into(), reason };
        if self.version != 1 {
            return Err(invalid("version", format!("this drystone reads study version 1, got {}", self.version)));
        }
        if self.realizations == 0 {
            return Err(invalid("realizations", "must be at least 1".into()));
        }
        if self.groups.is_empty() {
            return Err(invalid("groups", "at least one group is needed".into()));
        }
        let range =
            |table: &'static str| move |e: crate::range::OutOfRange| invalid(&format!("{table}.{}", e.key), e.reason());
        self.tilt.validate().map_err(range("tilt"))?;
        self.lateral.validate().map_err(range("lateral"))?;
        self.solver.validate().map_err(range("solver"))?;
        // Sweep points: cartesian product in key order, the last key varying fastest.
        let mut points: Vec<SweepPoint> = vec![Vec::new()];
        for (key, values) in &self.sweep {
            if values.is_empty() {
                return Err(invalid(&format!("sweep.{key}"), "needs at least one value".into()));
            }
            let mut next = Vec::new();
            for p in &points {
                for v in values {
                    let sv = to_value(v)
                        .ok_or_else(|| invalid(&format!("sweep.{key}"), format!("{v} is not a number or text")))?;
                    let mut q = p.clone();
                    q.push((key.clone(), sv));
                    next.push(q);
                }
            }
            points = next;
        }
        let dir = path.parent().unwrap_or(Path::new("."));
        let mut names = std::collections::BTreeSet::new();
        let mut groups = Vec::new();
        for g in &self.groups {
            if !names.insert(g.name.clone()) {
                return Err(invalid(&format!("groups[{}].name", g.name), "duplicate group name".into()));
            }
            if g.realizations == Some(0) {
                return Err(invalid(&format!("groups[{}].realizations", g.name), "must be at least 1".into()));
            }
            let wall_path = dir.join(&g.wall);
            let text = std::fs::read_to_string(&wall_path).map_err(|source| StudyError::Invalid {
                path: path.to_owned(),
                key: format!("groups[{}].wall", g.name),
                reason: format!("cannot read {}: {source}", wall_path.display()),
            })?;
            let base = WallSpec::from_toml(&text, &wall_path).map_err(|source| StudyError::Wall {
                path: path.to_owned(),
                group: g.name.clone(),
                source: Box::new(source),
            })?;
            let source = DistributionSource::default_for(&wall_path);
            let mut gspec = base.clone();
            for (k, v) in &g.overrides {
                let sv = to_value(v).ok_or_else(|| {
                    invalid(&format!("groups[{}].overrides.{k}", g.name), format!("{v} is not a number or text"))
                })?;
                apply(&mut gspec, k, &sv).map_err(|r| invalid(&format!("groups[{}].overrides.{k}", g.name), r))?;
            }
            let mut walls = Vec::with_capacity(points.len());
            for p in &points {
                let mut spec = gspec.clone();
                for (k, v) in p {
                    apply(&mut spec, k, v).map_err(|r| invalid(&format!("sweep.{k}"), r))?;
                }
                let wall = spec.resolve(&wall_path, &source).map_err(|source| StudyError::Wall {
                    path: path.to_owned(),
                    group: g.name.clone(),
                    source: Box::new(source),
                })?;
                walls.push(wall);
            }
            groups.push(Group {
                name: g.name.clone(),
                measured_group: g.measured_group.clone().unwrap_or_else(|| g.name.clone()),
                wall_path,
                walls,
                realizations: g.realizations,
                spec: gspec,
            });
        }
        let mut measured = Measured::default();
        if let Some(m) = &self.measured {
            let err = |source| StudyError::Measured { path: path.to_owned(), source };
            if let Some(c) = &m.collapse {
                measured.collapse = table::read_measured_collapse(&dir.join(c)).map_err(err)?;
            }
            if let Some(d) = &m.displacement {
                measured.displacement = table::read_measured_displacement(&dir.join(d)).map_err(err)?;
            }
            if let Some(d) = &m.paper_dem {
                measured.paper_dem = table::read_paper_dem(&dir.join(d)).map_err(err)?;
            }
        }
        let study = Study {
            name: self.name.clone(),
            description: self.description.clone(),
            path: path.to_owned(),
            seed: self.seed,
            realizations: self.realizations,
            protocol: self.protocol,
            tilt: self.tilt,
            lateral: self.lateral,
            solver: self.solver,
            groups,
            points,
            measured,
            paper: self.paper,
            calibrate: self.calibrate.clone(),
            discrepancy: self.discrepancy.clone().unwrap_or_default(),
        };
        study.discrepancy.validate().map_err(|e| invalid("discrepancy", e.to_string()))?;
        for (i, c) in study.calibrate.iter().enumerate() {
            c.check(&study).map_err(|r| invalid(&format!("calibrate[{i}]"), r))?;
        }
        if let Some(p) = study.paper {
            paper::check(p, &study).map_err(|r| invalid("paper", r))?;
        }
        Ok(study)
    }
}

impl Study {
    /// Reads and resolves a study file.
    ///
    /// # Errors
    /// Any [`StudyError`].
    pub fn from_file(path: &Path) -> Result<Study, StudyError> {
        StudySpec::from_file(path)?.resolve(path)
    }

    /// All work items of the study.
    pub fn items(&self) -> Vec<crate::ensemble::Item> {
        let counts: Vec<u64> = (0..self.groups.len()).map(|g| self.group_realizations(g)).collect();
        crate::ensemble::items_per_group(&counts, self.points.len())
    }

    /// The wall of group `g` with its overrides and then `values` applied (sweep keys),
    /// resolved and checked.
    ///
    /// # Errors
    /// [`StudyError::Invalid`] for a bad key or value, [`StudyError::Wall`] if the wall no
    /// longer checks.
    pub fn wall_with(&self, g: usize, values: &[(String, SweepValue)]) -> Result<Wall, StudyError> {
        let group = &self.groups[g];
        let mut spec = group.spec.clone();
        for (k, v) in values {
            apply(&mut spec, k, v).map_err(|reason| StudyError::Invalid {
                path: self.path.clone(),
                key: k.clone(),
                reason,
            })?;
        }
        let source = DistributionSource::default_for(&group.wall_path);
        spec.resolve(&group.wall_path, &source).map_err(|source| StudyError::Wall {
            path: self.path.clone(),
            group: group.name.clone(),
            source: Box::new(source),
        })
    }

    /// Realizations per sweep point of group `g`: its own count, or the study's.
    pub fn group_realizations(&self, g: usize) -> u64 {
        self.groups[g].realizations.unwrap_or(self.realizations)
    }
}
