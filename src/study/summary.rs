//! Per-cell statistics of a study's rows (one cell per group and sweep point) and the
//! errors of writing reports: shared by the study report and the paper's comparisons.

use super::Study;
use crate::ensemble::row::{RealizationRow, Status};
use crate::io::plot;
use crate::io::table::TableError;
use crate::stats::{self, LognormalFragility, Summary};
use std::path::PathBuf;

/// Report errors.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// Writing a table.
    #[error(transparent)]
    Table(#[from] TableError),
    /// Writing a plot.
    #[error(transparent)]
    Plot(#[from] plot::PlotError),
    /// Writing a file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

/// Statistics of one group at one sweep point.
#[derive(Debug, Clone)]
pub struct CellSummary {
    /// Group name.
    pub group: String,
    /// Group index.
    pub group_index: usize,
    /// Sweep point index.
    pub point: usize,
    /// Sweep label.
    pub sweep: String,
    /// Realizations in all.
    pub n: usize,
    /// Realizations that failed (layout, equilibrium at α = 0, blow-up).
    pub failed: usize,
    /// Realizations that stood to the largest tilt.
    pub stood: usize,
    /// Collapse angle, degrees (collapsed realizations).
    pub collapse: Summary,
    /// Fitted lognormal fragility of the collapse angle.
    pub fragility: Option<LognormalFragility>,
    /// Displacement measure at 5° and 10° (cm): the group's measure in the measured data
    /// (SBL: mean of the top points; SBR: centre minus mean of ends; default: mean).
    pub disp5: Summary,
    /// See `disp5`.
    pub disp10: Summary,
    /// Name of the displacement measure.
    pub measure: String,
    /// Collapse angles of the collapsed realizations, in index order.
    pub angles: Vec<f64>,
    /// Static lateral load: realizations that collapsed under the load.
    pub lateral_collapsed: usize,
    /// Static lateral load: top displacement (largest of the three top points), cm.
    pub lateral_max: Summary,
    /// Static lateral load: top-centre displacement, cm.
    pub lateral_centre: Summary,
    /// Static lateral load: drift (top displacement / H).
    pub drift: Summary,
}

pub(super) fn measure_of(study: &Study, group: usize) -> String {
    let mg = &study.groups[group].measured_group;
    study
        .measured
        .displacement
        .iter()
        .find(|d| &d.group == mg)
        .map(|d| d.measure.clone())
        .unwrap_or_else(|| "mean_of_left_center_right".into())
}

/// Summaries of every (group, point) cell, in group-major order.
pub fn summarize(study: &Study, rows: &[RealizationRow]) -> Vec<CellSummary> {
    let mut out = Vec::new();
    for (gi, g) in study.groups.iter().enumerate() {
        let measure = measure_of(study, gi);
        for (pi, p) in study.points.iter().enumerate() {
            let cell: Vec<&RealizationRow> =
                rows.iter().filter(|r| r.group == g.name && r.point as usize == pi).collect();
            let angles: Vec<f64> =
                cell.iter().filter(|r| r.status == Status::Collapsed).filter_map(|r| r.collapse_angle_deg).collect();
            let d5: Vec<f64> =
                cell.iter().filter(|r| r.status.is_ok()).filter_map(|r| r.disp_measure_at(&measure, 5.0)).collect();
            let d10: Vec<f64> =
                cell.iter().filter(|r| r.status.is_ok()).filter_map(|r| r.disp_measure_at(&measure, 10.0)).collect();
            let stream = (gi * study.points.len() + pi) as u64;
            let lateral = |f: fn(&RealizationRow) -> Option<f64>| -> Vec<f64> {
                cell.iter().filter(|r| r.status == Status::Stood).filter_map(|r| f(r)).collect()
            };
            // Bootstrap streams of the lateral quantities: disjoint from the tilt ones.
            let lstream = (1u64 << 32) + stream * 3;
            out.push(CellSummary {
                group: g.name.clone(),
                group_index: gi,
                point: pi,
                sweep: super::point_label(p),
                n: cell.len(),
                failed: cell.iter().filter(|r| !r.status.is_ok()).count(),
                stood: cell.iter().filter(|r| r.status == Status::Stood).count(),
                collapse: stats::summarize(&angles, study.seed, stream * 3),
                fragility: LognormalFragility::fit(&angles),
                disp5: stats::summarize(&d5, study.seed, stream * 3 + 1),
                disp10: stats::summarize(&d10, study.seed, stream * 3 + 2),
                measure: measure.clone(),
                angles,
                lateral_collapsed: if study.protocol == super::ProtocolKind::Lateral {
                    cell.iter().filter(|r| r.status == Status::Collapsed).count()
                } else {
                    0
                },
                lateral_max: stats::summarize(&lateral(|r| r.lateral_disp_max_cm), study.seed, lstream),
                lateral_centre: stats::summarize(&lateral(|r| r.lateral_disp_centre_cm), study.seed, lstream + 1),
                drift: stats::summarize(&lateral(|r| r.lateral_drift), study.seed, lstream + 2),
            });
        }
    }
    out
}

/// A number in scientific notation with 3 decimals, `–` when not finite.
pub(super) fn sci(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3e}")
    } else {
        "–".into()
    }
}
