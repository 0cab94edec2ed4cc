//! Geometry of the elevation plane (x–z, m) used by the construction: straight pieces of a
//! course's top surface, lines and half-planes, convex clipping, and the line of least area
//! above a surface. Pure functions; every polygon is counter-clockwise (x right, z up).

/// A point (x, z) of the elevation plane, m.
pub(crate) type P2 = [f64; 2];

/// A straight piece of a course's top surface, from (x0, z0) to (x1, z1), x0 < x1, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Seg {
    pub x0: f64,
    pub z0: f64,
    pub x1: f64,
    pub z1: f64,
}

impl Seg {
    pub(crate) fn at(&self, x: f64) -> f64 {
        if self.x1 == self.x0 {
            return self.z0.max(self.z1);
        }
        self.z0 + (self.z1 - self.z0) * (x - self.x0) / (self.x1 - self.x0)
    }

    /// The part over [a, b], if it has positive length.
    pub(crate) fn clip(&self, a: f64, b: f64) -> Option<Seg> {
        let (c, d) = (self.x0.max(a), self.x1.min(b));
        (d - c > 1e-12).then(|| Seg { x0: c, z0: self.at(c), x1: d, z1: self.at(d) })
    }
}

/// The line z = zm + m (x − xm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Line {
    pub xm: f64,
    pub zm: f64,
    pub m: f64,
}

impl Line {
    pub(crate) fn at(&self, x: f64) -> f64 {
        self.zm + self.m * (x - self.xm)
    }
}

/// The line of least area above the points of `segs` over [a, b] whose slope is at most
/// `max_slope` in magnitude: the edge of their upper convex hull over the midpoint (if the
/// midpoint is a hull vertex, the flattest line through it that stays above the hull); if
/// that edge is steeper than `max_slope`, the supporting line of slope ±`max_slope`.
pub(crate) fn least_line_above(segs: &[Seg], a: f64, b: f64, max_slope: f64) -> Option<Line> {
    let line = least_line_above_free(segs, a, b)?;
    if line.m.abs() <= max_slope {
        return Some(line);
    }
    let m = max_slope.copysign(line.m);
    let xm = 0.5 * (a + b);
    let zm = segs
        .iter()
        .flat_map(|s| [(s.x0, s.z0), (s.x1, s.z1)])
        .map(|(x, z)| z - m * (x - xm))
        .fold(f64::NEG_INFINITY, f64::max);
    Some(Line { xm, zm, m })
}

fn least_line_above_free(segs: &[Seg], a: f64, b: f64) -> Option<Line> {
    let mut pts: Vec<P2> = Vec::with_capacity(2 * segs.len());
    for s in segs {
        pts.push([s.x0, s.z0]);
        pts.push([s.x1, s.z1]);
    }
    if pts.is_empty() {
        return None;
    }
    pts.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    let mut hull: Vec<P2> = Vec::with_capacity(pts.len());
    for p in pts {
        while hull.len() >= 2 {
            let (o, q) = (hull[hull.len() - 2], hull[hull.len() - 1]);
            let cross = (q[0] - o[0]) * (p[1] - o[1]) - (q[1] - o[1]) * (p[0] - o[0]);
            if cross >= 0.0 {
                hull.pop();
            } else {
                break;
            }
        }
        // Same x as the last hull point: keep the higher (sorted ascending, so p).
        if let Some(q) = hull.last() {
            if q[0] == p[0] {
                hull.pop();
            }
        }
        hull.push(p);
    }
    let mid = 0.5 * (a + b);
    if hull.len() == 1 {
        return Some(Line { xm: mid, zm: hull[0][1], m: 0.0 });
    }
    let slope = |i: usize| (hull[i + 1][1] - hull[i][1]) / (hull[i + 1][0] - hull[i][0]);
    // The flattest slope between two adjacent edge slopes (the hull is concave).
    let flattest = |s1: f64, s2: f64| 0.0f64.max(s1.min(s2)).min(s1.max(s2));
    let last = hull.len() - 2;
    let i = (0..=last).find(|&i| mid <= hull[i + 1][0]).unwrap_or(last);
    let (p, q) = (hull[i], hull[i + 1]);
    let line = if mid == q[0] && i < last {
        Line { xm: q[0], zm: q[1], m: flattest(slope(i), slope(i + 1)) }
    } else if mid == p[0] && i > 0 {
        Line { xm: p[0], zm: p[1], m: flattest(slope(i - 1), slope(i)) }
    } else {
        Line { xm: p[0], zm: p[1], m: slope(i) }
    };
    Some(line)
}

/// A half-plane of the elevation plane bounded by a non-vertical line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum HalfPlane {
    /// z ≥ line(x).
    Above(Line),
    /// z ≤ line(x).
    Below(Line),
}

impl HalfPlane {
    pub(crate) fn z_max(level: f64) -> Self {
        HalfPlane::Below(Line { xm: 0.0, zm: level, m: 0.0 })
    }
    pub(crate) fn z_min(level: f64) -> Self {
        HalfPlane::Above(Line { xm: 0.0, zm: level, m: 0.0 })
    }
    /// Signed excess: ≤ 0 inside.
    fn excess(&self, p: &P2) -> f64 {
        match self {
            HalfPlane::Above(l) => l.at(p[0]) - p[1],
            HalfPlane::Below(l) => p[1] - l.at(p[0]),
        }
    }
    fn line(&self) -> &Line {
        match self {
            HalfPlane::Above(l) | HalfPlane::Below(l) => l,
        }
    }
}

/// Clips a convex polygon to a half-plane (Sutherland–Hodgman; convex stays convex). A
/// crossing on a vertical edge is put exactly on the boundary line (`line.at(x)`), so
/// pieces cut by the same line share bit-identical vertices.
fn clip(poly: &[P2], hp: &HalfPlane) -> Vec<P2> {
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 2);
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let (fp, fq) = (hp.excess(&p), hp.excess(&q));
        if fp <= 0.0 {
            out.push(p);
        }
        if (fp <= 0.0) != (fq <= 0.0) {
            if p[0] == q[0] {
                out.push([p[0], hp.line().at(p[0])]);
            } else if hp.line().m == 0.0 {
                let z = hp.line().zm;
                let t = (z - p[1]) / (q[1] - p[1]);
                out.push([p[0] + t * (q[0] - p[0]), z]);
            } else {
                let t = fp / (fp - fq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
    }
    out
}

/// The part of a convex polygon with `x0 ≤ x ≤ x1` (convex; empty or degenerate if the
/// strip misses it). A crossing is put exactly at x = x0 or x1, with z interpolated along
/// the edge in its own direction, so two pieces cut by the same line share bit-identical
/// vertices.
pub(crate) fn clip_x(poly: &[P2], x0: f64, x1: f64) -> Vec<P2> {
    let strip = |poly: &[P2], c: f64, keep_below: bool| -> Vec<P2> {
        let inside = |p: &P2| if keep_below { p[0] <= c } else { p[0] >= c };
        let n = poly.len();
        let mut out = Vec::with_capacity(n + 2);
        for i in 0..n {
            let (p, q) = (poly[i], poly[(i + 1) % n]);
            if inside(&p) {
                out.push(p);
            }
            if inside(&p) != inside(&q) && p[0] != c && q[0] != c {
                let t = (c - p[0]) / (q[0] - p[0]);
                out.push([c, p[1] + t * (q[1] - p[1])]);
            }
        }
        out
    };
    let a = strip(poly, x0, false);
    strip(&a, x1, true)
}

/// The convex region `x0 ≤ x ≤ x1` ∩ the half-planes, as a counter-clockwise polygon with
/// vertices closer than `snap` (m) merged by dropping one of them (which only shrinks the
/// region) and collinear vertices removed. Empty if the region is.
pub(crate) fn region(x0: f64, x1: f64, zlo: f64, zhi: f64, planes: &[HalfPlane], snap: f64) -> Vec<P2> {
    let mut poly = vec![[x0, zlo], [x1, zlo], [x1, zhi], [x0, zhi]];
    for hp in planes {
        poly = clip(&poly, hp);
        if poly.len() < 3 {
            return Vec::new();
        }
    }
    strictly_convex(dedup(poly, snap))
}

/// Removes repeated vertices (closer than `eps`, m) of a closed polygon.
fn dedup(poly: Vec<P2>, eps: f64) -> Vec<P2> {
    let mut out: Vec<P2> = Vec::with_capacity(poly.len());
    for p in poly {
        if out.last().is_none_or(|q| (q[0] - p[0]).abs() > eps || (q[1] - p[1]).abs() > eps) {
            out.push(p);
        }
    }
    while out.len() > 1 {
        let (f, l) = (out[0], out[out.len() - 1]);
        if (f[0] - l[0]).abs() <= eps && (f[1] - l[1]).abs() <= eps {
            out.pop();
        } else {
            break;
        }
    }
    out
}

/// Removes the vertices of a counter-clockwise convex polygon where it does not turn left
/// (collinear points, and the zero-width spikes that clipping leaves when a vertex lies on
/// the clip line), until every turn is strictly convex.
fn strictly_convex(mut poly: Vec<P2>) -> Vec<P2> {
    loop {
        let n = poly.len();
        if n < 3 {
            return poly;
        }
        // Degenerate turns (collinear or turning back) first, then any right turn.
        let turn = |i: usize| {
            let (p, q, r) = (poly[(i + n - 1) % n], poly[i], poly[(i + 1) % n]);
            let (e1, e2) = ([q[0] - p[0], q[1] - p[1]], [r[0] - q[0], r[1] - q[1]]);
            let cross = e1[0] * e2[1] - e1[1] * e2[0];
            let scale = (e1[0].hypot(e1[1])) * (e2[0].hypot(e2[1]));
            (cross, 1e-12 * scale)
        };
        let drop = (0..n).find(|&i| turn(i).0.abs() <= turn(i).1).or_else(|| (0..n).find(|&i| turn(i).0 < 0.0));
        match drop {
            Some(i) => {
                poly.remove(i);
            }
            None => return poly,
        }
    }
}

/// Signed area of a polygon, m² (positive counter-clockwise).
pub(crate) fn area(poly: &[P2]) -> f64 {
    let n = poly.len();
    let mut s = 0.0;
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        s += p[0] * q[1] - q[0] * p[1];
    }
    0.5 * s
}

/// The top edges of a counter-clockwise polygon as segments left to right.
pub(crate) fn top_segments(poly: &[P2], out: &mut Vec<Seg>) {
    let n = poly.len();
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        if q[0] < p[0] - 1e-12 {
            out.push(Seg { x0: q[0], z0: q[1], x1: p[0], z1: p[1] });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn least_line_over_a_step_touches_two_points() {
        // Left segment high at its right end, right segment low: a step down at x = 0.5.
        let segs = [Seg { x0: 0.0, z0: 0.10, x1: 0.5, z1: 0.2 }, Seg { x0: 0.5, z0: 0.12, x1: 1.0, z1: 0.15 }];
        let line = least_line_above(&segs, 0.0, 1.0, f64::INFINITY).unwrap();
        for s in &segs {
            assert!(line.at(s.x0) >= s.z0 - 1e-15 && line.at(s.x1) >= s.z1 - 1e-15);
        }
        // The hull has a vertex (0.5, 0.2) over the midpoint: any slope in [-0.1, 0.2] is as
        // good; the flattest (0) is taken.
        assert!((line.at(0.5) - 0.2).abs() < 1e-15);
        assert_eq!(line.m, 0.0);
        // Off the midpoint the hull edge is unique.
        let clipped: Vec<Seg> = segs.iter().filter_map(|s| s.clip(0.2, 1.0)).collect();
        let line = least_line_above(&clipped, 0.2, 1.0, f64::INFINITY).unwrap();
        assert!((line.m - (-0.1)).abs() < 1e-12, "{}", line.m);
        assert!((line.at(0.5) - 0.2).abs() < 1e-15);
    }

    #[test]
    fn least_line_over_flat_ground_is_flat() {
        let segs = [Seg { x0: 0.0, z0: 0.2, x1: 0.3, z1: 0.2 }, Seg { x0: 0.3, z0: 0.2, x1: 1.0, z1: 0.2 }];
        let line = least_line_above(&segs, 0.0, 1.0, f64::INFINITY).unwrap();
        assert_eq!(line.m, 0.0);
        assert_eq!(line.at(0.7), 0.2);
    }

    #[test]
    fn clipping_keeps_convex_polygons_convex() {
        let poly = vec![[0.0, 0.0], [1.0, 0.2], [1.0, 1.5], [0.0, 0.8]];
        assert!((area(&poly) - 1.05).abs() < 1e-12);
        let c = clip(&poly, &HalfPlane::z_max(1.0));
        assert!(c.iter().all(|p| p[1] <= 1.0));
        // Removed: the triangle (1, 1), (1, 1.5), (1 - 0.5/0.7, 1).
        assert!((area(&c) - (1.05 - 0.5 * 0.5 * 0.5 / 0.7)).abs() < 1e-12);
    }

    #[test]
    fn a_region_whose_bed_crosses_the_top_is_the_true_intersection() {
        // Bed rising through the wall top at x = 0.8: the region is the triangle under z = 1.
        let bed = Line { xm: 0.0, zm: 0.6, m: 0.5 };
        let r = region(0.0, 1.0, -1.0, 2.0, &[HalfPlane::Above(bed), HalfPlane::z_max(1.0)], 1e-9);
        assert_eq!(r.len(), 3);
        assert!((area(&r) - 0.5 * 0.8 * 0.4).abs() < 1e-12);
        assert!(r.iter().all(|p| p[1] >= bed.at(p[0]) - 1e-12 && p[0] <= 0.8 + 1e-12));
    }
}
