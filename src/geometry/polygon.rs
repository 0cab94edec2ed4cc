//! Planar convex polygons in a 2D basis of a plane: hulls, clipping, areas.
//!
//! Points are `[u, v]` coordinates in m along the basis vectors returned by [`plane_basis`].
//! Polygons are counter-clockwise about the plane normal.

use crate::math::Vec3;

/// An orthonormal basis (u, v) of the plane with unit normal `n`, such that (u, v, n) is
/// right-handed. Deterministic: depends on `n` only.
pub fn plane_basis(n: &Vec3) -> (Vec3, Vec3) {
    let a = if n.x.abs() < 0.6 {
        Vec3::x()
    } else if n.y.abs() < 0.6 {
        Vec3::y()
    } else {
        Vec3::z()
    };
    let u = (a - n * n.dot(&a)).normalize();
    let v = n.cross(&u);
    (u, v)
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Convex hull of 2D points (Andrew's monotone chain), counter-clockwise, without collinear
/// points. Returns 1 point for coincident input, 2 for collinear input.
pub fn hull2d(points: &[[f64; 2]], tol: f64) -> Vec<[f64; 2]> {
    let mut p: Vec<[f64; 2]> = points.to_vec();
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup_by(|a, b| (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol);
    if p.len() <= 2 {
        return p;
    }
    let scale = tol.max(1e-15);
    let mut lower: Vec<[f64; 2]> = Vec::new();
    for &q in &p {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], q) <= scale * scale {
            lower.pop();
        }
        lower.push(q);
    }
    let mut upper: Vec<[f64; 2]> = Vec::new();
    for &q in p.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], q) <= scale * scale {
            upper.pop();
        }
        upper.push(q);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    if lower.len() == 2 && (lower[0][0] - lower[1][0]).abs() <= tol && (lower[0][1] - lower[1][1]).abs() <= tol {
        lower.pop();
    }
    lower
}

/// Indices of the points of a counter-clockwise polygon that are true corners (the turn at
/// the point exceeds `tol` in area units of m²·(1/m)); used to drop collinear hull points.
pub fn strictly_convex_indices(p: &[[f64; 2]], tol: f64) -> Vec<usize> {
    let n = p.len();
    if n < 3 {
        return (0..n).collect();
    }
    (0..n)
        .filter(|&k| {
            let a = p[(k + n - 1) % n];
            let b = p[k];
            let c = p[(k + 1) % n];
            let l = ((c[0] - a[0]).powi(2) + (c[1] - a[1]).powi(2)).sqrt();
            cross(a, b, c) > tol * l.max(1e-15)
        })
        .collect()
}

/// Signed area (m²) of a polygon, positive if counter-clockwise.
pub fn area(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    if n < 3 {
        return 0.0;
    }
    let mut s = 0.0;
    for k in 0..n {
        let (a, b) = (p[k], p[(k + 1) % n]);
        s += a[0] * b[1] - a[1] * b[0];
    }
    0.5 * s
}

/// Area centroid of a counter-clockwise polygon with positive area.
pub fn centroid(p: &[[f64; 2]]) -> [f64; 2] {
    let n = p.len();
    let (mut cx, mut cy, mut a2) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let (a, b) = (p[k], p[(k + 1) % n]);
        let w = a[0] * b[1] - a[1] * b[0];
        cx += (a[0] + b[0]) * w;
        cy += (a[1] + b[1]) * w;
        a2 += w;
    }
    if a2.abs() < 1e-300 {
        let m = p.iter().fold([0.0, 0.0], |s, q| [s[0] + q[0], s[1] + q[1]]);
        return [m[0] / n as f64, m[1] / n as f64];
    }
    [cx / (3.0 * a2), cy / (3.0 * a2)]
}

/// Intersection of two convex 2D point sets given as CCW hulls (each may be a polygon, a
/// segment or a single point). Returns the hull of the intersection: a polygon, a segment,
/// a point, or empty. `tol` (m) widens the clipping half-planes so that touching features
/// count as intersecting.
pub fn intersect_convex(a: &[[f64; 2]], b: &[[f64; 2]], tol: f64) -> Vec<[f64; 2]> {
    match (a.len(), b.len()) {
        (0, _) | (_, 0) => Vec::new(),
        (_, n) if n >= 3 => clip_by_polygon(a, b, tol),
        (n, _) if n >= 3 => clip_by_polygon(b, a, tol),
        _ => intersect_low_dim(a, b, tol),
    }
}

/// Clips the convex set `subject` (polygon, segment or point) by the CCW polygon `clip`.
fn clip_by_polygon(subject: &[[f64; 2]], clip: &[[f64; 2]], tol: f64) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = subject.to_vec();
    let closed = subject.len() >= 3;
    let n = clip.len();
    for k in 0..n {
        if out.is_empty() {
            break;
        }
        let (a, b) = (clip[k], clip[(k + 1) % n]);
        let ex = b[0] - a[0];
        let ey = b[1] - a[1];
        let len = (ex * ex + ey * ey).sqrt();
        if len <= 0.0 {
            continue;
        }
        // Signed distance to the edge line, positive inside (left of a CCW edge).
        let dist = |p: [f64; 2]| (ex * (p[1] - a[1]) - ey * (p[0] - a[0])) / len + tol;
        let input = std::mem::take(&mut out);
        let m = input.len();
        if m == 1 {
            if dist(input[0]) >= 0.0 {
                out = input;
            }
            continue;
        }
        let segs = if closed { m } else { m - 1 };
        for i in 0..segs {
            let p = input[i];
            let q = input[(i + 1) % m];
            let (dp, dq) = (dist(p), dist(q));
            if dp >= 0.0 {
                out.push(p);
            }
            if (dp >= 0.0) != (dq >= 0.0) {
                let t = dp / (dp - dq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        if !closed && dist(input[m - 1]) >= 0.0 {
            out.push(input[m - 1]);
        }
    }
    hull2d(&out, tol * 1e-3)
}

/// Intersection of two sets of dimension ≤ 1 (points or segments).
fn intersect_low_dim(a: &[[f64; 2]], b: &[[f64; 2]], tol: f64) -> Vec<[f64; 2]> {
    let seg = |s: &[[f64; 2]]| if s.len() == 1 { (s[0], s[0]) } else { (s[0], s[1]) };
    let (p0, p1) = seg(a);
    let (q0, q1) = seg(b);
    // Closest points between the segments; if within tol, a contact point.
    let (c1, c2) = closest_points_segments(p0, p1, q0, q1);
    let d = ((c1[0] - c2[0]).powi(2) + (c1[1] - c2[1]).powi(2)).sqrt();
    if d > tol {
        return Vec::new();
    }
    // Collinear overlap: keep the overlapping part as a segment.
    let dp = [p1[0] - p0[0], p1[1] - p0[1]];
    let dq = [q1[0] - q0[0], q1[1] - q0[1]];
    let lp = (dp[0] * dp[0] + dp[1] * dp[1]).sqrt();
    let lq = (dq[0] * dq[0] + dq[1] * dq[1]).sqrt();
    if lp > tol && lq > tol && (dp[0] * dq[1] - dp[1] * dq[0]).abs() <= tol * lq.max(lp) {
        let u = [dp[0] / lp, dp[1] / lp];
        let proj = |p: [f64; 2]| (p[0] - p0[0]) * u[0] + (p[1] - p0[1]) * u[1];
        let (t0, t1) = {
            let (s0, s1) = (proj(q0), proj(q1));
            (s0.min(s1).max(0.0), s0.max(s1).min(lp))
        };
        if t1 > t0 + tol {
            return vec![[p0[0] + t0 * u[0], p0[1] + t0 * u[1]], [p0[0] + t1 * u[0], p0[1] + t1 * u[1]]];
        }
    }
    vec![[(c1[0] + c2[0]) / 2.0, (c1[1] + c2[1]) / 2.0]]
}

/// Closest points between segments p0–p1 and q0–q1 (Ericson, Real-Time Collision Detection,
/// §5.1.9).
pub fn closest_points_segments(p0: [f64; 2], p1: [f64; 2], q0: [f64; 2], q1: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    let d1 = [p1[0] - p0[0], p1[1] - p0[1]];
    let d2 = [q1[0] - q0[0], q1[1] - q0[1]];
    let r = [p0[0] - q0[0], p0[1] - q0[1]];
    let a = d1[0] * d1[0] + d1[1] * d1[1];
    let e = d2[0] * d2[0] + d2[1] * d2[1];
    let f = d2[0] * r[0] + d2[1] * r[1];
    let (s, t);
    if a <= 1e-30 && e <= 1e-30 {
        return (p0, q0);
    }
    if a <= 1e-30 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1[0] * r[0] + d1[1] * r[1];
        if e <= 1e-30 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1[0] * d2[0] + d1[1] * d2[1];
            let denom = a * e - b * b;
            let mut s0 = if denom > 1e-30 { ((b * f - c * e) / denom).clamp(0.0, 1.0) } else { 0.0 };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    ([p0[0] + d1[0] * s, p0[1] + d1[1] * s], [q0[0] + d2[0] * t, q0[1] + d2[1] * t])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_overlap_is_the_shared_rectangle() {
        let a = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
        let b = vec![[1.0, -1.0], [3.0, -1.0], [3.0, 0.5], [1.0, 0.5]];
        let c = intersect_convex(&a, &b, 0.0);
        assert!((area(&c) - 0.5).abs() < 1e-12);
        let cc = centroid(&c);
        assert!((cc[0] - 1.5).abs() < 1e-12 && (cc[1] - 0.25).abs() < 1e-12);
    }

    #[test]
    fn segment_clipped_by_square_and_crossing_segments() {
        let sq = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let s = vec![[-1.0, 0.5], [2.0, 0.5]];
        let c = intersect_convex(&s, &sq, 0.0);
        assert_eq!(c.len(), 2);
        let len = (c[1][0] - c[0][0]).abs();
        assert!((len - 1.0).abs() < 1e-12);
        let x = intersect_convex(&[[0.0, 0.0], [1.0, 1.0]], &[[0.0, 1.0], [1.0, 0.0]], 1e-9);
        assert_eq!(x.len(), 1);
        assert!((x[0][0] - 0.5).abs() < 1e-9);
    }

    #[test]
    fn hull_drops_interior_and_collinear_points() {
        let p = vec![[0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]];
        let h = hull2d(&p, 1e-12);
        assert_eq!(h.len(), 4);
        assert!((area(&h) - 1.0).abs() < 1e-12);
    }
}
