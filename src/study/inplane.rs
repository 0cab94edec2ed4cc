//! The in-plane shear–compression test's rows (`protocol = "in_plane"`): a realization run
//! by the study core ([`super::run::run_item`]: the study's method, the penalty DEM or
//! nscd, `[solver] kind`) gets its column group ([`InPlaneColumns`]) with limit analysis
//! beside it ([`in_plane_row`]), and the study's `realizations.csv` is the in-plane test's
//! columns ([`write_rows`]); `realizations.parquet`, the journal, shards and merge are the
//! core's. The study file is read by the study core ([`super::inplane_spec`]); its
//! statistics, comparison, figures and report are [`super::inplane_report`]'s.
//!
//! Realization i of group g is the wall generated with the study's seed and index
//! `g · 10000 + i` (its seed index, [`super::StudyProtocol::seed_index`]), with the group's
//! effects applied (`effects::realize`): the same bits on any thread count.

use super::Study;
use crate::dem::SolverParams;
use crate::ensemble::inplane_columns::InPlaneDrawing;
use crate::ensemble::row::{InPlaneColumns, RealizationRow, Status};
use crate::layout::Layout;
use crate::limit::inplane::limit_in_plane;
use crate::loading::inplane::{InPlaneParams, InPlaneResult};
use crate::loading::inplane_loops::{loop_damping_ratio, LOOP_MIN_DRIFT_PCT};
use crate::protocol::{InPlaneRun, ProtocolRun};
use std::fmt::Write as _;
use std::path::Path;
use std::sync::LazyLock;

pub use super::inplane_error::InPlaneStudyError;
pub use super::inplane_measured::{
    read_envelope, read_envelope_of, read_loops, read_specimens, EnvelopeReadings, Specimen, CURVE_COLUMNS,
};

/// A realization's row (`row`: its identification and block count) filled with what the
/// in-plane test gave (`run`, on `layout` with `params`, by `solver`), and limit analysis's
/// peak and mechanism of the same layout beside it: status `stood` with the readings, or
/// the run's error with the status `failure` ([`Status::of_failure`]) and the readings it
/// has.
pub(super) fn in_plane_row(
    mut row: RealizationRow,
    run: InPlaneRun,
    failure: Status,
    layout: &Layout,
    params: &InPlaneParams,
    solver: SolverParams,
) -> RealizationRow {
    let mut c = InPlaneColumns::default();
    let error = match run {
        InPlaneRun::Penalty(Ok(r)) | InPlaneRun::Nscd(Ok(r)) => {
            fill(&mut c, &r);
            (!r.shed_block.is_empty()).then(|| {
                let e =
                    format!("block {} shed from the wall (readings kept, left out of the statistics)", r.shed_block);
                (Status::ShedBlock, e)
            })
        }
        InPlaneRun::Penalty(Err(e)) | InPlaneRun::Nscd(Err(e)) | InPlaneRun::Limit(Err(e)) => {
            Some((failure, e.to_string()))
        }
        InPlaneRun::Limit(Ok(_)) => Some((failure, "limit analysis gives no curve".to_string())),
    };
    match error {
        None => row.status = Status::Stood,
        Some((status, e)) => {
            row.status = status;
            row.error = e;
        }
    }
    if let Ok(l) = limit_in_plane(layout, &solver, params, &solver.limit) {
        c.limit_peak_kn = l.peak_force_kn;
        c.limit_mechanism = l.mechanism.kind.name().into();
    }
    row.in_plane = Some(Box::new(c));
    row
}

fn fill(c: &mut InPlaneColumns, r: &InPlaneResult) {
    let nan = (f64::NAN, f64::NAN, f64::NAN, f64::NAN);
    let d = |x: Option<crate::loading::inplane::DirectionResult>| {
        x.map_or(nan, |d| (d.peak_force_kn, d.drift_at_peak_pct, d.ultimate_drift_pct, d.initial_stiffness_kn_per_mm))
    };
    (c.peak_pos_kn, c.drift_at_peak_pos_pct, c.ultimate_drift_pos_pct, c.stiffness_pos_kn_per_mm) = d(r.positive);
    (c.peak_neg_kn, c.drift_at_peak_neg_pct, c.ultimate_drift_neg_pct, c.stiffness_neg_kn_per_mm) = d(r.negative);
    if let Some(x) = r.positive {
        (c.force_at_0_25_pos_kn, c.force_at_0_5_pos_kn, c.force_at_1_pos_kn, c.force_at_2_pos_kn) =
            x.force_at_drift_kn.into();
        (c.drift_at_80_pos_pct, c.drift_at_95_pos_pct) = (x.drift_at_80_pct, x.drift_at_95_pct);
        c.plateau_slope_pos_kn_per_pct = x.plateau_slope_kn_per_pct;
    }
    if let Some(x) = r.negative {
        (c.force_at_0_25_neg_kn, c.force_at_0_5_neg_kn, c.force_at_1_neg_kn, c.force_at_2_neg_kn) =
            x.force_at_drift_kn.into();
        (c.drift_at_80_neg_pct, c.drift_at_95_neg_pct) = (x.drift_at_80_pct, x.drift_at_95_pct);
        c.plateau_slope_neg_kn_per_pct = x.plateau_slope_kn_per_pct;
    }
    c.vertical_modulus_mpa = r.wall_vertical_modulus_mpa;
    c.largest_block_excursion_mm = r.largest_block_excursion_mm;
    c.excursion_block = r.excursion_block.clone();
    c.course_widening_mm = r.course_widening_mm;
    c.in_plane_mechanism = r.mechanism.kind.name().into();
    c.failure_type = r.mechanism.kind.failure_type().unwrap_or(f64::NAN);
    c.opening_share = r.mechanism.opening_share;
    c.rocking_kn = r.rocking_force_kn;
    c.unconverged = r.unconverged as u64;
    c.curve_drift_pct = r.curve.iter().map(|p| p.drift_pct).collect();
    c.curve_force_kn = r.curve.iter().map(|p| p.force_kn).collect();
    c.damping_ratio = loop_damping_ratio(&c.curve(), LOOP_MIN_DRIFT_PCT);
    c.drawing = Some(Box::new((r.poses_at_reading.clone(), r.mechanism.clone())));
}

/// The in-plane readings of a row; every reading NaN for a row without them (a layout
/// that could not be made).
pub(super) fn readings(r: &RealizationRow) -> &InPlaneColumns {
    static NONE: LazyLock<InPlaneColumns> = LazyLock::new(InPlaneColumns::default);
    r.in_plane.as_deref().unwrap_or(&NONE)
}

/// The drawing of a row (its poses at the mechanism's reading and the mechanism): the one
/// its run kept, or, for a row read back from a journal or a shard, its realization run
/// again (the same layout and run, the same bits); `None` if that run fails.
pub(super) fn drawing(study: &Study, r: &RealizationRow) -> Option<InPlaneDrawing> {
    if let Some(d) = readings(r).drawing.as_deref() {
        return Some(d.clone());
    }
    let item = study.items().into_iter().nth(r.index as usize)?;
    let layout = super::run::realize_item(study, &item).ok()?;
    match study.protocol_of(item.group, item.point).run(&layout, study.solver) {
        ProtocolRun::InPlane(InPlaneRun::Penalty(Ok(x)) | InPlaneRun::Nscd(Ok(x))) => {
            Some((x.poses_at_reading, x.mechanism))
        }
        _ => None,
    }
}

/// A row of `realizations.csv` of an in-plane study: the core's row, its readings and its
/// seed index.
struct CsvRow<'a> {
    row: &'a RealizationRow,
    p: &'a InPlaneColumns,
    seed_index: u64,
}

/// The columns of `realizations.csv` of an in-plane study, in their order, each with its
/// cell: the one list the header and the rows follow (a test checks that every field of
/// [`InPlaneColumns`] but the curve is one of them). `index` is the realization's seed
/// index (`g · 10000 + i`), `status` `ok` for a run that gave its readings, else the
/// row's status (`no_initial_equilibrium`, `refused`, `blew_up`, or `shed_block` for a run
/// whose readings are kept but a block of its wall was shed,
/// [`crate::ensemble::row::Status`]) with the message in `error`.
const ROW_COLUMNS: &[(&str, fn(&CsvRow) -> String)] = &[
    ("group", |r| format!("\"{}\"", r.row.group)),
    ("realization", |r| r.row.realization.to_string()),
    ("index", |r| r.seed_index.to_string()),
    ("status", |r| if r.row.status.is_ok() { "ok" } else { r.row.status.as_str() }.to_string()),
    ("peak_pos_kn", |r| r.p.peak_pos_kn.to_string()),
    ("drift_at_peak_pos_pct", |r| r.p.drift_at_peak_pos_pct.to_string()),
    ("ultimate_drift_pos_pct", |r| r.p.ultimate_drift_pos_pct.to_string()),
    ("stiffness_pos_kn_per_mm", |r| r.p.stiffness_pos_kn_per_mm.to_string()),
    ("peak_neg_kn", |r| r.p.peak_neg_kn.to_string()),
    ("drift_at_peak_neg_pct", |r| r.p.drift_at_peak_neg_pct.to_string()),
    ("ultimate_drift_neg_pct", |r| r.p.ultimate_drift_neg_pct.to_string()),
    ("stiffness_neg_kn_per_mm", |r| r.p.stiffness_neg_kn_per_mm.to_string()),
    ("mechanism", |r| r.p.in_plane_mechanism.clone()),
    ("failure_type", |r| r.p.failure_type.to_string()),
    ("opening_share", |r| r.p.opening_share.to_string()),
    ("limit_peak_kn", |r| r.p.limit_peak_kn.to_string()),
    ("limit_mechanism", |r| r.p.limit_mechanism.clone()),
    ("rocking_kn", |r| r.p.rocking_kn.to_string()),
    ("damping_ratio", |r| r.p.damping_ratio.to_string()),
    ("force_at_0_25_pos_kn", |r| r.p.force_at_0_25_pos_kn.to_string()),
    ("force_at_0_5_pos_kn", |r| r.p.force_at_0_5_pos_kn.to_string()),
    ("force_at_1_pos_kn", |r| r.p.force_at_1_pos_kn.to_string()),
    ("force_at_2_pos_kn", |r| r.p.force_at_2_pos_kn.to_string()),
    ("drift_at_80_pos_pct", |r| r.p.drift_at_80_pos_pct.to_string()),
    ("drift_at_95_pos_pct", |r| r.p.drift_at_95_pos_pct.to_string()),
    ("plateau_slope_pos_kn_per_pct", |r| r.p.plateau_slope_pos_kn_per_pct.to_string()),
    ("force_at_0_25_neg_kn", |r| r.p.force_at_0_25_neg_kn.to_string()),
    ("force_at_0_5_neg_kn", |r| r.p.force_at_0_5_neg_kn.to_string()),
    ("force_at_1_neg_kn", |r| r.p.force_at_1_neg_kn.to_string()),
    ("force_at_2_neg_kn", |r| r.p.force_at_2_neg_kn.to_string()),
    ("drift_at_80_neg_pct", |r| r.p.drift_at_80_neg_pct.to_string()),
    ("drift_at_95_neg_pct", |r| r.p.drift_at_95_neg_pct.to_string()),
    ("plateau_slope_neg_kn_per_pct", |r| r.p.plateau_slope_neg_kn_per_pct.to_string()),
    ("vertical_modulus_mpa", |r| r.p.vertical_modulus_mpa.to_string()),
    ("largest_block_excursion_mm", |r| r.p.largest_block_excursion_mm.to_string()),
    ("excursion_block", |r| r.p.excursion_block.clone()),
    ("course_widening_mm", |r| r.p.course_widening_mm.to_string()),
    ("unconverged", |r| r.p.unconverged.to_string()),
    ("wall_time_s", |r| format!("{:.3}", r.row.wall_time_s)),
    ("error", |r| format!("\"{}\"", r.row.error.replace('"', "'"))),
];

/// Writes `realizations.csv` of the in-plane study `study` (its rows `rows`, in item order)
/// into `dir`: one line per realization, the columns of [`ROW_COLUMNS`].
///
/// # Errors
/// [`crate::io::FileError`] naming the file.
pub(super) fn write_rows(study: &Study, rows: &[RealizationRow], dir: &Path) -> Result<(), crate::io::FileError> {
    let items = study.items();
    let mut s = ROW_COLUMNS.iter().map(|(name, _)| *name).collect::<Vec<_>>().join(",");
    s.push('\n');
    for row in rows {
        let seed_index = items.get(row.index as usize).map_or(row.realization, |it| study.protocol.seed_index(it));
        let r = CsvRow { row, p: readings(row), seed_index };
        let _ = writeln!(s, "{}", ROW_COLUMNS.iter().map(|(_, cell)| cell(&r)).collect::<Vec<_>>().join(","));
    }
    crate::io::replace_file(&dir.join("realizations.csv"), s.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field of the in-plane column group the rows serialize but the curve is a column
    /// of `realizations.csv` ([`ROW_COLUMNS`], `in_plane_mechanism` as `mechanism`), with the
    /// core's columns of the row it writes, and every column one of those: a field added to
    /// [`InPlaneColumns`] without its column fails here.
    #[test]
    fn every_field_of_the_in_plane_group_is_a_column() {
        let serde_json::Value::Object(fields) = serde_json::to_value(InPlaneColumns::default()).unwrap() else {
            panic!()
        };
        let mut fields: Vec<&str> = fields
            .keys()
            .map(String::as_str)
            .filter(|f| !f.starts_with("curve_"))
            .map(|f| if f == "in_plane_mechanism" { "mechanism" } else { f })
            .chain(["group", "realization", "index", "status", "wall_time_s", "error"])
            .collect();
        let mut columns: Vec<&str> = ROW_COLUMNS.iter().map(|(name, _)| *name).collect();
        fields.sort_unstable();
        columns.sort_unstable();
        assert_eq!(fields, columns);
    }
}
