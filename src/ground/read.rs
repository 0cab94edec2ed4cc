//! Record files: PEER NGA `.AT2` and two-column CSV/TSV.
//!
//! **AT2** (the PEER NGA-West1 and -West2 databases): four header lines (title, event,
//! `ACCELERATION TIME SERIES IN UNITS OF G`, then `NPTS=  5590, DT=   .0050 SEC` or the
//! older `5590    .0050    NPTS, DT`), then NPTS accelerations in g, several per line.
//!
//! **CSV/TSV** (`.csv`, `.tsv`, `.txt`): lines starting with `#` are comments; the first
//! other line is the header, comma- or tab-separated: `time_s`, then exactly one horizontal
//! acceleration with its unit in the column name's suffix (`_g`, `_m_s2`, `_cm_s2` or
//! `_gal`), and optionally one vertical acceleration the same way, marked vertical by its
//! name (it starts with `vert` or `z`, or one of its `_`-separated words is `vert`,
//! `vertical`, `z` or `up`). Any other acceleration column is refused: a second
//! horizontal component (`accel_h1_g,accel_h2_g`) is not a vertical one. A [`ColumnMap`]
//! (`--columns time=t,h=acc_x_g,v=acc_z_g`, or `columns = { ... }` in a study's `[shake]`
//! table) names the columns instead; the others are then ignored. A vertical channel
//! whose mean is 0.5 g or more in size is refused: gravity is in it (a raw accelerometer
//! channel), or it is no ground motion. Times start at or after 0 and increase strictly; a
//! non-uniform time column is resampled by linear interpolation at its smallest interval.
//!
//! Every problem is refused naming the file and the line: a missing or unknown unit,
//! NPTS/DT missing or DT ≤ 0, a value that is not a finite number, fewer or more values
//! than NPTS, times that do not increase, an empty record, a record (or its resampling)
//! longer than [`super::MAX_MOTION_SAMPLES`] samples or [`super::MAX_MOTION_DURATION_S`]
//! seconds (refused before it is allocated, with what it would take).

use super::{check_motion_size, Motion, G};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The columns of a CSV/TSV record named explicitly: the time column (seconds; `time_s`
/// if not given), the horizontal acceleration `h` and optionally the vertical one `v`
/// (their units by their names' suffixes, as always). Other columns are ignored. On the
/// command line `--columns time=t,h=acc_x_g,v=acc_z_g` (`time` and `v` optional); in a
/// study `[shake] columns = { time = "t", h = "acc_x_g", v = "acc_z_g" }`, for every
/// CSV/TSV record of the study. Not used for AT2 files (one component, in g).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColumnMap {
    /// The time column, s \[`time_s`\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<String>,
    /// The horizontal acceleration column (along +y, out of plane).
    pub h: String,
    /// The vertical acceleration column (along +z, up); `None`: no vertical component.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v: Option<String>,
}

impl std::str::FromStr for ColumnMap {
    type Err = String;

    /// Parses `time=t,h=acc_x_g,v=acc_z_g` (keys `time`, `h`, `v`, each at most once; `h`
    /// required).
    fn from_str(text: &str) -> Result<Self, String> {
        let (mut time, mut h, mut v) = (None, None, None);
        for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let Some((key, name)) = part.split_once('=') else {
                return Err(format!("{part:?} is not KEY=COLUMN (keys time, h, v; e.g. time=t,h=acc_x_g,v=acc_z_g)"));
            };
            let (key, name) = (key.trim(), name.trim());
            if name.is_empty() {
                return Err(format!("{key}= names no column"));
            }
            let slot = match key {
                "time" | "t" => &mut time,
                "h" => &mut h,
                "v" => &mut v,
                other => return Err(format!("unknown key {other:?}: the keys are time, h and v")),
            };
            if slot.replace(name.to_string()).is_some() {
                return Err(format!("{key} is given twice"));
            }
        }
        let h = h.ok_or_else(|| "no h=COLUMN: the horizontal acceleration column is required".to_string())?;
        Ok(ColumnMap { time, h, v })
    }
}

/// Whether a column's name marks it vertical: it starts with `vert` or `z`, or one of its
/// words (separated by `_`, `-`, `.` or spaces) is `vert`, `vertical`, `z`, `up` or `ud`.
fn is_vertical_name(name: &str) -> bool {
    let n = name.trim().to_ascii_lowercase();
    n.starts_with("vert")
        || n.starts_with('z')
        || n.split(['_', '-', '.', ' ']).any(|w| matches!(w, "vert" | "vertical" | "z" | "up" | "ud"))
}

/// Largest |mean| of a vertical channel, g \[0.5\]: halfway to the 1 g a raw
/// accelerometer channel carries at rest; a ground motion's vertical acceleration
/// averages about 0.
pub const MAX_VERTICAL_MEAN_G: f64 = 0.5;

/// Why a record file was refused.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[error("{}{}: {message}", path.display(), line.map_or(String::new(), |l| format!(", line {l}")))]
pub struct RecordError {
    /// The file.
    pub path: PathBuf,
    /// The line (1-based), where one is at fault.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

fn err(path: &Path, line: Option<usize>, message: impl Into<String>) -> RecordError {
    RecordError { path: path.to_path_buf(), line, message: message.into() }
}

/// Reads a record file, by its extension: `.at2` (any case) as PEER NGA, `.csv`, `.tsv`
/// and `.txt` as columns. The motion is named by the file stem.
///
/// # Errors
/// [`RecordError`] naming the file and line (module doc).
pub fn read_record(path: &Path) -> Result<Motion, RecordError> {
    read_record_with(path, None)
}

/// As [`read_record`], with the columns of a CSV/TSV record named by `columns` (see
/// [`ColumnMap`]); `None`: by the header's names (module doc).
///
/// # Errors
/// As [`read_record`]; also a mapped column missing from the header, or a mapping given
/// for an AT2 record.
pub fn read_record_with(path: &Path, columns: Option<&ColumnMap>) -> Result<Motion, RecordError> {
    let text = std::fs::read_to_string(path).map_err(|e| err(path, None, format!("cannot read: {e}")))?;
    // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first line.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("record").to_string();
    let (dt_s, horizontal_g, vertical_g) = match ext.as_str() {
        "at2" if columns.is_some() => {
            return Err(err(path, None, "an AT2 record has one column (in g): a column mapping does not apply to it"))
        }
        "at2" => parse_at2(path, text).map(|(dt, a)| (dt, a, None))?,
        "csv" | "tsv" | "txt" => parse_columns(path, text, columns)?,
        other => {
            return Err(err(
                path,
                None,
                format!("unknown record format {other:?}: expected .AT2 (PEER NGA), .csv or .tsv"),
            ))
        }
    };
    Ok(Motion { name, dt_s, horizontal_g, vertical_g })
}

fn number(path: &Path, line: usize, token: &str) -> Result<f64, RecordError> {
    // Fortran exponents (`1.0D-03`) as in some record files.
    let v: f64 = token
        .replace(['D', 'd'], "E")
        .parse()
        .map_err(|_| err(path, Some(line), format!("{token:?} is not a number")))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(path, Some(line), format!("{token:?} is not a finite number")))
    }
}

fn parse_at2(path: &Path, text: &str) -> Result<(f64, Vec<f64>), RecordError> {
    let lines: Vec<&str> = text.lines().collect();
    if lines.len() < 4 {
        return Err(err(path, None, "an AT2 record needs four header lines and its values; the file is shorter"));
    }
    if !lines[2].to_ascii_uppercase().contains("UNITS OF G") {
        return Err(err(
            path,
            Some(3),
            format!("the third header line must state the unit (\"... IN UNITS OF G\"), got {:?}", lines[2].trim()),
        ));
    }
    let (npts, dt) = npts_dt(path, lines[3])?;
    if !(dt > 0.0) {
        return Err(err(path, Some(4), format!("DT must be > 0, got {dt}")));
    }
    check_motion_size(npts as f64, (npts as f64 - 1.0) * dt)
        .map_err(|m| err(path, Some(4), format!("NPTS = {npts}, DT = {dt} s: {m}")))?;
    let mut values = Vec::with_capacity(npts);
    for (i, l) in lines.iter().enumerate().skip(4) {
        for tok in l.split_whitespace() {
            if values.len() == npts {
                return Err(err(path, Some(i + 1), format!("more values than NPTS = {npts}")));
            }
            values.push(number(path, i + 1, tok)?);
        }
    }
    if values.is_empty() {
        return Err(err(path, None, "the record is empty (no values after the header)"));
    }
    if values.len() < npts {
        return Err(err(path, Some(lines.len()), format!("{} values, NPTS = {npts} in the header", values.len())));
    }
    Ok((dt, values))
}

/// NPTS and DT from the fourth header line, in either layout.
fn npts_dt(path: &Path, line: &str) -> Result<(usize, f64), RecordError> {
    let upper = line.to_ascii_uppercase();
    let bad =
        || err(path, Some(4), format!("expected NPTS and DT (\"NPTS= 5590, DT= .0050 SEC\"), got {:?}", line.trim()));
    let (n, dt) = if upper.contains("NPTS=") || upper.contains("NPTS =") {
        let after = |key: &str| -> Option<String> {
            let i = upper.find(key)? + key.len();
            let rest = upper[i..].trim_start().trim_start_matches('=').trim_start();
            Some(rest.split(|c: char| c == ',' || c.is_whitespace()).next()?.to_string())
        };
        (after("NPTS").ok_or_else(bad)?, after("DT").ok_or_else(bad)?)
    } else {
        let toks: Vec<&str> = upper.split(|c: char| c == ',' || c.is_whitespace()).filter(|t| !t.is_empty()).collect();
        if toks.len() < 2 {
            return Err(bad());
        }
        (toks[0].to_string(), toks[1].to_string())
    };
    let npts: usize = n.trim().parse().map_err(|_| bad())?;
    let dt = number(path, 4, dt.trim())?;
    if npts == 0 {
        return Err(err(path, Some(4), "NPTS is 0: the record is empty"));
    }
    Ok((npts, dt))
}

/// The size of a column's unit in g (the values are divided by it), by its name's suffix.
fn unit_to_g(name: &str) -> Option<f64> {
    let n = name.trim().to_ascii_lowercase();
    if n.ends_with("_cm_s2") || n.ends_with("_gal") {
        Some(100.0 * G)
    } else if n.ends_with("_m_s2") {
        Some(G)
    } else if n.ends_with("_g") {
        Some(1.0)
    } else {
        None
    }
}

/// A column file's record: the time step (s), the horizontal acceleration and the vertical
/// one if the file has it (g, one value a step).
type Columns = (f64, Vec<f64>, Option<Vec<f64>>);

/// The cells of a column file's line, trimmed: split at tabs if it has any, else at commas.
fn cells(l: &str) -> Vec<String> {
    if l.contains('\t') { l.split('\t') } else { l.split(',') }.map(|s| s.trim().to_string()).collect()
}

/// The size in g of the unit of column `name` (header line `hl`), by its name's suffix.
/// Errors: the name states no unit.
fn column_unit(path: &Path, hl: Option<usize>, name: &str) -> Result<f64, RecordError> {
    unit_to_g(name).ok_or_else(|| {
        err(path, hl, format!("column {name:?} states no unit: end its name with _g, _m_s2, _cm_s2 or _gal"))
    })
}

/// The (time, horizontal, vertical) columns, indices into `names`, that `--columns` names
/// (the time column `time_s` unless it names one). Errors: a name not in the header, or two
/// roles given one column.
fn mapped_columns(
    path: &Path,
    hl: Option<usize>,
    names: &[String],
    m: &ColumnMap,
) -> Result<(usize, usize, Option<usize>), RecordError> {
    let find = |key: &str, name: &str| -> Result<usize, RecordError> {
        names.iter().position(|n| n == name).ok_or_else(|| {
            err(path, hl, format!("--columns {key}={name}: no such column; the header has {}", names.join(", ")))
        })
    };
    let t = find("time", m.time.as_deref().unwrap_or("time_s"))?;
    let h = find("h", &m.h)?;
    let v = m.v.as_deref().map(|v| find("v", v)).transpose()?;
    if h == t || v == Some(t) || v == Some(h) {
        return Err(err(path, hl, "--columns: time, h and v must name three different columns"));
    }
    Ok((t, h, v))
}

/// The (time, horizontal, vertical) columns of a header without `--columns`: `time_s`
/// first, then one horizontal column and at most one vertical one (its name says so, see
/// `is_vertical_name`), every acceleration column with its unit. Errors: any other header.
fn named_columns(
    path: &Path,
    hl: Option<usize>,
    names: &[String],
    header: &str,
) -> Result<(usize, usize, Option<usize>), RecordError> {
    if names.len() < 2 || !names[0].eq_ignore_ascii_case("time_s") {
        return Err(err(
            path,
            hl,
            format!(
                "the header must be `time_s` then the acceleration with its unit (e.g. `time_s,accel_g`), got {header:?}"
            ),
        ));
    }
    for name in &names[1..] {
        column_unit(path, hl, name)?;
    }
    let (vert, horiz): (Vec<usize>, Vec<usize>) = (1..names.len()).partition(|&k| is_vertical_name(&names[k]));
    let quoted = |ks: &[usize]| ks.iter().map(|&k| format!("{:?}", names[k])).collect::<Vec<_>>().join(", ");
    let fix = "name the columns with --columns time=time_s,h=NAME[,v=NAME] \
               (a study: [shake] columns = { h = \"NAME\", v = \"NAME\" })";
    let hcol = match horiz.as_slice() {
        [h] => *h,
        [] => {
            return Err(err(
                path,
                hl,
                format!("a vertical column alone ({}): the horizontal one is missing", quoted(&vert)),
            ))
        }
        _ => {
            return Err(err(
                path,
                hl,
                format!(
                    "{} horizontal acceleration columns ({}): one is the motion, and a column is vertical only \
                     if its name says so (vert, z or up); {fix}",
                    horiz.len(),
                    quoted(&horiz)
                ),
            ))
        }
    };
    if vert.len() > 1 {
        return Err(err(path, hl, format!("{} vertical columns ({}): at most one; {fix}", vert.len(), quoted(&vert))));
    }
    Ok((0, hcol, vert.first().copied()))
}

/// A column file (CSV or TSV; `#` lines and blank lines skipped): a header naming the
/// columns, then one sample a line, the columns chosen by `map` or by their names.
/// Errors: a header or line that does not fit, times not increasing, a vertical column that
/// contains gravity, or a record too long.
fn parse_columns(path: &Path, text: &str, map: Option<&ColumnMap>) -> Result<Columns, RecordError> {
    let mut rows = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let Some((hline, header)) = rows.next() else {
        return Err(err(path, None, "the record is empty (no header line)"));
    };
    let names = cells(header);
    let hl = Some(hline + 1);
    // (time column, horizontal column, vertical column), indices into `names`.
    let (tcol, hcol, vcol) = match map {
        Some(m) => mapped_columns(path, hl, &names, m)?,
        None => named_columns(path, hl, &names, header)?,
    };
    let hf = column_unit(path, hl, &names[hcol])?;
    let vf = vcol.map(|k| column_unit(path, hl, &names[k])).transpose()?;
    let (mut t, mut h, mut v) = (Vec::new(), Vec::new(), Vec::new());
    for (i, l) in rows {
        let cells = cells(l);
        if cells.len() != names.len() {
            return Err(err(path, Some(i + 1), format!("{} columns, the header has {}", cells.len(), names.len())));
        }
        let time = number(path, i + 1, &cells[tcol])?;
        if time < 0.0 {
            return Err(err(path, Some(i + 1), format!("time {time} s is negative")));
        }
        if let Some(&last) = t.last() {
            if !(time > last) {
                return Err(err(
                    path,
                    Some(i + 1),
                    format!("time {time} s does not increase (the line before: {last} s)"),
                ));
            }
        }
        t.push(time);
        h.push(number(path, i + 1, &cells[hcol])? / hf);
        if let (Some(vc), Some(f)) = (vcol, vf) {
            v.push(number(path, i + 1, &cells[vc])? / f);
        }
    }
    if t.len() < 2 {
        return Err(err(path, None, format!("{} samples: a record needs at least two", t.len())));
    }
    if let Some(vc) = vcol {
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        if !(mean.abs() < MAX_VERTICAL_MEAN_G) {
            return Err(err(
                path,
                None,
                format!(
                    "the vertical column {:?} averages {mean:.3} g: it contains gravity (a raw accelerometer channel \
                     reads about ±1 g at rest; a ground motion's vertical acceleration averages about 0). Subtract \
                     the static reading from the column, or leave it out (--columns time={},h={})",
                    names[vc], names[tcol], names[hcol]
                ),
            ));
        }
    }
    uniform(path, &t, h, vcol.map(|_| v))
}

/// The record on a uniform time step from its samples at times `t` (s, increasing, at
/// least two) of the horizontal acceleration `h` and the vertical one `v` (g): as they are
/// when the times are uniform from 0, else resampled linearly from t = 0 at the smallest
/// interval (zero before the first sample). Errors: the record is too long (see
/// `check_motion_size`).
fn uniform(path: &Path, t: &[f64], h: Vec<f64>, v: Option<Vec<f64>>) -> Result<Columns, RecordError> {
    let dt = t.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
    let uniform = t.windows(2).all(|w| ((w[1] - w[0]) / dt - 1.0).abs() < 1e-6) && t[0] == 0.0;
    if uniform {
        check_motion_size(t.len() as f64, t[t.len() - 1]).map_err(|m| err(path, None, m))?;
        return Ok((dt, h, v));
    }
    // Resampled from t = 0 at the smallest interval (zero before the first sample).
    let last = t[t.len() - 1];
    let samples = (last / dt).round() + 1.0;
    check_motion_size(samples, last).map_err(|m| {
        err(
            path,
            None,
            format!(
                "the times are not uniform and their smallest interval is {dt:e} s: resampled at it to {last} s, {m}; \
                 resample the record uniformly"
            ),
        )
    })?;
    let n = samples as usize;
    let resample = |a: &[f64]| -> Vec<f64> {
        let mut j = 0;
        (0..n)
            .map(|k| {
                let tk = k as f64 * dt;
                if tk < t[0] {
                    return 0.0;
                }
                while j + 1 < t.len() && t[j + 1] < tk {
                    j += 1;
                }
                if j + 1 >= t.len() {
                    return a[a.len() - 1];
                }
                let f = ((tk - t[j]) / (t[j + 1] - t[j])).clamp(0.0, 1.0);
                a[j] * (1.0 - f) + a[j + 1] * f
            })
            .collect()
    };
    Ok((dt, resample(&h), v.as_deref().map(resample)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("drystone-records-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    const AT2: &str = "PEER NGA STRONG MOTION DATABASE RECORD\nTest event, 01/01/2000, Station, 000\n\
ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=     7, DT=   .0050 SEC\n  .1000000E-01  -.2000000E-01  .3000000E-01\n\
 .4000000E-01 -.5000000E-01\n  .6000000E-01  .0000000E+00\n";

    #[test]
    fn an_at2_record_reads_in_both_header_layouts() {
        let m = read_record(&write("a.AT2", AT2)).unwrap();
        assert_eq!(m.dt_s, 0.005);
        assert_eq!(m.horizontal_g.len(), 7);
        assert_eq!(m.horizontal_g[4], -0.05);
        assert_eq!(m.name, "a");
        let old = AT2.replace("NPTS=     7, DT=   .0050 SEC", "    7    .0050    NPTS, DT");
        assert_eq!(read_record(&write("b.at2", &old)).unwrap(), Motion { name: "b".into(), ..m });
    }

    #[test]
    fn bad_records_are_refused_naming_file_and_line() {
        let cases = [
            ("u.AT2", AT2.replace("IN UNITS OF G", "IN UNITS OF CM/S/S"), "line 3"),
            ("d.AT2", AT2.replace(".0050", "0.0"), "DT must be > 0"),
            ("n.AT2", AT2.replace(".4000000E-01", "NaN"), "line 6"),
            ("s.AT2", AT2.replace("NPTS=     7", "NPTS=     9"), "NPTS = 9"),
            ("e.AT2", AT2.lines().take(4).collect::<Vec<_>>().join("\n"), "empty"),
            ("c.csv", "time_s,accel\n0,0.1\n0.01,0.2\n".into(), "states no unit"),
            ("m.csv", "time_s,accel_g\n0,0.1\n0.01,0.2\n0.01,0.3\n".into(), "line 4"),
            ("x.csv", "time_s,accel_g\n0,0.1\n0.01,nan\n".into(), "line 3"),
            ("y.csv", "time_s,accel_g\n".into(), "0 samples"),
        ];
        for (name, text, needle) in cases {
            let e = read_record(&write(name, &text)).unwrap_err().to_string();
            assert!(e.contains(name) && e.contains(needle), "{name}: {e}");
        }
    }

    #[test]
    fn columns_read_with_their_units_and_resample() {
        let m = read_record(&write("r.csv", "# a comment\ntime_s,accel_m_s2\n0,9.80665\n0.01,-4.903325\n")).unwrap();
        assert_eq!(m.horizontal_g, vec![1.0, -0.5]);
        let t = read_record(&write("r.tsv", "time_s\tvert_g\taccel_cm_s2\n0\t0.5\t980.665\n0.02\t0\t0\n")).unwrap();
        assert_eq!(t.horizontal_g, vec![1.0, 0.0]);
        assert_eq!(t.vertical_g, Some(vec![0.5, 0.0]));
        // Non-uniform times: resampled at the smallest interval by linear interpolation.
        let u = read_record(&write("u.csv", "time_s,accel_g\n0,0\n0.01,0.1\n0.03,0.3\n")).unwrap();
        assert!((u.dt_s - 0.01).abs() < 1e-15);
        assert_eq!(u.horizontal_g.len(), 4);
        assert!((u.horizontal_g[2] - 0.2).abs() < 1e-12);
    }

    /// A UTF-8 byte-order mark before the header (as spreadsheets save a CSV) reads as the
    /// same record without it, in a column file and in an AT2 file.
    #[test]
    fn a_byte_order_mark_before_the_header_is_read_past() {
        let text = "time_s,accel_g\n0,0.1\n0.01,-0.2\n";
        let plain = read_record(&write("plain.csv", text)).unwrap();
        let marked = read_record(&write("plain_bom.csv", &format!("\u{feff}{text}"))).unwrap();
        assert_eq!(marked.horizontal_g, vec![0.1, -0.2]);
        assert_eq!(Motion { name: plain.name.clone(), ..marked }, plain);
        let at2 = read_record(&write("bom.AT2", &format!("\u{feff}{AT2}"))).unwrap();
        assert_eq!(at2.horizontal_g.len(), 7);
    }
}
