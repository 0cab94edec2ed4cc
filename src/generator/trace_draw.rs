//! The tracing tolerance drawn: a traced elevation's corners moved, each by at most the
//! tolerance, without opening an overlap between stones.
//!
//! Moving every corner on its own makes overlaps wherever stones meet: a corner shared by
//! two stones, a corner lying on a neighbour's edge (a T-junction), a bed joint that several
//! stones share. So the draw moves the joints, not the stones:
//!
//! 1. **Nodes.** Corners within [`SNAP_M`] of each other are one node, moved once.
//! 2. **Joint lines.** Edges that lie on one straight line and overlap (a bed joint that
//!    stones on both sides share, a head joint) are one joint line; a node inside a joint
//!    line (not one of its two ends) stays on it.
//! 3. **The draw.** A node on the table (z = 0) slides along it: Δx uniform on
//!    \[−t, t\], Δz = 0. A free node moves uniformly in the disc of radius t. A node inside
//!    one joint line is put on the moved line at its traced fraction of the line's length and
//!    slides along it, uniformly within the slide that keeps its displacement ≤ t; a node
//!    inside two joint lines goes to the moved lines' crossing. Lines are placed once their
//!    ends are. A circle of lines each ending inside the next (a pinwheel; an irregular
//!    wall's stones resting on one another's corners) is broken by holding its first node
//!    at its traced place, and with it every node of a line through a held node (so a line
//!    moves whole or not at all).
//! 4. **The check.** Every stone must stay convex and every corner within t of its traced
//!    place, and no two stones may overlap by more than
//!    [`crate::layout::OVERLAP_TOLERANCE_M`] (penetration depth of the convex polygons).
//!    Each node's place is a function of two uniform numbers of its own; when the check
//!    fails, the numbers of the corners of the stones at fault are drawn again (the next
//!    numbers of the same stream, in node order) and every node placed anew, up to
//!    [`MAX_ATTEMPTS`] checks.
//! 5. **The fallback.** If every attempt fails, the elevation is mapped by one affine map
//!    fixing the table (x' = x + a x + b z, z' = z + c z: the photograph's scale errors and
//!    shear), scaled so that no corner moves more than t. An affine map keeps straight edges
//!    straight, convex stones convex and stones apart, so it never fails; the draw reports
//!    that it was used.

use crate::layout::OVERLAP_TOLERANCE_M;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// Corners closer than this are one node, m; a node closer than this to an edge lies on it.
pub const SNAP_M: f64 = 1e-7;

/// The draws tried before the affine fallback.
pub const MAX_ATTEMPTS: u32 = 64;

/// How a realization's outlines were drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawReport {
    /// Draws made (1 when the first passed the check; [`MAX_ATTEMPTS`] when the fallback was
    /// used).
    pub attempts: u32,
    /// Whether the affine fallback was used.
    pub affine: bool,
    /// The largest corner displacement, m (≤ the tolerance).
    pub max_displacement_m: f64,
    /// Why the last refused per-corner draw was refused (stone indices in layout order),
    /// if one was.
    pub refused: Option<String>,
}

/// The outlines `polygons` (convex, counter-clockwise, table frame, m) with their corners
/// moved within `tolerance_m` (module doc), and how they were drawn. A tolerance of 0
/// returns the outlines unchanged and draws nothing.
pub fn draw(polygons: &[Vec<[f64; 2]>], tolerance_m: f64, rng: &mut ChaCha8Rng) -> (Vec<Vec<[f64; 2]>>, DrawReport) {
    let unchanged = DrawReport { attempts: 0, affine: false, max_displacement_m: 0.0, refused: None };
    if tolerance_m <= 0.0 || polygons.is_empty() {
        return (polygons.to_vec(), unchanged);
    }
    let net = Net::new(polygons);
    let mut raw: Vec<[f64; 2]> = (0..net.nodes.len()).map(|_| [rng.random(), rng.random()]).collect();
    let mut refused = None;
    for attempt in 1..=MAX_ATTEMPTS {
        let out = net.polygons(&net.place(&raw, tolerance_m));
        match check(polygons, &out, tolerance_m) {
            Ok(max) => {
                return (out, DrawReport { attempts: attempt, affine: false, max_displacement_m: max, refused });
            }
            Err((why, stones)) => {
                refused = Some(why);
                // Drawn again: the corners of the stones at fault, in node order.
                let mut again: Vec<usize> = stones.iter().flat_map(|&k| net.stones[k].iter().copied()).collect();
                again.sort_unstable();
                again.dedup();
                for i in again {
                    raw[i] = [rng.random(), rng.random()];
                }
            }
        }
    }
    let out = affine(polygons, tolerance_m, rng);
    let max = max_displacement(polygons, &out);
    (out, DrawReport { attempts: MAX_ATTEMPTS, affine: true, max_displacement_m: max, refused })
}

/// The nodes, the stones as node indices, and the joint lines.
struct Net {
    nodes: Vec<[f64; 2]>,
    stones: Vec<Vec<usize>>,
    /// Each joint line with three or more nodes: its nodes ordered along it (the first and
    /// last are its ends).
    lines: Vec<Vec<usize>>,
    /// Per node, the lines it lies inside.
    inside: Vec<Vec<usize>>,
    /// Per node, whether it is on the table.
    on_table: Vec<bool>,
    /// Per node, whether it keeps its traced place (a node of a circle of joint lines, and
    /// every node of a line through one such node).
    held: Vec<bool>,
}

impl Net {
    fn new(polygons: &[Vec<[f64; 2]>]) -> Self {
        let mut nodes: Vec<[f64; 2]> = Vec::new();
        let stones: Vec<Vec<usize>> = polygons
            .iter()
            .map(|poly| {
                poly.iter()
                    .map(|p| match nodes.iter().position(|q| near(p, q, SNAP_M)) {
                        Some(i) => i,
                        None => {
                            nodes.push(*p);
                            nodes.len() - 1
                        }
                    })
                    .collect()
            })
            .collect();
        let edges: Vec<(usize, usize)> =
            stones.iter().flat_map(|s| (0..s.len()).map(move |k| (s[k], s[(k + 1) % s.len()]))).collect();
        let lines = joint_lines(&nodes, &edges);
        let mut inside = vec![Vec::new(); nodes.len()];
        for (l, line) in lines.iter().enumerate() {
            for &n in &line[1..line.len() - 1] {
                inside[n].push(l);
            }
        }
        let z0 = nodes.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min).min(0.0);
        let on_table: Vec<bool> = nodes.iter().map(|p| p[1] <= z0 + SNAP_M).collect();
        let held = held_nodes(&lines, &inside, &on_table);
        Self { nodes, stones, lines, inside, on_table, held }
    }

    /// Every node's new place from its two uniform numbers `raw` (module doc, step 3).
    fn place(&self, raw: &[[f64; 2]], t: f64) -> Vec<[f64; 2]> {
        let n = self.nodes.len();
        let mut moved: Vec<Option<[f64; 2]>> = vec![None; n];
        for i in 0..n {
            let p = self.nodes[i];
            if self.held[i] {
                moved[i] = Some(p);
            } else if self.on_table[i] {
                moved[i] = Some([p[0] + t * (2.0 * raw[i][0] - 1.0), p[1]]);
            } else if self.inside[i].is_empty() {
                let (r, a) = (t * raw[i][0].sqrt(), std::f64::consts::TAU * raw[i][1]);
                moved[i] = Some([p[0] + r * a.cos(), p[1] + r * a.sin()]);
            }
        }
        loop {
            let mut progress = false;
            let mut first_open = None;
            for i in 0..n {
                if moved[i].is_some() {
                    continue;
                }
                let ready: Vec<usize> = self.inside[i]
                    .iter()
                    .copied()
                    .filter(|&l| {
                        let line = &self.lines[l];
                        moved[line[0]].is_some() && moved[line[line.len() - 1]].is_some()
                    })
                    .collect();
                if ready.len() < self.inside[i].len() {
                    first_open.get_or_insert(i);
                    continue;
                }
                moved[i] = Some(self.on_lines(i, &ready, &moved, t, raw[i][0]));
                progress = true;
            }
            match (progress, first_open) {
                (_, None) => break,
                (true, Some(_)) => {}
                (false, Some(i)) => moved[i] = Some(self.nodes[i]),
            }
        }
        moved.into_iter().map(|m| m.expect("every node placed")).collect()
    }

    /// The new place of node `i`, inside the (placed) lines `lines`.
    fn on_lines(&self, i: usize, lines: &[usize], moved: &[Option<[f64; 2]>], t: f64, u0: f64) -> [f64; 2] {
        let p = self.nodes[i];
        let ends = |l: usize| {
            let line = &self.lines[l];
            let (a, b) = (line[0], line[line.len() - 1]);
            (self.nodes[a], self.nodes[b], moved[a].expect("placed"), moved[b].expect("placed"))
        };
        if lines.len() >= 2 {
            let (_, _, a1, b1) = ends(lines[0]);
            let (_, _, a2, b2) = ends(lines[1]);
            if let Some(x) = crossing(a1, b1, a2, b2) {
                return x;
            }
        }
        let (a, b, a2, b2) = ends(lines[0]);
        let len = dist(&a, &b);
        let f = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / (len * len);
        let on = [a2[0] + f * (b2[0] - a2[0]), a2[1] + f * (b2[1] - a2[1])];
        let len2 = dist(&a2, &b2);
        let u = [(b2[0] - a2[0]) / len2, (b2[1] - a2[1]) / len2];
        // The slide s keeps |d + s u| ≤ t, d the displacement the line gives the node.
        let d = [on[0] - p[0], on[1] - p[1]];
        let du = d[0] * u[0] + d[1] * u[1];
        let disc = (du * du - (d[0] * d[0] + d[1] * d[1]) + t * t).max(0.0);
        let (lo, hi) = (-du - disc.sqrt(), -du + disc.sqrt());
        let s = lo + (hi - lo) * u0;
        [on[0] + s * u[0], on[1] + s * u[1]]
    }

    /// The stones' outlines with the nodes at `moved`.
    fn polygons(&self, moved: &[[f64; 2]]) -> Vec<Vec<[f64; 2]>> {
        self.stones.iter().map(|s| s.iter().map(|&i| moved[i]).collect()).collect()
    }
}

/// The nodes that keep their traced place: placing the nodes in the order of
/// [`Net::place`] (a node inside lines once their ends are placed), the first node of a
/// circle that never gets ready, and then every node of a line through a held node, until
/// no line has both held and free nodes. A line thus moves whole or not at all, and the
/// nodes inside it stay on it.
fn held_nodes(lines: &[Vec<usize>], inside: &[Vec<usize>], on_table: &[bool]) -> Vec<bool> {
    let n = inside.len();
    let mut held = vec![false; n];
    let mut placed: Vec<bool> = (0..n).map(|i| on_table[i] || inside[i].is_empty()).collect();
    loop {
        let mut progress = false;
        let mut first_open = None;
        for i in 0..n {
            if placed[i] {
                continue;
            }
            if inside[i].iter().all(|&l| placed[lines[l][0]] && placed[lines[l][lines[l].len() - 1]]) {
                placed[i] = true;
                progress = true;
            } else {
                first_open.get_or_insert(i);
            }
        }
        match (progress, first_open) {
            (_, None) => break,
            (true, Some(_)) => {}
            (false, Some(i)) => {
                placed[i] = true;
                held[i] = true;
            }
        }
    }
    loop {
        let mut changed = false;
        for line in lines {
            if line.iter().any(|&k| held[k]) && !line.iter().all(|&k| held[k]) {
                line.iter().for_each(|&k| held[k] = true);
                changed = true;
            }
        }
        if !changed {
            return held;
        }
    }
}

/// The joint lines of the edges `edges` (node pairs) with three or more nodes: edges on one
/// straight line that overlap by more than [`SNAP_M`] are joined; each line's nodes (its
/// edges' ends and every node inside one of them) ordered along it.
fn joint_lines(nodes: &[[f64; 2]], edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let m = edges.len();
    let mut parent: Vec<usize> = (0..m).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let on_line = |e: (usize, usize), p: &[f64; 2]| {
        let (a, b) = (nodes[e.0], nodes[e.1]);
        let len = dist(&a, &b);
        ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])).abs() / len <= SNAP_M
    };
    let along = |e: (usize, usize), p: &[f64; 2]| {
        let (a, b) = (nodes[e.0], nodes[e.1]);
        let len = dist(&a, &b);
        ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / len
    };
    for i in 0..m {
        for j in i + 1..m {
            let (e, g) = (edges[i], edges[j]);
            if !(on_line(e, &nodes[g.0]) && on_line(e, &nodes[g.1])) {
                continue;
            }
            let len = dist(&nodes[e.0], &nodes[e.1]);
            let (s0, s1) = (along(e, &nodes[g.0]), along(e, &nodes[g.1]));
            let overlap = s0.max(s1).min(len) - s0.min(s1).max(0.0);
            if overlap > SNAP_M {
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    let mut classes: std::collections::BTreeMap<usize, Vec<usize>> = std::collections::BTreeMap::new();
    for i in 0..m {
        let r = root(&mut parent, i);
        classes.entry(r).or_default().push(i);
    }
    let mut lines = Vec::new();
    for members in classes.values() {
        let e0 = edges[members[0]];
        let mut on: Vec<usize> = members.iter().flat_map(|&k| [edges[k].0, edges[k].1]).collect();
        for (n, p) in nodes.iter().enumerate() {
            let inside = members.iter().any(|&k| {
                let e = edges[k];
                let s = along(e, p);
                n != e.0 && n != e.1 && on_line(e, p) && s > SNAP_M && s < dist(&nodes[e.0], &nodes[e.1]) - SNAP_M
            });
            if inside {
                on.push(n);
            }
        }
        on.sort_by(|&a, &b| along(e0, &nodes[a]).total_cmp(&along(e0, &nodes[b])).then(a.cmp(&b)));
        on.dedup();
        if on.len() >= 3 {
            lines.push(on);
        }
    }
    lines
}

/// The largest corner displacement if the drawn outlines `out` pass the check (module doc),
/// else why not and the stones at fault (in layout order).
fn check(traced: &[Vec<[f64; 2]>], out: &[Vec<[f64; 2]>], t: f64) -> Result<f64, (String, Vec<usize>)> {
    let max = max_displacement(traced, out);
    let mut faults = Vec::new();
    let mut why = String::new();
    for (k, (a, b)) in traced.iter().zip(out).enumerate() {
        let far = a.iter().zip(b).map(|(p, q)| dist(p, q)).fold(0.0, f64::max);
        if far > t * (1.0 + 1e-9) + 1e-15 {
            why = format!("a corner of stone {k} moved {far:.3e} m");
            faults.push(k);
        } else if !convex(b) {
            why = format!("stone {k} is no longer convex");
            faults.push(k);
        }
    }
    let boxes: Vec<_> = out.iter().map(|p| bounds(p)).collect();
    for i in 0..out.len() {
        for j in i + 1..out.len() {
            let (a, b) = (&boxes[i], &boxes[j]);
            let gap = (a.0[0] - b.1[0]).max(b.0[0] - a.1[0]).max(a.0[1] - b.1[1]).max(b.0[1] - a.1[1]);
            let depth = if gap < -OVERLAP_TOLERANCE_M { penetration(&out[i], &out[j]) } else { 0.0 };
            if depth > OVERLAP_TOLERANCE_M {
                why = format!("stones {i} and {j} overlap by {depth:.3e} m");
                faults.extend([i, j]);
            }
        }
    }
    if faults.is_empty() {
        Ok(max)
    } else {
        Err((why, faults))
    }
}

/// The largest distance between a traced corner and its drawn place, m.
pub fn max_displacement(traced: &[Vec<[f64; 2]>], out: &[Vec<[f64; 2]>]) -> f64 {
    traced.iter().zip(out).flat_map(|(a, b)| a.iter().zip(b).map(|(p, q)| dist(p, q))).fold(0.0, f64::max)
}

/// Whether a counter-clockwise polygon is strictly convex (every turn to the left by more
/// than a sine of 1e-9) and winds once.
fn convex(poly: &[[f64; 2]]) -> bool {
    let n = poly.len();
    let mut winding = 0.0;
    for i in 0..n {
        let (p, q, r) = (poly[(i + n - 1) % n], poly[i], poly[(i + 1) % n]);
        let (e1, e2) = ([q[0] - p[0], q[1] - p[1]], [r[0] - q[0], r[1] - q[1]]);
        let cross = e1[0] * e2[1] - e1[1] * e2[0];
        if cross <= 1e-9 * e1[0].hypot(e1[1]) * e2[0].hypot(e2[1]) {
            return false;
        }
        winding += cross.atan2(e1[0] * e2[0] + e1[1] * e2[1]);
    }
    (winding - std::f64::consts::TAU).abs() < 1e-6
}

/// The affine fallback: x' = x + a (x − x̄) + b z, z' = z + c z with a, b, c uniform on
/// \[−1, 1\], scaled so that the largest corner displacement is a uniform fraction of `t`.
fn affine(polygons: &[Vec<[f64; 2]>], t: f64, rng: &mut ChaCha8Rng) -> Vec<Vec<[f64; 2]>> {
    let all = || polygons.iter().flatten();
    let count = all().count() as f64;
    let xm = all().map(|p| p[0]).sum::<f64>() / count;
    let [a, b, c]: [f64; 3] = std::array::from_fn(|_| 2.0 * rng.random::<f64>() - 1.0);
    let shift = |p: &[f64; 2]| [a * (p[0] - xm) + b * p[1], c * p[1]];
    let largest = all().map(|p| shift(p)[0].hypot(shift(p)[1])).fold(0.0, f64::max);
    let k = if largest > 0.0 { t * rng.random::<f64>() / largest } else { 0.0 };
    polygons
        .iter()
        .map(|poly| {
            poly.iter()
                .map(|p| {
                    let d = shift(p);
                    [p[0] + k * d[0], p[1] + k * d[1]]
                })
                .collect()
        })
        .collect()
}

/// The penetration depth of two convex polygons, m (≤ 0: apart or touching): the least
/// overlap of their projections on the normals of their edges.
pub fn penetration(p: &[[f64; 2]], q: &[[f64; 2]]) -> f64 {
    let mut depth = f64::INFINITY;
    for poly in [p, q] {
        let n = poly.len();
        for i in 0..n {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            let normal = [(b[1] - a[1]) / len, (a[0] - b[0]) / len];
            let project = |s: &[[f64; 2]]| {
                s.iter()
                    .map(|v| v[0] * normal[0] + v[1] * normal[1])
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)))
            };
            let ((p0, p1), (q0, q1)) = (project(p), project(q));
            depth = depth.min(p1.min(q1) - p0.max(q0));
        }
    }
    depth
}

/// The lower-left and upper-right corners of the points' bounding box.
fn bounds(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    points.iter().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), p| {
        ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
    })
}

/// The crossing of the lines through a1, b1 and through a2, b2, unless nearly parallel.
fn crossing(a1: [f64; 2], b1: [f64; 2], a2: [f64; 2], b2: [f64; 2]) -> Option<[f64; 2]> {
    let (d1, d2) = ([b1[0] - a1[0], b1[1] - a1[1]], [b2[0] - a2[0], b2[1] - a2[1]]);
    let den = d1[0] * d2[1] - d1[1] * d2[0];
    if den.abs() <= 1e-6 * d1[0].hypot(d1[1]) * d2[0].hypot(d2[1]) {
        return None;
    }
    let s = ((a2[0] - a1[0]) * d2[1] - (a2[1] - a1[1]) * d2[0]) / den;
    Some([a1[0] + s * d1[0], a1[1] + s * d1[1]])
}

fn dist(p: &[f64; 2], q: &[f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

fn near(p: &[f64; 2], q: &[f64; 2], eps: f64) -> bool {
    (p[0] - q[0]).abs() <= eps && (p[1] - q[1]).abs() <= eps
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{rng_for, Purpose};

    fn rect(x0: f64, z0: f64, x1: f64, z1: f64) -> Vec<[f64; 2]> {
        vec![[x0, z0], [x1, z0], [x1, z1], [x0, z1]]
    }

    /// Two courses in running bond: every bed joint a line shared by three stones, every
    /// head joint ending inside a bed joint.
    fn running_bond() -> Vec<Vec<[f64; 2]>> {
        let mut v = Vec::new();
        for (k, offset) in [(0, 0.0), (1, 0.2), (2, 0.0)] {
            let (z0, z1) = (0.2 * k as f64, 0.2 * (k + 1) as f64);
            let mut x = 0.0;
            let mut edges = vec![0.0];
            if offset > 0.0 {
                edges.push(offset);
            }
            while x + 0.4 < 1.6 - 1e-9 {
                x = if offset > 0.0 && edges.len() > 1 { edges[edges.len() - 1] + 0.4 } else { x + 0.4 };
                if x < 1.6 - 1e-9 {
                    edges.push(x);
                }
            }
            edges.push(1.6);
            edges.dedup();
            for w in edges.windows(2) {
                v.push(rect(w[0], z0, w[1], z1));
            }
        }
        v
    }

    #[test]
    fn running_bond_draws_stay_apart_and_within_the_tolerance() {
        let traced = running_bond();
        let net = Net::new(&traced);
        assert!(net.lines.len() >= 2, "bed joints found: {}", net.lines.len());
        assert!(net.held.iter().all(|h| !h), "a running bond has no circle of joint lines");
        for r in 0..20 {
            let mut rng = rng_for(3, r, Purpose::Survey);
            let (out, report) = draw(&traced, 0.01, &mut rng);
            assert!(!report.affine, "realization {r} fell back: {report:?}");
            assert!(report.max_displacement_m <= 0.01 * (1.0 + 1e-9));
            assert!(check(&traced, &out, 0.01).is_ok());
        }
    }

    #[test]
    fn the_affine_fallback_keeps_stones_apart() {
        let traced = running_bond();
        let mut rng = rng_for(5, 0, Purpose::Survey);
        let out = affine(&traced, 0.02, &mut rng);
        assert!(check(&traced, &out, 0.02).is_ok());
        assert!(out.iter().flatten().all(|p| p[1] >= 0.0));
    }

    #[test]
    fn zero_tolerance_is_the_trace() {
        let traced = running_bond();
        let mut rng = rng_for(5, 0, Purpose::Survey);
        let (out, report) = draw(&traced, 0.0, &mut rng);
        assert_eq!(out, traced);
        assert_eq!(report.attempts, 0);
    }
}
