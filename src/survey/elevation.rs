//! Traced elevations: outlines in the wall's x–z plane → through blocks. Each outline is
//! cleaned (repeated and collinear corners dropped), oriented counter-clockwise, checked for
//! convexity (or replaced by its convex hull), checked against every other for overlap, and
//! extruded through the section by the generator's own extrusion
//! ([`crate::generator::extrude_polygon`] between the faces of
//! [`crate::generator::faces_at`]).

use super::{check_size, check_unique_ids, read_text, ImportOptions, ImportedWall, Stone, StoneReport, SurveyError};
use super::{SurveyFormat, MAX_STONE_M};
use crate::generator::spec::Batter;
use crate::generator::trace_draw::penetration;
use crate::generator::{centroid_z, extrude_polygon, faces_at, hull_is_faithful, polygon_area};
use crate::layout::OVERLAP_TOLERANCE_M;
use std::path::Path;

/// A corner whose turn has |sin θ| at most this is dropped as collinear (or a zero-width
/// spike), as the generator drops them.
const COLLINEAR_SIN: f64 = 1e-9;

/// The section a traced elevation is extruded through: width `base_m` at the table (z = 0)
/// and `top_m` at the wall's top (its highest point), the faces affine in z between, placed
/// by the `batter` as in a wall description (`geometry.batter`: symmetric about y = 0, or
/// one vertical face). Every stone spans the whole section (a through stone).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Width at the base, m (> 0).
    pub base_m: f64,
    /// Width at the top, m (> 0, at most `base_m`).
    pub top_m: f64,
    /// Which faces lean. Default symmetric.
    pub batter: Batter,
}

impl Section {
    /// A section of constant width `thickness_m`, m.
    pub fn uniform(thickness_m: f64) -> Self {
        Self { base_m: thickness_m, top_m: thickness_m, batter: Batter::Symmetric }
    }

    /// Refuses widths that are not positive, or a top wider than the base.
    pub(super) fn check(&self) -> Result<(), SurveyError> {
        let bad = |option: &str, v: f64, reason: &str| SurveyError::Option {
            option: option.into(),
            value: v.to_string(),
            reason: reason.into(),
        };
        if !(self.base_m.is_finite() && self.base_m > 0.0 && self.base_m <= MAX_STONE_M) {
            return Err(bad("--thickness-m", self.base_m, "must be a positive number of metres, at most 5"));
        }
        if !(self.top_m.is_finite() && self.top_m > 0.0 && self.top_m <= self.base_m) {
            return Err(bad("--top-thickness-m", self.top_m, "must be positive and at most the base thickness"));
        }
        Ok(())
    }
}

/// A stone's block polygon and what it came from.
struct Shape {
    /// The block's polygon (convex, counter-clockwise), table frame, m.
    polygon: Vec<[f64; 2]>,
    /// The outline (counter-clockwise), table frame, m.
    outline: Vec<[f64; 2]>,
    hulled: bool,
}

/// A traced elevation read and checked: its stones and their shapes in the table frame,
/// the scale used and the translation to the table frame.
pub(super) struct Trace {
    pub stones: Vec<Stone>,
    shapes: Vec<Shape>,
    pub scale: (f64, String),
    pub offset: [f64; 2],
}

impl Trace {
    /// Each stone's block polygon (convex, counter-clockwise, table frame, m).
    pub fn polygons(&self) -> Vec<Vec<[f64; 2]>> {
        self.shapes.iter().map(|s| s.polygon.clone()).collect()
    }
}

/// Reads a traced elevation: its outlines cleaned, checked, made convex (or refused) and
/// checked for overlaps, in the table frame.
pub(super) fn trace(path: &Path, format: SurveyFormat, o: &ImportOptions) -> Result<Trace, SurveyError> {
    let text = read_text(path)?;
    let (outlines, scale) = match format {
        SurveyFormat::Svg => super::svg::read(path, &text, o.scale_m_per_unit)?,
        SurveyFormat::Dxf => {
            let names: Vec<String> = o.materials.materials.iter().map(|m| m.name.clone()).collect();
            super::dxf::read(path, &text, o.scale_m_per_unit, &names)?
        }
        _ => super::geojson::read(path, &text, o.scale_m_per_unit)?,
    };
    if outlines.is_empty() {
        return Err(SurveyError::File { path: path.to_owned(), reason: "no stone outline found".into() });
    }
    let stones: Vec<Stone> = outlines.iter().map(|l| l.stone.clone()).collect();
    check_unique_ids(path, &stones)?;
    super::check_materials(path, &stones, o)?;
    if let Some(section) = &o.section {
        for s in &stones {
            if let Some(d) = s.depth_m.filter(|d| !(d.is_finite() && *d > 0.0 && *d <= section.base_m)) {
                return Err(element(
                    path,
                    s,
                    format!(
                        "depth {d} m: a stone's depth from the traced face lies within (0, {}] m, the wall's \
                         thickness at its base",
                        section.base_m
                    ),
                ));
            }
        }
    }
    let all = || outlines.iter().flat_map(|l| l.points.iter());
    let x0 = all().map(|p| p[0]).fold(f64::INFINITY, f64::min);
    let z0 = all().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let unit = format!("{} m per unit", super::short_number(scale.0));
    let mut shapes = Vec::with_capacity(outlines.len());
    for l in &outlines {
        let moved: Vec<[f64; 2]> = l.points.iter().map(|p| [p[0] - x0, p[1] - z0]).collect();
        let (lo, hi) = bounds(&moved);
        check_size(path, &l.stone, (hi[0] - lo[0]).max(hi[1] - lo[1]), &unit)?;
        shapes.push(shape(path, &l.stone, &moved, o.hull_nonconvex)?);
    }
    check_overlaps(path, &stones, &shapes)?;
    Ok(Trace { stones, shapes, scale, offset: [-x0, -z0] })
}

/// Reads a traced elevation and makes its blocks.
pub(super) fn import(path: &Path, format: SurveyFormat, o: &ImportOptions) -> Result<ImportedWall, SurveyError> {
    let Trace { stones, shapes, scale, offset } = trace(path, format, o)?;
    let section = o.section.unwrap_or(Section::uniform(1.0));
    let (lo, hi) = bounds(&shapes.iter().flat_map(|s| s.polygon.iter().copied()).collect::<Vec<_>>());
    let height = hi[1];
    let faces = |z: f64| faces_at(section.batter, section.base_m, section.top_m, height, z);
    let mut blocks = Vec::with_capacity(shapes.len());
    let mut reports = Vec::with_capacity(shapes.len());
    for (s, sh) in stones.iter().zip(&shapes) {
        // A stone of a measured depth that leaves a core behind it: the face stone to its
        // depth and the core from there to the other face (`ID.core`), as the ensemble's
        // drawn depths make them ([`crate::generator::traced`]).
        let top = sh.polygon.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
        let (y0_top, y1_top) = faces(top);
        for (_, id, from, to) in crate::generator::traced::face_and_core(&s.id, s.depth_m, y1_top - y0_top) {
            let part_faces = |z: f64| {
                let (y0, y1) = faces(z);
                (y0 + from, to.map_or(y1, |d| y0 + d))
            };
            let vertices = extrude_polygon(&sh.polygon, part_faces);
            let prism_volume = |poly: &[[f64; 2]]| {
                let a = polygon_area(poly);
                let (y0, y1) = part_faces(centroid_z(poly, a));
                a * (y1 - y0)
            };
            let volume = prism_volume(&sh.polygon);
            if !hull_is_faithful(&vertices, volume) {
                return Err(element(
                    path,
                    s,
                    "the block is too thin for its convex hull to be built (a sliver)".into(),
                ));
            }
            reports.push(StoneReport {
                id: id.clone(),
                element: s.element.clone(),
                block_volume_m3: volume,
                survey_volume_m3: prism_volume(&sh.outline),
                hulled: sh.hulled,
                simplified: None,
            });
            blocks.push((id, s.material.clone(), vertices, None));
        }
    }
    Ok(ImportedWall {
        source: path.to_owned(),
        format,
        layout: super::layout_of(path, o, blocks),
        stones: reports,
        offset_m: [offset[0], 0.0, offset[1]],
        scale: Some(scale),
        length_m: hi[0] - lo[0],
        height_m: height,
    })
}

fn element(path: &Path, s: &Stone, reason: String) -> SurveyError {
    SurveyError::Element { path: path.to_owned(), element: s.element.clone(), reason }
}

/// The lower-left and upper-right corners of the points' bounding box.
fn bounds(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    points.iter().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), p| {
        ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
    })
}

/// The cleaned, counter-clockwise outline and its block polygon (itself if convex, else its
/// convex hull when `hull` is set, else an error naming the stone and its deficit).
fn shape(path: &Path, s: &Stone, points: &[[f64; 2]], hull: bool) -> Result<Shape, SurveyError> {
    let mut outline = clean(points);
    if outline.len() >= 4 && polygon_area(&outline) == 0.0 {
        // A bow tie's lobes cancel: name the crossing, not a missing area.
        if let Some((i, j)) = crossing(&outline) {
            return Err(element(
                path,
                s,
                format!("the outline crosses itself (its edges {i} and {j}, counted from its first corner)"),
            ));
        }
    }
    if outline.len() < 3 || polygon_area(&outline) == 0.0 {
        return Err(element(path, s, "the outline has fewer than 3 distinct corners or no area".into()));
    }
    if polygon_area(&outline) < 0.0 {
        outline[1..].reverse();
    }
    let turns = turns(&outline);
    let winding: f64 = turns.iter().map(|t| t.1).sum();
    let convex = turns.iter().all(|t| t.0 > 0.0) && (winding - std::f64::consts::TAU).abs() < 1e-6;
    if convex {
        return Ok(Shape { polygon: outline.clone(), outline, hulled: false });
    }
    if let Some((i, j)) = crossing(&outline) {
        return Err(element(
            path,
            s,
            format!("the outline crosses itself (its edges {i} and {j}, counted from its first corner)"),
        ));
    }
    let polygon = convex_hull(&outline);
    if hull {
        return Ok(Shape { polygon, outline, hulled: true });
    }
    let area = polygon_area(&outline);
    let corner = turns.iter().position(|t| t.0 < 0.0).map_or(outline[0], |i| outline[i]);
    Err(SurveyError::NonConvex {
        path: path.to_owned(),
        stone: s.id.clone(),
        element: s.element.clone(),
        area_m2: area,
        added_m2: polygon_area(&polygon) - area,
        corner,
    })
}

/// The outline without repeated corners (within 1e-12 of its size; the closing corner too)
/// and without collinear corners and zero-width spikes (|sin θ| ≤ [`COLLINEAR_SIN`]).
fn clean(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let (lo, hi) = bounds(points);
    let eps = 1e-12 * (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let same = |p: &[f64; 2], q: &[f64; 2]| (p[0] - q[0]).abs() <= eps && (p[1] - q[1]).abs() <= eps;
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(points.len());
    for p in points {
        if out.last().is_none_or(|q| !same(p, q)) {
            out.push(*p);
        }
    }
    while out.len() > 1 && same(&out[0], &out[out.len() - 1]) {
        out.pop();
    }
    loop {
        let n = out.len();
        if n < 3 {
            return out;
        }
        match turns(&out).iter().position(|t| t.0.abs() <= COLLINEAR_SIN) {
            Some(i) => {
                out.remove(i);
            }
            None => return out,
        }
    }
}

/// Per corner, the sine of its turn (positive to the left) and the signed turn angle, rad.
fn turns(poly: &[[f64; 2]]) -> Vec<(f64, f64)> {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (p, q, r) = (poly[(i + n - 1) % n], poly[i], poly[(i + 1) % n]);
            let (e1, e2) = ([q[0] - p[0], q[1] - p[1]], [r[0] - q[0], r[1] - q[1]]);
            let cross = e1[0] * e2[1] - e1[1] * e2[0];
            let dot = e1[0] * e2[0] + e1[1] * e2[1];
            (cross / (e1[0].hypot(e1[1]) * e2[0].hypot(e2[1])), cross.atan2(dot))
        })
        .collect()
}

/// Two edges of a closed polygon, not neighbours, that cross or touch, if any.
fn crossing(poly: &[[f64; 2]]) -> Option<(usize, usize)> {
    let n = poly.len();
    let orient = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (a, b, c, d) = (poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]);
            let (d1, d2) = (orient(a, b, c), orient(a, b, d));
            let (d3, d4) = (orient(c, d, a), orient(c, d, b));
            if d1 * d2 <= 0.0 && d3 * d4 <= 0.0 {
                return Some((i, j));
            }
        }
    }
    None
}

/// The convex hull (counter-clockwise, collinear points dropped; Andrew's monotone chain).
fn convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut pts = points.to_vec();
    pts.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    pts.dedup();
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(pts.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> =
            if pass == 0 { Box::new(pts.iter()) } else { Box::new(pts.iter().rev()) };
        for &p in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Refuses two block polygons that overlap by more than the layout's tolerance: the
/// penetration depth of two convex polygons (the least overlap of their projections on the
/// normals of their edges), after a bounding-box test.
fn check_overlaps(path: &Path, stones: &[Stone], shapes: &[Shape]) -> Result<(), SurveyError> {
    let boxes: Vec<_> = shapes.iter().map(|s| bounds(&s.polygon)).collect();
    for i in 0..shapes.len() {
        for j in i + 1..shapes.len() {
            let (a, b) = (&boxes[i], &boxes[j]);
            let gap = (a.0[0] - b.1[0]).max(b.0[0] - a.1[0]).max(a.0[1] - b.1[1]).max(b.0[1] - a.1[1]);
            if gap >= -OVERLAP_TOLERANCE_M {
                continue;
            }
            let depth = penetration(&shapes[i].polygon, &shapes[j].polygon);
            if depth > OVERLAP_TOLERANCE_M {
                let named = |s: &Stone| format!("{} ({})", s.id, s.element);
                return Err(SurveyError::Overlap {
                    path: path.to_owned(),
                    a: named(&stones[i]),
                    b: named(&stones[j]),
                    depth_m: depth,
                });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_of_an_l_is_its_bounding_square_less_a_corner_triangle() {
        let l = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
        let h = convex_hull(&l);
        assert_eq!(h.len(), 5);
        assert!((polygon_area(&h) - 3.5).abs() < 1e-15);
        assert!(crossing(&l).is_none());
        let bow = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(crossing(&bow).is_some());
    }

    #[test]
    fn cleaning_drops_repeats_and_collinear_corners() {
        let sq = [[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]];
        assert_eq!(clean(&sq), vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    }

    #[test]
    fn penetration_of_two_squares() {
        let a = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let b: Vec<[f64; 2]> = a.iter().map(|p| [p[0] + 0.75, p[1] + 0.5]).collect();
        assert!((penetration(&a, &b) - 0.25).abs() < 1e-15);
        let c: Vec<[f64; 2]> = a.iter().map(|p| [p[0] + 1.0, p[1]]).collect();
        assert!(penetration(&a, &c).abs() < 1e-15);
    }
}
