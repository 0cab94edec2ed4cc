//! SVG drawing of a generated wall: the front elevation (x–z, seen from −y) and the
//! cross-section at mid-length (y–z, seen from +x), blocks outlined, wedges filled in a
//! second colour, end-restrained blocks outlined in blue. One drawing unit is one pixel;
//! the scale is chosen so the elevation is about 1000 px wide.

use crate::generator::{GeneratedWall, PieceKind};
use std::fmt::Write as _;

const STONE: &str = "#d8d0c0";
const WEDGE: &str = "#e0833a";
const RESTRAINED: &str = "#1f5fbf";

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The z-interval of a convex polygon (x, z) on the vertical line at `x`, if it crosses it.
fn vertical_extent(poly: &[[f64; 2]], x: f64) -> Option<(f64, f64)> {
    let n = poly.len();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let (x0, x1) = (p[0].min(q[0]), p[0].max(q[0]));
        if x < x0 || x > x1 {
            continue;
        }
        if q[0] == p[0] {
            lo = lo.min(p[1].min(q[1]));
            hi = hi.max(p[1].max(q[1]));
        } else {
            let z = p[1] + (q[1] - p[1]) * (x - p[0]) / (q[0] - p[0]);
            lo = lo.min(z);
            hi = hi.max(z);
        }
    }
    (hi > lo).then_some((lo, hi))
}

/// The drawing's scale and placement: one metre is `s` px; the elevation's origin at
/// (`margin`, `top` + H s); the section's centre line at x = `sx0`.
struct Frame {
    l: f64,
    h: f64,
    bw: f64,
    s: f64,
    margin: f64,
    top: f64,
    sx0: f64,
    stroke: f64,
}

impl Frame {
    /// Elevation x (m) to px.
    fn ex(&self, x: f64) -> f64 {
        self.margin + x * self.s
    }
    /// Height z (m) to px (both views).
    fn ez(&self, z: f64) -> f64 {
        self.top + (self.h - z) * self.s
    }
    /// Section y (m) to px.
    fn sy(&self, y: f64) -> f64 {
        self.sx0 + y * self.s
    }
}

/// The SVG text. `faces_at(z)` gives the y of the two faces at height z (the wall's batter);
/// `title` is printed above the drawing.
pub fn wall_to_svg(g: &GeneratedWall, faces_at: impl Fn(f64) -> (f64, f64), title: &str) -> String {
    let [l, h, bw, _] = g.dimensions;
    let s = 1000.0 / l;
    let margin = 30.0;
    let gap = 60.0;
    let top = 60.0;
    let sec_w = bw * s;
    let width = margin + l * s + gap + sec_w + margin + 20.0;
    let height = top + h * s + 70.0;
    let sx0 = margin + l * s + gap + 0.5 * sec_w;
    let stroke = (0.6f64).max((s * 0.0015).min(1.2));
    let f = Frame { l, h, bw, s, margin, top, sx0, stroke };

    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.1} {height:.1}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let (stones, wedges) = g.counts();
    let _ = writeln!(out, r#"<text x="{margin}" y="20" font-size="15" font-weight="bold">{}</text>"#, esc(title));
    let _ = writeln!(
        out,
        r#"<text x="{margin}" y="40">seed {}, realization {}: {} stones, {} wedges; L {:.3} m, H {:.3} m, B {:.3} m, b {:.3} m; void {:.2} %</text>"#,
        g.seed,
        g.realization,
        stones,
        wedges,
        l,
        h,
        bw,
        g.dimensions[3],
        (100.0 * g.void_fraction()).max(0.0)
    );
    elevation(&mut out, g, &f);
    section(&mut out, g, &f, faces_at);
    legend(&mut out, &f, height);
    out.push_str("</svg>\n");
    out
}

/// The front elevation: every block's polygon, the table and the dashed line of the cut.
fn elevation(out: &mut String, g: &GeneratedWall, f: &Frame) {
    let (l, h, stroke) = (f.l, f.h, f.stroke);
    let x_cut = 0.5 * l;
    let _ = writeln!(out, r#"<g stroke-linejoin="round">"#);
    for p in &g.pieces {
        let pts: Vec<String> = p.polygon.iter().map(|q| format!("{:.2},{:.2}", f.ex(q[0]), f.ez(q[1]))).collect();
        let fill = if p.kind == PieceKind::Wedge { WEDGE } else { STONE };
        let st = if p.restrained { RESTRAINED } else { "#333" };
        let _ = writeln!(
            out,
            r#"<polygon points="{}" fill="{fill}" stroke="{st}" stroke-width="{stroke:.2}"><title>{}</title></polygon>"#,
            pts.join(" "),
            esc(&p.id)
        );
    }
    let _ = writeln!(out, "</g>");
    // Table and the cut line.
    let _ = writeln!(
        out,
        r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#000" stroke-width="2"/>"##,
        f.ex(0.0) - 10.0,
        f.ez(0.0) + 1.0,
        f.ex(l) + 10.0,
        f.ez(0.0) + 1.0
    );
    let _ = writeln!(
        out,
        r##"<line x1="{x:.1}" y1="{:.1}" x2="{x:.1}" y2="{:.1}" stroke="#888" stroke-dasharray="4 3"/>"##,
        f.ez(h) - 8.0,
        f.ez(0.0) + 8.0,
        x = f.ex(x_cut)
    );
    let _ = writeln!(
        out,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">front elevation (x along the wall, z up)</text>"#,
        f.ex(0.5 * l),
        f.ez(0.0) + 22.0
    );
}

/// The cross-section at mid-length: the part of every block the cut crosses, between the
/// two faces, and the table.
fn section(out: &mut String, g: &GeneratedWall, f: &Frame, faces_at: impl Fn(f64) -> (f64, f64)) {
    let (x_cut, bw, stroke, sx0) = (0.5 * f.l, f.bw, f.stroke, f.sx0);
    for p in &g.pieces {
        if let Some((z0, z1)) = vertical_extent(&p.polygon, x_cut) {
            let (a0, b0) = faces_at(z0);
            let (a1, b1) = faces_at(z1);
            let pts = [(a0, z0), (b0, z0), (b1, z1), (a1, z1)]
                .iter()
                .map(|(y, z)| format!("{:.2},{:.2}", f.sy(*y), f.ez(*z)))
                .collect::<Vec<_>>()
                .join(" ");
            let fill = if p.kind == PieceKind::Wedge { WEDGE } else { STONE };
            let _ = writeln!(
                out,
                r##"<polygon points="{pts}" fill="{fill}" stroke="#333" stroke-width="{stroke:.2}"><title>{}</title></polygon>"##,
                esc(&p.id)
            );
        }
    }
    let _ = writeln!(
        out,
        r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#000" stroke-width="2"/>"##,
        f.sy(-0.5 * bw) - 10.0,
        f.ez(0.0) + 1.0,
        f.sy(0.5 * bw) + 10.0,
        f.ez(0.0) + 1.0
    );
    let _ = writeln!(
        out,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">section x = L/2</text>"#,
        sx0,
        f.ez(0.0) + 22.0
    );
    let _ = writeln!(out, r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">(+y →)</text>"#, sx0, f.ez(0.0) + 38.0);
}

/// The legend along the bottom edge of a drawing `height` px high.
fn legend(out: &mut String, f: &Frame, height: f64) {
    let margin = f.margin;
    let ly = height - 16.0;
    let _ = writeln!(
        out,
        r##"<rect x="{margin}" y="{:.1}" width="14" height="10" fill="{STONE}" stroke="#333"/><text x="{:.1}" y="{ly:.1}">stone</text>"##,
        ly - 10.0,
        margin + 20.0
    );
    let _ = writeln!(
        out,
        r##"<rect x="{:.1}" y="{:.1}" width="14" height="10" fill="{WEDGE}" stroke="#333"/><text x="{:.1}" y="{ly:.1}">wedge</text>"##,
        margin + 80.0,
        ly - 10.0,
        margin + 100.0
    );
    let _ = writeln!(
        out,
        r##"<rect x="{:.1}" y="{:.1}" width="14" height="10" fill="{STONE}" stroke="{RESTRAINED}" stroke-width="2"/><text x="{:.1}" y="{ly:.1}">end-restrained</text>"##,
        margin + 160.0,
        ly - 10.0,
        margin + 180.0
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertical_extent_of_a_trapezoid() {
        let p = [[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [0.0, 1.0]];
        let (lo, hi) = vertical_extent(&p, 0.5).unwrap();
        assert!((lo - 0.0).abs() < 1e-15 && (hi - 1.5).abs() < 1e-15);
        assert!(vertical_extent(&p, 1.5).is_none());
    }
}
