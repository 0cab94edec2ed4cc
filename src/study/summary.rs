//! Statistics of a study's rows: one [`CellSummary`] per group and sweep point, the
//! measured-against-simulated [`Comparison`]s, and `summary.csv`. A deterministic function
//! of the rows (in index order) and the study: the bootstrap streams are numbered by cell.

use super::{point_label, Study};
use crate::ensemble::row::{Measure, RealizationRow, Status};
use crate::io::table::{SimpleTable, TableColumn, TableError};
use crate::stats::{self, LognormalFragility, Summary};
use std::fmt::Write as _;
use std::path::Path;

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
    /// Whether the cell holds collapse load multipliers (`[lateral] pushover = true`).
    pub pushover: bool,
    /// The collapse load multiplier λ of the pressure by the DEM pushover (its last stable
    /// λ), over the realizations that have one.
    pub lambda_dem: Summary,
    /// The collapse load multiplier λ by limit analysis, over the realizations that have
    /// one.
    pub lambda_limit: Summary,
    /// The ratio λ_DEM / λ_limit of each realization that has both.
    pub lambda_ratio: Summary,
}

/// A measured-vs-simulated comparison line.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// Group.
    pub group: String,
    /// What is compared, e.g. `collapse angle [deg]`.
    pub quantity: String,
    /// Measured specimens.
    pub measured_n: usize,
    /// Measured mean.
    pub measured_mean: f64,
    /// Measured σ.
    pub measured_sd: f64,
    /// Simulated realizations.
    pub simulated_n: usize,
    /// Simulated mean.
    pub simulated_mean: f64,
    /// Simulated σ.
    pub simulated_sd: f64,
    /// Simulated 95 % prediction band of one realization.
    pub band: (f64, f64),
    /// Measured mean inside the band.
    pub inside: bool,
    /// Measured specimens inside the band.
    pub specimens_inside: usize,
}

pub(super) fn measure_of(study: &Study, group: usize) -> Measure {
    let mg = &study.groups[group].measured_group;
    study.measured.displacement.iter().find(|d| &d.group == mg).map(|d| d.measure).unwrap_or_default()
}

/// Summaries of every (group, point) cell, in group-major order.
pub fn summarize(study: &Study, rows: &[RealizationRow]) -> Vec<CellSummary> {
    let mut out = Vec::new();
    for (gi, g) in study.groups.iter().enumerate() {
        let measure = measure_of(study, gi);
        for (pi, p) in study.points.iter().enumerate() {
            let cell: Vec<&RealizationRow> =
                rows.iter().filter(|r| r.group == g.name && r.point as usize == pi).collect();
            let angles: Vec<f64> = cell
                .iter()
                .filter(|r| r.status == Status::Collapsed)
                .filter_map(|r| r.collapse.collapse_angle_deg)
                .collect();
            let d5: Vec<f64> =
                cell.iter().filter(|r| r.status.is_ok()).filter_map(|r| r.disp_measure_at(measure, 5.0)).collect();
            let d10: Vec<f64> =
                cell.iter().filter(|r| r.status.is_ok()).filter_map(|r| r.disp_measure_at(measure, 10.0)).collect();
            let stream = (gi * study.points.len() + pi) as u64;
            let lateral = |f: fn(&RealizationRow) -> Option<f64>| -> Vec<f64> {
                cell.iter().filter(|r| r.status == Status::Stood).filter_map(|r| f(r)).collect()
            };
            // Bootstrap streams of the lateral quantities: disjoint from the tilt ones.
            let lstream = (1u64 << 32) + stream * 3;
            // Those of the collapse load multipliers: disjoint from both.
            let pstream = (2u64 << 32) + stream * 3;
            let pushed =
                |f: fn(&RealizationRow) -> Option<f64>| -> Vec<f64> { cell.iter().filter_map(|r| f(r)).collect() };
            let ratio: Vec<f64> = cell
                .iter()
                .filter_map(|r| Some(r.pushover.load_multiplier_dem? / r.pushover.load_multiplier_limit?))
                .collect();
            out.push(CellSummary {
                group: g.name.clone(),
                group_index: gi,
                point: pi,
                sweep: point_label(p),
                n: cell.len(),
                failed: cell.iter().filter(|r| !r.status.is_ok()).count(),
                stood: cell.iter().filter(|r| r.status == Status::Stood).count(),
                collapse: stats::summarize(&angles, study.seed, stream * 3),
                fragility: LognormalFragility::fit(&angles),
                disp5: stats::summarize(&d5, study.seed, stream * 3 + 1),
                disp10: stats::summarize(&d10, study.seed, stream * 3 + 2),
                measure: measure.name().to_string(),
                angles,
                lateral_collapsed: if study.protocol.counts_collapses_under_load() {
                    cell.iter().filter(|r| r.status == Status::Collapsed).count()
                } else {
                    0
                },
                lateral_max: stats::summarize(&lateral(|r| r.lateral.lateral_disp_max_cm), study.seed, lstream),
                lateral_centre: stats::summarize(
                    &lateral(|r| r.lateral.lateral_disp_centre_cm),
                    study.seed,
                    lstream + 1,
                ),
                drift: stats::summarize(&lateral(|r| r.lateral.lateral_drift), study.seed, lstream + 2),
                pushover: cell.iter().any(|r| r.pushover.any()),
                lambda_dem: stats::summarize(&pushed(|r| r.pushover.load_multiplier_dem), study.seed, pstream),
                lambda_limit: stats::summarize(&pushed(|r| r.pushover.load_multiplier_limit), study.seed, pstream + 1),
                lambda_ratio: stats::summarize(&ratio, study.seed, pstream + 2),
            });
        }
    }
    out
}

fn compare(group: &str, quantity: &str, measured: &[f64], sim: &Summary) -> Option<Comparison> {
    if measured.is_empty() || sim.n == 0 {
        return None;
    }
    let band = sim.prediction95;
    let m = stats::mean(measured);
    let inside = |v: f64| band.0 <= v && v <= band.1;
    Some(Comparison {
        group: group.into(),
        quantity: quantity.into(),
        measured_n: measured.len(),
        measured_mean: m,
        measured_sd: stats::sd(measured),
        simulated_n: sim.n,
        simulated_mean: sim.mean,
        simulated_sd: sim.sd,
        band,
        inside: inside(m),
        specimens_inside: measured.iter().filter(|v| inside(**v)).count(),
    })
}

/// Measured against simulated, per group (first sweep point of each group), for the
/// collapse angle and the displacement at 5° and 10°.
pub fn comparisons(study: &Study, cells: &[CellSummary]) -> Vec<Comparison> {
    let mut out = Vec::new();
    for c in cells.iter().filter(|c| c.point == 0) {
        let mg = &study.groups[c.group_index].measured_group;
        let coll: Vec<f64> =
            study.measured.collapse.iter().filter(|m| &m.group == mg).map(|m| m.collapse_angle_deg).collect();
        out.extend(compare(&c.group, "collapse angle [deg]", &coll, &c.collapse));
        for (tilt, s) in [(5.0, &c.disp5), (10.0, &c.disp10)] {
            let d: Vec<f64> = study
                .measured
                .displacement
                .iter()
                .filter(|m| &m.group == mg && (m.tilt_deg - tilt).abs() < 1e-9)
                .map(|m| m.displacement_cm)
                .collect();
            out.extend(compare(&c.group, &format!("displacement at {tilt}° [cm] ({})", c.measure), &d, s));
        }
    }
    out
}

/// The comparison as a plain-text table (printed by `drystone run`).
pub fn comparison_text(cmp: &[Comparison]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<6} {:<58} {:>16} {:>16} {:>8} {:>20} measured mean inside",
        "group", "quantity", "measured", "simulated", "diff", "sim. 95% band"
    );
    for c in cmp {
        let _ = writeln!(
            s,
            "{:<6} {:<58} {:>7.2} ± {:<6.2} {:>7.2} ± {:<6.2} {:>+8.2} {:>9.2} .. {:<7.2} {}",
            c.group,
            c.quantity,
            c.measured_mean,
            c.measured_sd,
            c.simulated_mean,
            c.simulated_sd,
            c.simulated_mean - c.measured_mean,
            c.band.0,
            c.band.1,
            if c.inside { "yes" } else { "NO" }
        );
    }
    s
}

/// Writes `summary.csv`: one row per cell, the statistics of every quantity.
///
/// # Errors
/// [`TableError`] naming the file.
pub fn write_summary_csv(cells: &[CellSummary], path: &Path) -> Result<(), TableError> {
    let text = |f: &dyn Fn(&CellSummary) -> String| TableColumn::Text(cells.iter().map(f).collect());
    let numc = |f: &dyn Fn(&CellSummary) -> f64| TableColumn::Number(cells.iter().map(f).collect());
    let count = |f: &dyn Fn(&CellSummary) -> usize| TableColumn::Count(cells.iter().map(|c| f(c) as u64).collect());
    let mut cols: Vec<(String, TableColumn)> = vec![
        ("group".into(), text(&|c| c.group.clone())),
        ("point".into(), count(&|c| c.point)),
        ("sweep".into(), text(&|c| c.sweep.clone())),
        ("realizations".into(), count(&|c| c.n)),
        ("failed".into(), count(&|c| c.failed)),
        ("stood".into(), count(&|c| c.stood)),
    ];
    let stats_cols = |prefix: &str, get: fn(&CellSummary) -> &Summary| -> Vec<(String, TableColumn)> {
        let n = |f: fn(&Summary) -> f64| TableColumn::Number(cells.iter().map(|c| f(get(c))).collect());
        vec![
            (format!("{prefix}_n"), TableColumn::Count(cells.iter().map(|c| get(c).n as u64).collect())),
            (format!("{prefix}_mean"), n(|s| s.mean)),
            (format!("{prefix}_sd"), n(|s| s.sd)),
            (format!("{prefix}_cov"), n(|s| s.cov)),
            (format!("{prefix}_min"), n(|s| s.min)),
            (format!("{prefix}_q05"), n(|s| s.q05)),
            (format!("{prefix}_q25"), n(|s| s.q25)),
            (format!("{prefix}_median"), n(|s| s.median)),
            (format!("{prefix}_q75"), n(|s| s.q75)),
            (format!("{prefix}_q95"), n(|s| s.q95)),
            (format!("{prefix}_max"), n(|s| s.max)),
            (format!("{prefix}_mean_ci95_lo"), n(|s| s.mean_ci95.0)),
            (format!("{prefix}_mean_ci95_hi"), n(|s| s.mean_ci95.1)),
            (format!("{prefix}_pred95_lo"), n(|s| s.prediction95.0)),
            (format!("{prefix}_pred95_hi"), n(|s| s.prediction95.1)),
            (format!("{prefix}_sd_boot95_lo"), n(|s| s.sd_boot95.0)),
            (format!("{prefix}_sd_boot95_hi"), n(|s| s.sd_boot95.1)),
            (format!("{prefix}_cov_boot95_lo"), n(|s| s.cov_boot95.0)),
            (format!("{prefix}_cov_boot95_hi"), n(|s| s.cov_boot95.1)),
        ]
    };
    cols.extend(stats_cols("collapse_angle_deg", |c| &c.collapse));
    cols.push(("fragility_median_deg".into(), numc(&|c| c.fragility.map_or(f64::NAN, |f| f.median))));
    cols.push(("fragility_beta".into(), numc(&|c| c.fragility.map_or(f64::NAN, |f| f.beta))));
    cols.push(("displacement_measure".into(), text(&|c| c.measure.clone())));
    cols.extend(stats_cols("disp_5deg_cm", |c| &c.disp5));
    cols.extend(stats_cols("disp_10deg_cm", |c| &c.disp10));
    cols.push(("lateral_collapsed".into(), numc(&|c| c.lateral_collapsed as f64)));
    cols.extend(stats_cols("lateral_disp_max_cm", |c| &c.lateral_max));
    cols.extend(stats_cols("lateral_disp_centre_cm", |c| &c.lateral_centre));
    cols.extend(stats_cols("lateral_drift", |c| &c.drift));
    // The collapse load multipliers of a pushover study, after the others; only there.
    if cells.iter().any(|c| c.pushover) {
        cols.extend(stats_cols("load_multiplier_dem", |c| &c.lambda_dem));
        cols.extend(stats_cols("load_multiplier_limit", |c| &c.lambda_limit));
        cols.extend(stats_cols("load_multiplier_dem_over_limit", |c| &c.lambda_ratio));
    }
    SimpleTable { columns: cols }.write_csv(path)
}
