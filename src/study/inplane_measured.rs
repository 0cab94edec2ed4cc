//! The measured specimens of an in-plane study: the Stone Masonry Database's table of walls
//! (`[measured] walls`), their envelopes and whole curves (read on the files' drift, checked
//! against their displacement column), the robust readings of an envelope and the loops'
//! damping ratio of a cyclic specimen.

use super::inplane_error::InPlaneStudyError;
use crate::loading::inplane_loops::{loop_damping_ratio, turning_points, LOOP_MIN_DRIFT_PCT, TURNING_NOISE_PCT};
use serde::Serialize;
use std::path::Path;

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
    /// The turning points of its measured history, drift % in the order the actuator
    /// reached them ([`crate::loading::inplane_loops::turning_points`] of the curve's drift
    /// column); empty for a monotonic test or without the curve ([`read_loops`]).
    pub reversals_pct: Vec<f64>,
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

/// A number of the specimens' table: every column read is a magnitude (a stress, a force,
/// a drift, a stiffness, a height, a modulus, a failure type), finite and not negative; a
/// missing value is an empty field. `Err` gives the reason.
fn magnitude(v: &str) -> Result<f64, String> {
    match v.parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        Ok(_) => Err(format!("{v:?} is not a finite number >= 0 (leave the field empty where the value is missing)")),
        Err(_) => Err(format!("{v:?} is not a number")),
    }
}

/// Reads the database's table of specimens (a CSV with a header; quoted fields). Every row
/// has the header's count of fields, every unit one row, every number read is finite and
/// not negative and every height (`H_mm`, `H0_mm`, `HLVDT_mm`) positive; the envelopes'
/// folder, when given, exists.
///
/// # Errors
/// Naming the file, the line and the column.
pub fn read_specimens(path: &Path, envelopes: Option<&Path>) -> Result<Vec<Specimen>, InPlaneStudyError> {
    let err = |message: String| InPlaneStudyError::File { path: path.to_owned(), message };
    if let Some(dir) = envelopes.filter(|d| !d.is_dir()) {
        return Err(InPlaneStudyError::File {
            path: dir.to_owned(),
            message: "[measured] envelopes: not a folder of the measured envelopes".into(),
        });
    }
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
    let mut seen: Vec<(String, usize)> = Vec::new();
    for (i, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let f = split_csv(line);
        if f.len() != header.len() {
            return Err(err(format!(
                "line {}: {} fields, the header has {} (a field missing or one too many: a missing value is an empty field)",
                i + 1,
                f.len(),
                header.len()
            )));
        }
        let get = |k: usize| f.get(c[k]).cloned().unwrap_or_default();
        let opt_num = |col: Option<usize>| -> Result<f64, InPlaneStudyError> {
            let Some(k) = col else { return Ok(f64::NAN) };
            let v = f.get(k).map(|x| x.trim().to_string()).unwrap_or_default();
            if v.is_empty() {
                return Ok(f64::NAN);
            }
            magnitude(&v).map_err(|why| err(format!("line {}: column {}: {why}", i + 1, header[k])))
        };
        let num = |k: usize| opt_num(Some(c[k]));
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
                    magnitude(&v).map_err(|why| err(format!("line {}: column H_mm: {why}", i + 1)))?
                }
                None => f64::NAN,
            },
            damping_ratio: f64::NAN,
            reversals_pct: Vec::new(),
            shear_span_mm: opt_num(h0_col)?,
            measuring_height_mm: f64::NAN,
            epc_mpa: opt_num(epc_col)?,
            dcr_pct: opt_num(dcr_col)?,
            vcr_kn: opt_num(vcr_col)?,
            readings_pos: EnvelopeReadings::default(),
            readings_neg: EnvelopeReadings::default(),
        };
        let hlvdt = opt_num(hlvdt_col)?;
        if let Some((name, _)) = [("H_mm", s.height_mm), ("H0_mm", s.shear_span_mm), ("HLVDT_mm", hlvdt)]
            .into_iter()
            .find(|(_, v)| *v == 0.0)
        {
            return Err(err(format!("line {}: column {name}: 0 is not a height (mm above the base)", i + 1)));
        }
        if let Some((_, first)) = seen.iter().find(|(u, _)| *u == s.unit) {
            return Err(err(format!(
                "line {}: column unit: {} is given twice (first on line {first}): a specimen has one row",
                i + 1,
                s.unit
            )));
        }
        seen.push((s.unit.clone(), i + 1));
        s.measuring_height_mm = if hlvdt.is_finite() { hlvdt } else { s.shear_span_mm };
        // The ultimate drift is read on the envelope's falling branch past the peak (the
        // database's rule: the drift where the force has dropped by 20 % past the peak, or the
        // largest drift tested): never before the peak.
        for (du, dmax, du_col, dmax_col) in [
            (s.du_pos_pct, s.dmax_pos_pct, "du_pos_pct", "dmax_pos_pct"),
            (s.du_neg_pct, s.dmax_neg_pct, "du_neg_pct", "dmax_neg_pct"),
        ] {
            if du < dmax {
                return Err(err(format!(
                    "line {}: column {du_col}: the ultimate drift {du} % is below the drift at the peak ({dmax_col} {dmax} %): the ultimate drift is read past the peak",
                    i + 1
                )));
            }
        }
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

/// The columns of a curve file of the database (its third header line) and their units (its
/// fourth), in order.
pub const CURVE_COLUMNS: [(&str, &str); 3] =
    [("top_displacement", "[mm]"), ("horizontal_force", "[kN]"), ("drift", "[%]")];

/// Reads a curve file of the database (an envelope or a whole curve): four header lines
/// (unit, reference, the columns `top_displacement,horizontal_force,drift`, their units
/// `[mm],[kN],[%]`: [`CURVE_COLUMNS`]), then `top_displacement mm, horizontal_force kN,
/// drift %` a line; returns the rows in order. A line of `NaN` in every column is kept (a
/// break between digitized segments, as the database marks it, which the readings pass
/// over); blank lines are passed over.
///
/// # Errors
/// Naming the file and the line: a header that does not name the columns or their units, a
/// line that is not three fields, a field that is not a number (naming its column), a number
/// that is infinite, or `NaN` in some columns of a line and not in all.
fn read_points(path: &Path) -> Result<Vec<[f64; 3]>, InPlaneStudyError> {
    let err = |message: String| InPlaneStudyError::File { path: path.to_owned(), message };
    let text = std::fs::read_to_string(path).map_err(|e| err(e.to_string()))?;
    let lines: Vec<&str> = text.lines().collect();
    let expected = |k: usize| CURVE_COLUMNS.iter().map(|c| if k == 0 { c.0 } else { c.1 }).collect::<Vec<_>>();
    for (k, what) in [(0usize, "the columns"), (1, "the columns' units")] {
        let line = lines.get(2 + k).copied().unwrap_or_default();
        let found: Vec<String> = split_csv(line).iter().map(|x| x.trim().to_string()).collect();
        let want = expected(k);
        if found != want {
            return Err(err(format!(
                "line {}: header {line:?} does not give {what} of a curve file: expected {:?} (four header lines: \
                 unit, reference, columns, units)",
                3 + k,
                want.join(",")
            )));
        }
    }
    let mut pts = Vec::new();
    for (i, line) in lines.iter().enumerate().skip(4) {
        if line.trim().is_empty() {
            continue;
        }
        let fields = split_csv(line);
        if fields.len() != 3 {
            return Err(err(format!("line {}: {line:?} is not three numbers ({} fields)", i + 1, fields.len())));
        }
        let mut v = [0.0f64; 3];
        for (k, (x, (column, unit))) in fields.iter().zip(CURVE_COLUMNS).enumerate() {
            let x = x.trim();
            v[k] =
                x.parse::<f64>().map_err(|_| err(format!("line {}: column {column}: {x:?} is not a number", i + 1)))?;
            if v[k].is_infinite() {
                return Err(err(format!(
                    "line {}: column {column}: {x:?} is not a finite reading ({unit} expected)",
                    i + 1
                )));
            }
        }
        let breaks = v.iter().filter(|x| x.is_nan()).count();
        if breaks != 0 && breaks != 3 {
            let k = v.iter().position(|x| x.is_nan()).unwrap_or_default();
            return Err(err(format!(
                "line {}: column {}: NaN beside numbers: a break between digitized segments is NaN in every \
                 column, a reading a number in every column",
                i + 1,
                CURVE_COLUMNS[k].0
            )));
        }
        pts.push(v);
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
/// Naming the file, the line and the column, where the drift disagrees; a file with no
/// reading (its header alone, or breaks only), which would compare as an envelope with none.
pub fn read_envelope_of(path: &Path, measuring_height_mm: f64) -> Result<Vec<(f64, f64)>, InPlaneStudyError> {
    let pts = read_points(path)?;
    if !pts.iter().any(|p| p.iter().all(|x| x.is_finite())) {
        return Err(InPlaneStudyError::File {
            path: path.to_owned(),
            message:
                "no reading after the four header lines: an envelope file holds at least one line of three numbers"
                    .into(),
        });
    }
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

/// Sets each cyclic specimen's [`Specimen::damping_ratio`] and [`Specimen::reversals_pct`] from its whole measured curve in
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
        let drifts: Vec<f64> = curve.iter().map(|q| q.0).collect();
        s.reversals_pct = turning_points(&drifts, TURNING_NOISE_PCT);
    }
    Ok(())
}

/// The database's file stem of a specimen: `<unit without dots>_<first author><year>`
/// (`WS1.100`, "Vasconcelos and Lourenço (2009)" → `WS1100_Vasconcelos2009`).
pub(super) fn file_stem(s: &Specimen) -> String {
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
