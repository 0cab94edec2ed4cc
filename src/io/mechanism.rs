//! SVG drawing of a collapse mechanism: the front elevation (x–z, seen from −y) and a
//! cross-section (y–z, seen from +x) of a layout in a displaced state, the moving blocks
//! filled by the magnitude of their displacement, the resting ones grey, the moving blocks'
//! outlines before the motion dashed, and the governing joint drawn as a thick red line.
//!
//! The motion at the first unstable state of a tilt is small (the test stops a trial when a
//! block has moved 5 % of the wall width within it), so the drawing magnifies it: every
//! block is drawn at its layout position moved by `k` times its translation and turned by
//! `k` times its rotation vector, `k` chosen so that the largest block displacement shows
//! as about 8 % of the wall height (`k` = 1 if it is larger already); the factor is printed.
//!
//! The section is cut at the x of the governing joint's centre (mid-length when the joint
//! is not found); each block cut by that plane is drawn as its exact section, a convex
//! polygon.

use crate::geometry::polygon::hull2d;
use crate::layout::Layout;
use crate::loading::monitors::BodyPose;
use crate::math::Vec3;
use nalgebra::UnitQuaternion;
use std::fmt::Write as _;

/// What [`mechanism_svg`] draws.
#[derive(Debug, Clone, Copy)]
pub struct MechanismFigure<'a> {
    /// The layout (its block vertices: the reference position, m, table frame).
    pub layout: &'a Layout,
    /// Pose of every block in the displaced state, in layout order: centroid (m) and
    /// rotation from the layout, a vertex v of the layout being at `pos + rot (v − c)` with
    /// c the block's centroid in the layout (the poses of `dem::Simulation`'s bodies).
    pub poses: &'a [BodyPose],
    /// Displacement magnitude of every block, m (the colour of the moving blocks).
    pub displacement_m: &'a [f64],
    /// Per block: part of the mechanism (coloured) or resting (grey).
    pub moving: &'a [bool],
    /// The governing joint, `table/ID` or `ID_A/ID_B` (empty: none marked).
    pub joint: &'a str,
    /// First line of the drawing.
    pub title: &'a str,
    /// Second line (e.g. the realization and its collapse angle).
    pub subtitle: &'a str,
}

const RESTING: &str = "#dcd8d0";
const JOINT: &str = "#d62728";

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// A colour of the map from light yellow (0) through orange to dark red (1).
fn heat(t: f64) -> String {
    const STOPS: [[f64; 3]; 4] = [[255.0, 237.0, 160.0], [254.0, 178.0, 76.0], [240.0, 59.0, 32.0], [128.0, 0.0, 38.0]];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 } * 3.0;
    let i = (t.floor() as usize).min(2);
    let f = t - i as f64;
    let c: Vec<u8> = (0..3).map(|k| (STOPS[i][k] + f * (STOPS[i + 1][k] - STOPS[i][k])).round() as u8).collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// A factor 1, 2 or 5 times a power of ten, at most `x` (1 if `x` ≤ 1).
fn nice_factor(x: f64) -> f64 {
    if !(x > 1.0 && x.is_finite()) {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0].iter().map(|m| m * p).find(|v| *v <= x).unwrap_or(p)
}

/// The drawn vertices of every block: the layout vertices moved by `k` times each pose's
/// motion.
fn drawn_blocks(f: &MechanismFigure, k: f64) -> Vec<Vec<Vec3>> {
    f.layout
        .blocks
        .iter()
        .zip(f.poses)
        .map(|(b, (pos, rot))| {
            let c = b.centroid();
            let r = UnitQuaternion::from_scaled_axis(rot.scaled_axis() * k);
            let p = c + (pos - c) * k;
            b.shape.vertices.iter().map(|v| p + r * (v - c)).collect()
        })
        .collect()
}

/// The section of a convex polyhedron (vertices, edges) by the plane x = `xc`, as (y, z).
fn section(verts: &[Vec3], edges: &[(usize, usize)], xc: f64) -> Vec<[f64; 2]> {
    let mut pts = Vec::new();
    for &(i, j) in edges {
        let (a, b) = (verts[i], verts[j]);
        let (da, db) = (a.x - xc, b.x - xc);
        if da == 0.0 {
            pts.push([a.y, a.z]);
        }
        if da * db < 0.0 {
            let t = da / (da - db);
            pts.push([a.y + t * (b.y - a.y), a.z + t * (b.z - a.z)]);
        }
    }
    if pts.len() < 3 {
        return vec![];
    }
    hull2d(&pts, 1e-12)
}

/// The points of the governing joint in the reference position and the index of the body
/// whose pose carries them (`None`: the table): the vertices of either block within
/// `tol` of the other.
fn joint_points(layout: &Layout, joint: &str, moving: &[bool]) -> Option<(Vec<Vec3>, Option<usize>)> {
    let (a, b) = joint.split_once('/')?;
    let find = |id: &str| layout.blocks.iter().position(|x| x.id == id);
    let bi = find(b)?;
    let sb = &layout.blocks[bi].shape;
    let size = sb.aabb().extent().min();
    let tol = (0.01 * size).max(1e-3);
    if a == "table" {
        let zmin = sb.vertices.iter().map(|v| v.z).fold(f64::INFINITY, f64::min);
        let pts: Vec<Vec3> = sb.vertices.iter().filter(|v| v.z <= zmin + tol).copied().collect();
        return Some((pts, None));
    }
    let ai = find(a)?;
    let sa = &layout.blocks[ai].shape;
    let mut pts: Vec<Vec3> = sb.vertices.iter().filter(|v| sa.signed_distance(v) >= -tol).copied().collect();
    pts.extend(sa.vertices.iter().filter(|v| sb.signed_distance(v) >= -tol));
    let carrier = if moving.get(ai).copied().unwrap_or(false) { bi } else { ai };
    (!pts.is_empty()).then_some((pts, Some(carrier)))
}

/// The figure's per-block inputs completed to every block of the layout: blocks beyond the
/// lengths of the figure's `poses`, `displacement_m` or `moving` at rest (pose at their
/// layout centroid, displacement 0 m, not moving).
struct Completed {
    poses: Vec<BodyPose>,
    moving: Vec<bool>,
    disp: Vec<f64>,
}

impl Completed {
    /// The inputs of `f`, one entry per block of its layout.
    fn of(f: &MechanismFigure) -> Completed {
        let layout = f.layout;
        let n = layout.blocks.len();
        let at_rest = (Vec3::zeros(), UnitQuaternion::identity());
        let mut poses: Vec<BodyPose> = Vec::with_capacity(n);
        for (i, b) in layout.blocks.iter().enumerate() {
            let c = b.centroid();
            poses.push(f.poses.get(i).copied().unwrap_or((c + at_rest.0, at_rest.1)));
        }
        let moving: Vec<bool> = (0..n).map(|i| f.moving.get(i).copied().unwrap_or(false)).collect();
        let disp: Vec<f64> = (0..n).map(|i| f.displacement_m.get(i).copied().unwrap_or(0.0)).collect();
        Completed { poses, moving, disp }
    }
}

/// The governing joint's points (m), carried by the pose (magnified by `k`) of its resting
/// side; `None` when the joint is not found.
fn magnified_joint(layout: &Layout, joint: &str, moving: &[bool], poses: &[BodyPose], k: f64) -> Option<Vec<Vec3>> {
    joint_points(layout, joint, moving).map(|(pts, carrier)| match carrier {
        None => pts,
        Some(i) => {
            let c = layout.blocks[i].centroid();
            let (pos, rot) = poses[i];
            let r = UnitQuaternion::from_scaled_axis(rot.scaled_axis() * k);
            let p = c + (pos - c) * k;
            pts.iter().map(|v| p + r * (v - c)).collect()
        }
    })
}

/// Every block's outline in both views, (x, z) in the elevation and (y, z) in the section at
/// x = `xc`, m: as drawn (`drawn`, displaced) and at rest (`*_ref`, the layout's vertices).
/// An outline of fewer than three points is not drawn.
struct Outlines {
    elev: Vec<Vec<[f64; 2]>>,
    elev_ref: Vec<Vec<[f64; 2]>>,
    sec: Vec<Vec<[f64; 2]>>,
    sec_ref: Vec<Vec<[f64; 2]>>,
}

impl Outlines {
    /// The outlines of the blocks of `layout` drawn at `drawn`, the section cut at `xc` (m).
    fn new(layout: &Layout, drawn: &[Vec<Vec3>], xc: f64) -> Outlines {
        let reference: Vec<Vec<Vec3>> = layout.blocks.iter().map(|b| b.shape.vertices.clone()).collect();
        let elevation = |v: &Vec<Vec3>| hull2d(&v.iter().map(|p| [p.x, p.z]).collect::<Vec<_>>(), 1e-12);
        Outlines {
            elev: drawn.iter().map(elevation).collect(),
            elev_ref: reference.iter().map(elevation).collect(),
            sec: drawn.iter().zip(&layout.blocks).map(|(v, b)| section(v, &b.shape.edges, xc)).collect(),
            sec_ref: reference.iter().zip(&layout.blocks).map(|(v, b)| section(v, &b.shape.edges, xc)).collect(),
        }
    }
}

/// The page: where the elevation and the section stand, px, and the scale from metres.
struct Page {
    /// px per m.
    s: f64,
    /// Left (and right) margin, px.
    margin: f64,
    /// The page's height, px.
    height: f64,
    /// The page's width, px.
    width: f64,
    /// The height of the title block above the views, px.
    top: f64,
    /// The elevation's x range, m.
    ex0: f64,
    ex1: f64,
    /// The section's y range, m.
    sy0: f64,
    sy1: f64,
    /// The top of both views, m.
    z1: f64,
    /// The left edge of the section, px.
    sx_off: f64,
}

impl Page {
    /// The page that holds both views of `outlines` (the section's y range that of `all`
    /// when no block is cut), the wall's length `l` (m) drawn 900 px long.
    fn new(outlines: &Outlines, all: &crate::geometry::Aabb, l: f64) -> Page {
        // Extents of both views (m).
        let ext = |polys: &[&Vec<Vec<[f64; 2]>>]| {
            polys
                .iter()
                .flat_map(|p| p.iter().flatten())
                .fold((f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY), |(a, b, c, d), q| {
                    (a.min(q[0]), b.max(q[0]), c.min(q[1]), d.max(q[1]))
                })
        };
        let (ex0, ex1, ez0, ez1) = ext(&[&outlines.elev, &outlines.elev_ref]);
        let (sy0, sy1, sz0, sz1) = ext(&[&outlines.sec, &outlines.sec_ref]);
        let (sy0, sy1) = if sy0.is_finite() { (sy0, sy1) } else { (all.min.y, all.max.y) };
        let (z0, z1) = (ez0.min(sz0).min(0.0), ez1.max(sz1));
        let s = 900.0 / l.max(1e-9);
        let (margin, gap, top) = (40.0, 80.0, 80.0);
        // The section's label is wider than a narrow section.
        let width = margin + (ex1 - ex0) * s + gap + ((sy1 - sy0) * s).max(200.0) + margin;
        let height = top + (z1 - z0) * s + 110.0;
        let sx_off = margin + (ex1 - ex0) * s + gap + (0.5 * (200.0 - (sy1 - sy0) * s)).max(0.0);
        Page { s, margin, height, width, top, ex0, ex1, sy0, sy1, z1, sx_off }
    }

    /// The page x (px) of an elevation's x (m).
    fn ex(&self, x: f64) -> f64 {
        self.margin + (x - self.ex0) * self.s
    }

    /// The page y (px) of a height z (m), in both views.
    fn zz(&self, z: f64) -> f64 {
        self.top + (self.z1 - z) * self.s
    }

    /// The page x (px) of a section's y (m).
    fn sy(&self, y: f64) -> f64 {
        self.sx_off + (y - self.sy0) * self.s
    }

    /// The points attribute of a polygon, its first coordinate placed by `fx`, its second a
    /// height.
    fn points(&self, p: &[[f64; 2]], fx: &dyn Fn(f64) -> f64) -> String {
        p.iter().map(|q| format!("{:.2},{:.2}", fx(q[0]), self.zz(q[1]))).collect::<Vec<_>>().join(" ")
    }
}

/// The SVG text of a mechanism drawing (module documentation). Blocks beyond the lengths of
/// `poses`, `displacement_m` or `moving` are drawn at rest.
pub fn mechanism_svg(f: &MechanismFigure) -> String {
    let layout = f.layout;
    let Completed { poses, moving, disp } = Completed::of(f);
    let ff = MechanismFigure { poses: &poses, moving: &moving, displacement_m: &disp, ..*f };
    let all = layout.bounds();
    let (h, l) = (all.extent().z, all.extent().x);
    let dmax = disp.iter().zip(&moving).filter(|(_, m)| **m).map(|(d, _)| *d).fold(0.0, f64::max);
    let largest = disp.iter().cloned().fold(0.0, f64::max);
    let k = nice_factor(0.08 * h / largest);
    let drawn = drawn_blocks(&ff, k);
    let joint = magnified_joint(layout, f.joint, &moving, &poses, k);
    let xc = joint.as_ref().map_or(0.5 * (all.min.x + all.max.x), |p| {
        let (lo, hi) = p.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v.x), b.max(v.x)));
        0.5 * (lo + hi)
    });
    let outlines = Outlines::new(layout, &drawn, xc);
    let page = Page::new(&outlines, &all, l);
    let fill = |i: usize| if moving[i] { heat(if dmax > 0.0 { disp[i] / dmax } else { 0.0 }) } else { RESTING.into() };

    let mut o = String::new();
    heading(&mut o, f, &page, k, &moving);
    blocks(&mut o, &ff, &page, &outlines, &drawn, &fill);
    if let Some(p) = &joint {
        joint_lines(&mut o, &page, p);
    }
    table_and_labels(&mut o, &page, xc);
    legend(&mut o, page.margin, page.height, dmax);
    o.push_str("</svg>\n");
    o
}

/// The opening of the SVG: the page, the title, the subtitle and the line naming the
/// magnification `k`, the number of moving blocks and the governing joint.
fn heading(o: &mut String, f: &MechanismFigure, page: &Page, k: f64, moving: &[bool]) {
    let (width, height, margin) = (page.width, page.height, page.margin);
    let n = f.layout.blocks.len();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.1} {height:.1}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(o, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(o, r#"<text x="{margin}" y="22" font-size="15" font-weight="bold">{}</text>"#, esc(f.title));
    let _ = writeln!(o, r#"<text x="{margin}" y="42">{}</text>"#, esc(f.subtitle));
    let mag = if k > 1.0 { format!("displacements magnified ×{k}") } else { "displacements to scale".into() };
    let _ = writeln!(
        o,
        r#"<text x="{margin}" y="60">{mag}; {} of {n} blocks moving; governing joint <tspan fill="{JOINT}" font-weight="bold">{}</tspan></text>"#,
        moving.iter().filter(|m| **m).count(),
        esc(if f.joint.is_empty() { "none" } else { f.joint })
    );
}

/// The blocks of both views (`f` completed to every block): the elevation's far blocks
/// (large y) first, each filled by `fill` and titled with its id (and its displacement in
/// the elevation), then the moving blocks' outlines at rest dashed.
fn blocks(
    o: &mut String,
    f: &MechanismFigure,
    page: &Page,
    outlines: &Outlines,
    drawn: &[Vec<Vec3>],
    fill: &dyn Fn(usize) -> String,
) {
    let (layout, moving, disp) = (f.layout, f.moving, f.displacement_m);
    let n = layout.blocks.len();
    let Outlines { elev, elev_ref, sec, sec_ref } = outlines;
    let stroke = (0.6f64).max((page.s * 0.0015).min(1.2));
    let (ex, sy) = (|x: f64| page.ex(x), |y: f64| page.sy(y));
    // Elevation: far blocks (large y) first.
    let mut order: Vec<usize> = (0..n).collect();
    let mean_y = |i: usize| drawn[i].iter().map(|v| v.y).sum::<f64>() / drawn[i].len().max(1) as f64;
    order.sort_by(|&a, &b| mean_y(b).total_cmp(&mean_y(a)).then(a.cmp(&b)));
    let _ = writeln!(o, r#"<g stroke-linejoin="round">"#);
    for &i in &order {
        if elev[i].len() >= 3 {
            let _ = writeln!(
                o,
                r##"<polygon points="{}" fill="{}" stroke="#333" stroke-width="{stroke:.2}"><title>{} {:.2} cm</title></polygon>"##,
                page.points(&elev[i], &ex),
                fill(i),
                esc(&layout.blocks[i].id),
                100.0 * disp[i]
            );
        }
    }
    dashed_at_rest(o, page, elev_ref, moving, stroke, &ex);
    // Section.
    for i in 0..n {
        if sec[i].len() >= 3 {
            let _ = writeln!(
                o,
                r##"<polygon points="{}" fill="{}" stroke="#333" stroke-width="{stroke:.2}"><title>{}</title></polygon>"##,
                page.points(&sec[i], &sy),
                fill(i),
                esc(&layout.blocks[i].id)
            );
        }
    }
    dashed_at_rest(o, page, sec_ref, moving, stroke, &sy);
    let _ = writeln!(o, "</g>");
}

/// The outlines at rest of the moving blocks of one view, dashed, their first coordinate
/// placed by `fx`.
fn dashed_at_rest(
    o: &mut String,
    page: &Page,
    outlines: &[Vec<[f64; 2]>],
    moving: &[bool],
    stroke: f64,
    fx: &dyn Fn(f64) -> f64,
) {
    for i in (0..outlines.len()).filter(|&i| moving[i] && outlines[i].len() >= 3) {
        let _ = writeln!(
            o,
            r##"<polygon points="{}" fill="none" stroke="#555" stroke-width="{stroke:.2}" stroke-dasharray="5 3"/>"##,
            page.points(&outlines[i], fx)
        );
    }
}

/// The governing joint (its points `p`, m): its extent along each view's horizontal axis, a
/// thick line with a ring around its middle so that a short joint shows too.
fn joint_lines(o: &mut String, page: &Page, p: &[Vec3]) {
    let line = |key: &dyn Fn(&Vec3) -> f64, fx: &dyn Fn(f64) -> f64| {
        let lo = p.iter().min_by(|a, b| key(a).total_cmp(&key(b)));
        let hi = p.iter().max_by(|a, b| key(a).total_cmp(&key(b)));
        if let (Some(a), Some(b)) = (lo, hi) {
            format!(
                r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{JOINT}" stroke-width="4" stroke-linecap="round"/><circle cx="{:.2}" cy="{:.2}" r="9" fill="none" stroke="{JOINT}" stroke-width="2"/>"#,
                fx(key(a)),
                page.zz(a.z),
                fx(key(b)),
                page.zz(b.z),
                0.5 * (fx(key(a)) + fx(key(b))),
                0.5 * (page.zz(a.z) + page.zz(b.z))
            )
        } else {
            String::new()
        }
    };
    let _ = writeln!(o, "{}", line(&|v| v.x, &|x| page.ex(x)));
    let _ = writeln!(o, "{}", line(&|v| v.y, &|y| page.sy(y)));
}

/// The table under both views, the section's cut line at x = `xc` (m) on the elevation, and
/// the views' labels.
fn table_and_labels(o: &mut String, page: &Page, xc: f64) {
    let (ex0, ex1, sy0, sy1) = (page.ex0, page.ex1, page.sy0, page.sy1);
    let base = page.zz(0.0) + 1.0;
    let _ = writeln!(
        o,
        r##"<line x1="{:.1}" y1="{base:.1}" x2="{:.1}" y2="{base:.1}" stroke="#000" stroke-width="2"/><line x1="{:.1}" y1="{base:.1}" x2="{:.1}" y2="{base:.1}" stroke="#000" stroke-width="2"/>"##,
        page.ex(ex0) - 10.0,
        page.ex(ex1) + 10.0,
        page.sy(sy0) - 10.0,
        page.sy(sy1) + 10.0
    );
    let _ = writeln!(
        o,
        r##"<line x1="{x:.1}" y1="{:.1}" x2="{x:.1}" y2="{:.1}" stroke="#888" stroke-dasharray="4 3"/>"##,
        page.zz(page.z1) - 8.0,
        base + 8.0,
        x = page.ex(xc)
    );
    let _ = writeln!(
        o,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">front elevation (x along the wall, z up)</text><text x="{:.1}" y="{:.1}" text-anchor="middle">section x = {xc:.3} m (+y →)</text>"#,
        page.ex(0.5 * (ex0 + ex1)),
        base + 22.0,
        page.sy(0.5 * (sy0 + sy1)),
        base + 22.0
    );
}

/// The colour bar (0 to `dmax`, in cm) and the keys, along the bottom edge.
fn legend(o: &mut String, margin: f64, height: f64, dmax: f64) {
    let y = height - 40.0;
    let _ = writeln!(o, r#"<defs><linearGradient id="heat">"#);
    for k in 0..=6 {
        let t = k as f64 / 6.0;
        let _ = writeln!(o, r#"<stop offset="{t:.3}" stop-color="{}"/>"#, heat(t));
    }
    let _ = writeln!(o, "</linearGradient></defs>");
    let _ = writeln!(
        o,
        r##"<rect x="{margin}" y="{y:.1}" width="200" height="12" fill="url(#heat)" stroke="#333"/><text x="{margin}" y="{:.1}">0</text><text x="{:.1}" y="{:.1}" text-anchor="end">{:.2} cm</text><text x="{:.1}" y="{:.1}">displacement of the moving blocks</text>"##,
        y + 28.0,
        margin + 200.0,
        y + 28.0,
        100.0 * dmax,
        margin + 210.0,
        y + 11.0
    );
    let x2 = margin + 460.0;
    let _ = writeln!(
        o,
        r##"<rect x="{x2:.1}" y="{y:.1}" width="14" height="12" fill="{RESTING}" stroke="#333"/><text x="{:.1}" y="{:.1}">resting</text><rect x="{:.1}" y="{y:.1}" width="14" height="12" fill="none" stroke="#555" stroke-dasharray="5 3"/><text x="{:.1}" y="{:.1}">before the motion</text><line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{JOINT}" stroke-width="4"/><text x="{:.1}" y="{:.1}">governing joint</text>"##,
        x2 + 20.0,
        y + 11.0,
        x2 + 90.0,
        x2 + 110.0,
        y + 11.0,
        x2 + 250.0,
        y + 6.0,
        x2 + 275.0,
        y + 6.0,
        x2 + 282.0,
        y + 11.0
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heat_ends_and_nice_factors() {
        assert_eq!(heat(0.0), "#ffeda0");
        assert_eq!(heat(1.0), "#800026");
        assert_eq!(nice_factor(0.5), 1.0);
        assert_eq!(nice_factor(37.0), 20.0);
        assert_eq!(nice_factor(600.0), 500.0);
    }

    #[test]
    fn section_of_a_unit_cube_is_a_square() {
        let c = crate::geometry::ConvexBlock::cuboid(Vec3::zeros(), Vec3::new(1.0, 2.0, 3.0)).unwrap();
        let s = section(&c.vertices, &c.edges, 0.5);
        assert_eq!(s.len(), 4);
        let (ymax, zmax) = s.iter().fold((0.0f64, 0.0f64), |(a, b), p| (a.max(p[0]), b.max(p[1])));
        assert_eq!((ymax, zmax), (2.0, 3.0));
    }
}
