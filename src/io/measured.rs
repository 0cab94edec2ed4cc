//! Measured data (CSV): collapse angles (`specimen, group, collapse_angle_deg`, the source
//! paper's Table 2), top displacements (`specimen, group, measure, tilt_deg,
//! displacement_cm`, its Table 3) and failure mechanisms as seen (`specimen, group,
//! failure_height_fraction, failure_height_low, failure_height_high, kind, start`, optional
//! `extent_fraction` and `source`: its §2.2), read and checked row by row. Other columns are
//! ignored.
//!
//! Every refusal names the file, the line (1-based, the header is line 1) and the column.
//! A file is refused when:
//!
//! | check | column |
//! | --- | --- |
//! | a required column is missing from the header | it |
//! | a row with another number of fields than the header, or an unclosed quote | – |
//! | an empty specimen or group | `specimen`, `group` |
//! | a number that does not parse or is not finite | it |
//! | a collapse angle outside (0°, 90°) | `collapse_angle_deg` |
//! | a tilt outside [0°, 90°) | `tilt_deg` |
//! | a displacement larger than [`MAX_DISPLACEMENT_CM`] in magnitude | `displacement_cm` |
//! | an unknown measure | `measure` |
//! | a specimen twice in the collapse file, or a (specimen, measure, tilt) twice | `specimen` |
//! | a specimen in two groups | `group` |
//! | a failure height, its low or high bound outside [0, 1], or not low ≤ value ≤ high, or given without both bounds | `failure_height_*` |
//! | an unknown kind (known: `toppling`, `sliding`, `bending`, `mixed`) | `kind` |
//! | an unknown start (known: `end`, `centre`, `uniform`, `random`) | `start` |
//! | an extent outside (0, 1] | `extent_fraction` |
//! | a specimen twice in the mechanism file | `specimen` |
//!
//! In the mechanism file every field but `specimen` and `group` may be empty (not seen or
//! not reported).
//!
//! [`check_against_study`] adds the checks that need the study: every displacement tilt on
//! the grid of tilts the study observes (a multiple of its `[tilt] step_deg`), no
//! displacement larger than the height of the group's wall, no displacement at a tilt
//! beyond the specimen's own collapse angle, and one group per specimen across the files;
//! [`check_mechanism_against_study`] that every mechanism row is of a group the study has and
//! of a specimen the other files know (when they hold any).

use super::error::TableError;
use crate::ensemble::row::Measure;
use crate::loading::mechanism::{FailureKind, FailureStart};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The largest top displacement a measured-data file may hold, cm (10 m: beyond the height
/// of any wall the tool models; the study check bounds it by the wall's own height).
pub const MAX_DISPLACEMENT_CM: f64 = 1000.0;

/// A measured collapse angle (the paper's Table 2).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeasuredCollapse {
    /// Specimen, e.g. `SBL2`.
    pub specimen: String,
    /// Group, e.g. `SBL`.
    pub group: String,
    /// Collapse tilt, degrees, in (0, 90).
    pub collapse_angle_deg: f64,
    /// The file it was read from (empty for data made in memory).
    pub file: PathBuf,
    /// Its line in the file (0 for data made in memory).
    pub line: usize,
}

/// A measured out-of-plane displacement (the paper's Table 3).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeasuredDisplacement {
    /// Specimen.
    pub specimen: String,
    /// Group.
    pub group: String,
    /// The measure (`mean_of_left_center_right` or `center_minus_mean_of_ends` in the
    /// file).
    pub measure: Measure,
    /// Tilt, degrees, in [0, 90).
    pub tilt_deg: f64,
    /// Displacement, cm.
    pub displacement_cm: f64,
    /// The file it was read from (empty for data made in memory).
    pub file: PathBuf,
    /// Its line in the file (0 for data made in memory).
    pub line: usize,
}

fn value_error(path: &Path, line: usize, column: &str, message: String) -> TableError {
    TableError::Value { path: path.to_owned(), line, column: column.to_string(), message }
}

/// The fields of one CSV line (RFC 4180 quoting, `""` for a quote inside quotes; fields
/// trimmed of surrounding blanks).
fn fields(text: &str) -> Option<Vec<String>> {
    let (mut out, mut cur, mut quoted, mut was_quoted) = (Vec::new(), String::new(), false, false);
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            '"' => {
                quoted = !quoted;
                was_quoted = true;
            }
            ',' if !quoted => {
                out.push(if was_quoted {
                    std::mem::take(&mut cur)
                } else {
                    std::mem::take(&mut cur).trim().to_string()
                });
                was_quoted = false;
            }
            _ => cur.push(c),
        }
    }
    if quoted {
        return None;
    }
    out.push(if was_quoted { cur } else { cur.trim().to_string() });
    Some(out)
}

/// A CSV file: its path, and its data rows as (line, column name → field).
struct Csv {
    path: PathBuf,
    rows: Vec<(usize, BTreeMap<String, String>)>,
}

impl Csv {
    /// Reads `path` and checks that its header has `required` columns.
    fn read(path: &Path, required: &[&str]) -> Result<Csv, TableError> {
        let text = std::fs::read_to_string(path).map_err(|source| TableError::Io { path: path.to_owned(), source })?;
        let bad = |line: usize, column: &str, m: String| value_error(path, line, column, m);
        let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim_end_matches('\r')));
        let Some((hl, header)) = lines.find(|(_, l)| !l.trim().is_empty()) else {
            return Err(bad(1, required[0], "the file is empty: no header line".into()));
        };
        let header = fields(header).ok_or_else(|| bad(hl, "-", "a quote is not closed".into()))?;
        for r in required {
            if !header.iter().any(|h| h == r) {
                return Err(bad(hl, r, format!("missing from the header (columns: {})", header.join(", "))));
            }
        }
        let mut rows = Vec::new();
        for (n, l) in lines.filter(|(_, l)| !l.trim().is_empty()) {
            let f = fields(l).ok_or_else(|| bad(n, "-", "a quote is not closed".into()))?;
            if f.len() != header.len() {
                return Err(bad(n, "-", format!("{} fields, the header has {}", f.len(), header.len())));
            }
            rows.push((n, header.iter().cloned().zip(f).collect()));
        }
        Ok(Csv { path: path.to_owned(), rows })
    }

    /// A field that may be empty.
    fn optional<'a>(&self, row: &'a BTreeMap<String, String>, column: &str) -> Option<&'a str> {
        row.get(column).map(String::as_str).filter(|v| !v.is_empty())
    }

    /// A finite number in `range` that may be empty.
    fn optional_number(
        &self,
        line: usize,
        row: &BTreeMap<String, String>,
        column: &str,
        ok: impl Fn(f64) -> bool,
        what: &str,
    ) -> Result<Option<f64>, TableError> {
        if self.optional(row, column).is_none() {
            return Ok(None);
        }
        self.number(line, row, column, ok, what).map(Some)
    }

    fn text<'a>(&self, line: usize, row: &'a BTreeMap<String, String>, column: &str) -> Result<&'a str, TableError> {
        let v = row.get(column).map_or("", String::as_str);
        if v.is_empty() {
            return Err(value_error(&self.path, line, column, "empty".into()));
        }
        Ok(v)
    }

    /// A finite number in `range` (`what` states the range in words).
    fn number(
        &self,
        line: usize,
        row: &BTreeMap<String, String>,
        column: &str,
        ok: impl Fn(f64) -> bool,
        what: &str,
    ) -> Result<f64, TableError> {
        let text = self.text(line, row, column)?;
        let v: f64 =
            text.parse().map_err(|_| value_error(&self.path, line, column, format!("`{text}` is not a number")))?;
        if !v.is_finite() || !ok(v) {
            return Err(value_error(&self.path, line, column, format!("{text} is not {what}")));
        }
        Ok(v)
    }
}

/// Every specimen of the collapse data with its group and where it was first read.
///
/// # Errors
/// [`TableError::Value`] for a specimen in two groups ([`one_group`]).
fn collapse_groups(collapse: &[MeasuredCollapse]) -> Result<SpecimenGroups, TableError> {
    let mut groups = BTreeMap::new();
    for c in collapse {
        one_group(&mut groups, &c.specimen, &c.group, &c.file, c.line)?;
    }
    Ok(groups)
}

/// Specimen → (its group, the file and the line it was first read at).
type SpecimenGroups = BTreeMap<String, (String, PathBuf, usize)>;

/// Records `specimen`'s group and refuses a second group.
fn one_group(
    seen: &mut SpecimenGroups,
    specimen: &str,
    group: &str,
    path: &Path,
    line: usize,
) -> Result<(), TableError> {
    match seen.get(specimen) {
        Some((g, p, l)) if g != group => Err(value_error(
            path,
            line,
            "group",
            format!("specimen {specimen} is in group {group} here and in group {g} on line {l} of {}", p.display()),
        )),
        Some(_) => Ok(()),
        None => {
            seen.insert(specimen.to_string(), (group.to_string(), path.to_owned(), line));
            Ok(())
        }
    }
}

/// Reads measured collapse angles: columns `specimen`, `group`, `collapse_angle_deg`.
///
/// # Errors
/// [`TableError`] naming the file, the line and the column (see the module table).
pub fn read_measured_collapse(path: &Path) -> Result<Vec<MeasuredCollapse>, TableError> {
    let csv = Csv::read(path, &["specimen", "group", "collapse_angle_deg"])?;
    let mut out: Vec<MeasuredCollapse> = Vec::new();
    for (line, row) in &csv.rows {
        let line = *line;
        let specimen = csv.text(line, row, "specimen")?.to_string();
        let group = csv.text(line, row, "group")?.to_string();
        let a = csv.number(line, row, "collapse_angle_deg", |a| a > 0.0 && a < 90.0, "in (0, 90) degrees")?;
        if let Some(first) = out.iter().find(|c| c.specimen == specimen) {
            return Err(value_error(
                path,
                line,
                "specimen",
                format!("specimen {specimen} has a collapse angle on line {} already (one per specimen)", first.line),
            ));
        }
        out.push(MeasuredCollapse { specimen, group, collapse_angle_deg: a, file: path.to_owned(), line });
    }
    Ok(out)
}

/// Reads measured displacements: columns `specimen`, `group`, `measure`, `tilt_deg`,
/// `displacement_cm`.
///
/// # Errors
/// [`TableError`] naming the file, the line and the column (see the module table).
pub fn read_measured_displacement(path: &Path) -> Result<Vec<MeasuredDisplacement>, TableError> {
    let csv = Csv::read(path, &["specimen", "group", "measure", "tilt_deg", "displacement_cm"])?;
    let mut out: Vec<MeasuredDisplacement> = Vec::new();
    let mut groups = BTreeMap::new();
    for (line, row) in &csv.rows {
        let line = *line;
        let specimen = csv.text(line, row, "specimen")?.to_string();
        let group = csv.text(line, row, "group")?.to_string();
        let name = csv.text(line, row, "measure")?;
        let Some(measure) = Measure::from_name(name) else {
            return Err(value_error(
                path,
                line,
                "measure",
                format!("unknown measure `{name}` (known: {})", Measure::ALL.map(Measure::name).join(", ")),
            ));
        };
        let t = csv.number(line, row, "tilt_deg", |t| (0.0..90.0).contains(&t), "in [0, 90) degrees")?;
        let bound = format!("a displacement within ±{MAX_DISPLACEMENT_CM} cm");
        let d = csv.number(line, row, "displacement_cm", |d| d.abs() <= MAX_DISPLACEMENT_CM, &bound)?;
        one_group(&mut groups, &specimen, &group, path, line)?;
        if let Some(first) = out.iter().find(|o| o.specimen == specimen && o.measure == measure && o.tilt_deg == t) {
            return Err(value_error(
                path,
                line,
                "specimen",
                format!("specimen {specimen} has a {} at {t} degrees on line {} already", measure.name(), first.line),
            ));
        }
        out.push(MeasuredDisplacement {
            specimen,
            group,
            measure,
            tilt_deg: t,
            displacement_cm: d,
            file: path.to_owned(),
            line,
        });
    }
    Ok(out)
}

/// What the measured data are checked against: the study's groups by their measured-group
/// name with the height of their wall (m, the tallest over the sweep), and the tilt step
/// (degrees) of a tilting-table study (`None` for another protocol).
#[derive(Debug, Clone, Default)]
pub struct StudyContext {
    /// (measured group name, wall height in m).
    pub groups: Vec<(String, f64)>,
    /// `[tilt] step_deg` of a tilting-table study.
    pub step_deg: Option<f64>,
}

/// Checks measured data against each other and the study (see the module documentation).
///
/// # Errors
/// [`TableError::Value`] naming the file, the line and the column.
pub fn check_against_study(
    collapse: &[MeasuredCollapse],
    displacement: &[MeasuredDisplacement],
    study: &StudyContext,
) -> Result<(), TableError> {
    let mut groups = collapse_groups(collapse)?;
    for d in displacement {
        let bad = |column: &str, m: String| value_error(&d.file, d.line, column, m);
        one_group(&mut groups, &d.specimen, &d.group, &d.file, d.line)?;
        if let Some(step) = study.step_deg {
            let k = d.tilt_deg / step;
            if (k - k.round()).abs() > 1e-9 * k.abs().max(1.0) {
                return Err(bad(
                    "tilt_deg",
                    format!(
                        "{} degrees is not a tilt the study observes: not a multiple of its [tilt] step_deg = {step}",
                        d.tilt_deg
                    ),
                ));
            }
        }
        if let Some((_, h)) = study.groups.iter().find(|(g, _)| g == &d.group) {
            let cm = crate::units::m_to_cm(*h);
            if d.displacement_cm.abs() > cm {
                return Err(bad(
                    "displacement_cm",
                    format!(
                        "{} cm is more than the height of the group's wall ({cm} cm): the wall would have fallen",
                        d.displacement_cm
                    ),
                ));
            }
        }
        if let Some(c) = collapse.iter().find(|c| c.specimen == d.specimen && d.tilt_deg > c.collapse_angle_deg) {
            return Err(bad(
                "tilt_deg",
                format!(
                    "a displacement of specimen {} at {} degrees, beyond its collapse angle of {} degrees (line {} of {})",
                    d.specimen,
                    d.tilt_deg,
                    c.collapse_angle_deg,
                    c.line,
                    c.file.display()
                ),
            ));
        }
    }
    Ok(())
}

/// A failure mechanism as seen on a specimen (the paper's §2.2 and Figures 5–7): every
/// field but the specimen and its group may be missing.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeasuredMechanism {
    /// Specimen.
    pub specimen: String,
    /// Group.
    pub group: String,
    /// Failure height: the bed joint at the bottom of the moving part as a fraction of the
    /// wall's height (0: the table joint), read as `(value, low, high)`, the interval the
    /// reading stands for, `0 ≤ low ≤ value ≤ high ≤ 1`.
    pub failure_height: Option<(f64, f64, f64)>,
    /// Kind of failure.
    pub kind: Option<FailureKind>,
    /// Where along the wall it started.
    pub start: Option<FailureStart>,
    /// The share of the wall's length that failed in the end, in (0, 1] (recorded, not
    /// scored: a realization's extent is read at its first unstable state).
    pub extent: Option<f64>,
    /// The sentence of the source the row comes from.
    pub source: String,
    /// The file it was read from (empty for data made in memory).
    pub file: PathBuf,
    /// Its line in the file (0 for data made in memory).
    pub line: usize,
}

/// An optional category cell of column `column`: empty is `None`, else the category `parse`
/// names.
///
/// # Errors
/// A name `parse` does not know, the message listing the `known` names.
fn category<T>(
    cell: Option<&str>,
    column: &str,
    parse: fn(&str) -> Option<T>,
    known: &[&str],
) -> Result<Option<T>, String> {
    cell.map(|k| parse(k).ok_or_else(|| format!("unknown {column} `{k}` (known: {})", known.join(", ")))).transpose()
}

/// Reads observed failure mechanisms: columns `specimen`, `group`,
/// `failure_height_fraction`, `failure_height_low`, `failure_height_high`, `kind`, `start`;
/// optional `extent_fraction` and `source`. Empty fields are missing observations.
///
/// # Errors
/// [`TableError`] naming the file, the line and the column (see the module table).
pub fn read_measured_mechanism(path: &Path) -> Result<Vec<MeasuredMechanism>, TableError> {
    let h = ["failure_height_fraction", "failure_height_low", "failure_height_high"];
    let csv = Csv::read(path, &["specimen", "group", h[0], h[1], h[2], "kind", "start"])?;
    let mut out: Vec<MeasuredMechanism> = Vec::new();
    for (line, row) in &csv.rows {
        let line = *line;
        let bad = |column: &str, m: String| value_error(path, line, column, m);
        let specimen = csv.text(line, row, "specimen")?.to_string();
        let group = csv.text(line, row, "group")?.to_string();
        let unit = |v: f64| (0.0..=1.0).contains(&v);
        let [v, lo, hi] = h.map(|c| csv.optional_number(line, row, c, unit, "a fraction of the wall height in [0, 1]"));
        let (v, lo, hi) = (v?, lo?, hi?);
        let failure_height = match (v, lo, hi) {
            (None, None, None) => None,
            (Some(v), Some(lo), Some(hi)) => {
                if !(lo <= v && v <= hi) {
                    return Err(bad(
                        h[0],
                        format!("{v} is not within its reading interval [{lo}, {hi}] (low ≤ value ≤ high)"),
                    ));
                }
                Some((v, lo, hi))
            }
            (None, _, _) => {
                return Err(bad(h[0], "empty, but a bound of its reading interval is given".into()));
            }
            (Some(_), None, _) => {
                return Err(bad(h[1], "empty: a failure height needs its reading interval (low and high)".into()))
            }
            (Some(_), Some(_), None) => {
                return Err(bad(h[2], "empty: a failure height needs its reading interval (low and high)".into()))
            }
        };
        let kind = category(
            csv.optional(row, "kind"),
            "kind",
            FailureKind::from_name,
            &FailureKind::ALL.map(FailureKind::name),
        )
        .map_err(|m| bad("kind", m))?;
        let start = category(
            csv.optional(row, "start"),
            "start",
            FailureStart::from_name,
            &FailureStart::ALL.map(FailureStart::name),
        )
        .map_err(|m| bad("start", m))?;
        let extent = csv.optional_number(line, row, "extent_fraction", |e| e > 0.0 && e <= 1.0, "in (0, 1]")?;
        if let Some(first) = out.iter().find(|m| m.specimen == specimen) {
            return Err(bad(
                "specimen",
                format!("specimen {specimen} has a mechanism on line {} already (one per specimen)", first.line),
            ));
        }
        let source = csv.optional(row, "source").unwrap_or_default().to_string();
        out.push(MeasuredMechanism {
            specimen,
            group,
            failure_height,
            kind,
            start,
            extent,
            source,
            file: path.to_owned(),
            line,
        });
    }
    Ok(out)
}

/// Checks observed mechanisms against the study and the other measured data: every row's
/// group is one of the study's (by its measured-group name), its specimen is known to the
/// collapse or displacement data when they hold any specimen, in the same group.
///
/// # Errors
/// [`TableError::Value`] naming the file, the line and the column.
pub fn check_mechanism_against_study(
    mechanism: &[MeasuredMechanism],
    collapse: &[MeasuredCollapse],
    displacement: &[MeasuredDisplacement],
    study: &StudyContext,
) -> Result<(), TableError> {
    let mut groups = collapse_groups(collapse)?;
    for d in displacement {
        one_group(&mut groups, &d.specimen, &d.group, &d.file, d.line)?;
    }
    let known: Vec<String> = groups.keys().cloned().collect();
    for m in mechanism {
        if !study.groups.is_empty() && !study.groups.iter().any(|(g, _)| g == &m.group) {
            let names: Vec<&str> = study.groups.iter().map(|(g, _)| g.as_str()).collect();
            return Err(value_error(
                &m.file,
                m.line,
                "group",
                format!("group {} is not a group of the study (groups: {})", m.group, names.join(", ")),
            ));
        }
        if !known.is_empty() && !groups.contains_key(&m.specimen) {
            return Err(value_error(
                &m.file,
                m.line,
                "specimen",
                format!(
                    "unknown specimen {}: not in the collapse or displacement data (specimens: {})",
                    m.specimen,
                    known.join(", ")
                ),
            ));
        }
        one_group(&mut groups, &m.specimen, &m.group, &m.file, m.line)?;
    }
    Ok(())
}

/// The file name of observed mechanisms beside the collapse and displacement files (as
/// `drystone synthesize` and an extended study write them).
pub const MECHANISM_FILE: &str = "tilting_table_mechanism.csv";

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Observed mechanisms as the CSV text [`read_measured_mechanism`] reads (numbers in their
/// shortest round-trip form; missing fields empty).
pub fn mechanism_csv(rows: &[MeasuredMechanism]) -> String {
    let mut t = String::from(
        "specimen,group,failure_height_fraction,failure_height_low,failure_height_high,kind,start,extent_fraction,source\n",
    );
    for m in rows {
        let (v, lo, hi) = m.failure_height.map_or((String::new(), String::new(), String::new()), |(v, lo, hi)| {
            (v.to_string(), lo.to_string(), hi.to_string())
        });
        t += &format!(
            "{},{},{v},{lo},{hi},{},{},{},{}\n",
            csv_field(&m.specimen),
            csv_field(&m.group),
            m.kind.map_or("", FailureKind::name),
            m.start.map_or("", FailureStart::name),
            m.extent.map_or(String::new(), |e| e.to_string()),
            csv_field(&m.source)
        );
    }
    t
}
