//! Stone outlines from GeoJSON: a `FeatureCollection` (or one `Feature`, or a bare
//! geometry) of `Polygon` and `MultiPolygon` geometries whose coordinates are `[x, z]`, x
//! along the wall and z up, in metres (times the scale if one is given). A polygon is its
//! outer ring (closed, its last position its first); a polygon with holes is refused. A
//! feature's id is its `id` (or the `id` or `name` property), else `s<N>` by its order; the
//! polygons of a `MultiPolygon` are stones `ID.0`, `ID.1`, …; the `material` property names
//! the stone's material.

use super::{Outline, Stone, SurveyError};
use serde_json::Value;
use std::path::Path;

/// The outlines of the GeoJSON `text` read from `path`, m, with the scale used.
pub(super) fn read(path: &Path, text: &str, scale: Option<f64>) -> Result<(Vec<Outline>, (f64, String)), SurveyError> {
    let doc: Value = serde_json::from_str(text)
        .map_err(|e| SurveyError::File { path: path.to_owned(), reason: format!("not valid JSON: {e}") })?;
    let file = |reason: String| SurveyError::File { path: path.to_owned(), reason };
    let features: Vec<&Value> = match doc.get("type").and_then(Value::as_str) {
        Some("FeatureCollection") => doc
            .get("features")
            .and_then(Value::as_array)
            .ok_or_else(|| file("a FeatureCollection needs its \"features\" array".into()))?
            .iter()
            .collect(),
        Some("Feature") => vec![&doc],
        Some("Polygon" | "MultiPolygon") => vec![&doc],
        other => {
            let t = other.map_or_else(|| "none".to_string(), |t| format!("{t:?}"));
            return Err(file(format!("type {t}: a FeatureCollection, Feature, Polygon or MultiPolygon is expected")));
        }
    };
    let (k, scale_text) = match scale {
        Some(s) => (s, "--scale-m-per-unit".to_string()),
        None => (1.0, "coordinates in metres".to_string()),
    };
    let mut outlines = Vec::new();
    for (i, f) in features.iter().enumerate() {
        let (id, element) = names(f, i);
        let err = |reason: String| SurveyError::Element { path: path.to_owned(), element: element.clone(), reason };
        let geometry =
            if f.get("type").and_then(Value::as_str) == Some("Feature") { f.get("geometry") } else { Some(*f) };
        let geometry = geometry.filter(|g| !g.is_null()).ok_or_else(|| err("no geometry".into()))?;
        let coords = geometry.get("coordinates").ok_or_else(|| err("the geometry has no coordinates".into()))?;
        let polygons: Vec<&Value> = match geometry.get("type").and_then(Value::as_str) {
            Some("Polygon") => vec![coords],
            Some("MultiPolygon") => {
                coords.as_array().ok_or_else(|| err("coordinates: an array expected".into()))?.iter().collect()
            }
            other => {
                let t = other.unwrap_or("none");
                return Err(err(format!("geometry type {t:?}: a stone is a Polygon (or a MultiPolygon)")));
            }
        };
        let material = f.get("properties").and_then(|p| p.get("material")).and_then(Value::as_str).map(str::to_owned);
        let depth_m = match f.get("properties").and_then(|p| p.get("depth_m")) {
            None | Some(Value::Null) => None,
            Some(v) => {
                Some(v.as_f64().ok_or_else(|| err(format!("property depth_m {v}: a number of metres expected")))?)
            }
        };
        for (j, poly) in polygons.iter().enumerate() {
            let (id, element) =
                if polygons.len() > 1 || geometry.get("type").and_then(Value::as_str) == Some("MultiPolygon") {
                    (format!("{id}.{j}"), format!("{element}, polygon {j}"))
                } else {
                    (id.clone(), element.clone())
                };
            let ring = outer_ring(poly).map_err(|reason| SurveyError::Element {
                path: path.to_owned(),
                element: element.clone(),
                reason,
            })?;
            let points = ring.iter().map(|p| [p[0] * k, p[1] * k]).collect();
            outlines.push(Outline { stone: Stone { id, element, material: material.clone(), depth_m }, points });
        }
    }
    Ok((outlines, (k, scale_text)))
}

/// The stone id and the description of feature `i`.
fn names(f: &Value, i: usize) -> (String, String) {
    let text = |v: &Value| match v {
        Value::String(s) if !s.trim().is_empty() => Some(s.clone()),
        Value::String(_) => None,
        Value::Number(n) => Some(n.to_string()),
        _ => None,
    };
    let props = f.get("properties");
    let id = f
        .get("id")
        .and_then(text)
        .or_else(|| props.and_then(|p| p.get("id")).and_then(text))
        .or_else(|| props.and_then(|p| p.get("name")).and_then(text));
    match id {
        Some(id) => (id.clone(), format!("feature {i} (id {id:?})")),
        None => (format!("s{i}"), format!("feature {i}")),
    }
}

/// The outer ring of a Polygon's coordinates, open (its closing position dropped).
fn outer_ring(poly: &Value) -> Result<Vec<[f64; 2]>, String> {
    let rings = poly.as_array().ok_or("polygon coordinates: an array of rings expected")?;
    match rings.len() {
        0 => return Err("the polygon has no ring".into()),
        1 => {}
        n => return Err(format!("the polygon has holes ({}): a stone is one outline without holes", n - 1)),
    }
    let ring = rings[0].as_array().ok_or("ring: an array of positions expected")?;
    let mut pts = Vec::with_capacity(ring.len());
    for (k, pos) in ring.iter().enumerate() {
        let xy = pos.as_array().ok_or_else(|| format!("position {k}: an array [x, z] expected"))?;
        let num = |v: &Value| v.as_f64().filter(|x| x.is_finite());
        match xy.as_slice() {
            [x, z] => match (num(x), num(z)) {
                (Some(x), Some(z)) => pts.push([x, z]),
                _ => return Err(format!("position {k}: {pos} is not two numbers")),
            },
            _ => return Err(format!("position {k}: {pos} is not [x, z] (x along the wall, z up, m)")),
        }
    }
    if pts.len() < 4 || pts.first() != pts.last() {
        return Err("the ring is not closed: GeoJSON rings end on their first position (at least 4 positions)".into());
    }
    pts.pop();
    Ok(pts)
}
