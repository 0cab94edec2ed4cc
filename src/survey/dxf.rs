//! Stone outlines from an ASCII DXF drawing (x along the wall, y up as CAD draws: z = y ×
//! scale). In the `ENTITIES` section, every entity not on a layer named `IGNORE` (any
//! case) is one of:
//!
//! * a stone: a closed `LWPOLYLINE`, or a closed old-style `POLYLINE` with its `VERTEX`
//!   entities and `SEQEND` (2D, no curve or spline fitting); a bulge (an arc segment) or an
//!   open polyline is refused;
//! * a depth label: a `TEXT` or `MTEXT` whose text is `depth_m=D` (any case; D the depth of
//!   the stone in metres, whatever the drawing's unit), its insertion point inside the
//!   outline of the stone it measures (one label a stone).
//!
//! Anything else (lines, hatches, block references, other text) is refused naming its type,
//! handle and line, with the advice to put it on the `IGNORE` layer; paper-space entities
//! (group 67 = 1) and viewports are no part of the model and are skipped. The scale is
//! `--scale-m-per-unit`, else the header's `$INSUNITS` (mm, cm or m). A stone's id is its
//! handle (group 5), else `s<N>`; its layer names its material when a material of that name
//! is given.

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
    let mut labels: Vec<Label> = Vec::new();
    let mut k = 0;
    while k < entities.len() {
        let e = &entities[k];
        k += 1;
        let get = |c: i32| e.iter().find(|p| p.0 == c).map(|p| p.1.as_str());
        let kind = e[0].1.as_str();
        let layer = get(8).unwrap_or("0");
        let element = match get(5).filter(|h| !h.trim().is_empty()) {
            Some(h) => format!("{kind} (handle {h}) at line {}", e[0].2),
            None => format!("{kind} at line {}", e[0].2),
        };
        let err = |reason: String| SurveyError::Element { path: path.to_owned(), element: element.clone(), reason };
        // An old-style polyline is its POLYLINE header, its VERTEX entities and a SEQEND.
        let mut vertices: Vec<&Entity> = Vec::new();
        if kind == "POLYLINE" {
            while k < entities.len() && entities[k][0].1 == "VERTEX" {
                vertices.push(&entities[k]);
                k += 1;
            }
            if entities.get(k).is_none_or(|n| n[0].1 != "SEQEND") {
                return Err(err("the polyline's VERTEX entities are not ended by a SEQEND: a truncated entity".into()));
            }
            k += 1;
        }
        if layer.eq_ignore_ascii_case("ignore") || kind == "VIEWPORT" || get(67) == Some("1") {
            // On the IGNORE layer, or no part of the model (paper space and its viewports).
            continue;
        }
        let points = match kind {
            "LWPOLYLINE" => polyline(e).map_err(err)?,
            "POLYLINE" => old_polyline(e, &vertices).map_err(err)?,
            "TEXT" | "MTEXT" => {
                labels.push(label(e, element.clone()).map_err(err)?);
                continue;
            }
            _ => {
                return Err(err(format!(
                    "a {kind} entity is neither a stone (a closed LWPOLYLINE or POLYLINE) nor a depth label (a TEXT \
                     `depth_m=D`): put it on a layer named IGNORE, or explode it into polylines"
                )))
            }
        };
        let id = get(5).filter(|h| !h.trim().is_empty()).map_or_else(|| format!("s{}", outlines.len()), str::to_owned);
        let material = materials.iter().any(|m| m == layer).then(|| layer.to_string());
        outlines.push(Outline { stone: Stone { id, element, material, depth_m: None }, points });
    }
    place_labels(path, &labels, &mut outlines)?;
    for o in &mut outlines {
        o.points = o.points.iter().map(|p| [p[0] * scale.0, p[1] * scale.0]).collect();
    }
    Ok((outlines, scale))
}

/// A depth label: a TEXT or MTEXT entity whose text is `depth_m=D`, its insertion point in
/// drawing units, the depth in metres, its element.
struct Label {
    at: [f64; 2],
    depth_m: f64,
    element: String,
}

/// The depth label of a TEXT or MTEXT entity: its text (group 1) `depth_m=D` (any case,
/// spaces around `=` allowed; D in metres), its insertion point (10, 20).
fn label(e: &Entity, element: String) -> Result<Label, String> {
    let get = |c: i32| e.iter().find(|p| p.0 == c);
    let text = get(1).map_or("", |p| p.1.as_str());
    let value = text.split_once('=').filter(|(k, _)| k.trim().eq_ignore_ascii_case("depth_m")).map(|(_, v)| v.trim());
    let Some(value) = value else {
        return Err(format!(
            "text {text:?} is not a depth label (`depth_m=D`, D the stone's depth in metres): put other text on a \
             layer named IGNORE"
        ));
    };
    let depth_m = value.parse::<f64>().map_err(|_| format!("depth_m {value:?} is not a number of metres"))?;
    let coordinate = |c: i32| -> Result<f64, String> {
        let (_, v, line) = get(c).ok_or_else(|| format!("the label has no insertion point ({c})"))?;
        v.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("line {line}: {v:?} is not a finite number"))
    };
    Ok(Label { at: [coordinate(10)?, coordinate(20)?], depth_m, element })
}

/// Gives each stone the depth of the label inside its outline. A label inside no outline,
/// or inside two, and two labels in one outline are refused naming them.
fn place_labels(path: &Path, labels: &[Label], outlines: &mut [Outline]) -> Result<(), SurveyError> {
    let mut by: Vec<Option<&str>> = vec![None; outlines.len()];
    for l in labels {
        let err = |reason: String| SurveyError::Element { path: path.to_owned(), element: l.element.clone(), reason };
        let inside: Vec<usize> = (0..outlines.len()).filter(|&i| contains(&outlines[i].points, l.at)).collect();
        let i = match inside.as_slice() {
            [i] => *i,
            [] => {
                return Err(err(format!(
                    "the depth label at ({}, {}) lies inside no stone's outline: put its insertion point inside the \
                     stone it measures",
                    l.at[0], l.at[1]
                )))
            }
            [a, b, ..] => {
                return Err(err(format!(
                    "the depth label lies inside two outlines, {} and {}",
                    outlines[*a].stone.element, outlines[*b].stone.element
                )))
            }
        };
        if let Some(first) = by[i] {
            return Err(err(format!("stone {} has a second depth label (the first: {first})", outlines[i].stone.id)));
        }
        by[i] = Some(&l.element);
        outlines[i].stone.depth_m = Some(l.depth_m);
    }
    Ok(())
}

/// Whether the point `p` lies strictly inside the polygon `poly` (even–odd rule).
fn contains(poly: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut inside = false;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
            inside = !inside;
        }
    }
    inside
}

/// The corners of a closed old-style POLYLINE (its header `e`, its VERTEX entities
/// `vertices`): a 2D polyline without bulges, curve or spline fitting.
fn old_polyline(e: &Entity, vertices: &[&Entity]) -> Result<Vec<[f64; 2]>, String> {
    let int = |v: &str, line: usize| {
        v.trim().parse::<i32>().map_err(|_| format!("line {line}: flags {v:?} are not an integer"))
    };
    let mut flags = 0;
    for (code, value, line) in e.iter().skip(1) {
        if *code == 70 {
            flags = int(value, *line)?;
        }
    }
    if flags & (2 | 4) != 0 {
        return Err("a curve-fit or spline-fit polyline: a stone outline is straight segments (decurve it)".into());
    }
    if flags & (8 | 16 | 64) != 0 {
        return Err("a 3D polyline or a mesh: a stone outline is a 2D polyline in the elevation's plane".into());
    }
    let mut points = Vec::with_capacity(vertices.len());
    for v in vertices {
        let at = v[0].2;
        let mut corner: Vec<(i32, &str, usize)> = vec![(0, "LWPOLYLINE", at)];
        for (code, value, line) in v.iter().skip(1) {
            match code {
                70 if int(value, *line)? & (1 | 8 | 16 | 32 | 64 | 128) != 0 => {
                    return Err(format!(
                        "line {line}: the VERTEX at line {at} is a fitted, spline, 3D or mesh vertex: a stone outline \
                         is a 2D polyline of straight segments"
                    ))
                }
                10 | 20 | 42 => corner.push((*code, value, *line)),
                _ => {}
            }
        }
        let one: Entity = corner.into_iter().map(|(c, v, l)| (c, v.to_string(), l)).collect();
        match polyline_points(&one)?.as_slice() {
            [p] => points.push(*p),
            _ => return Err(format!("line {at}: a VERTEX needs one point (10, 20)")),
        }
    }
    if flags & 1 == 0 {
        return Err("the polyline is not closed (flag 70 bit 1): close it, or put it on a layer named IGNORE".into());
    }
    Ok(points)
}

/// The corners (10, 20) of a polyline's group codes, a bulge (42) refused.
fn polyline_points(e: &Entity) -> Result<Vec<[f64; 2]>, String> {
    let num = |v: &str, line: usize| match v.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("line {line}: {v:?} is not a finite number")),
    };
    let mut points: Vec<[f64; 2]> = Vec::new();
    for (code, value, line) in e.iter().skip(1) {
        match code {
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
    Ok(points)
}

/// The corners of a closed LWPOLYLINE without bulges.
fn polyline(e: &Entity) -> Result<Vec<[f64; 2]>, String> {
    let mut flags = 0;
    let mut count: Option<(usize, usize)> = None;
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
            _ => {}
        }
    }
    let points = polyline_points(e)?;
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
