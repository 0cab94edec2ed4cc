//! Tables with polars: realizations and summaries to Parquet and CSV, and back; the source
//! paper's DEM angles from CSV. Polars is used in this module only; the measured data are
//! read and checked line by line in [`measured`](super::measured).
//!
//! `realizations.parquet` keeps the per-increment series (tilt, top displacements) as list
//! columns; `realizations.csv` writes them as `;`-separated numbers in one cell.

pub use super::measured::{
    read_measured_collapse, read_measured_displacement, read_measured_mechanism, MeasuredCollapse,
    MeasuredDisplacement, MeasuredMechanism,
};
use crate::ensemble::row::{
    CollapseColumns, CompressionColumns, InPlaneColumns, LateralColumns, PushoverColumns, RealizationRow, ShakeColumns,
    Status, TiltColumns,
};
use crate::protocol::Loading;
use polars::prelude::*;
use std::fs::File;
use std::path::Path;

pub use super::error::TableError;

fn pe(path: &Path) -> impl Fn(PolarsError) -> TableError + '_ {
    move |e| TableError::Polars { path: path.to_owned(), message: e.to_string() }
}

/// A column of the realizations table: how a row writes it and, but for the derived
/// columns, how a row read back gets it.
#[derive(Clone, Copy)]
enum Field {
    /// An unsigned count (0 for a missing value on reading).
    Count(fn(&RealizationRow) -> u64, fn(&mut RealizationRow, u64)),
    /// An optional count.
    OptCount(fn(&RealizationRow) -> Option<u64>, fn(&mut RealizationRow, Option<u64>)),
    /// Text ("" for a missing value); the setter checks it (`Err`: the reason).
    Text(fn(&RealizationRow) -> String, fn(&mut RealizationRow, String) -> Result<(), String>),
    /// A number (NaN for a missing value on reading).
    Number(fn(&RealizationRow) -> f64, fn(&mut RealizationRow, f64)),
    /// An optional number.
    OptNumber(fn(&RealizationRow) -> Option<f64>, fn(&mut RealizationRow, Option<f64>)),
    /// A per-increment series: a list column in Parquet, `;`-joined numbers in CSV.
    Series(fn(&RealizationRow) -> &Vec<f64>, fn(&mut RealizationRow) -> &mut Vec<f64>),
    /// Derived from other columns when written (a summary of the series); not read.
    Derived(fn(&RealizationRow) -> Option<f64>),
}

/// Whether the columns of `protocol` (a column's [`RowColumn::protocol`]) are written to
/// the table of `rows`: every column of every protocol, but a protocol's whose columns are
/// optional ([`Loading::optional_columns`]: the pushover's load multipliers) only when a
/// row holds one of them.
fn written(protocol: Option<Loading>, rows: &[RealizationRow]) -> bool {
    match protocol {
        Some(p) if p.optional_columns() => {
            COLUMNS.iter().filter(|c| c.protocol == Some(p)).any(|c| rows.iter().any(|r| c.field.holds(r)))
        }
        Some(_) | None => true,
    }
}

impl Field {
    /// Whether row `r` holds a value in this column (a count always does; a number unless
    /// NaN; text and a series unless empty).
    fn holds(&self, r: &RealizationRow) -> bool {
        match self {
            Field::Count(..) => true,
            Field::OptCount(get, _) => get(r).is_some(),
            Field::Text(get, _) => !get(r).is_empty(),
            Field::Number(get, _) => !get(r).is_nan(),
            Field::OptNumber(get, _) => get(r).is_some(),
            Field::Series(get, _) => !get(r).is_empty(),
            Field::Derived(get) => get(r).is_some(),
        }
    }
}

/// One column: its name, the protocol whose results it holds, its field, and whether a
/// table may lack it (a column added after the first tables were written: missing, it
/// reads as empty).
struct RowColumn {
    name: &'static str,
    /// The protocol whose results the column holds (its row of the compatibility table:
    /// the tilting table's curves, which its hand-rolled form fills too, the lateral load's
    /// displacements, which the pushover fills at its service level, the shaking table's,
    /// the pushover's load multipliers); `None` for the columns of every row (identity,
    /// status and cost) and for the collapse and its mechanism, which the tilting table,
    /// limit analysis and the pushover fill.
    protocol: Option<Loading>,
    field: Field,
    optional: bool,
}

const fn column(name: &'static str, protocol: Option<Loading>, field: Field) -> RowColumn {
    RowColumn { name, protocol, field, optional: false }
}

const fn later(name: &'static str, protocol: Option<Loading>, field: Field) -> RowColumn {
    RowColumn { name, protocol, field, optional: true }
}

fn status_of(r: &mut RealizationRow, v: String) -> Result<(), String> {
    r.status = Status::parse(&v).ok_or_else(|| format!("unknown status {v:?}"))?;
    Ok(())
}

fn reason_of(r: &mut RealizationRow, v: String) -> Result<(), String> {
    use crate::loading::tilt::CollapseReason;
    if !v.is_empty() && CollapseReason::from_name(&v).is_none() {
        let known: Vec<&str> = CollapseReason::ALL.iter().map(|x| x.name()).collect();
        return Err(format!("unknown collapse reason `{v}` (known: {})", known.join(", ")));
    }
    r.collapse.collapse_reason = v;
    Ok(())
}

/// The [`Field`] of a row's field by its path: `field!(count index)`,
/// `field!(opt_number collapse.collapse_angle_deg)`, `field!(series tilt.tilt_deg)`.
macro_rules! field {
    (count $($f:ident).+) => { Field::Count(|r| r.$($f).+, |r, v| r.$($f).+ = v) };
    (opt_count $($f:ident).+) => { Field::OptCount(|r| r.$($f).+, |r, v| r.$($f).+ = v) };
    (text $($f:ident).+) => {
        Field::Text(|r| r.$($f).+.clone(), |r, v| {
            r.$($f).+ = v;
            Ok(())
        })
    };
    (number $($f:ident).+) => { Field::Number(|r| r.$($f).+, |r, v| r.$($f).+ = v) };
    (opt_number $($f:ident).+) => { Field::OptNumber(|r| r.$($f).+, |r, v| r.$($f).+ = v) };
    (series $($f:ident).+) => { Field::Series(|r| &r.$($f).+, |r| &mut r.$($f).+) };
    // The in-plane test's group, `None` for the other protocols (a number reads NaN, a
    // text empty, a count and a series absent); a value set makes the group.
    (in_plane number $f:ident) => {
        Field::Number(|r| r.in_plane.as_ref().map_or(f64::NAN, |p| p.$f), |r, v| in_plane(r).$f = v)
    };
    (in_plane text $f:ident) => {
        Field::Text(|r| r.in_plane.as_ref().map(|p| p.$f.clone()).unwrap_or_default(), |r, v| {
            in_plane(r).$f = v;
            Ok(())
        })
    };
    (in_plane count $f:ident) => {
        Field::OptCount(|r| r.in_plane.as_ref().map(|p| p.$f), |r, v| in_plane(r).$f = v.unwrap_or(0))
    };
    (in_plane series $f:ident) => {
        Field::Series(|r| r.in_plane.as_ref().map_or(&NO_SERIES, |p| &p.$f), |r| &mut in_plane(r).$f)
    };
    // The compression test's group, as the in-plane test's.
    (compression number $f:ident) => {
        Field::Number(|r| r.compression.as_ref().map_or(f64::NAN, |p| p.$f), |r, v| compression(r).$f = v)
    };
    (compression count $f:ident) => {
        Field::OptCount(|r| r.compression.as_ref().map(|p| p.$f), |r, v| compression(r).$f = v.unwrap_or(0))
    };
    (compression series $f:ident) => {
        Field::Series(|r| r.compression.as_ref().map_or(&NO_SERIES, |p| &p.$f), |r| &mut compression(r).$f)
    };
}

/// The series of a row without the group that holds it.
static NO_SERIES: Vec<f64> = Vec::new();

/// The compression group of a row, made (every reading NaN) if it has none.
fn compression(r: &mut RealizationRow) -> &mut CompressionColumns {
    r.compression.get_or_insert_with(Box::default)
}

/// The in-plane group of a row, made (every reading NaN) if it has none.
fn in_plane(r: &mut RealizationRow) -> &mut InPlaneColumns {
    r.in_plane.get_or_insert_with(Box::default)
}

/// Every field of a row by name, each column group's too: a destructuring without `..`, so
/// that the compiler points here at a new field of [`RealizationRow`] or of one of its
/// groups, whose column then joins [`COLUMNS`] below (a series of the tilting table's is
/// also read by the derived columns).
const _FIELDS: fn(&RealizationRow) = |r| {
    let RealizationRow {
        index: _,
        study: _,
        group: _,
        point: _,
        sweep: _,
        seed: _,
        realization: _,
        status: _,
        error: _,
        blocks: _,
        collapse,
        tilt,
        lateral,
        shake,
        pushover,
        in_plane,
        compression,
        steps: _,
        iterations: _,
        dt_s: _,
        wall_time_s: _,
    } = r;
    let CollapseColumns {
        collapse_angle_deg: _,
        first_unstable_deg: _,
        collapse_reason: _,
        mechanism: _,
        joint: _,
        moving_blocks: _,
        failure_height_fraction: _,
        mechanism_kind: _,
        mechanism_start: _,
        mechanism_extent: _,
    } = collapse;
    let TiltColumns { tilt_deg: _, disp_top_left_cm: _, disp_top_centre_cm: _, disp_top_right_cm: _ } = tilt;
    let LateralColumns {
        lateral_disp_left_cm: _,
        lateral_disp_centre_cm: _,
        lateral_disp_right_cm: _,
        lateral_disp_max_cm: _,
        lateral_drift: _,
    } = lateral;
    let ShakeColumns {
        motion: _,
        pga_g: _,
        collapse_time_s: _,
        max_rotation_deg: _,
        max_drift: _,
        residual_drift: _,
        blocks_fallen: _,
        unconverged_steps: _,
        max_natural_residual: _,
    } = shake;
    let PushoverColumns { load_multiplier_dem: _, load_multiplier_dem_unstable: _, load_multiplier_limit: _ } =
        pushover;
    if let Some(p) = in_plane {
        let InPlaneColumns {
            peak_pos_kn: _,
            drift_at_peak_pos_pct: _,
            ultimate_drift_pos_pct: _,
            stiffness_pos_kn_per_mm: _,
            peak_neg_kn: _,
            drift_at_peak_neg_pct: _,
            ultimate_drift_neg_pct: _,
            stiffness_neg_kn_per_mm: _,
            in_plane_mechanism: _,
            failure_type: _,
            opening_share: _,
            limit_peak_kn: _,
            limit_mechanism: _,
            rocking_kn: _,
            damping_ratio: _,
            force_at_0_25_pos_kn: _,
            force_at_0_5_pos_kn: _,
            force_at_1_pos_kn: _,
            force_at_2_pos_kn: _,
            drift_at_80_pos_pct: _,
            drift_at_95_pos_pct: _,
            plateau_slope_pos_kn_per_pct: _,
            force_at_0_25_neg_kn: _,
            force_at_0_5_neg_kn: _,
            force_at_1_neg_kn: _,
            force_at_2_neg_kn: _,
            drift_at_80_neg_pct: _,
            drift_at_95_neg_pct: _,
            plateau_slope_neg_kn_per_pct: _,
            vertical_modulus_mpa: _,
            largest_block_excursion_mm: _,
            course_widening_mm: _,
            excursion_block: _,
            unconverged: _,
            curve_drift_pct: _,
            curve_force_kn: _,
            // The mechanism figure's poses: not a column (not serialized).
            drawing: _,
        } = &**p;
    }
    if let Some(c) = compression {
        let CompressionColumns {
            compression_modulus_mpa: _,
            loading_secants_mpa: _,
            residual_settlements_mm: _,
            strength_low_mpa: _,
            strength_high_mpa: _,
            compression_unconverged: _,
            curve_stress_mpa: _,
            curve_shortening_mm: _,
        } = &**c;
    }
};

#[rustfmt::skip]
/// The columns of `realizations.parquet` and `.csv`, in their order: the one list the
/// writer ([`realizations_frame`]) and the reader ([`read_realizations`]) follow. A new
/// column is one line here (and its field in [`RealizationRow`], which `_FIELDS` names).
const COLUMNS: &[RowColumn] = &[
    column("index", None, field!(count index)),
    column("study", None, field!(text study)),
    column("group", None, field!(text group)),
    column("point", None, field!(count point)),
    column("sweep", None, field!(text sweep)),
    column("seed", None, field!(count seed)),
    column("realization", None, field!(count realization)),
    column("status", None, Field::Text(|r| r.status.as_str().to_string(), status_of)),
    column("error", None, field!(text error)),
    column("blocks", None, field!(count blocks)),
    column("collapse_angle_deg", None, field!(opt_number collapse.collapse_angle_deg)),
    column("first_unstable_deg", None, field!(opt_number collapse.first_unstable_deg)),
    column("collapse_reason", None, Field::Text(|r| r.collapse.collapse_reason.clone(), reason_of)),
    column("mechanism", None, field!(text collapse.mechanism)),
    column("joint", None, field!(text collapse.joint)),
    column("moving_blocks", None, field!(count collapse.moving_blocks)),
    later("failure_height_fraction", None, field!(opt_number collapse.failure_height_fraction)),
    later("mechanism_kind", None, field!(text collapse.mechanism_kind)),
    later("mechanism_start", None, field!(text collapse.mechanism_start)),
    later("mechanism_extent", None, field!(opt_number collapse.mechanism_extent)),
    column("disp_mean_5deg_cm", Some(Loading::Tilt), Field::Derived(|r| r.disp_mean_at(5.0))),
    column("disp_mean_10deg_cm", Some(Loading::Tilt), Field::Derived(|r| r.disp_mean_at(10.0))),
    column("disp_centre_rel_5deg_cm", Some(Loading::Tilt), Field::Derived(|r| r.disp_centre_rel_at(5.0))),
    column("disp_centre_rel_10deg_cm", Some(Loading::Tilt), Field::Derived(|r| r.disp_centre_rel_at(10.0))),
    column("lateral_disp_left_cm", Some(Loading::Lateral), field!(opt_number lateral.lateral_disp_left_cm)),
    column("lateral_disp_centre_cm", Some(Loading::Lateral), field!(opt_number lateral.lateral_disp_centre_cm)),
    column("lateral_disp_right_cm", Some(Loading::Lateral), field!(opt_number lateral.lateral_disp_right_cm)),
    column("lateral_disp_max_cm", Some(Loading::Lateral), field!(opt_number lateral.lateral_disp_max_cm)),
    column("lateral_drift", Some(Loading::Lateral), field!(opt_number lateral.lateral_drift)),
    later("motion", Some(Loading::Shake), field!(text shake.motion)),
    later("pga_g", Some(Loading::Shake), field!(opt_number shake.pga_g)),
    later("collapse_time_s", Some(Loading::Shake), field!(opt_number shake.collapse_time_s)),
    later("max_rotation_deg", Some(Loading::Shake), field!(opt_number shake.max_rotation_deg)),
    later("max_drift", Some(Loading::Shake), field!(opt_number shake.max_drift)),
    later("residual_drift", Some(Loading::Shake), field!(opt_number shake.residual_drift)),
    later("blocks_fallen", Some(Loading::Shake), field!(opt_count shake.blocks_fallen)),
    later("unconverged_steps", Some(Loading::Shake), field!(opt_count shake.unconverged_steps)),
    later("max_natural_residual", Some(Loading::Shake), field!(opt_number shake.max_natural_residual)),
    column("tilt_deg", Some(Loading::Tilt), field!(series tilt.tilt_deg)),
    column("disp_top_left_cm", Some(Loading::Tilt), field!(series tilt.disp_top_left_cm)),
    column("disp_top_centre_cm", Some(Loading::Tilt), field!(series tilt.disp_top_centre_cm)),
    column("disp_top_right_cm", Some(Loading::Tilt), field!(series tilt.disp_top_right_cm)),
    column("steps", None, field!(count steps)),
    column("iterations", None, field!(count iterations)),
    column("dt_s", None, field!(number dt_s)),
    column("wall_time_s", None, field!(number wall_time_s)),
    later("load_multiplier_dem", Some(Loading::Pushover), field!(opt_number pushover.load_multiplier_dem)),
    later("load_multiplier_dem_unstable", Some(Loading::Pushover), field!(opt_number pushover.load_multiplier_dem_unstable)),
    later("load_multiplier_limit", Some(Loading::Pushover), field!(opt_number pushover.load_multiplier_limit)),
    later("peak_pos_kn", Some(Loading::InPlane), field!(in_plane number peak_pos_kn)),
    later("drift_at_peak_pos_pct", Some(Loading::InPlane), field!(in_plane number drift_at_peak_pos_pct)),
    later("ultimate_drift_pos_pct", Some(Loading::InPlane), field!(in_plane number ultimate_drift_pos_pct)),
    later("stiffness_pos_kn_per_mm", Some(Loading::InPlane), field!(in_plane number stiffness_pos_kn_per_mm)),
    later("peak_neg_kn", Some(Loading::InPlane), field!(in_plane number peak_neg_kn)),
    later("drift_at_peak_neg_pct", Some(Loading::InPlane), field!(in_plane number drift_at_peak_neg_pct)),
    later("ultimate_drift_neg_pct", Some(Loading::InPlane), field!(in_plane number ultimate_drift_neg_pct)),
    later("stiffness_neg_kn_per_mm", Some(Loading::InPlane), field!(in_plane number stiffness_neg_kn_per_mm)),
    later("in_plane_mechanism", Some(Loading::InPlane), field!(in_plane text in_plane_mechanism)),
    later("failure_type", Some(Loading::InPlane), field!(in_plane number failure_type)),
    later("opening_share", Some(Loading::InPlane), field!(in_plane number opening_share)),
    later("limit_peak_kn", Some(Loading::InPlane), field!(in_plane number limit_peak_kn)),
    later("limit_mechanism", Some(Loading::InPlane), field!(in_plane text limit_mechanism)),
    later("rocking_kn", Some(Loading::InPlane), field!(in_plane number rocking_kn)),
    later("damping_ratio", Some(Loading::InPlane), field!(in_plane number damping_ratio)),
    later("force_at_0_25_pos_kn", Some(Loading::InPlane), field!(in_plane number force_at_0_25_pos_kn)),
    later("force_at_0_5_pos_kn", Some(Loading::InPlane), field!(in_plane number force_at_0_5_pos_kn)),
    later("force_at_1_pos_kn", Some(Loading::InPlane), field!(in_plane number force_at_1_pos_kn)),
    later("force_at_2_pos_kn", Some(Loading::InPlane), field!(in_plane number force_at_2_pos_kn)),
    later("drift_at_80_pos_pct", Some(Loading::InPlane), field!(in_plane number drift_at_80_pos_pct)),
    later("drift_at_95_pos_pct", Some(Loading::InPlane), field!(in_plane number drift_at_95_pos_pct)),
    later("plateau_slope_pos_kn_per_pct", Some(Loading::InPlane), field!(in_plane number plateau_slope_pos_kn_per_pct)),
    later("force_at_0_25_neg_kn", Some(Loading::InPlane), field!(in_plane number force_at_0_25_neg_kn)),
    later("force_at_0_5_neg_kn", Some(Loading::InPlane), field!(in_plane number force_at_0_5_neg_kn)),
    later("force_at_1_neg_kn", Some(Loading::InPlane), field!(in_plane number force_at_1_neg_kn)),
    later("force_at_2_neg_kn", Some(Loading::InPlane), field!(in_plane number force_at_2_neg_kn)),
    later("drift_at_80_neg_pct", Some(Loading::InPlane), field!(in_plane number drift_at_80_neg_pct)),
    later("drift_at_95_neg_pct", Some(Loading::InPlane), field!(in_plane number drift_at_95_neg_pct)),
    later("plateau_slope_neg_kn_per_pct", Some(Loading::InPlane), field!(in_plane number plateau_slope_neg_kn_per_pct)),
    later("vertical_modulus_mpa", Some(Loading::InPlane), field!(in_plane number vertical_modulus_mpa)),
    later("largest_block_excursion_mm", Some(Loading::InPlane), field!(in_plane number largest_block_excursion_mm)),
    later("excursion_block", Some(Loading::InPlane), field!(in_plane text excursion_block)),
    later("course_widening_mm", Some(Loading::InPlane), field!(in_plane number course_widening_mm)),
    later("unconverged", Some(Loading::InPlane), field!(in_plane count unconverged)),
    later("curve_drift_pct", Some(Loading::InPlane), field!(in_plane series curve_drift_pct)),
    later("curve_force_kn", Some(Loading::InPlane), field!(in_plane series curve_force_kn)),
    later("compression_modulus_mpa", Some(Loading::Compression), field!(compression number compression_modulus_mpa)),
    later("loading_secants_mpa", Some(Loading::Compression), field!(compression series loading_secants_mpa)),
    later("residual_settlements_mm", Some(Loading::Compression), field!(compression series residual_settlements_mm)),
    later("strength_low_mpa", Some(Loading::Compression), field!(compression number strength_low_mpa)),
    later("strength_high_mpa", Some(Loading::Compression), field!(compression number strength_high_mpa)),
    later("compression_unconverged", Some(Loading::Compression), field!(compression count compression_unconverged)),
    later("curve_stress_mpa", Some(Loading::Compression), field!(compression series curve_stress_mpa)),
    later("curve_shortening_mm", Some(Loading::Compression), field!(compression series curve_shortening_mm)),
];

/// The column `c` of `rows`; `lists` chooses list columns (Parquet) or joined strings
/// (CSV) for the series.
fn write_column(c: &RowColumn, rows: &[RealizationRow], lists: bool) -> Column {
    let name = c.name.into();
    match c.field {
        Field::Count(get, _) => Column::new(name, rows.iter().map(get).collect::<Vec<u64>>()),
        Field::OptCount(get, _) => Column::new(name, rows.iter().map(get).collect::<Vec<Option<u64>>>()),
        Field::Text(get, _) => Column::new(name, rows.iter().map(get).collect::<Vec<String>>()),
        Field::Number(get, _) => Column::new(name, rows.iter().map(get).collect::<Vec<f64>>()),
        Field::OptNumber(get, _) | Field::Derived(get) => {
            Column::new(name, rows.iter().map(get).collect::<Vec<Option<f64>>>())
        }
        Field::Series(get, _) if lists => {
            let series: Vec<Series> = rows.iter().map(|r| Series::new("".into(), get(r).as_slice())).collect();
            Series::new(name, series.as_slice()).into_column()
        }
        Field::Series(get, _) => {
            let v: Vec<String> =
                rows.iter().map(|r| get(r).iter().map(|x| format!("{x}")).collect::<Vec<_>>().join(";")).collect();
            Column::new(name, v)
        }
    }
}

/// The realizations as a data frame, in the order of the column list; `lists` chooses
/// list columns (Parquet) or joined strings (CSV) for the per-increment series. The
/// pushover's columns are written only when a row has one ([`Loading::optional_columns`]).
pub fn realizations_frame(rows: &[RealizationRow], lists: bool) -> PolarsResult<DataFrame> {
    let columns: Vec<Column> =
        COLUMNS.iter().filter(|c| written(c.protocol, rows)).map(|c| write_column(c, rows, lists)).collect();
    DataFrame::new_infer_height(columns)
}

/// Writes `realizations.parquet` and `realizations.csv` into `dir`, each replaced whole
/// ([`super::replace_file`]).
///
/// # Errors
/// [`TableError`] naming the file.
pub fn write_realizations(rows: &[RealizationRow], dir: &Path) -> Result<(), TableError> {
    write_realizations_parquet(rows, dir)?;
    let csv = dir.join("realizations.csv");
    let mut df = realizations_frame(rows, false).map_err(pe(&csv))?;
    write_csv(&mut df, &csv)
}

/// Writes `realizations.parquet` into `dir`, replaced whole: every column of the rows,
/// what `drystone merge` reads back ([`read_realizations`]) whatever the protocol's
/// `realizations.csv`.
///
/// # Errors
/// [`TableError`] naming the file.
pub fn write_realizations_parquet(rows: &[RealizationRow], dir: &Path) -> Result<(), TableError> {
    let pq = dir.join("realizations.parquet");
    let mut df = realizations_frame(rows, true).map_err(pe(&pq))?;
    let mut bytes = Vec::new();
    ParquetWriter::new(&mut bytes).finish(&mut df).map_err(pe(&pq))?;
    replace(&pq, &bytes)
}

/// Writes a data frame as CSV with a header, replacing the file whole.
///
/// # Errors
/// [`TableError`] naming the file.
pub fn write_csv(df: &mut DataFrame, path: &Path) -> Result<(), TableError> {
    let mut bytes = Vec::new();
    CsvWriter::new(&mut bytes).include_header(true).finish(df).map_err(pe(path))?;
    replace(path, &bytes)
}

/// The bytes of a table into `path`, whole.
fn replace(path: &Path, bytes: &[u8]) -> Result<(), TableError> {
    super::replace_file(path, bytes).map_err(|e| TableError::Io { path: e.path, source: e.source })
}

fn col<'a>(df: &'a DataFrame, path: &Path, name: &str) -> Result<&'a Column, TableError> {
    df.column(name).map_err(|e| TableError::Column {
        path: path.to_owned(),
        column: name.into(),
        message: e.to_string(),
    })
}

/// Typed columns of a data frame read from `path`; missing values as 0, "", NaN or None.
struct Columns<'a> {
    df: &'a DataFrame,
    path: &'a Path,
}

impl Columns<'_> {
    fn bad(&self, c: &str, e: PolarsError) -> TableError {
        TableError::Column { path: self.path.to_owned(), column: c.into(), message: e.to_string() }
    }

    fn u64s(&self, c: &str) -> Result<Vec<u64>, TableError> {
        let ca = col(self.df, self.path, c)?.u64().map_err(|e| self.bad(c, e))?.clone();
        Ok(ca.iter().map(|v| v.unwrap_or(0)).collect())
    }

    fn opt_u64s(&self, c: &str) -> Result<Vec<Option<u64>>, TableError> {
        let ca = col(self.df, self.path, c)?.u64().map_err(|e| self.bad(c, e))?.clone();
        Ok(ca.iter().collect())
    }

    fn strs(&self, c: &str) -> Result<Vec<String>, TableError> {
        let ca = col(self.df, self.path, c)?.str().map_err(|e| self.bad(c, e))?.clone();
        Ok(ca.iter().map(|v| v.unwrap_or("").to_string()).collect())
    }

    fn opts(&self, c: &str) -> Result<Vec<Option<f64>>, TableError> {
        let ca = col(self.df, self.path, c)?.f64().map_err(|e| self.bad(c, e))?.clone();
        Ok(ca.iter().collect())
    }

    fn f64s(&self, c: &str) -> Result<Vec<f64>, TableError> {
        Ok(self.opts(c)?.into_iter().map(|v| v.unwrap_or(f64::NAN)).collect())
    }

    fn lists(&self, c: &str) -> Result<Vec<Vec<f64>>, TableError> {
        let ca = col(self.df, self.path, c)?.list().map_err(|e| self.bad(c, e))?.clone();
        let mut out = Vec::with_capacity(ca.len());
        for s in ca.amortized_iter() {
            let v = match s {
                Some(s) => {
                    s.as_ref().f64().map_err(|e| self.bad(c, e))?.iter().map(|v| v.unwrap_or(f64::NAN)).collect()
                }
                None => Vec::new(),
            };
            out.push(v);
        }
        Ok(out)
    }
}

/// Reads `realizations.parquet` back into rows (for `drystone merge`), column by column
/// from the list the writer follows.
///
/// # Errors
/// [`TableError`] naming the file and column (and the row of a bad value).
pub fn read_realizations(path: &Path) -> Result<Vec<RealizationRow>, TableError> {
    let f = File::open(path).map_err(|source| TableError::Io { path: path.to_owned(), source })?;
    let df = ParquetReader::new(f).finish().map_err(pe(path))?;
    let r = Columns { df: &df, path };
    let mut rows = vec![RealizationRow::default(); df.height()];
    for c in COLUMNS {
        if c.optional && df.column(c.name).is_err() {
            continue;
        }
        match c.field {
            Field::Count(_, set) => r.u64s(c.name)?.into_iter().zip(&mut rows).for_each(|(v, row)| set(row, v)),
            Field::OptCount(_, set) => r.opt_u64s(c.name)?.into_iter().zip(&mut rows).for_each(|(v, row)| set(row, v)),
            Field::Text(_, set) => {
                for (i, (v, row)) in r.strs(c.name)?.into_iter().zip(&mut rows).enumerate() {
                    set(row, v).map_err(|message| TableError::Column {
                        path: path.to_owned(),
                        column: c.name.into(),
                        message: format!("row {}: {message}", i + 1),
                    })?;
                }
            }
            Field::Number(_, set) => r.f64s(c.name)?.into_iter().zip(&mut rows).for_each(|(v, row)| set(row, v)),
            Field::OptNumber(_, set) => r.opts(c.name)?.into_iter().zip(&mut rows).for_each(|(v, row)| set(row, v)),
            Field::Series(_, set) => r.lists(c.name)?.into_iter().zip(&mut rows).for_each(|(v, row)| *set(row) = v),
            Field::Derived(_) => {}
        }
    }
    Ok(rows)
}

fn read_csv(path: &Path) -> Result<DataFrame, TableError> {
    if !path.exists() {
        return Err(TableError::Io {
            path: path.to_owned(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
        });
    }
    CsvReadOptions::default()
        .with_has_header(true)
        .with_infer_schema_length(None)
        .try_into_reader_with_file_path(Some(path.to_owned()))
        .map_err(pe(path))?
        .finish()
        .map_err(pe(path))
}

fn str_col(df: &DataFrame, path: &Path, name: &str) -> Result<Vec<String>, TableError> {
    let c = col(df, path, name)?;
    let c = c.cast(&DataType::String).map_err(pe(path))?;
    let ca = c.str().map_err(pe(path))?.clone();
    Ok(ca.iter().map(|v| v.unwrap_or("").to_string()).collect())
}

fn f64_col(df: &DataFrame, path: &Path, name: &str) -> Result<Vec<f64>, TableError> {
    let c = col(df, path, name)?;
    let c = c.cast(&DataType::Float64).map_err(pe(path))?;
    let ca = c.f64().map_err(pe(path))?.clone();
    ca.iter()
        .enumerate()
        .map(|(i, v)| {
            v.filter(|x| x.is_finite()).ok_or_else(|| TableError::Column {
                path: path.to_owned(),
                column: name.into(),
                message: format!("row {} is missing or not a finite number", i + 1),
            })
        })
        .collect()
}

/// A collapse angle of the source paper's own DEM (its Table 7, YADE clump model).
#[derive(Debug, Clone, PartialEq)]
pub struct PaperDemAngle {
    /// The paper's model label (`SBL_or_CBL`, `SBR`).
    pub model: String,
    /// `free` or `restrained`.
    pub ends: String,
    /// Friction angle φ, degrees.
    pub friction_deg: f64,
    /// Joint normal stiffness Kn, Pa/m.
    pub kn_pa_per_m: f64,
    /// Collapse angle α_max, degrees.
    pub collapse_angle_deg: f64,
}

/// Reads the paper's DEM collapse angles: columns `model`, `ends`, `phi_deg`,
/// `kn_pa_per_m`, `collapse_angle_deg`.
///
/// # Errors
/// [`TableError`] naming the file and column.
pub fn read_paper_dem(path: &Path) -> Result<Vec<PaperDemAngle>, TableError> {
    let df = read_csv(path)?;
    let mo = str_col(&df, path, "model")?;
    let en = str_col(&df, path, "ends")?;
    let ph = f64_col(&df, path, "phi_deg")?;
    let kn = f64_col(&df, path, "kn_pa_per_m")?;
    let a = f64_col(&df, path, "collapse_angle_deg")?;
    Ok((0..mo.len())
        .map(|i| PaperDemAngle {
            model: mo[i].clone(),
            ends: en[i].clone(),
            friction_deg: ph[i],
            kn_pa_per_m: kn[i],
            collapse_angle_deg: a[i],
        })
        .collect())
}

/// A generic table of named columns (numbers or text) written as CSV through polars.
#[derive(Debug, Clone, Default)]
pub struct SimpleTable {
    /// Columns in order: name and values.
    pub columns: Vec<(String, TableColumn)>,
}

/// A column of a [`SimpleTable`].
#[derive(Debug, Clone)]
pub enum TableColumn {
    /// Text.
    Text(Vec<String>),
    /// Numbers (NaN written as empty).
    Number(Vec<f64>),
    /// Counts (written as integers).
    Count(Vec<u64>),
}

impl SimpleTable {
    /// Writes the table as CSV.
    ///
    /// # Errors
    /// [`TableError`] naming the file.
    pub fn write_csv(&self, path: &Path) -> Result<(), TableError> {
        let cols: Vec<Column> = self
            .columns
            .iter()
            .map(|(n, c)| match c {
                TableColumn::Text(v) => Column::new(n.as_str().into(), v.clone()),
                TableColumn::Number(v) => Column::new(
                    n.as_str().into(),
                    v.iter().map(|x| if x.is_finite() { Some(*x) } else { None }).collect::<Vec<Option<f64>>>(),
                ),
                TableColumn::Count(v) => Column::new(n.as_str().into(), v.clone()),
            })
            .collect();
        let mut df = DataFrame::new_infer_height(cols).map_err(pe(path))?;
        write_csv(&mut df, path)
    }
}

#[cfg(test)]
#[path = "table_tests.rs"]
mod tests;
