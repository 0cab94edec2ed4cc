//! Stone outlines from an ASCII DXF drawing: every closed `LWPOLYLINE` of the `ENTITIES`
//! section is a stone (x along the wall, y up as CAD draws: z = y × scale). A polyline
//! with a bulge (an arc segment) or an open one is refused; entities on a layer named
//! `IGNORE` (any case) and every other kind of entity (lines, text, hatches, block
//! references) are not stones. The scale is `--scale-m-per-unit`, else the header's
//! `$INSUNITS` (mm, cm or m). A stone's id is its handle (group 5), else `s<N>`; its layer
//! names its material when a material of that name is given.

use super::{Outline, Stone, SurveyError};
use std::path::Path;

/// The group codes and values of one entity, with the line of each code.
type Entity = Vec<(i32, String, usize)>;

/// The outlines of the DXF `text` read from `path`, m, with the scale used.
pub(super) fn read(
    path: &Path,
    text: &str,
    scale: Option<f64>,
    materials: &[String],
) -> Result<(Vec<Outline>, (f64, String)), SurveyError> {
    let file = |reason: String| SurveyError::File { path: path.to_owned(), reason };
    if text.starts_with("AutoCAD Binary DXF") {
        return Err(file("a binary DXF: save the drawing as ASCII DXF".into()));
    }
    let lines: Vec<&str> = text.lines().collect();
    let mut pairs = Vec::with_capacity(lines.len() / 2);
    for k in (0..lines.len().saturating_sub(1)).step_by(2) {
        let code = lines[k].trim().parse::<i32>().map_err(|_| {
            file(format!("line {}: {:?} is not a group code (an ASCII DXF is code and value lines)", k + 1, lines[k]))
        })?;
        pairs.push((code, lines[k + 1].trim().to_string(), k + 1));
    }
    let (mut section, mut units, mut entities) = (String::new(), None, Vec::<Entity>::new());
    let mut after_units = false;
    for (i, (code, value, line)) in pairs.iter().enumerate() {
        match (*code, value.as_str()) {
            (0, "SECTION") => section = pairs.get(i + 1).map_or_else(String::new, |p| p.1.clone()),
            (0, "ENDSEC") => section.clear(),
            (9, v) => after_units = v == "$INSUNITS",
            (70, v) if after_units && section == "HEADER" => {
                units = v.parse::<i32>().ok();
                after_units = false;
            }
            (0, _) if section == "ENTITIES" => entities.push(vec![(*code, value.clone(), *line)]),
            _ if section == "ENTITIES" => {
                if let Some(e) = entities.last_mut() {
                    e.push((*code, value.clone(), *line));
                }
            }
            _ => {}
        }
    }
    let scale = match (scale, units) {
        (Some(s), _) => (s, "--scale-m-per-unit".to_string()),
        (None, Some(4)) => (0.001, "$INSUNITS = 4 (mm)".to_string()),
        (None, Some(5)) => (0.01, "$INSUNITS = 5 (cm)".to_string()),
        (None, Some(6)) => (1.0, "$INSUNITS = 6 (m)".to_string()),
        _ => {
            return Err(file("no scale: give --scale-m-per-unit, or set the drawing's $INSUNITS to mm, cm or m".into()))
        }
    };
    let mut outlines = Vec::new();
    for e in entities.iter().filter(|e| e[0].1 == "LWPOLYLINE") {
        let get = |c: i32| e.iter().find(|p| p.0 == c).map(|p| p.1.as_str());
        let layer = get(8).unwrap_or("0");
        if layer.eq_ignore_ascii_case("ignore") {
            continue;
        }
        let element = match get(5) {
            Some(h) => format!("LWPOLYLINE (handle {h}) at line {}", e[0].2),
            None => format!("LWPOLYLINE at line {}", e[0].2),
        };
        let err = |reason: String| SurveyError::Element { path: path.to_owned(), element: element.clone(), reason };
        let points = polyline(e).map_err(err)?;
        let id = get(5).filter(|h| !h.trim().is_empty()).map_or_else(|| format!("s{}", outlines.len()), str::to_owned);
        let material = materials.iter().any(|m| m == layer).then(|| layer.to_string());
        let points = points.iter().map(|p| [p[0] * scale.0, p[1] * scale.0]).collect();
        outlines.push(Outline { stone: Stone { id, element, material, depth_m: None }, points });
    }
    Ok((outlines, scale))
}

/// The corners of a closed LWPOLYLINE without bulges.
fn polyline(e: &Entity) -> Result<Vec<[f64; 2]>, String> {
    let num = |v: &str, line: usize| match v.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("line {line}: {v:?} is not a finite number")),
    };
    let mut flags = 0;
    let mut count: Option<(usize, usize)> = None;
    let mut points: Vec<[f64; 2]> = Vec::new();
    for (code, value, line) in e.iter().skip(1) {
        match code {
            70 => {
                flags = value.parse::<i32>().map_err(|_| format!("line {line}: flags {value:?} are not an integer"))?
            }
            90 => {
                let n = value
                    .trim()
                    .parse::<usize>()
                    .map_err(|_| format!("line {line}: the vertex count {value:?} is not a count"))?;
                count = Some((n, *line));
            }
            10 => points.push([num(value, *line)?, f64::NAN]),
            20 => match points.last_mut() {
                Some(p) if p[1].is_nan() => p[1] = num(value, *line)?,
                _ => return Err(format!("line {line}: a y (20) without its x (10)")),
            },
            42 if num(value, *line)? != 0.0 => {
                return Err(format!("line {line}: a bulge (an arc segment): a stone outline is straight segments"))
            }
            _ => {}
        }
    }
    if let Some(k) = points.iter().position(|p| p[1].is_nan()) {
        return Err(format!("corner {k} has no y (20)"));
    }
    if let Some((n, line)) = count.filter(|(n, _)| *n != points.len()) {
        return Err(format!(
            "line {line}: the vertex count (90) is {n}, but the polyline has {} vertices: a truncated or edited entity",
            points.len()
        ));
    }
    if flags & 1 == 0 {
        return Err("the polyline is not closed (flag 70 bit 1): close it, or put it on a layer named IGNORE".into());
    }
    Ok(points)
}
