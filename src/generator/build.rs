//! The construction in the wall's elevation plane (x–z), course by course. See the
//! [module doc](super) for the method; this file only implements it.

use super::wall::{Arrangement, HeadGap, Wall};
use super::{GeneratorError, PieceKind, Samples};
use rand::distr::Distribution as _;
use rand::Rng;

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
    fn at(&self, x: f64) -> f64 {
        if self.x1 == self.x0 {
            return self.z0.max(self.z1);
        }
        self.z0 + (self.z1 - self.z0) * (x - self.x0) / (self.x1 - self.x0)
    }

    /// The part over [a, b], if it has positive length.
    fn clip(&self, a: f64, b: f64) -> Option<Seg> {
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
    fn at(&self, x: f64) -> f64 {
        self.zm + self.m * (x - self.xm)
    }
}

/// One piece in the elevation plane, before extrusion.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Piece2 {
    pub kind: PieceKind,
    pub course: usize,
    /// Counter-clockwise polygon (x right, z up), m.
    pub polygon: Vec<P2>,
    /// Drawn dip of the stone's top, degrees (stones below the top course).
    pub dip_deg: Option<f64>,
}

/// Output of the elevation construction.
pub(crate) struct Elevation {
    pub pieces: Vec<Piece2>,
    pub course_tops: Vec<f64>,
    pub samples: Samples,
}

fn infeasible(wall: &Wall, key: &str, reason: String) -> GeneratorError {
    GeneratorError::Infeasible { path: wall.source.clone(), key: key.into(), reason }
}

/// Nominal course tops Z_1..Z_n (Z_n = H exactly).
fn course_tops<R: Rng + ?Sized>(wall: &Wall, rng: &mut R, samples: &mut Samples) -> Vec<f64> {
    let h = wall.height;
    let d = &wall.course_height;
    let mut heights = Vec::new();
    if d.is_fixed() {
        let n = ((h / d.mean()).round() as usize).max(1);
        heights = vec![h / n as f64; n];
    } else {
        let mean = d.mean();
        let top_min = 0.5 * mean;
        let mut sum = 0.0;
        loop {
            let x = d.sample(rng);
            if sum + x <= h - top_min {
                samples.course_heights_m.push(x);
                heights.push(x);
                sum += x;
            } else {
                break;
            }
        }
        let rest = h - sum;
        let k = ((rest / mean).round() as usize).max(1);
        for _ in 0..k {
            heights.push(rest / k as f64);
        }
    }
    let mut tops = Vec::with_capacity(heights.len());
    let mut z = 0.0;
    for (i, hk) in heights.iter().enumerate() {
        z += hk;
        tops.push(if i + 1 == heights.len() { h } else { z });
    }
    tops
}

/// Head-joint positions of course `k`: 0 = x_0 < x_1 < … < x_m = L.
fn head_joints<R: Rng + ?Sized>(wall: &Wall, k: usize, rng: &mut R, samples: &mut Samples) -> Vec<f64> {
    let l = wall.length;
    let d = &wall.block_length;
    let lbar = d.mean();
    let e_min = wall.min_end_fraction * lbar;
    let mut xs = vec![0.0];
    match &wall.arrangement {
        Arrangement::Continuous | Arrangement::Discontinuous { .. } => {
            let offset = match wall.arrangement {
                Arrangement::Discontinuous { overlap } if k % 2 == 1 => overlap * lbar,
                _ => 0.0,
            };
            let mut j = 0usize;
            loop {
                let x = offset + j as f64 * lbar;
                j += 1;
                if x >= l - e_min {
                    break;
                }
                if x >= e_min {
                    xs.push(x);
                }
            }
        }
        Arrangement::Irregular(_) => {
            let first = d.sample(rng) * rand::distr::Uniform::new(0.5, 1.0).expect("valid").sample(rng);
            let mut x = first.max(e_min);
            let mut lengths = Vec::new();
            if x < l - e_min {
                xs.push(x);
                loop {
                    let li = d.sample(rng);
                    if x + li <= l - e_min {
                        x += li;
                        xs.push(x);
                        lengths.push(li);
                    } else {
                        break;
                    }
                }
                // An over-long last piece is split in two.
                let rest = l - x;
                if rest > d.practical_max() && rest / 2.0 >= e_min {
                    xs.push(x + rest / 2.0);
                }
            }
            samples.block_lengths_m.push(lengths);
        }
    }
    xs.push(l);
    xs
}

/// The line of least area above the points of `segs` over [a, b] whose slope is at most
/// `max_slope` in magnitude: the edge of their upper convex hull over the midpoint (if the
/// midpoint is a hull vertex, the flattest line through it that stays above the hull); if
/// that edge is steeper than `max_slope`, the supporting line of slope ±`max_slope`.
fn least_line_above(segs: &[Seg], a: f64, b: f64, max_slope: f64) -> Option<Line> {
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
    fn z_max(level: f64) -> Self {
        HalfPlane::Below(Line { xm: 0.0, zm: level, m: 0.0 })
    }
    fn z_min(level: f64) -> Self {
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

/// The convex region `x0 ≤ x ≤ x1` ∩ the half-planes, as a counter-clockwise polygon with
/// vertices closer than `snap` (m) merged by dropping one of them (which only shrinks the
/// region) and collinear vertices removed. Empty if the region is.
fn region(x0: f64, x1: f64, zlo: f64, zhi: f64, planes: &[HalfPlane], snap: f64) -> Vec<P2> {
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
fn top_segments(poly: &[P2], out: &mut Vec<Seg>) {
    let n = poly.len();
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        if q[0] < p[0] - 1e-12 {
            out.push(Seg { x0: q[0], z0: q[1], x1: p[0], z1: p[1] });
        }
    }
}

/// Builds the elevation of one realization. `rng` is the realization's layout stream.
#[allow(clippy::needless_range_loop)] // k is the course number, not only an index
pub(crate) fn build<R: Rng + ?Sized>(wall: &Wall, rng: &mut R) -> Result<Elevation, GeneratorError> {
    let (l, h) = (wall.length, wall.height);
    let mut samples = Samples::default();
    let tops = course_tops(wall, rng, &mut samples);
    let n = tops.len();
    let hbar = wall.course_height.mean();
    let lbar = wall.block_length.mean();
    let snap = 1e-4 * hbar;
    let (irregular, t_w, l_w) = match &wall.arrangement {
        Arrangement::Irregular(ir) => {
            (Some(ir), ir.min_wedge_thickness.max(snap), ir.min_wedge_length.max(1e-6 * lbar))
        }
        _ => (None, f64::INFINITY, f64::INFINITY),
    };
    // Slope of the steepest dip the law can draw.
    let tan_max = match irregular {
        Some(ir) => {
            let (lo, hi) = ir.dip.support();
            crate::units::deg_to_rad(lo.abs().max(hi.abs())).tan()
        }
        None => 0.0,
    };
    let nominal = |k: usize| tops[k] - if k == 0 { 0.0 } else { tops[k - 1] };
    let top_min = wall.min_thickness_fraction * nominal(n - 1);
    let mut lower = vec![Seg { x0: 0.0, z0: 0.0, x1: l, z1: 0.0 }];
    let mut pieces = Vec::new();

    for k in 0..n {
        let xs = head_joints(wall, k, rng, &mut samples);
        let m = xs.len() - 1;
        let gap = match wall.head_gap {
            HeadGap::Closed => 0.0,
            HeadGap::Width(w) => w,
            HeadGap::VoidFraction(f) => {
                if m > 1 {
                    f * l / (m - 1) as f64
                } else {
                    0.0
                }
            }
        };
        let single_shrink = match wall.head_gap {
            HeadGap::VoidFraction(f) if m == 1 => 0.5 * f * l,
            _ => 0.0,
        };
        let h_min = wall.min_thickness_fraction * nominal(k);
        // Ceiling of this course's tops: an unshifted top segment never reaches it (it is
        // the nominal top plus the rise of the steepest dip over half the longest block);
        // below the top course it also leaves the top course its minimum thickness.
        let longest = xs.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
        let mut cap = tops[k] + 0.5 * longest * tan_max;
        if k + 2 == n {
            cap = cap.min(h - top_min);
        }
        let mut new_top: Vec<Seg> = Vec::with_capacity(m + 2);
        for i in 0..m {
            let a = if i == 0 { single_shrink } else { xs[i] + 0.5 * gap };
            let b = if i + 1 == m { l - single_shrink } else { xs[i + 1] - 0.5 * gap };
            if b - a <= 0.0 {
                return Err(infeasible(
                    wall,
                    "head_joints",
                    format!("course {k}: the open head joints ({gap} m) leave no room for block {i}"),
                ));
            }
            let mid = 0.5 * (a + b);
            let under: Vec<Seg> = lower.iter().filter_map(|s| s.clip(a, b)).collect();
            // Bed slope limit: the steepest dip, and a rise over half the stone of at most
            // half the course height (so a capped stone keeps half its course height).
            let max_bed_slope = tan_max.min(0.5 * nominal(k) / (0.5 * (b - a)));
            let bottom = if k == 0 {
                Line { xm: mid, zm: 0.0, m: 0.0 }
            } else if k + 1 == n {
                // The top course (the copes) lies flat on the highest point under it.
                let zmax = under.iter().map(|s| s.z0.max(s.z1)).fold(f64::NEG_INFINITY, f64::max);
                if !zmax.is_finite() {
                    return Err(infeasible(
                        wall,
                        "head_joints",
                        format!("course {k}, block {i}: nothing underneath to rest on"),
                    ));
                }
                Line { xm: mid, zm: zmax, m: 0.0 }
            } else {
                least_line_above(&under, a, b, max_bed_slope).ok_or_else(|| {
                    infeasible(wall, "head_joints", format!("course {k}, block {i}: nothing underneath to rest on"))
                })?
            };
            // The stone's ceiling: the course cap below the top course (see above).
            let stone_cap = (k + 1 < n).then_some(cap);
            // Wedges in the gaps between this stone's bed line and the course below:
            // * under the same ceiling as the stone (where a steep bed rises above the cap
            //   the stone is cut short, and a wedge there must not reach above it either);
            // * over the stone's whole slot, out to the middle of its open head joints (and to
            //   the wall's ends), so that an open joint reaches down only to its neighbours'
            //   bed level and leaves the stated void (an unfilled column under it would add
            //   up to the stated void again under steep beds). With closed head joints the
            //   slot is the stone itself.
            let mut wedge_tops: Vec<Seg> = Vec::new();
            if k > 0 && irregular.is_some() {
                let wedge_len = irregular.and_then(|ir| ir.wedge_length.as_ref());
                let fill = irregular.map_or(1.0, |ir| ir.wedge_fill);
                let slot = (if i == 0 { 0.0 } else { xs[i] }, if i + 1 == m { l } else { xs[i + 1] });
                let slot_under: Vec<Seg> = lower.iter().filter_map(|s| s.clip(slot.0, slot.1)).collect();
                for s in &slot_under {
                    let (gl, gr) = (bottom.at(s.x0) - s.z0, bottom.at(s.x1) - s.z1);
                    if gl.max(gr) < t_w || s.x1 - s.x0 < l_w {
                        continue;
                    }
                    // Wedge frequency: a draw only when some gaps stay empty.
                    if fill < 1.0 && rand::distr::Uniform::new(0.0, 1.0).expect("valid").sample(rng) >= fill {
                        continue;
                    }
                    // Cut points along x (wedge length law), else one wedge.
                    let mut cuts = vec![s.x0];
                    if let Some(wl) = wedge_len {
                        let mut x = s.x0;
                        loop {
                            let w = wl.sample(rng).max(l_w);
                            if x + w >= s.x1 - l_w {
                                break;
                            }
                            x += w;
                            cuts.push(x);
                        }
                    }
                    cuts.push(s.x1);
                    for c in cuts.windows(2) {
                        let (c0, c1) = (c[0], c[1]);
                        let (z0, z1) = (s.at(c0), s.at(c1));
                        let (g0, g1) = (bottom.at(c0) - z0, bottom.at(c1) - z1);
                        if g0.max(g1) < t_w {
                            continue;
                        }
                        let under_line = Line { xm: s.x0, zm: s.z0, m: (s.z1 - s.z0) / (s.x1 - s.x0) };
                        let mut planes = vec![
                            HalfPlane::Above(under_line),
                            HalfPlane::Below(bottom),
                            HalfPlane::z_min(0.0),
                            HalfPlane::z_max(h),
                        ];
                        if let Some(c) = stone_cap {
                            planes.push(HalfPlane::z_max(c));
                        }
                        let poly = region(c0, c1, -h, 2.0 * h, &planes, snap);
                        if poly.len() >= 3 && area(&poly) > 1e-6 * hbar * lbar {
                            top_segments(&poly, &mut wedge_tops);
                            pieces.push(Piece2 { kind: PieceKind::Wedge, course: k, polygon: poly, dip_deg: None });
                        }
                    }
                }
            }
            // The stone's top.
            let (top, dip_deg) = if k + 1 == n {
                (Line { xm: mid, zm: h, m: 0.0 }, None)
            } else {
                let dip = match irregular {
                    Some(ir) => ir.dip.sample(rng),
                    None => 0.0,
                };
                samples.dips_deg.push(dip);
                let mut t = Line { xm: mid, zm: tops[k], m: crate::units::deg_to_rad(dip).tan() };
                let short = (h_min - (t.at(a) - bottom.at(a))).max(h_min - (t.at(b) - bottom.at(b)));
                if short > 0.0 {
                    t.zm += short;
                }
                (t, Some(dip))
            };
            let mut planes =
                vec![HalfPlane::Above(bottom), HalfPlane::Below(top), HalfPlane::z_min(0.0), HalfPlane::z_max(h)];
            if let Some(c) = stone_cap {
                planes.push(HalfPlane::z_max(c));
            }
            let poly = region(a, b, -h, 2.0 * h, &planes, snap);
            if poly.len() < 3 || area(&poly) <= 1e-4 * hbar * lbar {
                return Err(infeasible(
                    wall,
                    "arrangement.dip_deg",
                    format!(
                        "course {k}, block {i} (x {a:.4}..{b:.4} m) has no room between its bed and the wall top: \
                         dips too steep for the course heights"
                    ),
                ));
            }
            top_segments(&poly, &mut new_top);
            // Wedge tops beyond the stone's x-range (where the cap cut the stone short) are
            // exposed: the next course rests on them too.
            let (sx0, sx1) =
                poly.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
            for t in &wedge_tops {
                new_top.extend(t.clip(f64::NEG_INFINITY, sx0));
                new_top.extend(t.clip(sx1, f64::INFINITY));
            }
            pieces.push(Piece2 { kind: PieceKind::Stone, course: k, polygon: poly, dip_deg });
        }
        new_top.sort_by(|p, q| p.x0.total_cmp(&q.x0));
        lower = new_top;
    }
    Ok(Elevation { pieces, course_tops: tops, samples })
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
