//! Drawings of the in-plane shear–compression test: the wall at the reading of its
//! mechanism with the moving joints marked (as the laboratories' crack maps draw them), and
//! force–drift curves of an ensemble over measured ones (plotters).

use super::plot::{colour, PlotError};
use crate::layout::Layout;
use crate::loading::inplane::{InPlaneMechanism, MechanismJoint, BEAM_ID};
use crate::math::Vec3;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// The wall of the rig's layout `rig` (the loading beam its last block) with every body at
/// `poses` (centroid m, rotation as a scaled axis rad, table frame; layout order) drawn in
/// elevation (x–z), the blocks that move with the beam shaded, and the moving joints
/// (`mechanism.joints`, with their points in `joints`) drawn as thick red lines: an SVG
/// document, 1 px = 2.5 mm at the default scale, `title` above it.
pub fn crack_map_svg(
    rig: &Layout,
    poses: &[(Vec3, Vec3)],
    joints: &[MechanismJoint],
    mechanism: &InPlaneMechanism,
    title: &str,
) -> String {
    let bodies = crate::dem::state::bodies_of(rig);
    let mut polys: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let (mut x0, mut x1, mut z0, mut z1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for (b, &(p, w)) in bodies.iter().zip(poses) {
        let mut b = b.clone();
        b.pos = p;
        b.rot = nalgebra::UnitQuaternion::from_scaled_axis(w);
        b.rot_mat = *b.rot.to_rotation_matrix().matrix();
        let shape = b.world_shape();
        let pts: Vec<(f64, f64)> = shape.vertices.iter().map(|v| (v.x, v.z)).collect();
        for &(x, z) in &pts {
            (x0, x1, z0, z1) = (x0.min(x), x1.max(x), z0.min(z), z1.max(z));
        }
        polys.push((b.id.clone(), hull(pts)));
    }
    let scale = 400.0;
    let pad = 20.0;
    let w = (x1 - x0) * scale + 2.0 * pad;
    let h = (z1 - z0) * scale + 2.0 * pad + 20.0;
    let sx = |x: f64| pad + (x - x0) * scale;
    let sz = |z: f64| 20.0 + pad + (z1 - z) * scale;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.1} {h:.1}" font-family="sans-serif">"#
    );
    let _ = writeln!(s, r#"<text x="{pad}" y="14" font-size="12">{}</text>"#, escape(title));
    for (id, poly) in &polys {
        let fill = if id == BEAM_ID {
            "#555555"
        } else if mechanism.moving_blocks.contains(id) {
            "#f4c27a"
        } else {
            "#d9d9d9"
        };
        let pts: Vec<String> = poly.iter().map(|&(x, z)| format!("{:.1},{:.1}", sx(x), sz(z))).collect();
        let _ = writeln!(
            s,
            r##"<polygon points="{}" fill="{fill}" stroke="#333" stroke-width="0.6"><title>{}</title></polygon>"##,
            pts.join(" "),
            escape(id)
        );
    }
    for j in joints.iter().filter(|j| mechanism.joints.contains(&j.name)) {
        if j.points.is_empty() {
            continue;
        }
        // The joint's trace in elevation: its extreme points along the in-plane tangent.
        let t = Vec3::new(-j.normal.z, 0.0, j.normal.x);
        let t = if t.norm() > 1e-9 { t.normalize() } else { Vec3::x() };
        let (lo, hi) = j.points.iter().fold((j.points[0], j.points[0]), |(lo, hi), p| {
            (if p.dot(&t) < lo.dot(&t) { *p } else { lo }, if p.dot(&t) > hi.dot(&t) { *p } else { hi })
        });
        let _ = writeln!(
            s,
            r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#d62728" stroke-width="3"><title>{}</title></line>"##,
            sx(lo.x),
            sz(lo.z),
            sx(hi.x),
            sz(hi.z),
            escape(&j.name)
        );
    }
    s.push_str("</svg>\n");
    s
}

/// The convex hull of points in the plane, counter-clockwise (Andrew's monotone chain).
fn hull(mut p: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    p.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let mut lower: Vec<(f64, f64)> = Vec::new();
    for &q in &p {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], q) <= 0.0 {
            lower.pop();
        }
        lower.push(q);
    }
    let mut upper: Vec<(f64, f64)> = Vec::new();
    for &q in p.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], q) <= 0.0 {
            upper.pop();
        }
        upper.push(q);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// A curve of a force–drift chart: its label, colour index, whether measured (drawn dark
/// and thick) and its points (drift %, force kN).
#[derive(Debug, Clone)]
pub struct ForceDriftCurve {
    /// Legend label (`None`: no legend entry, as for every realization but the first).
    pub label: Option<String>,
    /// Colour index ([`colour`]).
    pub colour: usize,
    /// A measured curve.
    pub measured: bool,
    /// Points: drift %, force kN.
    pub points: Vec<(f64, f64)>,
}

/// Writes a force–drift chart (SVG) of `curves` to `path`.
///
/// # Errors
/// [`PlotError`] naming the file.
pub fn force_drift(path: &Path, title: &str, curves: &[ForceDriftCurve]) -> Result<(), PlotError> {
    let e = |m: String| PlotError { path: path.display().to_string(), message: m };
    let (mut x0, mut x1, mut y0, mut y1) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    for c in curves {
        for &(x, y) in &c.points {
            if x.is_finite() && y.is_finite() {
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
    }
    let (dx, dy) = ((x1 - x0).max(1e-3) * 0.05, (y1 - y0).max(1e-3) * 0.05);
    let root = SVGBackend::new(path, (800, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d((x0 - dx)..(x1 + dx), (y0 - dy)..(y1 + dy))
        .map_err(|x| e(x.to_string()))?;
    chart.configure_mesh().x_desc("drift (%)").y_desc("horizontal force (kN)").draw().map_err(|x| e(x.to_string()))?;
    for c in curves {
        let col = if c.measured { RGBColor(20, 20, 20) } else { colour(c.colour) };
        let style = ShapeStyle {
            color: col.mix(if c.measured { 1.0 } else { 0.6 }),
            filled: false,
            stroke_width: if c.measured { 2 } else { 1 },
        };
        let s = chart
            .draw_series(LineSeries::new(
                c.points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()),
                style,
            ))
            .map_err(|x| e(x.to_string()))?;
        if let Some(l) = &c.label {
            s.label(l.clone()).legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], style));
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()
        .map_err(|x| e(x.to_string()))?;
    root.present().map_err(|x| e(x.to_string()))?;
    Ok(())
}
