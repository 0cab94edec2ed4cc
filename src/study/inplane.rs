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
use crate::generator::{DistributionSource, Wall};
use crate::io::inplane::{crack_map_svg, force_drift, ForceDriftCurve};
use crate::limit::inplane::limit_in_plane;
use crate::loading::inplane::{mechanism_joints, History, InPlaneParams, InPlaneResult, Rig};
use crate::loading::inplane_loops::{loop_damping_ratio, LOOP_MIN_DRIFT_PCT};
use crate::stats::{mean, quantile, sd};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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
    /// The wall file, relative to the study file.
    pub wall: PathBuf,
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

/// Errors of the in-plane study, each naming its file and key.
#[derive(Debug, thiserror::Error)]
pub enum InPlaneStudyError {
    /// A file could not be read or parsed.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A key's value is refused.
    #[error("{path}: {key}: {message}")]
    Invalid {
        /// The study file.
        path: PathBuf,
        /// The key.
        key: String,
        /// Why.
        message: String,
    },
    /// An output could not be written.
    #[error("{0}")]
    Write(String),
}

/// Whether a study file names the in-plane protocol (`protocol = "in_plane"`).
pub fn is_in_plane(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .is_some_and(|t| t.get("protocol").and_then(|p| p.as_str()) == Some("in_plane"))
}

/// One measured specimen (the database's row).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Specimen {
    /// Its name.
    pub unit: String,
    /// Its source.
    pub reference: String,
    /// `Cyclic` or `Monotonic`: the history of the imposed displacement (the measured file's
    /// column; not a `protocol::Loading`).
    pub loading: String,
    /// Vertical stress applied, MPa.
    pub sigma0_mpa: f64,
    /// Peak force and drift at the peak, +, kN and %.
    pub vmax_pos_kn: f64,
    /// See `vmax_pos_kn`.
    pub dmax_pos_pct: f64,
    /// The same, −, kN and % (NaN for monotonic tests).
    pub vmax_neg_kn: f64,
    /// See `vmax_neg_kn`.
    pub dmax_neg_pct: f64,
    /// Ultimate drift +, − (%).
    pub du_pos_pct: f64,
    /// See `du_pos_pct`.
    pub du_neg_pct: f64,
    /// Initial stiffness +, − (kN/mm).
    pub kel_pos: f64,
    /// See `kel_pos`.
    pub kel_neg: f64,
    /// The failure modes the authors reported.
    pub modes: String,
    /// The database's failure type (1 flexural, 0.5 mixed, 0 shear).
    pub failure_type: f64,
    /// The envelope (drift %, force kN), if found.
    pub envelope: Vec<(f64, f64)>,
    /// The wall's height, mm (the column `H_mm`; NaN where the table has none).
    pub height_mm: f64,
    /// The equivalent viscous damping ratio of its loops
    /// ([`crate::loading::inplane_loops::loop_damping_ratio`] of its whole measured curve, the
    /// cycles of at least [`LOOP_MIN_DRIFT_PCT`] % of the file's drift, the displacement at
    /// the measuring point over its height); NaN for a monotonic test or without the curve
    /// ([`read_loops`]).
    pub damping_ratio: f64,
    /// The shear span `H0_mm`, mm (NaN where the table has none).
    pub shear_span_mm: f64,
    /// The height of the measuring point, mm: `HLVDT_mm`, or the shear span where it is
    /// empty (the database's rule; NaN where the table has neither).
    pub measuring_height_mm: f64,
    /// The wall's vertical modulus from the compression cycles at the start of the test,
    /// MPa (`Epc_MPa`; NaN where the table has none).
    pub epc_mpa: f64,
    /// The onset of cracking: drift (%) and force (kN) as the authors reported
    /// (`dcr_pct`, `Vcr_kN`; NaN where the table has none).
    pub dcr_pct: f64,
    /// See `dcr_pct`.
    pub vcr_kn: f64,
    /// The robust readings of the measured envelope, + and − directions
    /// ([`crate::loading::inplane::envelope_readings`]: force at
    /// [`crate::loading::inplane::READING_DRIFTS_PCT`], drifts at 80 % and 95 % of the peak,
    /// plateau slope); NaN without an envelope.
    pub readings_pos: EnvelopeReadings,
    /// See `readings_pos`.
    pub readings_neg: EnvelopeReadings,
}

/// The robust readings of one direction of an envelope (see
/// [`crate::loading::inplane::DirectionResult`]).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct EnvelopeReadings {
    /// The force at [`crate::loading::inplane::READING_DRIFTS_PCT`], kN.
    pub force_at_drift_kn: [f64; crate::loading::inplane::READING_DRIFTS_PCT.len()],
    /// The drift at 80 % of the peak, %.
    pub drift_at_80_pct: f64,
    /// The drift at 95 % of the peak, %.
    pub drift_at_95_pct: f64,
    /// The plateau's slope, kN per % drift.
    pub plateau_slope_kn_per_pct: f64,
}

impl Default for EnvelopeReadings {
    fn default() -> Self {
        EnvelopeReadings {
            force_at_drift_kn: [f64::NAN; crate::loading::inplane::READING_DRIFTS_PCT.len()],
            drift_at_80_pct: f64::NAN,
            drift_at_95_pct: f64::NAN,
            plateau_slope_kn_per_pct: f64::NAN,
        }
    }
}

impl EnvelopeReadings {
    /// The readings of the `sign` (+1 or −1) direction of a measured envelope (drift %,
    /// force kN, in the file's order): its points of that sign's drift, from the origin
    /// outwards, read by [`crate::loading::inplane::envelope_readings`], the same function
    /// as a run's.
    pub fn of(envelope: &[(f64, f64)], sign: f64) -> EnvelopeReadings {
        let mut env: Vec<(f64, f64)> =
            envelope.iter().map(|&(d, f)| (sign * d, sign * f)).filter(|p| p.0 > 0.0 && p.1.is_finite()).collect();
        env.sort_by(|a, b| a.0.total_cmp(&b.0));
        env.insert(0, (0.0, 0.0));
        let Some((ip, &(_, fp))) = env.iter().enumerate().max_by(|a, b| a.1 .1.total_cmp(&b.1 .1)) else {
            return EnvelopeReadings::default();
        };
        if env.len() < 2 || !(fp > 0.0) {
            return EnvelopeReadings::default();
        }
        let (force_at_drift_kn, drift_at_80_pct, drift_at_95_pct, plateau_slope_kn_per_pct) =
            crate::loading::inplane::envelope_readings(&env, ip, fp);
        EnvelopeReadings { force_at_drift_kn, drift_at_80_pct, drift_at_95_pct, plateau_slope_kn_per_pct }
    }
}

/// Reads the database's table of specimens (a CSV with a header; quoted fields).
///
/// # Errors
/// Naming the file, the line and the column.
pub fn read_specimens(path: &Path, envelopes: Option<&Path>) -> Result<Vec<Specimen>, InPlaneStudyError> {
    let err = |message: String| InPlaneStudyError::File { path: path.to_owned(), message };
    let text = std::fs::read_to_string(path).map_err(|e| err(e.to_string()))?;
    let mut lines = text.lines().enumerate();
    let header = split_csv(lines.next().ok_or_else(|| err("empty file".into()))?.1.trim_start_matches('\u{feff}'));
    let col = |name: &str| header.iter().position(|h| h == name).ok_or_else(|| err(format!("no column {name}")));
    let c = [
        "unit",
        "reference",
        "loading",
        "sigma0_applied_MPa",
        "Vmax_pos_kN",
        "dmax_pos_pct",
        "Vmax_neg_kN",
        "dmax_neg_pct",
        "du_pos_pct",
        "du_neg_pct",
        "Kel_pos_kN_per_mm",
        "Kel_neg_kN_per_mm",
        "failure_modes_reported",
        "failure_type",
    ]
    .map(col);
    let c: Vec<usize> = c.into_iter().collect::<Result<_, _>>()?;
    let height = header.iter().position(|h| h == "H_mm");
    // Columns the database added later: NaN where a table does not have them.
    let optional = |name: &str| header.iter().position(|h| h == name);
    let (h0_col, hlvdt_col, epc_col, dcr_col, vcr_col) =
        (optional("H0_mm"), optional("HLVDT_mm"), optional("Epc_MPa"), optional("dcr_pct"), optional("Vcr_kN"));
    let mut out = Vec::new();
    for (i, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let f = split_csv(line);
        let get = |k: usize| f.get(c[k]).cloned().unwrap_or_default();
        let opt_num = |col: Option<usize>| -> Result<f64, InPlaneStudyError> {
            let Some(k) = col else { return Ok(f64::NAN) };
            let v = f.get(k).map(|x| x.trim().to_string()).unwrap_or_default();
            if v.is_empty() {
                return Ok(f64::NAN);
            }
            v.parse::<f64>().map_err(|_| err(format!("line {}: column {}: {v:?} is not a number", i + 1, header[k])))
        };
        let num = |k: usize| -> Result<f64, InPlaneStudyError> {
            let s = get(k);
            if s.trim().is_empty() {
                return Ok(f64::NAN);
            }
            s.trim()
                .parse::<f64>()
                .map_err(|_| err(format!("line {}: column {}: {s:?} is not a number", i + 1, header[c[k]])))
        };
        let mut s = Specimen {
            unit: get(0),
            reference: get(1),
            loading: get(2),
            sigma0_mpa: num(3)?,
            vmax_pos_kn: num(4)?,
            dmax_pos_pct: num(5)?,
            vmax_neg_kn: num(6)?,
            dmax_neg_pct: num(7)?,
            du_pos_pct: num(8)?,
            du_neg_pct: num(9)?,
            kel_pos: num(10)?,
            kel_neg: num(11)?,
            modes: get(12),
            failure_type: num(13)?,
            envelope: Vec::new(),
            height_mm: match height {
                Some(k) => {
                    let v = f.get(k).map(|x| x.trim().to_string()).unwrap_or_default();
                    v.parse::<f64>().map_err(|_| err(format!("line {}: column H_mm: {v:?} is not a number", i + 1)))?
                }
                None => f64::NAN,
            },
            damping_ratio: f64::NAN,
            shear_span_mm: opt_num(h0_col)?,
            measuring_height_mm: f64::NAN,
            epc_mpa: opt_num(epc_col)?,
            dcr_pct: opt_num(dcr_col)?,
            vcr_kn: opt_num(vcr_col)?,
            readings_pos: EnvelopeReadings::default(),
            readings_neg: EnvelopeReadings::default(),
        };
        let hlvdt = opt_num(hlvdt_col)?;
        s.measuring_height_mm = if hlvdt.is_finite() { hlvdt } else { s.shear_span_mm };
        if s.epc_mpa.is_finite() && !s.sigma0_mpa.is_finite() {
            return Err(err(format!(
                "line {}: column Epc_MPa: a vertical modulus without the stress it was read at (sigma0_applied_MPa is empty)",
                i + 1
            )));
        }
        if let Some(dir) = envelopes {
            // `envelope_<unit without dots>_<first author><year>.csv`, the database's names.
            let p = dir.join(format!("envelope_{}.csv", file_stem(&s)));
            if p.exists() {
                s.envelope = read_envelope_of(&p, s.measuring_height_mm)?;
                s.readings_pos = EnvelopeReadings::of(&s.envelope, 1.0);
                s.readings_neg = EnvelopeReadings::of(&s.envelope, -1.0);
            }
        }
        out.push(s);
    }
    Ok(out)
}

/// Reads a curve file of the database (an envelope or a whole curve): four header lines
/// (unit, reference, columns, units), then `top_displacement mm, horizontal_force kN,
/// drift %` a line (`NaN` where a digitized segment breaks); returns the rows in order.
///
/// # Errors
/// Naming the file and the line.
fn read_points(path: &Path) -> Result<Vec<[f64; 3]>, InPlaneStudyError> {
    let err = |message: String| InPlaneStudyError::File { path: path.to_owned(), message };
    let text = std::fs::read_to_string(path).map_err(|e| err(e.to_string()))?;
    let mut pts = Vec::new();
    for (i, line) in text.lines().enumerate().skip(4) {
        if line.trim().is_empty() {
            continue;
        }
        let v: Vec<f64> = split_csv(line)
            .iter()
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| err(format!("line {}: {line:?} is not three numbers", i + 1)))?;
        if v.len() < 3 {
            return Err(err(format!("line {}: {line:?} is not three numbers", i + 1)));
        }
        pts.push([v[0], v[1], v[2]]);
    }
    Ok(pts)
}

/// Reads an envelope file ([`read_points`]'s format); returns (drift %, force kN).
///
/// # Errors
/// Naming the file and the line.
pub fn read_envelope(path: &Path) -> Result<Vec<(f64, f64)>, InPlaneStudyError> {
    Ok(read_points(path)?.into_iter().map(|p| (p[2], p[1])).collect())
}

/// Reads a curve or envelope file ([`read_points`]'s format) of a specimen whose
/// displacement is read at `measuring_height_mm` (NaN: not checked) and checks that its
/// drift column is its displacement column over that height (to the files' rounding:
/// 0.01 % of drift, or 1 % of the drift); returns (drift %, force kN).
///
/// # Errors
/// Naming the file, the line and the column, where the drift disagrees.
pub fn read_envelope_of(path: &Path, measuring_height_mm: f64) -> Result<Vec<(f64, f64)>, InPlaneStudyError> {
    let pts = read_points(path)?;
    check_drift_column(path, &pts, measuring_height_mm)?;
    Ok(pts.into_iter().map(|p| (p[2], p[1])).collect())
}

/// Checks that a curve file's drift column (% ) is its displacement column (mm) over
/// `height_mm` (NaN: not checked) to the files' rounding (0.01 % of drift or 1 % of it).
fn check_drift_column(path: &Path, pts: &[[f64; 3]], height_mm: f64) -> Result<(), InPlaneStudyError> {
    if !height_mm.is_finite() {
        return Ok(());
    }
    for (k, p) in pts.iter().enumerate() {
        let expect = 100.0 * p[0] / height_mm;
        if p[0].is_finite() && p[2].is_finite() && (p[2] - expect).abs() > 0.01_f64.max(0.01 * expect.abs()) {
            return Err(InPlaneStudyError::File {
                path: path.to_owned(),
                message: format!(
                    "data row {} (line {}): column drift: {} % is not the displacement {} mm over the measuring \
                     point's height {height_mm} mm ({expect:.4} %): the drift and displacement columns disagree",
                    k + 1,
                    k + 5,
                    p[2],
                    p[0]
                ),
            });
        }
    }
    Ok(())
}

/// Sets each cyclic specimen's [`Specimen::damping_ratio`] from its whole measured curve in
/// `dir` (`FD_<unit without dots>_<source>.csv`, [`read_points`]'s format), read on the
/// file's drift (the displacement at the measuring point over its height, checked against
/// the displacement column). A specimen without a curve file keeps NaN.
///
/// # Errors
/// `dir` not a folder, or a curve file that cannot be read or holds a line that is not
/// numbers, naming the folder or the file and the line.
pub fn read_loops(specimens: &mut [Specimen], dir: &Path) -> Result<(), InPlaneStudyError> {
    if !dir.is_dir() {
        return Err(InPlaneStudyError::File {
            path: dir.to_owned(),
            message: "[measured] curves: not a folder of the measured curves".into(),
        });
    }
    for s in specimens.iter_mut() {
        let p = dir.join(format!("FD_{}.csv", file_stem(s)));
        if !p.exists() {
            continue;
        }
        let pts = read_points(&p)?;
        check_drift_column(&p, &pts, s.measuring_height_mm)?;
        let curve: Vec<(f64, f64)> = pts.into_iter().map(|q| (q[2], q[1])).collect();
        s.damping_ratio = loop_damping_ratio(&curve, LOOP_MIN_DRIFT_PCT);
    }
    Ok(())
}

/// The database's file stem of a specimen: `<unit without dots>_<first author><year>`
/// (`WS1.100`, "Vasconcelos and Lourenço (2009)" → `WS1100_Vasconcelos2009`).
fn file_stem(s: &Specimen) -> String {
    let unit: String = s.unit.chars().filter(|c| *c != '.').collect();
    let author = s.reference.split_whitespace().next().unwrap_or_default();
    let year: String = s.reference.chars().filter(char::is_ascii_digit).collect();
    format!("{unit}_{author}{year}")
}

fn split_csv(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    for ch in line.chars() {
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur)),
            c => cur.push(c),
        }
    }
    out.push(cur);
    out
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

/// The observables compared, with their row accessors.
const OBSERVABLES: [(&str, &str, fn(&InPlaneRow) -> f64, fn(&Specimen) -> f64); 17] = [
    ("peak_pos_kn", "peak force + (kN)", |r| r.peak_pos_kn, |s| s.vmax_pos_kn),
    ("peak_neg_kn", "peak force − (kN)", |r| r.peak_neg_kn, |s| s.vmax_neg_kn),
    ("drift_at_peak_pos_pct", "drift at peak + (%)", |r| r.drift_at_peak_pos_pct, |s| s.dmax_pos_pct),
    ("drift_at_peak_neg_pct", "drift at peak − (%)", |r| r.drift_at_peak_neg_pct, |s| s.dmax_neg_pct),
    ("ultimate_drift_pos_pct", "ultimate drift + (%)", |r| r.ultimate_drift_pos_pct, |s| s.du_pos_pct),
    ("stiffness_pos_kn_per_mm", "initial stiffness + (kN/mm)", |r| r.stiffness_pos_kn_per_mm, |s| s.kel_pos),
    ("failure_type", "failure type (1 rocking, 0.5 mixed, 0 shear)", |r| r.failure_type, |s| s.failure_type),
    ("damping_ratio", "loops' equivalent damping ratio, cycles ≥ 1 % drift", |r| r.damping_ratio, |s| s.damping_ratio),
    (
        "force_at_0_5_pos_kn",
        "envelope's force at 0.5 % drift + (kN)",
        |r| r.force_at_0_5_pos_kn,
        |s| s.readings_pos.force_at_drift_kn[1],
    ),
    (
        "force_at_1_pos_kn",
        "envelope's force at 1 % drift + (kN)",
        |r| r.force_at_1_pos_kn,
        |s| s.readings_pos.force_at_drift_kn[2],
    ),
    (
        "force_at_2_pos_kn",
        "envelope's force at 2 % drift + (kN)",
        |r| r.force_at_2_pos_kn,
        |s| s.readings_pos.force_at_drift_kn[3],
    ),
    (
        "force_at_1_neg_kn",
        "envelope's force at 1 % drift − (kN)",
        |r| r.force_at_1_neg_kn,
        |s| s.readings_neg.force_at_drift_kn[2],
    ),
    (
        "drift_at_80_pos_pct",
        "drift at 80 % of the peak + (%)",
        |r| r.drift_at_80_pos_pct,
        |s| s.readings_pos.drift_at_80_pct,
    ),
    (
        "drift_at_95_pos_pct",
        "drift at 95 % of the peak + (%)",
        |r| r.drift_at_95_pos_pct,
        |s| s.readings_pos.drift_at_95_pct,
    ),
    (
        "plateau_slope_pos_kn_per_pct",
        "plateau slope past 95 % of the peak + (kN per % drift)",
        |r| r.plateau_slope_pos_kn_per_pct,
        |s| s.readings_pos.plateau_slope_kn_per_pct,
    ),
    ("vertical_modulus_mpa", "wall's vertical modulus, loading phase (MPa)", |r| r.vertical_modulus_mpa, |s| s.epc_mpa),
    (
        "largest_block_excursion_mm",
        "largest excursion of a block from its course (mm), simulated only",
        |r| r.largest_block_excursion_mm,
        |_| f64::NAN,
    ),
];

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
        let p = InPlaneParams { sigma0_mpa: group.sigma0_mpa, history: group.history, ..spec.in_plane.clone() };
        p.validate().map_err(|e| bad(&format!("groups[{g}] ({}): in_plane", group.name), e.to_string()))?;
        if group.realizations == Some(0) {
            return Err(bad(&format!("groups[{g}].realizations"), "must be at least 1".into()));
        }
        let wall = path.parent().unwrap_or(Path::new(".")).join(&group.wall);
        if !wall.exists() {
            return Err(bad(&format!("groups[{g}].wall"), format!("{} does not exist", wall.display())));
        }
    }
    refuse_out_of_plane(&spec, path)?;
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

/// What a study's runs and outputs read: its file checked, its measured specimens, its
/// groups' walls and effects.
pub(super) struct Prepared {
    /// The study file.
    pub spec: InPlaneStudySpec,
    /// The measured specimens (none without `[measured]`).
    pub specimens: Vec<Specimen>,
    /// Each group's wall.
    pub walls: Vec<Wall>,
    /// Each group's effects.
    pub effects: Vec<Vec<crate::effects::Effect>>,
}

impl Prepared {
    /// Reads the study `path` and everything its runs read.
    ///
    /// # Errors
    /// A bad study file, wall or measured file (named).
    pub fn read(path: &Path) -> Result<Prepared, InPlaneStudyError> {
        let spec = load(path)?;
        let base = path.parent().unwrap_or(Path::new("."));
        let specimens = match &spec.measured {
            Some(m) => {
                let mut s =
                    read_specimens(&base.join(&m.walls), m.envelopes.as_ref().map(|e| base.join(e)).as_deref())?;
                if let Some(c) = &m.curves {
                    read_loops(&mut s, &base.join(c))?;
                }
                s
            }
            None => Vec::new(),
        };
        for (g, group) in spec.groups.iter().enumerate() {
            if let Some(s) = group.specimens.iter().find(|s| !specimens.iter().any(|m| &m.unit == *s)) {
                return Err(InPlaneStudyError::Invalid {
                    path: path.to_owned(),
                    key: format!("groups[{g}].specimens"),
                    message: format!("{s} is not a unit of the measured file"),
                });
            }
        }
        let walls: Vec<Wall> = spec
            .groups
            .iter()
            .map(|g| {
                let p = base.join(&g.wall);
                Wall::from_file_with(&p, &DistributionSource::default_for(&p))
                    .map_err(|e| InPlaneStudyError::File { path: p.clone(), message: e.to_string() })
            })
            .collect::<Result<_, _>>()?;
        let effects: Vec<Vec<crate::effects::Effect>> =
            (0..spec.groups.len()).map(|g| group_effects(&spec, path, g, &walls[g])).collect::<Result<_, _>>()?;
        Ok(Prepared { spec, specimens, walls, effects })
    }

    /// Realizations per group.
    pub fn realizations(&self) -> Vec<u64> {
        self.spec.groups.iter().map(|g| g.realizations.unwrap_or(self.spec.realizations)).collect()
    }

    /// Realization `i` of group `g` (generator index `g · 10000 + i`).
    pub fn run_one(&self, g: usize, i: u64) -> InPlaneRow {
        let group = &self.spec.groups[g];
        let params =
            InPlaneParams { sigma0_mpa: group.sigma0_mpa, history: group.history, ..self.spec.in_plane.clone() };
        realization(&self.walls[g], &self.effects[g], self.spec.seed, g, i, group, &params, self.spec.solver)
    }

    /// Writes the rows (`realizations.csv`) into `dir`, and with `whole` (every item of the
    /// study, not a shard's) the statistics, the comparison, the figures and the report;
    /// returns the report's text. A group's first row that lacks its drawing (read back
    /// from a journal, which does not keep it) is drawn again from its realization, the
    /// same bits.
    ///
    /// # Errors
    /// An output that cannot be written.
    pub fn write(
        &self,
        path: &Path,
        dir: &Path,
        rows: &mut [InPlaneRow],
        whole: bool,
        elapsed_s: f64,
    ) -> Result<String, InPlaneStudyError> {
        write_rows(&dir.join("realizations.csv"), rows)?;
        if !whole {
            return Ok(String::new());
        }
        for (g, group) in self.spec.groups.iter().enumerate() {
            if let Some(r) = rows.iter_mut().find(|r| r.group == group.name && r.status == "ok") {
                if r.drawing.is_none() {
                    r.drawing = self.run_one(g, r.realization).drawing;
                }
            }
        }
        let s = &self.spec;
        report(s, path, dir, rows, &self.specimens, &self.walls, &self.effects, s.solver, elapsed_s)
    }
}

fn nan_dir() -> (f64, f64, f64, f64) {
    (f64::NAN, f64::NAN, f64::NAN, f64::NAN)
}

/// The layout of realization `index` of a group's wall with its effects.
fn realized(
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
fn realization(
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

fn write_rows(path: &Path, rows: &[InPlaneRow]) -> Result<(), InPlaneStudyError> {
    let mut s = ROW_COLUMNS.iter().map(|(name, _)| *name).collect::<Vec<_>>().join(",");
    s.push('\n');
    for r in rows {
        let _ = writeln!(s, "{}", ROW_COLUMNS.iter().map(|(_, cell)| cell(r)).collect::<Vec<_>>().join(","));
    }
    crate::io::replace_file(path, s.as_bytes()).map_err(|e| InPlaneStudyError::Write(e.to_string()))
}

/// Mean, σ, COV and the 95 % band (2.5 % and 97.5 % quantiles) of the finite values.
fn stats(x: &[f64]) -> (usize, f64, f64, f64, f64, f64) {
    let v: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
    let (m, s) = (mean(&v), sd(&v));
    (v.len(), m, s, s / m, quantile(&v, 0.025), quantile(&v, 0.975))
}

fn f(v: f64, d: usize) -> String {
    if v.is_finite() {
        format!("{v:.d$}")
    } else {
        "–".into()
    }
}

/// The method of the study's runs in the report's words: the penalty DEM with its
/// tolerance, another method with what it gives (its cell of the protocol's `WAYS`).
fn method_words(solver: SolverParams) -> String {
    let method = solver.kind.method();
    if solver.kind.is_penalty() {
        let cascade =
            if solver.kind.names_cascade() { format!(", the {} cascade", solver.kind.name()) } else { String::new() };
        format!(
            "the penalty DEM (dynamic relaxation to the unbalanced-force ratio {:e} per increment of the imposed \
             displacement{cascade})",
            solver.penalty.tolerance
        )
    } else {
        let what = crate::protocol::methods(crate::protocol::Loading::InPlane, method).unwrap_or_default();
        format!("{} ({what})", method.describe())
    }
}

#[allow(clippy::too_many_arguments)]
fn report(
    spec: &InPlaneStudySpec,
    path: &Path,
    out: &Path,
    rows: &[InPlaneRow],
    specimens: &[Specimen],
    walls: &[Wall],
    effects: &[Vec<crate::effects::Effect>],
    solver: SolverParams,
    elapsed_s: f64,
) -> Result<String, InPlaneStudyError> {
    let mut md = String::new();
    let mut summary = String::from("group,observable,n,mean,sd,cov,band_lo,band_hi\n");
    let mut comparison = String::from(
        "group,specimen,observable,measured,sim_mean,sim_sd,band_lo,band_hi,inside_band,ratio_measured_to_mean\n",
    );
    let _ = writeln!(md, "# {}\n", spec.name);
    let _ = writeln!(md, "{}\n", spec.description.trim());
    let ok = rows.iter().filter(|r| r.status == "ok").count();
    let _ = writeln!(
        md,
        "Study file `{}`; seed {}; {} realizations ({} failed); {:.1} s of wall-clock time. Method: {}, and limit \
         analysis beside it. Shear span {} m, largest drift {} %.\n",
        path.display(),
        spec.seed,
        rows.len(),
        rows.len() - ok,
        elapsed_s,
        method_words(solver),
        spec.in_plane.shear_span_m.map_or("–".into(), |h| h.to_string()),
        spec.in_plane.drift_pct
    );
    let _ = writeln!(
        md,
        "Readings as the measured files define them: the displacement is read on the loading beam at the measuring \
         point ({}), the drift is that displacement over the point's height (`drift_% = displacement_mm / {} × 100`), \
         and the stiffness (kN/mm) is read on the same displacement. The wall's vertical modulus is the secant of the \
         vertical loading phase (the stress the actuator adds over the wall's shortening, the beam's settlement \
         over the wall's height), as the database's `Epc` is read from the compression cycles at the start of each \
         test. Measured columns are data drystone did not make; the simulated columns are its own.\n",
        spec.in_plane.measuring_height_m.map_or_else(
            || "the actuator's height, the shear span, where a test reports none".to_string(),
            |h| format!("{h} m")
        ),
        spec.in_plane
            .measuring_height_m
            .or(spec.in_plane.shear_span_m)
            .map_or("H".to_string(), |h| format!("{}", h * 1e3))
    );
    for (g, group) in spec.groups.iter().enumerate() {
        let rs: Vec<&InPlaneRow> = rows.iter().filter(|r| r.group == group.name && r.status == "ok").collect();
        let ms: Vec<&Specimen> =
            group.specimens.iter().filter_map(|u| specimens.iter().find(|s| &s.unit == u)).collect();
        let slug: String =
            group.name.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '_' }).collect();
        let _ = writeln!(md, "## {}\n", group.name);
        if !effects[g].is_empty() {
            let stated: Vec<String> = stated_effects(spec, g)
                .iter()
                .map(|(_, name, values)| {
                    let v: Vec<String> = values.iter().map(|(k, v)| format!("{k} = {v}")).collect();
                    format!("`{name}` ({})", v.join(", "))
                })
                .collect();
            let _ = writeln!(md, "The model extended by {}.\n", stated.join(", "));
        }
        let _ = writeln!(
            md,
            "σ0 = {} MPa, {} history, wall `{}`; {} realizations; measured: {}.\n",
            group.sigma0_mpa,
            match group.history {
                History::Monotonic => "monotonic",
                History::Cyclic => "cyclic",
            },
            group.wall.display(),
            rs.len(),
            if ms.is_empty() {
                "none".to_string()
            } else {
                ms.iter().map(|m| m.unit.clone()).collect::<Vec<_>>().join(", ")
            }
        );
        let _ = writeln!(md, "| observable | measured | simulated mean | σ | COV | 95 % band | measured inside |");
        let _ = writeln!(md, "| --- | --- | --- | --- | --- | --- | --- |");
        for (key, label, get, meas) in OBSERVABLES {
            let d = if key == "damping_ratio" { 3 } else { 2 };
            let x: Vec<f64> = rs.iter().map(|r| get(r)).collect();
            let (n, m, s, cov, lo, hi) = stats(&x);
            if n == 0 {
                continue;
            }
            let _ = writeln!(summary, "\"{}\",{key},{n},{m},{s},{cov},{lo},{hi}", group.name);
            let measured: Vec<f64> = ms.iter().map(|s| meas(s)).filter(|v| v.is_finite()).collect();
            let inside = measured.iter().filter(|v| **v >= lo && **v <= hi).count();
            for (sp, v) in ms.iter().map(|s| (s, meas(s))).filter(|(_, v)| v.is_finite()) {
                let _ = writeln!(
                    comparison,
                    "\"{}\",{},{key},{v},{m},{s},{lo},{hi},{},{}",
                    group.name,
                    sp.unit,
                    v >= lo && v <= hi,
                    v / m
                );
            }
            let _ = writeln!(
                md,
                "| {label} | {} | {} | {} | {} | [{}, {}] | {} |",
                if measured.is_empty() {
                    "–".into()
                } else {
                    measured.iter().map(|v| f(*v, d)).collect::<Vec<_>>().join(", ")
                },
                f(m, d),
                f(s, d),
                f(cov, 3),
                f(lo, d),
                f(hi, d),
                if measured.is_empty() { "–".into() } else { format!("{inside} of {}", measured.len()) }
            );
        }
        let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
        for r in &rs {
            *kinds.entry(r.mechanism.as_str()).or_default() += 1;
        }
        let la: Vec<f64> = rs.iter().map(|r| r.limit_peak_kn).collect();
        let (_, la_m, _, _, _, _) = stats(&la);
        let mut la_kinds: BTreeMap<&str, usize> = BTreeMap::new();
        for r in &rs {
            *la_kinds.entry(r.limit_mechanism.as_str()).or_default() += 1;
        }
        let rock = rs.first().map_or(f64::NAN, |r| r.rocking_kn);
        let _ = writeln!(
            md,
            "\nMechanism ({}): {}; measured: {}. Limit analysis: peak {} kN (mean), mechanism {}. The \
             monolith's rigid rocking capacity N_total L / (2 H0) is {} kN.\n",
            solver.kind.method().describe().trim_start_matches("the "),
            kinds.iter().map(|(k, n)| format!("{k} {n}")).collect::<Vec<_>>().join(", "),
            if ms.is_empty() {
                "–".into()
            } else {
                ms.iter().map(|m| format!("{} ({})", m.modes, m.unit)).collect::<Vec<_>>().join(", ")
            },
            f(la_m, 2),
            la_kinds.iter().map(|(k, n)| format!("{k} {n}")).collect::<Vec<_>>().join(", "),
            f(rock, 2)
        );
        // The curves over the measured envelopes.
        let mut curves: Vec<ForceDriftCurve> = rs
            .iter()
            .enumerate()
            .map(|(k, r)| ForceDriftCurve {
                label: (k == 0).then(|| "simulated (each realization)".to_string()),
                colour: 0,
                measured: false,
                points: r.curve.clone(),
            })
            .collect();
        for (k, m) in ms.iter().enumerate() {
            if !m.envelope.is_empty() {
                curves.push(ForceDriftCurve {
                    label: Some(format!("{} envelope (measured)", m.unit)),
                    colour: k + 1,
                    measured: true,
                    points: m.envelope.clone(),
                });
            }
        }
        let svg = out.join(format!("curves_{slug}.svg"));
        force_drift(&svg, &group.name, &curves).map_err(|e| InPlaneStudyError::Write(e.to_string()))?;
        let _ = writeln!(md, "![force-drift curves](curves_{slug}.svg)\n");
        // The mechanism of realization 0 beside the measured crack map.
        if let Some((r0, (poses, mechanism))) = rs.first().and_then(|r| r.drawing.as_ref().map(|d| (r, d))) {
            let params =
                InPlaneParams { sigma0_mpa: group.sigma0_mpa, history: group.history, ..spec.in_plane.clone() };
            let layout = realized(&walls[g], &effects[g], spec.seed, r0.index, &group.name);
            if let Ok(rig) =
                layout.map_err(|e| e.to_string()).and_then(|l| Rig::build(&l, &params).map_err(|e| e.to_string()))
            {
                {
                    let sim = crate::dem::Simulation::new(&rig.layout, solver);
                    let svg = crack_map_svg(
                        &rig.layout,
                        poses,
                        &mechanism_joints(&sim),
                        mechanism,
                        &format!("{}: realization 0, {}", group.name, mechanism.kind.name()),
                    );
                    let p = out.join(format!("mechanism_{slug}.svg"));
                    crate::io::replace_file(&p, svg.as_bytes()).map_err(|e| InPlaneStudyError::Write(e.to_string()))?;
                    let _ = write!(md, "![mechanism, realization 0](mechanism_{slug}.svg)");
                    if let Some(dir) = spec.measured.as_ref().and_then(|m| m.crackmaps.as_ref()) {
                        for m in &ms {
                            let name = format!("crackmap_{}.png", file_stem(m));
                            let from = path.parent().unwrap_or(Path::new(".")).join(dir).join(&name);
                            if from.exists() && std::fs::copy(&from, out.join(&name)).is_ok() {
                                let _ = write!(md, " ![measured crack map {}]({name})", m.unit);
                            }
                        }
                    }
                    md.push_str("\n\n");
                }
            }
        }
    }
    let w = |name: &str, text: &str| {
        crate::io::replace_file(&out.join(name), text.as_bytes()).map_err(|e| InPlaneStudyError::Write(e.to_string()))
    };
    w("summary.csv", &summary)?;
    w("comparison.csv", &comparison)?;
    w("report.md", &md)?;
    Ok(md)
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
