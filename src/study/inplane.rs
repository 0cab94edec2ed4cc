//! The in-plane shear–compression test's rows (`protocol = "in_plane"`): one realization
//! run by the study's method (the penalty DEM or nscd, `[solver] kind`) with limit analysis
//! beside it ([`realization`]), its row ([`InPlaneRow`]) and `realizations.csv`. The study
//! file is read by the study core ([`super::inplane_spec`]); its run directory, journal,
//! shards and merge are [`super::inplane_run`]'s, its statistics, comparison, figures and
//! report [`super::inplane_report`]'s.
//!
//! Realization i of group g is the wall generated with the study's seed and index
//! `g · 10000 + i` (`generator::generate`), with the group's effects applied
//! (`effects::realize`): the same bits on any thread count.

use crate::dem::SolverParams;
use crate::generator::Wall;
use crate::limit::inplane::limit_in_plane;
use crate::loading::inplane::{InPlaneParams, InPlaneResult};
use crate::loading::inplane_loops::{loop_damping_ratio, LOOP_MIN_DRIFT_PCT};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

pub use super::inplane_error::InPlaneStudyError;
pub use super::inplane_measured::{
    read_envelope, read_envelope_of, read_loops, read_specimens, EnvelopeReadings, Specimen, CURVE_COLUMNS,
};

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
    group: &str,
    params: &InPlaneParams,
    solver: SolverParams,
) -> InPlaneRow {
    let t0 = std::time::Instant::now();
    let index = g as u64 * 10_000 + i;
    let mut row = InPlaneRow::empty(group.to_string(), i, index);
    let layout = match realized(wall, effects, seed, index, group) {
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
