//! The study file as written: serde types, strict (`deny_unknown_fields`), `version = 1`.
//! [`StudySpec::resolve`](crate::study::StudySpec::resolve) checks it into a
//! [`Study`](crate::study::Study).

use super::{StudyError, SweepKey};
use crate::dem::SolverParams;
use crate::loading::inplane::{History, InPlaneParams};
use crate::loading::lateral::LateralParams;
use crate::loading::shake::ShakeParams;
use crate::loading::tilt::TiltParams;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The loading protocol a study file names (`protocol = "tilt"`): the protocol registry's
/// [`crate::protocol::ProtocolKind`].
pub use crate::protocol::ProtocolKind;

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
    /// Shaking-table parameters and motions (protocol `shake`; see [`ShakeSpec`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shake: Option<ShakeSpec>,
    /// The in-plane test's parameters shared by the groups (protocol `in_plane`;
    /// [`crate::loading::inplane::InPlaneParams`] but `sigma0_mpa` and `history`, which are
    /// each group's; see [`super::inplane`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub in_plane: Option<InPlaneParams>,
    /// The compression test's parameters (protocol `compression`;
    /// [`crate::loading::compression::CompressionParams`], its `sigma0_mpa` the groups'
    /// default; see [`super::compression`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compression: Option<crate::loading::compression::CompressionParams>,
    /// Solver parameters: the method (`kind`) and its settings (`[solver.penalty]`,
    /// `[solver.nscd]`, `[solver.limit]`). The penalty settings the protocol's table
    /// still accepts under their former keys (`[tilt] tolerance`, ...; deprecated,
    /// `crate::dem::MovedKey`) are applied here when the study is resolved, with a warning.
    /// Without `kind`, a study read by [`StudySpec::from_file`] runs by
    /// its protocol's default solver (`protocol::Loading::default_solver`, as the command
    /// line does): `nscd` for the shaking table, the penalty DEM for every other protocol;
    /// a spec deserialized by other means keeps the penalty DEM.
    #[serde(default)]
    pub solver: SolverParams,
    /// Groups (≥ 1).
    pub groups: Vec<GroupSpec>,
    /// Sweep: key → values; every combination is a point (keys in sorted order, the last
    /// varying fastest). Keys: [`super::SweepKey`].
    #[serde(default)]
    pub sweep: BTreeMap<String, Vec<toml::Value>>,
    /// Measured data.
    #[serde(default)]
    pub measured: Option<MeasuredSpec>,
    /// Which of the source paper's studies this reproduces: adds its comparison to the
    /// report (see `paper`).
    #[serde(default)]
    pub paper: Option<PaperStudy>,
    /// Calibration steps (`drystone calibrate`; see [`calibrate`](super::calibrate)).
    #[serde(default)]
    pub calibrate: Vec<CalibrateSpec>,
    /// Model-discrepancy settings (`drystone discrepancy`; see
    /// [`crate::discrepancy::Settings`]).
    #[serde(default)]
    pub discrepancy: Option<crate::discrepancy::Settings>,
    /// Effects applied to every group's model: `{ NAME = { PARAM = VALUE } }` (see
    /// [`crate::effects`]). Default none.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub effects: EffectsSpec,
    /// Effect definition files (TOML, [`crate::effects::EffectDef::from_file`]), relative to
    /// the study file: their effects join the library by name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effect_files: Vec<PathBuf>,
}

/// The `[shake]` table of a study (protocol `shake`): the shaking-table parameters of
/// [`crate::loading::shake::ShakeParams`] (each optional, its default otherwise), the
/// motions and the intensity levels of the incremental dynamic analysis.
///
/// ```toml
/// [shake]
/// pga_g = [0.1, 0.2, 0.3]             # PGA levels, g (> 0, increasing)
/// records = ["records/RSN1.AT2"]      # PEER NGA .AT2 or .csv/.tsv, relative to the study file
/// stochastic = { count = 10, duration_s = 5.0 }   # generated motions (ground::StochasticMotion keys)
/// pulses = [{ kind = "one-sine", amplitude_g = 1.0, period_s = 0.5 }]  # built-in pulses
/// baseline_correction = false         # baseline-correct the records
/// tail_s = 2.0                        # ShakeParams keys
/// ```
///
/// Motion `i` of `stochastic` is `StochasticMotion::generate(study seed, i)`. Every motion
/// is scaled to every level ([`crate::ground::Motion::scaled_to_pga`]): the sweep keys
/// `motion` and `pga_g` of the study's points.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShakeSpec {
    /// PGA levels of the incremental dynamic analysis, g (> 0, strictly increasing; ≥ 1).
    #[serde(default)]
    pub pga_g: Vec<f64>,
    /// Record files (PEER NGA `.AT2`, `.csv`, `.tsv`), relative to the study file.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub records: Vec<PathBuf>,
    /// The columns of every CSV/TSV record named explicitly
    /// (`{ time = "t", h = "acc_x_g", v = "acc_z_g" }`, [`crate::ground::ColumnMap`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub columns: Option<crate::ground::ColumnMap>,
    /// Generated motions: `count` (≥ 1) and any key of
    /// [`crate::ground::StochasticMotion`] (its defaults otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stochastic: Option<toml::Table>,
    /// Built-in pulses (`{ kind = "one-sine" | "ricker", amplitude_g, period_s }`), sampled
    /// at the solver's time step; their amplitude is rescaled to each level like any motion.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pulses: Vec<crate::ground::Pulse>,
    /// Baseline-correct the records ([`crate::ground::Motion::baseline_corrected`])
    /// \[false\]. Generated motions are corrected by their model; pulses are not.
    #[serde(default)]
    pub baseline_correction: bool,
    /// [`ShakeParams::tail_s`], s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tail_s: Option<f64>,
    /// [`ShakeParams::duration_s`], s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// [`ShakeParams::settle_s`], s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settle_s: Option<f64>,
    /// [`ShakeParams::fall_rotation_deg`], degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fall_rotation_deg: Option<f64>,
    /// [`ShakeParams::stop_at_collapse`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop_at_collapse: Option<bool>,
    /// [`ShakeParams::vertical`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical: Option<bool>,
    /// [`ShakeParams::history_dt_s`], s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history_dt_s: Option<f64>,
    /// Deprecated: `[solver.penalty] contact_restitution` ([`ShakeParams::contact_restitution`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_restitution: Option<f64>,
    /// Deprecated: `[solver.penalty] step_fraction` ([`ShakeParams::penalty_step_fraction`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub penalty_step_fraction: Option<f64>,
}

impl ShakeSpec {
    /// The shaking-table parameters: the table's values over the defaults.
    pub fn params(&self) -> ShakeParams {
        let d = ShakeParams::default();
        ShakeParams {
            tail_s: self.tail_s.unwrap_or(d.tail_s),
            duration_s: self.duration_s.or(d.duration_s),
            settle_s: self.settle_s.unwrap_or(d.settle_s),
            fall_rotation_deg: self.fall_rotation_deg.unwrap_or(d.fall_rotation_deg),
            stop_at_collapse: self.stop_at_collapse.unwrap_or(d.stop_at_collapse),
            vertical: self.vertical.unwrap_or(d.vertical),
            history_dt_s: self.history_dt_s.unwrap_or(d.history_dt_s),
            contact_restitution: self.contact_restitution,
            penalty_step_fraction: self.penalty_step_fraction,
        }
    }
}

/// Effects with their parameter values: effect name → parameter name → value (in the
/// parameter's unit).
pub type EffectsSpec = BTreeMap<String, BTreeMap<String, f64>>;

/// A group of realizations: one wall description, or one survey (exactly one of `wall`
/// and `survey`).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupSpec {
    /// Group name.
    pub name: String,
    /// Wall description file, relative to the study file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall: Option<PathBuf>,
    /// A survey, relative to the study file: a traced elevation (.svg, .geojson, .dxf), the
    /// group's realizations the ensemble around it ([`crate::survey::ensemble`]), drawn as
    /// its `import` table states; or scanned stones (a folder, .obj, .stl), every
    /// realization the survey as scanned.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub survey: Option<PathBuf>,
    /// With `survey`: the options of `drystone import` and the survey's uncertainty
    /// ([`super::survey_spec::SurveyImportSpec`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub import: Option<super::survey_spec::SurveyImportSpec>,
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
    /// Effects applied to this group's model, on top of the study's `effects` (the same
    /// effect here replaces the study's values).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub effects: EffectsSpec,
    /// The vertical stress the in-plane test applies to this group, MPa (protocol
    /// `in_plane`, required there; protocol `compression`, the stress its modulus is read
    /// at, `[compression] sigma0_mpa` by default; refused by the other protocols).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma0_mpa: Option<f64>,
    /// The in-plane test's loading history of this group (protocol `in_plane`) \[monotonic\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<History>,
    /// The measured specimens compared with this group (protocol `in_plane`: units of
    /// `[measured] walls`). Default none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub specimens: Vec<String>,
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
    /// Failure mechanisms as seen: `specimen, group, failure_height_fraction,
    /// failure_height_low, failure_height_high, kind, start` (optional `extent_fraction`,
    /// `source`; see [`crate::io::measured`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mechanism: Option<PathBuf>,
    /// The paper's own DEM collapse angles (Table 7): `model, ends, phi_deg, kn_pa_per_m,
    /// collapse_angle_deg`.
    #[serde(default)]
    pub paper_dem: Option<PathBuf>,
    /// The in-plane test's specimens (protocol `in_plane`): the Stone Masonry Database's
    /// table (`unit`, `loading`, `Vmax_pos_kN`, `dmax_pos_pct`, …; [`super::inplane`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub walls: Option<PathBuf>,
    /// With `walls`: the folder of the envelopes `envelope_<unit without dots>_<source>.csv`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub envelopes: Option<PathBuf>,
    /// With `walls`: the folder of the crack maps (PNG), linked in the report.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crackmaps: Option<PathBuf>,
    /// With `walls`: the folder of the whole measured curves `FD_<unit without
    /// dots>_<source>.csv`, read for the cyclic specimens' loops.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curves: Option<PathBuf>,
}

impl StudySpec {
    /// Reads a study file.
    ///
    /// # Errors
    /// [`StudyError::Io`], [`StudyError::Parse`].
    pub fn from_file(path: &Path) -> Result<Self, StudyError> {
        let text = std::fs::read_to_string(path).map_err(|source| StudyError::Io { path: path.to_owned(), source })?;
        let parse = |message: String| StudyError::Parse { path: path.to_owned(), message };
        let mut spec: StudySpec = match text.parse::<toml::Table>().ok().and_then(|t| by_protocol_name(t).transpose()) {
            // `protocol = "tilt_by_hand"` or `"pushover"`: read as its kind with its table's choice.
            Some(table) => table.map_err(parse)?.try_into().map_err(|e: toml::de::Error| parse(e.to_string()))?,
            None => toml::from_str(&text).map_err(|e| parse(e.to_string()))?,
        };
        // Without `[solver] kind` a study runs by its protocol's default solver
        // (`protocol::Loading::default_solver`), as the command line does: the shaking
        // table's is nscd (docs/shake.md), every other protocol's the penalty DEM.
        spec.solver = super::solver::with_default_kind(spec.solver, spec.loading(), &text);
        // The in-plane test's groups' own keys: given in `[in_plane]` they would be
        // overwritten by every group (the table's type has them for the command line).
        let shared =
            text.parse::<toml::Table>().ok().and_then(|t| t.get("in_plane").and_then(|v| v.as_table()).cloned());
        if let Some(key) =
            ["sigma0_mpa", "history"].into_iter().find(|k| shared.as_ref().is_some_and(|t| t.contains_key(*k)))
        {
            return Err(StudyError::Invalid {
                path: path.to_owned(),
                key: format!("in_plane.{key}"),
                reason: format!("is each group's ([[groups]] {key}), not the study's: give it in every group"),
            });
        }
        Ok(spec)
    }
}

/// The key of its kind's table that chooses a protocol within its kind, and the value that
/// chooses it (`[tilt] by_hand`: a table, its keys' defaults; `[lateral] pushover = true`);
/// `None` for the first protocol of its kind, which its kind's name chooses. A study file
/// names either the protocol (`protocol = "tilt_by_hand"`, `"pushover"`: its
/// [`Loading::name`](crate::protocol::Loading::name), as `drystone.supports` does) or its
/// kind with this key (the former spelling, still read). The protocol states it
/// ([`crate::protocol::LoadingProtocol::CHOSEN_BY`]).
pub fn chosen_by(protocol: crate::protocol::Loading) -> Option<(&'static str, &'static str, toml::Value)> {
    use crate::protocol::Choice;
    protocol.chosen_by().map(|c| {
        let value = match c.value {
            Choice::Table => toml::Value::Table(toml::Table::new()),
            Choice::True => toml::Value::Boolean(true),
        };
        (c.table, c.key, value)
    })
}

/// A study file that names a protocol within a kind (`protocol = "tilt_by_hand"`,
/// `"pushover"`) rewritten as its kind with its table's choice ([`chosen_by`]): the same
/// study as the former spelling. `None` for a file that names a kind (or no protocol).
///
/// # Errors
/// The protocol's choice contradicted by its table (`protocol = "pushover"` with `[lateral]
/// pushover = false`).
fn by_protocol_name(mut table: toml::Table) -> Result<Option<toml::Table>, String> {
    let Some(name) = table.get("protocol").and_then(toml::Value::as_str).map(str::to_owned) else { return Ok(None) };
    let Some(protocol) = crate::protocol::Loading::from_name(&name) else { return Ok(None) };
    let Some((kind_table, key, value)) = chosen_by(protocol) else { return Ok(None) };
    table.insert("protocol".into(), toml::Value::String(protocol.kind().name().into()));
    let t = table.entry(kind_table).or_insert_with(|| toml::Value::Table(toml::Table::new()));
    let Some(t) = t.as_table_mut() else { return Err(format!("[{kind_table}] is not a table")) };
    match t.get(key) {
        None => {
            t.insert(key.into(), value);
        }
        Some(given) if given.same_type(&value) && (given.is_table() || *given == value) => {}
        Some(given) => {
            return Err(format!("protocol = {name:?} with [{kind_table}] {key} = {given}: the protocol chooses {key}"))
        }
    }
    Ok(Some(table))
}

/// Which of the source paper's studies a study file reproduces (`paper = "…"` in the study
/// file; see [`paper`](super::paper)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PaperStudy {
    /// Figure 10: joint arrangement under the static lateral load, swept over Kn.
    JointArrangement,
    /// Figure 11: drift against L/H, restrained and free ends.
    LengthHeight,
    /// Tables 7 and 8: collapse angle against Kn and φ, free and restrained ends.
    KnPhi,
}

/// One calibration step of a study file (`[[calibrate]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrateSpec {
    /// The group whose measured mean collapse angle is the target.
    pub group: String,
    /// `kn_pa_per_m` (searched in log10) or `friction_deg`.
    pub parameter: String,
    /// Lower end of the search interval (Pa/m or degrees).
    pub lower: f64,
    /// Upper end of the search interval.
    pub upper: f64,
    /// Tolerance on log10(Kn) or on φ (degrees). Default 0.02 for Kn, 0.5 for φ.
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// Brent iterations after the two end evaluations \[12\].
    #[serde(default = "default_iters")]
    pub max_iters: u64,
    /// Groups that take the value found in later steps.
    #[serde(default)]
    pub carry_to: Vec<String>,
    /// The paper's calibrated value, for the report.
    #[serde(default)]
    pub paper_value: Option<f64>,
}

fn default_iters() -> u64 {
    12
}

impl CalibrateSpec {
    /// Whether the parameter is Kn (searched in log10) rather than φ.
    pub(crate) fn is_kn(&self) -> bool {
        self.parameter == "kn_pa_per_m"
    }

    /// The sweep key of the parameter.
    pub(crate) fn key(&self) -> SweepKey {
        if self.is_kn() {
            SweepKey::KnPaPerM
        } else {
            SweepKey::FrictionDeg
        }
    }
}
