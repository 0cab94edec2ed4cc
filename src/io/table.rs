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
use crate::ensemble::row::{CollapseColumns, LateralColumns, RealizationRow, Status, TiltColumns};
use polars::prelude::*;
use std::fs::File;
use std::path::Path;

pub use super::error::TableError;

fn pe(path: &Path) -> impl Fn(PolarsError) -> TableError + '_ {
    move |e| TableError::Polars { path: path.to_owned(), message: e.to_string() }
}

fn list_column(name: &str, rows: &[RealizationRow], f: impl Fn(&RealizationRow) -> &Vec<f64>) -> Column {
    let series: Vec<Series> = rows.iter().map(|r| Series::new("".into(), f(r).as_slice())).collect();
    Series::new(name.into(), series.as_slice()).into_column()
}

fn joined_column(name: &str, rows: &[RealizationRow], f: impl Fn(&RealizationRow) -> &Vec<f64>) -> Column {
    let v: Vec<String> =
        rows.iter().map(|r| f(r).iter().map(|x| format!("{x}")).collect::<Vec<_>>().join(";")).collect();
    Column::new(name.into(), v)
}

/// The realizations as a data frame; `lists` chooses list columns (Parquet) or joined
/// strings (CSV) for the per-increment series.
pub fn realizations_frame(rows: &[RealizationRow], lists: bool) -> PolarsResult<DataFrame> {
    let u = |f: fn(&RealizationRow) -> u64| rows.iter().map(f).collect::<Vec<u64>>();
    let s = |f: fn(&RealizationRow) -> String| rows.iter().map(f).collect::<Vec<String>>();
    let of = |f: fn(&RealizationRow) -> Option<f64>| rows.iter().map(f).collect::<Vec<Option<f64>>>();
    let series = |name: &str, f: fn(&RealizationRow) -> &Vec<f64>| {
        if lists {
            list_column(name, rows, f)
        } else {
            joined_column(name, rows, f)
        }
    };
    let mut columns = vec![
        Column::new("index".into(), u(|r| r.index)),
        Column::new("study".into(), s(|r| r.study.clone())),
        Column::new("group".into(), s(|r| r.group.clone())),
        Column::new("point".into(), u(|r| r.point)),
        Column::new("sweep".into(), s(|r| r.sweep.clone())),
        Column::new("seed".into(), u(|r| r.seed)),
        Column::new("realization".into(), u(|r| r.realization)),
        Column::new("status".into(), s(|r| r.status.as_str().to_string())),
        Column::new("error".into(), s(|r| r.error.clone())),
        Column::new("blocks".into(), u(|r| r.blocks)),
        Column::new("collapse_angle_deg".into(), of(|r| r.collapse.collapse_angle_deg)),
        Column::new("first_unstable_deg".into(), of(|r| r.collapse.first_unstable_deg)),
        Column::new("collapse_reason".into(), s(|r| r.collapse.collapse_reason.clone())),
        Column::new("mechanism".into(), s(|r| r.collapse.mechanism.clone())),
        Column::new("joint".into(), s(|r| r.collapse.joint.clone())),
        Column::new("moving_blocks".into(), u(|r| r.collapse.moving_blocks)),
        Column::new("failure_height_fraction".into(), of(|r| r.collapse.failure_height_fraction)),
        Column::new("mechanism_kind".into(), s(|r| r.collapse.mechanism_kind.clone())),
        Column::new("mechanism_start".into(), s(|r| r.collapse.mechanism_start.clone())),
        Column::new("mechanism_extent".into(), of(|r| r.collapse.mechanism_extent)),
        Column::new("disp_mean_5deg_cm".into(), of(|r| r.disp_mean_at(5.0))),
        Column::new("disp_mean_10deg_cm".into(), of(|r| r.disp_mean_at(10.0))),
        Column::new("disp_centre_rel_5deg_cm".into(), of(|r| r.disp_centre_rel_at(5.0))),
        Column::new("disp_centre_rel_10deg_cm".into(), of(|r| r.disp_centre_rel_at(10.0))),
        Column::new("lateral_disp_left_cm".into(), of(|r| r.lateral.lateral_disp_left_cm)),
        Column::new("lateral_disp_centre_cm".into(), of(|r| r.lateral.lateral_disp_centre_cm)),
        Column::new("lateral_disp_right_cm".into(), of(|r| r.lateral.lateral_disp_right_cm)),
        Column::new("lateral_disp_max_cm".into(), of(|r| r.lateral.lateral_disp_max_cm)),
        Column::new("lateral_drift".into(), of(|r| r.lateral.lateral_drift)),
        Column::new("motion".into(), s(|r| r.shake.motion.clone())),
        Column::new("pga_g".into(), of(|r| r.shake.pga_g)),
        Column::new("collapse_time_s".into(), of(|r| r.shake.collapse_time_s)),
        Column::new("max_rotation_deg".into(), of(|r| r.shake.max_rotation_deg)),
        Column::new("max_drift".into(), of(|r| r.shake.max_drift)),
        Column::new("residual_drift".into(), of(|r| r.shake.residual_drift)),
        Column::new("blocks_fallen".into(), rows.iter().map(|r| r.shake.blocks_fallen).collect::<Vec<Option<u64>>>()),
        series("tilt_deg", |r| &r.tilt.tilt_deg),
        series("disp_top_left_cm", |r| &r.tilt.disp_top_left_cm),
        series("disp_top_centre_cm", |r| &r.tilt.disp_top_centre_cm),
        series("disp_top_right_cm", |r| &r.tilt.disp_top_right_cm),
        Column::new("steps".into(), u(|r| r.steps)),
        Column::new("iterations".into(), u(|r| r.iterations)),
        Column::new("dt_s".into(), rows.iter().map(|r| r.dt_s).collect::<Vec<f64>>()),
        Column::new("wall_time_s".into(), rows.iter().map(|r| r.wall_time_s).collect::<Vec<f64>>()),
    ];
    // The collapse load multipliers of a pushover study, after the others; only there.
    if rows.iter().any(|r| r.pushover.any()) {
        columns.extend([
            Column::new("load_multiplier_dem".into(), of(|r| r.pushover.load_multiplier_dem)),
            Column::new("load_multiplier_dem_unstable".into(), of(|r| r.pushover.load_multiplier_dem_unstable)),
            Column::new("load_multiplier_limit".into(), of(|r| r.pushover.load_multiplier_limit)),
        ]);
    }
    DataFrame::new_infer_height(columns)
}

/// Writes `realizations.parquet` and `realizations.csv` into `dir`, each replaced whole
/// ([`super::replace_file`]).
///
/// # Errors
/// [`TableError`] naming the file.
pub fn write_realizations(rows: &[RealizationRow], dir: &Path) -> Result<(), TableError> {
    let pq = dir.join("realizations.parquet");
    let mut df = realizations_frame(rows, true).map_err(pe(&pq))?;
    let mut bytes = Vec::new();
    ParquetWriter::new(&mut bytes).finish(&mut df).map_err(pe(&pq))?;
    replace(&pq, &bytes)?;
    let csv = dir.join("realizations.csv");
    let mut df = realizations_frame(rows, false).map_err(pe(&csv))?;
    write_csv(&mut df, &csv)
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

/// Reads `realizations.parquet` back into rows (for `drystone merge`).
///
/// # Errors
/// [`TableError`] naming the file and column.
pub fn read_realizations(path: &Path) -> Result<Vec<RealizationRow>, TableError> {
    let f = File::open(path).map_err(|source| TableError::Io { path: path.to_owned(), source })?;
    let df = ParquetReader::new(f).finish().map_err(pe(path))?;
    let r = Columns { df: &df, path };
    let index = r.u64s("index")?;
    let study = r.strs("study")?;
    let group = r.strs("group")?;
    let point = r.u64s("point")?;
    let sweep = r.strs("sweep")?;
    let seed = r.u64s("seed")?;
    let realization = r.u64s("realization")?;
    let status = r.strs("status")?;
    let error = r.strs("error")?;
    let blocks = r.u64s("blocks")?;
    let collapse = r.opts("collapse_angle_deg")?;
    let unstable = r.opts("first_unstable_deg")?;
    let reason = r.strs("collapse_reason")?;
    if let Some((i, bad)) = reason
        .iter()
        .enumerate()
        .find(|(_, x)| !x.is_empty() && crate::loading::tilt::CollapseReason::from_name(x).is_none())
    {
        let known: Vec<&str> = crate::loading::tilt::CollapseReason::ALL.iter().map(|x| x.name()).collect();
        return Err(TableError::Column {
            path: path.to_owned(),
            column: "collapse_reason".into(),
            message: format!("row {}: unknown collapse reason `{bad}` (known: {})", i + 1, known.join(", ")),
        });
    }
    let mechanism = r.strs("mechanism")?;
    let joint = r.strs("joint")?;
    let moving = r.u64s("moving_blocks")?;
    // Columns added later: a table written before them reads as without a mechanism.
    let n = index.len();
    let has = |c: &str| df.column(c).is_ok();
    let height = if has("failure_height_fraction") { r.opts("failure_height_fraction")? } else { vec![None; n] };
    let mkind = if has("mechanism_kind") { r.strs("mechanism_kind")? } else { vec![String::new(); n] };
    let mstart = if has("mechanism_start") { r.strs("mechanism_start")? } else { vec![String::new(); n] };
    let extent = if has("mechanism_extent") { r.opts("mechanism_extent")? } else { vec![None; n] };
    let lat_l = r.opts("lateral_disp_left_cm")?;
    let lat_c = r.opts("lateral_disp_centre_cm")?;
    let lat_r = r.opts("lateral_disp_right_cm")?;
    let lat = r.opts("lateral_disp_max_cm")?;
    let drift = r.opts("lateral_drift")?;
    // The shaking table's columns (added later: a table without them reads as rows of
    // another protocol).
    let shake_text = |c: &str| if has(c) { r.strs(c) } else { Ok(vec![String::new(); n]) };
    let shake_num = |c: &str| if has(c) { r.opts(c) } else { Ok(vec![None; n]) };
    let motion = shake_text("motion")?;
    let pga = shake_num("pga_g")?;
    let collapse_time = shake_num("collapse_time_s")?;
    let rotation = shake_num("max_rotation_deg")?;
    let max_drift = shake_num("max_drift")?;
    let residual = shake_num("residual_drift")?;
    let pushover_num = |c: &str| if has(c) { r.opts(c) } else { Ok(vec![None; n]) };
    let lambda_dem = pushover_num("load_multiplier_dem")?;
    let lambda_dem_up = pushover_num("load_multiplier_dem_unstable")?;
    let lambda_limit = pushover_num("load_multiplier_limit")?;
    let fallen = if has("blocks_fallen") { r.opt_u64s("blocks_fallen")? } else { vec![None; n] };
    let tilt = r.lists("tilt_deg")?;
    let dl = r.lists("disp_top_left_cm")?;
    let dc = r.lists("disp_top_centre_cm")?;
    let dr = r.lists("disp_top_right_cm")?;
    let steps = r.u64s("steps")?;
    let iterations = r.u64s("iterations")?;
    let dt = r.f64s("dt_s")?;
    let wall = r.f64s("wall_time_s")?;
    let mut rows = Vec::with_capacity(index.len());
    for i in 0..index.len() {
        let st = Status::parse(&status[i]).ok_or_else(|| TableError::Column {
            path: path.to_owned(),
            column: "status".into(),
            message: format!("unknown status {:?} in row {i}", status[i]),
        })?;
        rows.push(RealizationRow {
            index: index[i],
            study: study[i].clone(),
            group: group[i].clone(),
            point: point[i],
            sweep: sweep[i].clone(),
            seed: seed[i],
            realization: realization[i],
            status: st,
            error: error[i].clone(),
            blocks: blocks[i],
            collapse: CollapseColumns {
                collapse_angle_deg: collapse[i],
                first_unstable_deg: unstable[i],
                collapse_reason: reason[i].clone(),
                mechanism: mechanism[i].clone(),
                joint: joint[i].clone(),
                moving_blocks: moving[i],
                failure_height_fraction: height[i],
                mechanism_kind: mkind[i].clone(),
                mechanism_start: mstart[i].clone(),
                mechanism_extent: extent[i],
            },
            tilt: TiltColumns {
                tilt_deg: tilt[i].clone(),
                disp_top_left_cm: dl[i].clone(),
                disp_top_centre_cm: dc[i].clone(),
                disp_top_right_cm: dr[i].clone(),
            },
            lateral: LateralColumns {
                lateral_disp_left_cm: lat_l[i],
                lateral_disp_centre_cm: lat_c[i],
                lateral_disp_right_cm: lat_r[i],
                lateral_disp_max_cm: lat[i],
                lateral_drift: drift[i],
            },
            shake: crate::ensemble::row::ShakeColumns {
                motion: motion[i].clone(),
                pga_g: pga[i],
                collapse_time_s: collapse_time[i],
                max_rotation_deg: rotation[i],
                max_drift: max_drift[i],
                residual_drift: residual[i],
                blocks_fallen: fallen[i],
            },
            pushover: crate::ensemble::row::PushoverColumns {
                load_multiplier_dem: lambda_dem[i],
                load_multiplier_dem_unstable: lambda_dem_up[i],
                load_multiplier_limit: lambda_limit[i],
            },
            steps: steps[i],
            iterations: iterations[i],
            dt_s: dt[i],
            wall_time_s: wall[i],
        });
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
