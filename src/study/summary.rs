//! Statistics of a study's rows: one [`CellSummary`] per group and sweep point, the
//! measured-against-simulated [`Comparison`]s, and `summary.csv`. A deterministic function
//! of the rows (in index order) and the study: the bootstrap streams are numbered by cell.
//!
//! One list, [`SUMMARY_COLUMNS`], is `summary.csv`'s columns in their order; a statistic
//! of a cell ([`Statistic`]: a [`Summary`] field of [`CellSummary`]) holds there its
//! columns' prefix and its bootstrap stream (its [`StreamBlock`] and slot), so that the
//! columns, the fields and the streams are not kept apart. The tests check that every
//! `Summary` field of a cell is in the list, that no two statistics share a stream, and
//! that the Python package's typed columns (`_TEXT_SUMMARY_COLUMNS`,
//! `_COUNT_SUMMARY_COLUMNS` of `python/drystone/__init__.py`) are the list's.

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
    /// Whether the cell holds the compression test's readings (`protocol =
    /// "compression"`).
    pub compression: bool,
    /// The compression test's wall vertical modulus, MPa (the secant of the first loading
    /// branch, the database's `Epc`), over the realizations that have one.
    pub modulus: Summary,
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

/// A block of 2³² bootstrap streams, those of one kind of statistics: a cell's statistics
/// of a block draw from `base + cell · SLOTS + slot` ([`Statistic::stream`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StreamBlock {
    /// The tilting table's: the collapse angle and the displacements at 5° and 10°.
    Tilt,
    /// The static lateral load's displacements and drift.
    Lateral,
    /// The collapse load multipliers of a pushover.
    Pushover,
    /// The shaking table's fragility bands (`study::shaking`: group `g` draws from
    /// `base + g`). They share the pushover's block: a study is a pushover or shakes the
    /// table, never both.
    Shaking,
    /// The compression test's vertical modulus.
    Compression,
}

impl StreamBlock {
    /// The block's first stream.
    pub const fn base(self) -> u64 {
        match self {
            StreamBlock::Tilt => 0,
            StreamBlock::Lateral => 1 << 32,
            StreamBlock::Pushover | StreamBlock::Shaking => 2 << 32,
            StreamBlock::Compression => 3 << 32,
        }
    }
}

/// The streams a cell uses in one block: its statistics' slots are below it.
pub const SLOTS: u64 = 3;

/// A statistic of a cell: a [`Summary`] field of [`CellSummary`], written to `summary.csv`
/// as the columns `{prefix}_n`, `{prefix}_mean`, … ([`summary_stats_columns`]), its
/// bootstrap drawn from its own stream.
pub struct Statistic {
    /// The prefix of its columns.
    pub prefix: &'static str,
    /// Its field of a cell.
    pub field: fn(&CellSummary) -> &Summary,
    /// Its block of bootstrap streams.
    pub block: StreamBlock,
    /// Its slot in the block (below [`SLOTS`]).
    pub slot: u64,
    /// Written only when a cell holds one (the pushover's load multipliers, after the
    /// others: [`CellSummary::pushover`]); `None`: always.
    pub when: Option<fn(&CellSummary) -> bool>,
}

impl Statistic {
    /// Its bootstrap stream in cell `cell` (group-major index of the group and sweep point).
    pub const fn stream(&self, cell: u64) -> u64 {
        self.block.base() + cell * SLOTS + self.slot
    }
}

const fn stat(prefix: &'static str, field: fn(&CellSummary) -> &Summary, block: StreamBlock, slot: u64) -> Statistic {
    Statistic { prefix, field, block, slot, when: None }
}

/// The collapse angle, degrees.
pub const COLLAPSE: Statistic = stat("collapse_angle_deg", |c| &c.collapse, StreamBlock::Tilt, 0);
/// The displacement measure at 5°, cm.
pub const DISP5: Statistic = stat("disp_5deg_cm", |c| &c.disp5, StreamBlock::Tilt, 1);
/// The displacement measure at 10°, cm.
pub const DISP10: Statistic = stat("disp_10deg_cm", |c| &c.disp10, StreamBlock::Tilt, 2);
/// The lateral load's top displacement, cm.
pub const LATERAL_MAX: Statistic = stat("lateral_disp_max_cm", |c| &c.lateral_max, StreamBlock::Lateral, 0);
/// The lateral load's top-centre displacement, cm.
pub const LATERAL_CENTRE: Statistic = stat("lateral_disp_centre_cm", |c| &c.lateral_centre, StreamBlock::Lateral, 1);
/// The lateral load's drift.
pub const DRIFT: Statistic = stat("lateral_drift", |c| &c.drift, StreamBlock::Lateral, 2);
/// The pushover's λ by the DEM.
pub const LAMBDA_DEM: Statistic = Statistic {
    when: Some(|c| c.pushover),
    ..stat("load_multiplier_dem", |c| &c.lambda_dem, StreamBlock::Pushover, 0)
};
/// The pushover's λ by limit analysis.
pub const LAMBDA_LIMIT: Statistic = Statistic {
    when: Some(|c| c.pushover),
    ..stat("load_multiplier_limit", |c| &c.lambda_limit, StreamBlock::Pushover, 1)
};
/// The ratio λ_DEM / λ_limit.
pub const LAMBDA_RATIO: Statistic = Statistic {
    when: Some(|c| c.pushover),
    ..stat("load_multiplier_dem_over_limit", |c| &c.lambda_ratio, StreamBlock::Pushover, 2)
};

/// The compression test's wall vertical modulus, MPa.
pub const MODULUS: Statistic = Statistic {
    when: Some(|c| c.compression),
    ..stat("vertical_modulus_mpa", |c| &c.modulus, StreamBlock::Compression, 0)
};

/// A column (or, for a statistic, the columns) of `summary.csv`.
pub enum SummaryColumn {
    /// Text.
    Text(&'static str, fn(&CellSummary) -> String),
    /// A count.
    Count(&'static str, fn(&CellSummary) -> usize),
    /// A number (written empty when not finite).
    Number(&'static str, fn(&CellSummary) -> f64),
    /// The columns of a statistic.
    Stats(&'static Statistic),
}

/// `summary.csv`'s columns, in their order: the one list the writer
/// ([`write_summary_csv`]) follows and the statistics' streams are read from.
pub const SUMMARY_COLUMNS: &[SummaryColumn] = &[
    SummaryColumn::Text("group", |c| c.group.clone()),
    SummaryColumn::Count("point", |c| c.point),
    SummaryColumn::Text("sweep", |c| c.sweep.clone()),
    SummaryColumn::Count("realizations", |c| c.n),
    SummaryColumn::Count("failed", |c| c.failed),
    SummaryColumn::Count("stood", |c| c.stood),
    SummaryColumn::Stats(&COLLAPSE),
    SummaryColumn::Number("fragility_median_deg", |c| c.fragility.map_or(f64::NAN, |f| f.median)),
    SummaryColumn::Number("fragility_beta", |c| c.fragility.map_or(f64::NAN, |f| f.beta)),
    SummaryColumn::Text("displacement_measure", |c| c.measure.clone()),
    SummaryColumn::Stats(&DISP5),
    SummaryColumn::Stats(&DISP10),
    SummaryColumn::Number("lateral_collapsed", |c| c.lateral_collapsed as f64),
    SummaryColumn::Stats(&LATERAL_MAX),
    SummaryColumn::Stats(&LATERAL_CENTRE),
    SummaryColumn::Stats(&DRIFT),
    SummaryColumn::Stats(&LAMBDA_DEM),
    SummaryColumn::Stats(&LAMBDA_LIMIT),
    SummaryColumn::Stats(&LAMBDA_RATIO),
    SummaryColumn::Stats(&MODULUS),
];

/// The `Summary` fields of a cell: a destructuring without `..`, so that the compiler
/// points here at a new field of [`CellSummary`]; a new statistic then joins
/// [`SUMMARY_COLUMNS`] (a test checks that every one listed here is there).
#[cfg(test)]
const CELL_STATISTICS: for<'a> fn(&'a CellSummary) -> Vec<&'a Summary> = |c| {
    let CellSummary {
        group: _,
        group_index: _,
        point: _,
        sweep: _,
        n: _,
        failed: _,
        stood: _,
        collapse,
        fragility: _,
        disp5,
        disp10,
        measure: _,
        angles: _,
        lateral_collapsed: _,
        lateral_max,
        lateral_centre,
        drift,
        pushover: _,
        lambda_dem,
        lambda_limit,
        lambda_ratio,
        compression: _,
        modulus,
    } = c;
    vec![collapse, disp5, disp10, lateral_max, lateral_centre, drift, lambda_dem, lambda_limit, lambda_ratio, modulus]
};

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
                collapse: stats::summarize(&angles, study.seed, COLLAPSE.stream(stream)),
                fragility: LognormalFragility::fit(&angles),
                disp5: stats::summarize(&d5, study.seed, DISP5.stream(stream)),
                disp10: stats::summarize(&d10, study.seed, DISP10.stream(stream)),
                measure: measure.name().to_string(),
                angles,
                lateral_collapsed: if study.protocol.counts_collapses_under_load() {
                    cell.iter().filter(|r| r.status == Status::Collapsed).count()
                } else {
                    0
                },
                lateral_max: stats::summarize(
                    &lateral(|r| r.lateral.lateral_disp_max_cm),
                    study.seed,
                    LATERAL_MAX.stream(stream),
                ),
                lateral_centre: stats::summarize(
                    &lateral(|r| r.lateral.lateral_disp_centre_cm),
                    study.seed,
                    LATERAL_CENTRE.stream(stream),
                ),
                drift: stats::summarize(&lateral(|r| r.lateral.lateral_drift), study.seed, DRIFT.stream(stream)),
                pushover: cell.iter().any(|r| r.pushover.any()),
                lambda_dem: stats::summarize(
                    &pushed(|r| r.pushover.load_multiplier_dem),
                    study.seed,
                    LAMBDA_DEM.stream(stream),
                ),
                lambda_limit: stats::summarize(
                    &pushed(|r| r.pushover.load_multiplier_limit),
                    study.seed,
                    LAMBDA_LIMIT.stream(stream),
                ),
                lambda_ratio: stats::summarize(&ratio, study.seed, LAMBDA_RATIO.stream(stream)),
                compression: cell.iter().any(|r| r.compression.is_some()),
                modulus: stats::summarize(
                    &pushed(|r| r.compression.as_ref().map(|c| c.compression_modulus_mpa).filter(|v| v.is_finite())),
                    study.seed,
                    MODULUS.stream(stream),
                ),
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

/// The columns of statistic `s` over `cells`: `{prefix}_n`, `_mean`, `_sd`, `_cov`, `_min`,
/// the quantiles, `_max`, and the bands.
fn summary_stats_columns(cells: &[CellSummary], s: &Statistic) -> Vec<(String, TableColumn)> {
    let (prefix, get) = (s.prefix, s.field);
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
}

/// The columns of `summary.csv` for `cells`, in [`SUMMARY_COLUMNS`]' order (a statistic
/// written only when a cell holds one left out otherwise).
pub fn summary_columns(cells: &[CellSummary]) -> Vec<(String, TableColumn)> {
    let mut cols = Vec::new();
    for c in SUMMARY_COLUMNS {
        match c {
            SummaryColumn::Text(name, f) => {
                cols.push((name.to_string(), TableColumn::Text(cells.iter().map(f).collect())))
            }
            SummaryColumn::Count(name, f) => {
                cols.push((name.to_string(), TableColumn::Count(cells.iter().map(|c| f(c) as u64).collect())))
            }
            SummaryColumn::Number(name, f) => {
                cols.push((name.to_string(), TableColumn::Number(cells.iter().map(f).collect())))
            }
            SummaryColumn::Stats(s) => {
                if s.when.is_none_or(|w| cells.iter().any(w)) {
                    cols.extend(summary_stats_columns(cells, s));
                }
            }
        }
    }
    cols
}

/// Writes `summary.csv`: one row per cell, the statistics of every quantity
/// ([`SUMMARY_COLUMNS`]).
///
/// # Errors
/// [`TableError`] naming the file.
pub fn write_summary_csv(cells: &[CellSummary], path: &Path) -> Result<(), TableError> {
    SimpleTable { columns: summary_columns(cells) }.write_csv(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell() -> CellSummary {
        let s = |x: f64| stats::summarize(&[x, x + 1.0, x + 3.0], 1, 0);
        CellSummary {
            group: "G".into(),
            group_index: 0,
            point: 0,
            sweep: String::new(),
            n: 3,
            failed: 0,
            stood: 0,
            collapse: s(1.0),
            fragility: None,
            disp5: s(2.0),
            disp10: s(3.0),
            measure: Measure::default().name().into(),
            angles: vec![],
            lateral_collapsed: 0,
            lateral_max: s(4.0),
            lateral_centre: s(5.0),
            drift: s(6.0),
            pushover: true,
            lambda_dem: s(7.0),
            lambda_limit: s(8.0),
            lambda_ratio: s(9.0),
            compression: true,
            modulus: s(10.0),
        }
    }

    fn statistics() -> Vec<&'static Statistic> {
        SUMMARY_COLUMNS
            .iter()
            .filter_map(|c| match c {
                SummaryColumn::Stats(s) => Some(*s),
                SummaryColumn::Text(..) | SummaryColumn::Count(..) | SummaryColumn::Number(..) => None,
            })
            .collect()
    }

    /// Every `Summary` field of a cell is a statistic of the list, once; no two statistics
    /// draw from one stream; the streams keep their values (the collapse angle of cell `k`
    /// at `3k`, the lateral load's at `2³² + 3k + i`, the pushover's at `2³³ + 3k + i`, the
    /// compression test's modulus at `3 · 2³² + 3k`).
    #[test]
    fn every_statistic_of_a_cell_is_listed_once_with_a_stream_of_its_own() {
        let c = cell();
        let listed: Vec<*const Summary> = statistics().iter().map(|s| (s.field)(&c) as *const Summary).collect();
        let fields: Vec<*const Summary> = CELL_STATISTICS(&c).into_iter().map(|s| s as *const Summary).collect();
        for (i, f) in fields.iter().enumerate() {
            assert_eq!(listed.iter().filter(|l| *l == f).count(), 1, "field {i} of CELL_STATISTICS is not listed once");
        }
        assert_eq!(listed.len(), fields.len());
        let mut streams: Vec<(u64, u64)> = statistics().iter().map(|s| (s.block.base(), s.slot)).collect();
        assert!(streams.iter().all(|&(_, slot)| slot < SLOTS));
        streams.sort_unstable();
        streams.dedup();
        assert_eq!(streams.len(), statistics().len(), "two statistics share a stream");
        let k = 7;
        assert_eq!(
            statistics().iter().map(|s| s.stream(k)).collect::<Vec<_>>(),
            [
                21,
                22,
                23,
                (1 << 32) + 21,
                (1 << 32) + 22,
                (1 << 32) + 23,
                (2 << 32) + 21,
                (2 << 32) + 22,
                (2 << 32) + 23,
                (3 << 32) + 21
            ]
        );
        assert_eq!(StreamBlock::Shaking.base(), 1 << 33);
    }

    /// The Python package reads `summary.csv` with the types of its columns: its lists of
    /// text and count columns (`python/drystone/__init__.py`; the columns ending in `_n`
    /// are counts there) are the list's, and no number ends in `_n`.
    #[test]
    fn the_python_packages_summary_types_are_the_lists() {
        let text = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("python/drystone/__init__.py"),
        )
        .unwrap();
        let set = |name: &str| -> Vec<String> {
            let line =
                text.lines().find(|l| l.starts_with(&format!("{name} = {{"))).unwrap_or_else(|| panic!("{name}"));
            let inner = line.split_once('{').unwrap().1.rsplit_once('}').unwrap().0;
            let mut v: Vec<String> = inner.split(',').map(|s| s.trim().trim_matches('"').to_string()).collect();
            v.sort();
            v
        };
        let cols = summary_columns(&[cell()]);
        let of = |kind: fn(&TableColumn) -> bool| -> Vec<String> {
            let mut v: Vec<String> =
                cols.iter().filter(|(n, c)| kind(c) && !n.ends_with("_n")).map(|(n, _)| n.clone()).collect();
            v.sort();
            v
        };
        assert_eq!(set("_TEXT_SUMMARY_COLUMNS"), of(|c| matches!(c, TableColumn::Text(_))));
        assert_eq!(set("_COUNT_SUMMARY_COLUMNS"), of(|c| matches!(c, TableColumn::Count(_))));
        for (n, c) in &cols {
            assert_eq!(
                n.ends_with("_n"),
                matches!(c, TableColumn::Count(_)) && !set("_COUNT_SUMMARY_COLUMNS").contains(n),
                "{n}"
            );
        }
    }
}
