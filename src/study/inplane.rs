//! The study of the in-plane shear–compression test (`protocol = "in_plane"`): groups of
//! generated walls, each under its vertical stress and loading history, run as ensembles
//! by the penalty DEM (and by limit analysis beside it), compared with measured specimens.
//!
//! The protocol owns its outputs here: its study file's keys ([`InPlaneStudySpec`]), its
//! rows (`realizations.csv`, one per realization, and the run's journal, each row synced
//! as it finishes so that nothing finished is lost if the run is stopped), its statistics
//! (`summary.csv`: per group and observable the ensemble's mean, σ, COV and 95 % band), its
//! comparison with the measured specimens (`comparison.csv`), its figures (the ensemble's
//! force–drift curves over the measured envelopes, `curves_<group>.svg`; the mechanism of
//! realization 0 drawn over the wall, `mechanism_<group>.svg`) and its report (`report.md`).
//!
//! # The study file
//!
//! ```toml
//! version = 1
//! name = "inplane_granite"
//! seed = 20090301
//! realizations = 8
//! protocol = "in_plane"
//!
//! [in_plane]                 # every group's test (loading::inplane::InPlaneParams)
//! shear_span_m = 1.325
//! drift_pct = 3.25
//!
//! [[groups]]
//! name = "0.5 MPa monotonic"
//! wall = "walls/granite_vasconcelos.toml"
//! sigma0_mpa = 0.5
//! history = "monotonic"      # or "cyclic"
//! specimens = ["WS.100"]     # rows of the measured file compared with this group
//! realizations = 8           # optional: the study's by default
//! effects = { seating_gap = { max_gap_m = 4.2e-4 } }  # optional: on top of the study's
//!
//! [effects]                  # optional: every group's model extended (crate::effects)
//! jack_tilt = { inverse_length_per_m = 0.54 }
//!
//! [measured]
//! walls = "../data/inplane_granite/walls.csv"          # the database's columns
//! envelopes = "../data/inplane_granite/envelopes"      # envelope_<unit>_<source>.csv
//! crackmaps = "../data/inplane_granite/crackmaps"      # optional: linked in the report
//! ```
//!
//! Realization i of group g is the wall generated with the study's seed and index
//! `g · 10000 + i` (`generator::generate`), with the group's effects applied
//! (`effects::realize`): the same bits on any thread count.

use crate::dem::SolverParams;
use crate::generator::Wall;
use crate::limit::inplane::limit_in_plane;
use crate::loading::inplane::{History, InPlaneParams, InPlaneResult};
use crate::loading::inplane_loops::{loop_damping_ratio, LOOP_MIN_DRIFT_PCT};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

pub use super::inplane_error::InPlaneStudyError;
pub use super::inplane_measured::{
    read_envelope, read_envelope_of, read_loops, read_specimens, EnvelopeReadings, Specimen, CURVE_COLUMNS,
};

/// The in-plane study file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InPlaneStudySpec {
    /// Format version: 1.
    pub version: u32,
    /// The study's name (the output folder's by default).
    pub name: String,
    /// What it is, with the sources of its parameters.
    #[serde(default)]
    pub description: String,
    /// Master seed.
    pub seed: u64,
    /// Realizations per group (a group may give its own), ≥ 1.
    pub realizations: u64,
    /// `"in_plane"`.
    pub protocol: String,
    /// The test's parameters shared by the groups (`sigma0_mpa` and `history` are the
    /// groups').
    #[serde(default)]
    pub in_plane: InPlaneParams,
    /// The groups.
    pub groups: Vec<InPlaneGroupSpec>,
    /// The method every realization's test runs by and its settings (`[solver]`, as in
    /// every study: `kind` any method of the protocol's `WAYS` that draws the curve, the
    /// penalty DEM with any of its cascades or nscd; the protocol's default without it).
    /// Limit analysis runs beside it whatever the kind (`limit_peak_kn`), by
    /// `[solver.limit]`.
    #[serde(default)]
    pub solver: SolverParams,
    /// Effects applied to every group's model (`[effects] NAME = { PARAM = VALUE }`, as in a
    /// tilting-table study: [`crate::effects`]), e.g. the extended model a discrepancy
    /// analysis fitted. Default none.
    #[serde(default)]
    pub effects: super::spec::EffectsSpec,
    /// The measured specimens.
    #[serde(default)]
    pub measured: Option<InPlaneMeasuredSpec>,
    /// The settings of its discrepancy analysis (`drystone discrepancy`;
    /// [`super::inplane_discrepancy`]).
    #[serde(default)]
    pub discrepancy: Option<crate::discrepancy::Settings>,
}

/// One group: a wall under one vertical stress and history.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InPlaneGroupSpec {
    /// Its name.
    pub name: String,
    /// The wall description file, relative to the study file (exactly one of `wall` and
    /// `survey`).
    #[serde(default)]
    pub wall: Option<PathBuf>,
    /// A surveyed wall instead (a traced elevation or scanned stones, as `drystone import`
    /// reads them), relative to the study file: the realizations are the ensemble around it
    /// ([`crate::survey::ensemble`]) that `import` states.
    #[serde(default)]
    pub survey: Option<PathBuf>,
    /// With `survey`: the import's options and the survey's uncertainty, as a core study's
    /// group states them ([`super::survey_spec::SurveyImportSpec`]; `thickness_m` and the
    /// stones' material required).
    #[serde(default)]
    pub import: Option<super::survey_spec::SurveyImportSpec>,
    /// The vertical stress applied, MPa.
    pub sigma0_mpa: f64,
    /// The history.
    #[serde(default)]
    pub history: History,
    /// The measured specimens compared with it (`unit` of the measured file).
    #[serde(default)]
    pub specimens: Vec<String>,
    /// Its realizations (the study's when absent).
    #[serde(default)]
    pub realizations: Option<u64>,
    /// Effects applied to this group's model on top of the study's `effects` (a value
    /// given here replaces the study's for that effect). Default none.
    #[serde(default)]
    pub effects: super::spec::EffectsSpec,
}

impl InPlaneGroupSpec {
    /// The file its wall comes from: the wall description, or the survey (relative to the
    /// study file).
    pub fn source(&self) -> &Path {
        self.wall.as_deref().or(self.survey.as_deref()).unwrap_or(Path::new(""))
    }
}

/// The wall of group `g` of the in-plane study `spec` read from the file `path`: its wall
/// description, or the ensemble around its survey ([`super::survey::wall_of_survey`]).
///
/// # Errors
/// A wall description that cannot be read (named), a survey that cannot be imported or an
/// `import` table that does not state it (naming the group's key).
pub(super) fn group_wall(spec: &InPlaneStudySpec, path: &Path, g: usize) -> Result<Wall, InPlaneStudyError> {
    let group = &spec.groups[g];
    let base = path.parent().unwrap_or(Path::new("."));
    match (&group.wall, &group.survey) {
        (None, Some(survey)) => {
            let import = group.import.clone().unwrap_or_default();
            super::survey::wall_of_survey(&group.name, &import, survey, base, path)
                .map_err(|(key, message)| InPlaneStudyError::Invalid { path: path.to_owned(), key, message })
        }
        _ => {
            let p = base.join(group.source());
            Wall::from_file_with(&p, &crate::generator::DistributionSource::default_for(&p))
                .map_err(|e| InPlaneStudyError::File { path: p.clone(), message: e.to_string() })
        }
    }
}

/// Where the measured specimens are.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InPlaneMeasuredSpec {
    /// The specimens' table (the Stone Masonry Database's columns: `unit`, `loading`,
    /// `Vmax_pos_kN`, `dmax_pos_pct`, …), relative to the study file.
    pub walls: PathBuf,
    /// The folder of the envelopes `envelope_<unit without dots>_<source>.csv`.
    #[serde(default)]
    pub envelopes: Option<PathBuf>,
    /// The folder of the crack maps (PNG), linked in the report.
    #[serde(default)]
    pub crackmaps: Option<PathBuf>,
    /// The folder of the whole measured curves `FD_<unit without dots>_<source>.csv` (the
    /// database's), read for the cyclic specimens' loops ([`Specimen::damping_ratio`]).
    #[serde(default)]
    pub curves: Option<PathBuf>,
}

/// Whether a study file names the in-plane protocol (`protocol = "in_plane"`).
pub fn is_in_plane(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .is_some_and(|t| t.get("protocol").and_then(|p| p.as_str()) == Some("in_plane"))
}

/// One realization's row.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct InPlaneRow {
    /// Group name.
    pub group: String,
    /// Realization index within the group.
    pub realization: u64,
    /// The generator's index (`g · 10000 + i`).
    pub index: u64,
    /// `ok` or `error`.
    pub status: String,
    /// The error, if any.
    pub error: String,
    /// Peak force, drift at peak, ultimate drift, initial stiffness, + direction.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub peak_pos_kn: f64,
    /// See `peak_pos_kn`.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub drift_at_peak_pos_pct: f64,
    /// See `peak_pos_kn`.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub ultimate_drift_pos_pct: f64,
    /// See `peak_pos_kn`.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub stiffness_pos_kn_per_mm: f64,
    /// The same, − direction (NaN for monotonic runs).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub peak_neg_kn: f64,
    /// See `peak_neg_kn`.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub drift_at_peak_neg_pct: f64,
    /// See `peak_neg_kn`.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub ultimate_drift_neg_pct: f64,
    /// See `peak_neg_kn`.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub stiffness_neg_kn_per_mm: f64,
    /// The mechanism's kind.
    pub mechanism: String,
    /// The database's failure type of the mechanism.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub failure_type: f64,
    /// The share of the crack's motion that is opening.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub opening_share: f64,
    /// Limit analysis's peak force, kN.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub limit_peak_kn: f64,
    /// Limit analysis's mechanism.
    pub limit_mechanism: String,
    /// The rigid rocking capacity N_total L / (2 H0), kN.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub rocking_kn: f64,
    /// The equivalent viscous damping ratio of its loops (the cycles of at least
    /// [`LOOP_MIN_DRIFT_PCT`] % drift, [`loop_damping_ratio`]); NaN for a monotonic run.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub damping_ratio: f64,
    /// Robust reading of the envelope (the envelope's force at 0.5 % drift, + (kN); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub force_at_0_5_pos_kn: f64,
    /// Robust reading of the envelope (the envelope's force at 1 % drift, + (kN); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub force_at_1_pos_kn: f64,
    /// Robust reading of the envelope (the envelope's force at 2 % drift, + (kN); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub force_at_2_pos_kn: f64,
    /// Robust reading of the envelope (drift at 80 % of the peak, + (%); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub drift_at_80_pos_pct: f64,
    /// Robust reading of the envelope (drift at 95 % of the peak, + (%); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub drift_at_95_pos_pct: f64,
    /// Robust reading of the envelope (plateau slope past 95 % of the peak, + (kN per % drift); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub plateau_slope_pos_kn_per_pct: f64,
    /// Robust reading of the envelope (the envelope's force at 0.5 % drift, − (kN); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub force_at_0_5_neg_kn: f64,
    /// Robust reading of the envelope (the envelope's force at 1 % drift, − (kN); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub force_at_1_neg_kn: f64,
    /// Robust reading of the envelope (the envelope's force at 2 % drift, − (kN); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub force_at_2_neg_kn: f64,
    /// Robust reading of the envelope (drift at 80 % of the peak, − (%); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub drift_at_80_neg_pct: f64,
    /// Robust reading of the envelope (drift at 95 % of the peak, − (%); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub drift_at_95_neg_pct: f64,
    /// Robust reading of the envelope (plateau slope past 95 % of the peak, − (kN per % drift); [`crate::loading::inplane::DirectionResult`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub plateau_slope_neg_kn_per_pct: f64,
    /// The wall's vertical modulus read in the vertical loading phase, MPa (the database's
    /// `Epc`; [`InPlaneResult::wall_vertical_modulus_mpa`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub vertical_modulus_mpa: f64,
    /// The largest excursion of a block from its course over the history, mm
    /// ([`InPlaneResult::largest_block_excursion_mm`]).
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub largest_block_excursion_mm: f64,
    /// The block of `largest_block_excursion_mm`.
    pub excursion_block: String,
    /// Static solves that did not reach equilibrium.
    pub unconverged: usize,
    /// Wall-clock time, s.
    #[serde(with = "crate::ensemble::row::exact::one")]
    pub wall_time_s: f64,
    /// The curve (drift %, force kN), not written to the CSV (journaled, for the figures
    /// of a resumed or merged run).
    #[serde(with = "crate::ensemble::row::exact::pairs")]
    pub curve: Vec<(f64, f64)>,
    /// The poses at the mechanism's reading and the mechanism, for the report's drawing.
    #[serde(skip)]
    pub drawing: Option<(Vec<(crate::math::Vec3, crate::math::Vec3)>, crate::loading::inplane::InPlaneMechanism)>,
}

impl InPlaneRow {
    /// A row of group `group`'s realization `realization` (generator index `index`) with
    /// status `error`, every reading NaN and no curve: what a realization that fails before
    /// it gives anything reports.
    pub fn empty(group: String, realization: u64, index: u64) -> InPlaneRow {
        InPlaneRow {
            group,
            realization,
            index,
            status: "error".into(),
            error: String::new(),
            peak_pos_kn: f64::NAN,
            drift_at_peak_pos_pct: f64::NAN,
            ultimate_drift_pos_pct: f64::NAN,
            stiffness_pos_kn_per_mm: f64::NAN,
            peak_neg_kn: f64::NAN,
            drift_at_peak_neg_pct: f64::NAN,
            ultimate_drift_neg_pct: f64::NAN,
            stiffness_neg_kn_per_mm: f64::NAN,
            mechanism: String::new(),
            failure_type: f64::NAN,
            opening_share: f64::NAN,
            limit_peak_kn: f64::NAN,
            limit_mechanism: String::new(),
            rocking_kn: f64::NAN,
            damping_ratio: f64::NAN,
            force_at_0_5_pos_kn: f64::NAN,
            force_at_1_pos_kn: f64::NAN,
            force_at_2_pos_kn: f64::NAN,
            drift_at_80_pos_pct: f64::NAN,
            drift_at_95_pos_pct: f64::NAN,
            plateau_slope_pos_kn_per_pct: f64::NAN,
            force_at_0_5_neg_kn: f64::NAN,
            force_at_1_neg_kn: f64::NAN,
            force_at_2_neg_kn: f64::NAN,
            drift_at_80_neg_pct: f64::NAN,
            drift_at_95_neg_pct: f64::NAN,
            plateau_slope_neg_kn_per_pct: f64::NAN,
            vertical_modulus_mpa: f64::NAN,
            largest_block_excursion_mm: f64::NAN,
            excursion_block: String::new(),
            unconverged: 0,
            wall_time_s: 0.0,
            curve: Vec::new(),
            drawing: None,
        }
    }
}

/// What a run of the study gave.
#[derive(Debug, Clone)]
pub struct InPlaneStudyRun {
    /// The rows, group by group, realization by realization.
    pub rows: Vec<InPlaneRow>,
    /// The report's text (empty for a shard).
    pub report: String,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
    /// How many of the rows came from the journal of an earlier run (`--resume`).
    pub resumed: usize,
}

/// Reads and checks an in-plane study file.
///
/// # Errors
/// Naming the file and the key.
pub fn load(path: &Path) -> Result<InPlaneStudySpec, InPlaneStudyError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| InPlaneStudyError::File { path: path.to_owned(), message: e.to_string() })?;
    let mut spec: InPlaneStudySpec =
        toml::from_str(&text).map_err(|e| InPlaneStudyError::File { path: path.to_owned(), message: e.to_string() })?;
    let bad =
        |key: &str, message: String| InPlaneStudyError::Invalid { path: path.to_owned(), key: key.into(), message };
    // The groups' own keys: given in `[in_plane]` they would be overwritten by every group.
    if let Some(t) =
        text.parse::<toml::Table>().ok().and_then(|t| t.get("in_plane").and_then(|v| v.as_table()).cloned())
    {
        for key in ["sigma0_mpa", "history"] {
            if t.contains_key(key) {
                return Err(bad(
                    &format!("in_plane.{key}"),
                    format!("is each group's ([[groups]] {key}), not the study's: give it in every group"),
                ));
            }
        }
    }
    spec.solver = super::solver::with_default_kind(spec.solver, crate::protocol::Loading::InPlane, &text);
    spec.solver.validate_static().map_err(|e| bad(&format!("solver.{}", e.key), e.reason()))?;
    super::solver::check_method(crate::protocol::Loading::InPlane, &spec.solver)
        .map_err(|(key, why)| bad(&key, why))?;
    if !spec.solver.kind.method().draws_curves() {
        return Err(bad(
            "solver.kind",
            format!(
                "{:?}: {} gives no force-displacement curve, which the study's rows read (it runs beside \
                 every realization, limit_peak_kn): give kind = \"penalty\" or \"nscd\"",
                spec.solver.kind.name(),
                spec.solver.kind.method().describe()
            ),
        ));
    }
    if spec.version != 1 {
        return Err(bad("version", format!("{} is not a known version (1)", spec.version)));
    }
    if spec.protocol != "in_plane" {
        return Err(bad("protocol", format!("{:?}: this reader runs \"in_plane\"", spec.protocol)));
    }
    if spec.realizations == 0 {
        return Err(bad("realizations", "must be at least 1".into()));
    }
    if spec.groups.is_empty() {
        return Err(bad("groups", "at least one [[groups]] table".into()));
    }
    for (g, group) in spec.groups.iter().enumerate() {
        if let Some((k, s)) = group.specimens.iter().enumerate().find(|(k, s)| group.specimens[..*k].contains(s)) {
            return Err(bad(
                &format!("groups[{g}].specimens[{k}]"),
                format!("{s} is named twice: a specimen is compared once with its group"),
            ));
        }
        if let Some(first) = spec.groups[..g].iter().position(|o| o.name == group.name) {
            return Err(bad(
                &format!("groups[{g}].name"),
                format!("{:?} is also the name of groups[{first}]: every group needs its own name", group.name),
            ));
        }
        let p = InPlaneParams { sigma0_mpa: group.sigma0_mpa, history: group.history, ..spec.in_plane.clone() };
        p.validate().map_err(|e| bad(&format!("groups[{g}] ({}): in_plane", group.name), e.to_string()))?;
        if group.realizations == Some(0) {
            return Err(bad(&format!("groups[{g}].realizations"), "must be at least 1".into()));
        }
        let key = match (&group.wall, &group.survey) {
            (Some(_), None) if group.import.is_some() => {
                return Err(bad(
                    &format!("groups[{g}].import"),
                    "is for a group naming a survey; this group names a wall description".into(),
                ))
            }
            (Some(_), None) => "wall",
            (None, Some(_)) => "survey",
            (Some(_), Some(_)) => {
                return Err(bad(
                    &format!("groups[{g}]"),
                    "names both a wall and a survey: a group is one wall description (wall) or one survey (survey)"
                        .into(),
                ))
            }
            (None, None) => {
                return Err(bad(
                    &format!("groups[{g}]"),
                    "names no wall: give wall = a wall description, or survey = a traced elevation".into(),
                ))
            }
        };
        let wall = path.parent().unwrap_or(Path::new(".")).join(group.source());
        if !wall.exists() {
            return Err(bad(&format!("groups[{g}].{key}"), format!("{} does not exist", wall.display())));
        }
    }
    refuse_out_of_plane(&spec, path)?;
    if let Some((key, why)) = spec.in_plane.unread_key(spec.groups.iter().any(|g| g.history == History::Cyclic)) {
        return Err(bad(&format!("in_plane.{key}"), why.into()));
    }
    Ok(spec)
}

/// Refuses the effects an in-plane study states that the in-plane test does not read
/// ([`crate::effects::EffectDef::not_read_in_plane`]: `initial_lean`, `table_kick`,
/// `restraint_stiffness`, `end_rope`, `base_restraint`, `leaf_split`, `transverse_dip`),
/// in its model (`effects`, `groups[g].effects`) and in its analysis's candidates
/// (`[discrepancy] effects`, `also_effects`): accepted, they would run the plain wall (or,
/// for a lean or base stops, a wall whose extent across its plane gives the rig another
/// thickness) under the effect's name. An unknown effect is left to the reader that
/// resolves it.
///
/// # Errors
/// [`InPlaneStudyError::Invalid`] naming the key and the effect.
pub fn refuse_out_of_plane(spec: &InPlaneStudySpec, path: &Path) -> Result<(), InPlaneStudyError> {
    let library = crate::effects::Library::builtin();
    let refuse = |key: &str, name: &str| -> Result<(), InPlaneStudyError> {
        match library.get(name).ok().and_then(|d| d.not_read_in_plane()) {
            Some(reason) => Err(InPlaneStudyError::Invalid {
                path: path.to_owned(),
                key: key.to_string(),
                message: format!("{name}: the in-plane test does not read it ({reason})"),
            }),
            None => Ok(()),
        }
    };
    for g in 0..spec.groups.len() {
        for (key, name, _) in super::inplane::stated_effects(spec, g) {
            refuse(&key, name)?;
        }
    }
    if let Some(d) = &spec.discrepancy {
        for (list, names) in [("effects", &d.effects), ("also_effects", &d.also_effects)] {
            for name in names {
                refuse(&format!("discrepancy.{list}"), name)?;
            }
        }
    }
    Ok(())
}

/// The effects of group `g`'s model, each with the key that states it: the study's
/// `effects` the group does not restate, then the group's own.
pub fn stated_effects(spec: &InPlaneStudySpec, g: usize) -> Vec<(String, &str, &BTreeMap<String, f64>)> {
    let group = &spec.groups[g];
    let mut v: Vec<(String, &str, &BTreeMap<String, f64>)> = spec
        .effects
        .iter()
        .filter(|(n, _)| !group.effects.contains_key(*n))
        .map(|(n, values)| (format!("effects.{n}"), n.as_str(), values))
        .collect();
    v.extend(group.effects.iter().map(|(n, values)| (format!("groups[{g}].effects.{n}"), n.as_str(), values)));
    v
}

/// The effects of group `g`'s model ([`stated_effects`]) resolved in the built-in library
/// for its wall, applied to every realization ([`crate::effects::realize`]).
///
/// # Errors
/// [`InPlaneStudyError::Invalid`] naming the effect's key: an unknown effect or parameter,
/// a value out of its range, an effect that cannot act on realization 0 of the wall.
pub fn group_effects(
    spec: &InPlaneStudySpec,
    path: &Path,
    g: usize,
    wall: &Wall,
) -> Result<Vec<crate::effects::Effect>, InPlaneStudyError> {
    let library = crate::effects::Library::builtin();
    let course_m = crate::effects::course_height_of(wall);
    let bad =
        |key: &str, message: String| InPlaneStudyError::Invalid { path: path.to_owned(), key: key.into(), message };
    let stated = stated_effects(spec, g);
    let effects: Vec<crate::effects::Effect> = stated
        .iter()
        .map(|(key, name, values)| library.from_values(name, values, course_m).map_err(|e| bad(key, e.to_string())))
        .collect::<Result<_, _>>()?;
    if let Some((key, ..)) = stated.first() {
        if let Err(e) = crate::effects::realize(wall, spec.seed, 0, &spec.groups[g].name, &effects) {
            if !matches!(e, crate::effects::EffectError::Generator(_)) {
                return Err(bad(key, e.to_string()));
            }
        }
    }
    Ok(effects)
}

fn nan_dir() -> (f64, f64, f64, f64) {
    (f64::NAN, f64::NAN, f64::NAN, f64::NAN)
}

/// The layout of realization `index` of a group's wall with its effects.
pub(super) fn realized(
    wall: &Wall,
    effects: &[crate::effects::Effect],
    seed: u64,
    index: u64,
    group: &str,
) -> Result<crate::layout::Layout, String> {
    crate::effects::realize(wall, seed, index, group, effects).map(|(_, l)| l).map_err(|e| e.to_string())
}

/// One realization: the generated wall with its group's effects, its test by the penalty
/// DEM and by limit analysis.
#[allow(clippy::too_many_arguments)]
pub(super) fn realization(
    wall: &Wall,
    effects: &[crate::effects::Effect],
    seed: u64,
    g: usize,
    i: u64,
    group: &InPlaneGroupSpec,
    params: &InPlaneParams,
    solver: SolverParams,
) -> InPlaneRow {
    let t0 = std::time::Instant::now();
    let index = g as u64 * 10_000 + i;
    let mut row = InPlaneRow::empty(group.name.clone(), i, index);
    let layout = match realized(wall, effects, seed, index, &group.name) {
        Ok(l) => l,
        Err(e) => {
            row.error = e;
            return row;
        }
    };
    match crate::protocol::run(&crate::protocol::InPlane(params.clone()), &layout, solver, &mut ()) {
        Ok(crate::protocol::InPlaneRun::Penalty(Ok(r)) | crate::protocol::InPlaneRun::Nscd(Ok(r))) => {
            fill(&mut row, &r)
        }
        Ok(
            crate::protocol::InPlaneRun::Penalty(Err(e))
            | crate::protocol::InPlaneRun::Nscd(Err(e))
            | crate::protocol::InPlaneRun::Limit(Err(e)),
        ) => row.error = e.to_string(),
        Ok(crate::protocol::InPlaneRun::Limit(Ok(_))) => row.error = "limit analysis gives no curve".into(),
        Err(e) => row.error = e.to_string(),
    }
    if let Ok(l) = limit_in_plane(&layout, &solver, params, &solver.limit) {
        row.limit_peak_kn = l.peak_force_kn;
        row.limit_mechanism = l.mechanism.kind.name().into();
    }
    row.wall_time_s = t0.elapsed().as_secs_f64();
    row
}

fn fill(row: &mut InPlaneRow, r: &InPlaneResult) {
    row.status = "ok".into();
    let d = |x: Option<crate::loading::inplane::DirectionResult>| {
        x.map_or(nan_dir(), |d| {
            (d.peak_force_kn, d.drift_at_peak_pct, d.ultimate_drift_pct, d.initial_stiffness_kn_per_mm)
        })
    };
    (row.peak_pos_kn, row.drift_at_peak_pos_pct, row.ultimate_drift_pos_pct, row.stiffness_pos_kn_per_mm) =
        d(r.positive);
    (row.peak_neg_kn, row.drift_at_peak_neg_pct, row.ultimate_drift_neg_pct, row.stiffness_neg_kn_per_mm) =
        d(r.negative);
    if let Some(x) = r.positive {
        row.force_at_0_5_pos_kn = x.force_at_drift_kn[1];
        row.force_at_1_pos_kn = x.force_at_drift_kn[2];
        row.force_at_2_pos_kn = x.force_at_drift_kn[3];
        row.drift_at_80_pos_pct = x.drift_at_80_pct;
        row.drift_at_95_pos_pct = x.drift_at_95_pct;
        row.plateau_slope_pos_kn_per_pct = x.plateau_slope_kn_per_pct;
    }
    if let Some(x) = r.negative {
        row.force_at_0_5_neg_kn = x.force_at_drift_kn[1];
        row.force_at_1_neg_kn = x.force_at_drift_kn[2];
        row.force_at_2_neg_kn = x.force_at_drift_kn[3];
        row.drift_at_80_neg_pct = x.drift_at_80_pct;
        row.drift_at_95_neg_pct = x.drift_at_95_pct;
        row.plateau_slope_neg_kn_per_pct = x.plateau_slope_kn_per_pct;
    }
    row.vertical_modulus_mpa = r.wall_vertical_modulus_mpa;
    row.largest_block_excursion_mm = r.largest_block_excursion_mm;
    row.excursion_block = r.excursion_block.clone();
    row.mechanism = r.mechanism.kind.name().into();
    row.failure_type = r.mechanism.kind.failure_type().unwrap_or(f64::NAN);
    row.opening_share = r.mechanism.opening_share;
    row.rocking_kn = r.rocking_force_kn;
    row.unconverged = r.unconverged;
    row.curve = r.curve.iter().map(|p| (p.drift_pct, p.force_kn)).collect();
    row.damping_ratio = loop_damping_ratio(&row.curve, LOOP_MIN_DRIFT_PCT);
    row.drawing = Some((r.poses_at_reading.clone(), r.mechanism.clone()));
}

/// The columns of `realizations.csv` of an in-plane study, in their order, each with its
/// cell: the one list the header and the rows follow (a test checks that every field of
/// [`InPlaneRow`] the rows serialize is one of them).
const ROW_COLUMNS: &[(&str, fn(&InPlaneRow) -> String)] = &[
    ("group", |r| format!("\"{}\"", r.group)),
    ("realization", |r| r.realization.to_string()),
    ("index", |r| r.index.to_string()),
    ("status", |r| r.status.clone()),
    ("peak_pos_kn", |r| r.peak_pos_kn.to_string()),
    ("drift_at_peak_pos_pct", |r| r.drift_at_peak_pos_pct.to_string()),
    ("ultimate_drift_pos_pct", |r| r.ultimate_drift_pos_pct.to_string()),
    ("stiffness_pos_kn_per_mm", |r| r.stiffness_pos_kn_per_mm.to_string()),
    ("peak_neg_kn", |r| r.peak_neg_kn.to_string()),
    ("drift_at_peak_neg_pct", |r| r.drift_at_peak_neg_pct.to_string()),
    ("ultimate_drift_neg_pct", |r| r.ultimate_drift_neg_pct.to_string()),
    ("stiffness_neg_kn_per_mm", |r| r.stiffness_neg_kn_per_mm.to_string()),
    ("mechanism", |r| r.mechanism.clone()),
    ("failure_type", |r| r.failure_type.to_string()),
    ("opening_share", |r| r.opening_share.to_string()),
    ("limit_peak_kn", |r| r.limit_peak_kn.to_string()),
    ("limit_mechanism", |r| r.limit_mechanism.clone()),
    ("rocking_kn", |r| r.rocking_kn.to_string()),
    ("damping_ratio", |r| r.damping_ratio.to_string()),
    ("force_at_0_5_pos_kn", |r| r.force_at_0_5_pos_kn.to_string()),
    ("force_at_1_pos_kn", |r| r.force_at_1_pos_kn.to_string()),
    ("force_at_2_pos_kn", |r| r.force_at_2_pos_kn.to_string()),
    ("drift_at_80_pos_pct", |r| r.drift_at_80_pos_pct.to_string()),
    ("drift_at_95_pos_pct", |r| r.drift_at_95_pos_pct.to_string()),
    ("plateau_slope_pos_kn_per_pct", |r| r.plateau_slope_pos_kn_per_pct.to_string()),
    ("force_at_0_5_neg_kn", |r| r.force_at_0_5_neg_kn.to_string()),
    ("force_at_1_neg_kn", |r| r.force_at_1_neg_kn.to_string()),
    ("force_at_2_neg_kn", |r| r.force_at_2_neg_kn.to_string()),
    ("drift_at_80_neg_pct", |r| r.drift_at_80_neg_pct.to_string()),
    ("drift_at_95_neg_pct", |r| r.drift_at_95_neg_pct.to_string()),
    ("plateau_slope_neg_kn_per_pct", |r| r.plateau_slope_neg_kn_per_pct.to_string()),
    ("vertical_modulus_mpa", |r| r.vertical_modulus_mpa.to_string()),
    ("largest_block_excursion_mm", |r| r.largest_block_excursion_mm.to_string()),
    ("excursion_block", |r| r.excursion_block.clone()),
    ("unconverged", |r| r.unconverged.to_string()),
    ("wall_time_s", |r| format!("{:.3}", r.wall_time_s)),
    ("error", |r| format!("\"{}\"", r.error.replace('"', "'"))),
];

pub(super) fn write_rows(path: &Path, rows: &[InPlaneRow]) -> Result<(), InPlaneStudyError> {
    let mut s = ROW_COLUMNS.iter().map(|(name, _)| *name).collect::<Vec<_>>().join(",");
    s.push('\n');
    for r in rows {
        let _ = writeln!(s, "{}", ROW_COLUMNS.iter().map(|(_, cell)| cell(r)).collect::<Vec<_>>().join(","));
    }
    crate::io::replace_file(path, s.as_bytes()).map_err(|e| InPlaneStudyError::Write(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field of a row the rows serialize is a column of `realizations.csv`
    /// ([`ROW_COLUMNS`]), and every column a field: a field added to [`InPlaneRow`]
    /// without its column fails here.
    #[test]
    fn every_field_of_an_in_plane_row_is_a_column() {
        let row = InPlaneRow::empty("G".into(), 0, 0);
        let serde_json::Value::Object(fields) = serde_json::to_value(&row).unwrap() else { panic!() };
        // The curve is journaled for the figures, not a column.
        let mut fields: Vec<&str> = fields.keys().map(String::as_str).filter(|f| *f != "curve").collect();
        let mut columns: Vec<&str> = ROW_COLUMNS.iter().map(|(name, _)| *name).collect();
        fields.sort_unstable();
        columns.sort_unstable();
        assert_eq!(fields, columns);
    }
}
