//! Narrow phase: the contact plane and contact polygon between two convex blocks (or a
//! block and the table), and its division into sub-contacts.
//!
//! # Method (3DEC style; Cundall 1988, "Formulation of a three-dimensional distinct element
//! model", Int. J. Rock Mech. 25(3))
//!
//! 1. **Contact normal** by the separating-axis test: candidate axes are the face normals of
//!    both blocks and the cross products of their edges; the axis of largest separation is
//!    the common-plane normal `n`, pointing from A to B. Face axes win ties (face–face and
//!    edge–face contacts), edge axes give edge–edge contacts.
//! 2. **Contact features**: on each side, the face best aligned with `n` (within
//!    [`PatchParams::face_angle_tolerance_rad`]) touching the support plane, else the
//!    vertices within [`PatchParams::feature_tolerance_m`] of it (an edge or a vertex).
//! 3. **Contact polygon**: both features projected onto the mid-plane and intersected
//!    (convex clipping): a polygon (face–face), a segment (edge–face, edge–edge parallel) or
//!    a point (vertex–face, edge–edge crossing).
//! 4. **Sub-contacts**: the polygon is split into a fan of triangles about its centroid,
//!    each subdivided `n × n`; every sub-triangle is a sub-contact with its own area and
//!    joint history, and its three corners are *nodes*. A segment or point contact is first
//!    widened into a thin rectangle or small square of nominal width `w`
//!    (see [`PatchParams::degenerate_width_fraction`]).
//!
//! Each node is stored as two material points, one on the surface of each block straight
//! across the mid-plane along `n`; the normal gap at the node is their separation along `n`,
//! and it varies linearly over a sub-triangle (two planar faces). See
//! [`super::law`] for how the pressure is integrated over each sub-contact.

use crate::geometry::polygon::{self, plane_basis};
use crate::geometry::sat::separation_until;
use crate::geometry::ConvexBlock;
use crate::math::Vec3;

/// What the narrow phase needs of the solver's parameters (`SolverParams::patch` makes it;
/// the narrow phase does not see the rest). Lengths in m, angles in rad.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchParams {
    /// Pairs closer than this get a contact, m.
    pub contact_margin_m: f64,
    /// Vertices within this distance of the support plane form an edge/vertex feature, m.
    pub feature_tolerance_m: f64,
    /// Faces within this angle of the contact normal form a face feature, rad.
    pub face_angle_tolerance_rad: f64,
    /// Nominal width of edge and vertex contacts, fraction of the smaller block's smallest
    /// dimension.
    pub degenerate_width_fraction: f64,
    /// Subdivisions of each fan triangle per edge, ≥ 1.
    pub subcontact_subdivisions: u32,
    /// How a contact polygon is fanned into triangles.
    pub fan: Fan,
}

/// The ranges of the contact-detection parameters that both engines take, under the same
/// keys (the penalty DEM's `SolverParams`, nscd's `NscdParams`): the margin and the feature
/// tolerance (m, > 0), the face angle tolerance (degrees, in (0, 45)) and the fraction of
/// the margin a body moves before contacts are re-detected (in (0, 1]). One rule, checked
/// with `crate::range::check_ranges` by each engine's `validate`.
pub fn detection_ranges(
    contact_margin_m: f64,
    feature_tolerance_m: f64,
    face_angle_tolerance_deg: f64,
    redetect_fraction: f64,
) -> [(&'static str, f64, bool, &'static str); 4] {
    [
        ("contact_margin_m", contact_margin_m, contact_margin_m > 0.0, "> 0"),
        ("feature_tolerance_m", feature_tolerance_m, feature_tolerance_m > 0.0, "> 0"),
        (
            "face_angle_tolerance_deg",
            face_angle_tolerance_deg,
            face_angle_tolerance_deg > 0.0 && face_angle_tolerance_deg < 45.0,
            "in (0, 45)",
        ),
        ("redetect_fraction", redetect_fraction, redetect_fraction > 0.0 && redetect_fraction <= 1.0, "in (0, 1]"),
    ]
}

/// A node of the sub-contact mesh: two surface points straight across the mid-plane, in
/// the frame of the blocks given to the narrow phase (the world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodePoint {
    /// Point on A's surface, m.
    pub on_a: Vec3,
    /// Point on B's surface, m.
    pub on_b: Vec3,
}

/// A sub-contact triangle: three node indices (counter-clockwise about the normal) and its
/// area.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    /// Node indices.
    pub nodes: [u32; 3],
    /// Area, m².
    pub area: f64,
}

/// How a contact polygon is split into triangles before subdivision.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fan {
    /// From its first vertex: n − 2 triangles (the fewest; the contact points of the
    /// non-smooth solver, which takes the polygon's corners).
    Vertex,
    /// From its first vertex as [`Fan::Vertex`], but a triangle from its centroid (three
    /// triangles): used with the penalty DEM's exact integration, which is exact on any
    /// triangulation for the normal pressure but carries one shear spring per sub-contact,
    /// at its centroid; a single one resists no twist about the joint's normal.
    Shear,
    /// From its centroid: n triangles, symmetric node areas (used with the 3DEC vertex
    /// quadrature, whose lumped areas would otherwise depend on the diagonal chosen).
    Centroid,
}

/// Kind of contact by the dimension of the features' overlap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PatchKind {
    /// Polygon with area (face–face).
    Face,
    /// Segment (edge–face or parallel edges), widened to a thin rectangle.
    Edge,
    /// Point (vertex–face or crossing edges), widened to a small square.
    Vertex,
}

/// A contact patch: the common plane and its sub-contact mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// Unit normal A → B.
    pub normal: Vec3,
    /// Gap between the support planes, m (negative: overlap).
    pub gap: f64,
    /// Polygon kind.
    pub kind: PatchKind,
    /// Total area of the sub-contacts, m² (the nominal area for edges and vertices).
    pub area: f64,
    /// Nodes.
    pub nodes: Vec<NodePoint>,
    /// Sub-contact triangles.
    pub triangles: Vec<Triangle>,
}

/// The feature of `blk` on its support plane `n·x = h` (see the module doc, step 2): its
/// vertices, and the index of its face when the feature is a face.
fn support_plane_feature(
    blk: &ConvexBlock,
    n: &Vec3,
    h: f64,
    s: &PatchParams,
    outward_sign: f64,
) -> (Vec<Vec3>, Option<usize>) {
    // outward_sign = +1: A's side (support max along n); -1: B's side (support min along n).
    let cos_tol = s.face_angle_tolerance_rad.cos();
    let mut best: Option<(f64, usize)> = None;
    for (k, f) in blk.faces.iter().enumerate() {
        let al = outward_sign * f.normal.dot(n);
        if al < cos_tol {
            continue;
        }
        let touches =
            f.vertices.iter().any(|&i| (outward_sign * (h - n.dot(&blk.vertices[i]))).abs() <= s.feature_tolerance_m);
        if touches && best.is_none_or(|(b, _)| al > b) {
            best = Some((al, k));
        }
    }
    if let Some((_, k)) = best {
        return (blk.faces[k].vertices.iter().map(|&i| blk.vertices[i]).collect(), Some(k));
    }
    let vertices = blk
        .vertices
        .iter()
        .filter(|v| (outward_sign * (h - n.dot(v))).abs() <= s.feature_tolerance_m)
        .copied()
        .collect();
    (vertices, None)
}

fn min_edge(blk: &ConvexBlock) -> f64 {
    let e = blk.aabb().extent();
    e.x.min(e.y).min(e.z)
}

/// Ray from `x` along `n`: the parameter where it crosses the plane of the feature's face
/// `face` (a face feature), or else where it leaves the block through the faces facing `n`
/// (sign +1) or enters through the faces facing `−n` (sign −1).
///
/// A node of a face–face patch lies on the boundary of a feature's face wherever the patch
/// polygon's corner is one of the face's own (up to rounding, and by a nanometre where the
/// block leans on the ray). A side face almost parallel to the ray would then bound the
/// ray at `ε / (n·normal)` for an offset ε of the node outside it: up to the feature
/// tolerance away from the face, a normal gap of that size where the joint is closed. The
/// node's surface point is the face's plane, as for the nodes inside it.
fn surface_param(blk: &ConvexBlock, face: Option<usize>, x: &Vec3, n: &Vec3, sign: f64) -> f64 {
    if let Some(k) = face {
        let f = &blk.faces[k];
        return (f.offset - f.normal.dot(x)) / f.normal.dot(n);
    }
    ray_param(blk, x, n, sign)
}

/// Ray from `x` along `n`: the parameter where it leaves the block through the faces facing
/// `n` (sign +1) or enters through the faces facing `−n` (sign −1).
fn ray_param(blk: &ConvexBlock, x: &Vec3, n: &Vec3, sign: f64) -> f64 {
    let mut t = if sign > 0.0 { f64::INFINITY } else { f64::NEG_INFINITY };
    for f in &blk.faces {
        let dn = f.normal.dot(n);
        if sign * dn > 1e-9 {
            let s = (f.offset - f.normal.dot(x)) / dn;
            t = if sign > 0.0 { t.min(s) } else { t.max(s) };
        }
    }
    t
}

/// The contact patch between blocks A and B, or `None` if they are farther apart than the
/// margin or their features do not overlap in projection.
pub fn block_block(a: &ConvexBlock, b: &ConvexBlock, s: &PatchParams) -> Option<Patch> {
    let sep = separation_until(a, b, s.contact_margin_m);
    if sep.distance > s.contact_margin_m {
        return None;
    }
    let n = sep.normal;
    let h_a = a.vertices.iter().map(|v| n.dot(v)).fold(f64::NEG_INFINITY, f64::max);
    let h_b = b.vertices.iter().map(|v| n.dot(v)).fold(f64::INFINITY, f64::min);
    let (fa, face_a) = support_plane_feature(a, &n, h_a, s, 1.0);
    let (fb, face_b) = support_plane_feature(b, &n, h_b, s, -1.0);
    let width = s.degenerate_width_fraction * min_edge(a).min(min_edge(b));
    // The surface point of a feature lies between the feature's extremes along n.
    let lo_a = fa.iter().map(|v| n.dot(v)).fold(f64::INFINITY, f64::min) - s.feature_tolerance_m;
    let hi_b = fb.iter().map(|v| n.dot(v)).fold(f64::NEG_INFINITY, f64::max) + s.feature_tolerance_m;
    let surfaces = |x: &Vec3| {
        let ta = surface_param(a, face_a, x, &n, 1.0).clamp(lo_a - n.dot(x), h_a - n.dot(x));
        let tb = surface_param(b, face_b, x, &n, -1.0).clamp(h_b - n.dot(x), hi_b - n.dot(x));
        (x + n * ta, x + n * tb)
    };
    build_patch(&fa, &fb, &n, 0.5 * (h_a + h_b), h_b - h_a, width, s, surfaces)
}

/// The contact patch between the table (the half-space z ≤ 0, body A) and block B.
pub fn table_block(b: &ConvexBlock, s: &PatchParams) -> Option<Patch> {
    let n = Vec3::z();
    let h_b = b.vertices.iter().map(|v| v.z).fold(f64::INFINITY, f64::min);
    if h_b > s.contact_margin_m {
        return None;
    }
    let (fb, face_b) = support_plane_feature(b, &n, h_b, s, -1.0);
    let width = s.degenerate_width_fraction * min_edge(b);
    let hi_b = fb.iter().map(|v| v.z).fold(f64::NEG_INFINITY, f64::max) + s.feature_tolerance_m;
    let surfaces = |x: &Vec3| {
        let tb = surface_param(b, face_b, x, &n, -1.0).clamp(h_b - x.z, hi_b - x.z);
        (Vec3::new(x.x, x.y, 0.0), x + n * tb)
    };
    // The table's feature: B's feature projected (the table is unbounded).
    build_patch(&fb, &fb, &n, 0.5 * h_b, h_b, width, s, surfaces)
}

#[allow(clippy::too_many_arguments)]
fn build_patch(
    fa: &[Vec3],
    fb: &[Vec3],
    n: &Vec3,
    plane_offset: f64,
    gap: f64,
    width: f64,
    s: &PatchParams,
    surfaces: impl Fn(&Vec3) -> (Vec3, Vec3),
) -> Option<Patch> {
    let (u, w) = plane_basis(n);
    let proj = |pts: &[Vec3]| -> Vec<[f64; 2]> { pts.iter().map(|p| [p.dot(&u), p.dot(&w)]).collect() };
    let tol2d = 1e-9;
    let ha = polygon::hull2d(&proj(fa), tol2d);
    let hb = polygon::hull2d(&proj(fb), tol2d);
    let poly = polygon::intersect_convex(&ha, &hb, 1e-12);
    if poly.is_empty() {
        return None;
    }
    let to_world = |q: [f64; 2]| u * q[0] + w * q[1] + n * plane_offset;
    let area = polygon::area(&poly);
    let m = s.subcontact_subdivisions.max(1) as usize;
    let (kind, shape) = if poly.len() >= 3 && area > width * width * 1e-3 {
        (PatchKind::Face, poly)
    } else if poly.len() >= 2 {
        // Longest extent of the degenerate polygon, widened into a thin rectangle.
        let (mut i0, mut i1, mut best) = (0, 1, -1.0);
        for i in 0..poly.len() {
            for j in i + 1..poly.len() {
                let d = (poly[i][0] - poly[j][0]).powi(2) + (poly[i][1] - poly[j][1]).powi(2);
                if d > best {
                    best = d;
                    i0 = i;
                    i1 = j;
                }
            }
        }
        let (p, q) = (poly[i0], poly[i1]);
        let len = best.sqrt();
        let h = 0.5 * width / len;
        let perp = [-(q[1] - p[1]) * h, (q[0] - p[0]) * h];
        let rect = vec![
            [p[0] - perp[0], p[1] - perp[1]],
            [q[0] - perp[0], q[1] - perp[1]],
            [q[0] + perp[0], q[1] + perp[1]],
            [p[0] + perp[0], p[1] + perp[1]],
        ];
        (PatchKind::Edge, rect)
    } else {
        let (c, h) = (poly[0], 0.5 * width);
        (
            PatchKind::Vertex,
            vec![[c[0] - h, c[1] - h], [c[0] + h, c[1] - h], [c[0] + h, c[1] + h], [c[0] - h, c[1] + h]],
        )
    };
    let (pts, triangles) = subdivide_polygon(&shape, m, s.fan);
    let nodes: Vec<NodePoint> = pts
        .into_iter()
        .map(|q| {
            let x = to_world(q);
            let (on_a, on_b) = surfaces(&x);
            NodePoint { on_a, on_b }
        })
        .collect();
    let total = triangles.iter().map(|t| t.area).sum();
    Some(Patch { normal: *n, gap, kind, area: total, nodes, triangles })
}

/// A fan of a convex polygon (see [`Fan`]) with each triangle subdivided `m × m`: nodes
/// (deduplicated) and counter-clockwise sub-triangles.
pub fn subdivide_polygon(poly: &[[f64; 2]], m: usize, fan: Fan) -> (Vec<[f64; 2]>, Vec<Triangle>) {
    let fan = match fan {
        Fan::Shear if poly.len() == 3 => Fan::Centroid,
        Fan::Shear => Fan::Vertex,
        f => f,
    };
    let c = match fan {
        Fan::Centroid => polygon::centroid(poly),
        Fan::Vertex | Fan::Shear => poly[0],
    };
    let mut nodes: Vec<[f64; 2]> = Vec::new();
    let mut tris = Vec::new();
    let scale = poly.iter().fold(0.0f64, |s, p| s.max((p[0] - c[0]).abs()).max((p[1] - c[1]).abs()));
    let eps = 1e-12 * scale.max(1e-9);
    let index = |p: [f64; 2], nodes: &mut Vec<[f64; 2]>| -> u32 {
        if let Some(k) = nodes.iter().position(|q| (q[0] - p[0]).abs() <= eps && (q[1] - p[1]).abs() <= eps) {
            k as u32
        } else {
            nodes.push(p);
            (nodes.len() - 1) as u32
        }
    };
    let nv = poly.len();
    let mf = m as f64;
    let fans: Vec<usize> = match fan {
        Fan::Centroid => (0..nv).collect(),
        Fan::Vertex | Fan::Shear => (1..nv.saturating_sub(1)).collect(),
    };
    for k in fans {
        let p = poly[k];
        let q = poly[(k + 1) % nv];
        let e1 = [p[0] - c[0], p[1] - c[1]];
        let e2 = [q[0] - c[0], q[1] - c[1]];
        let node = |i: usize, j: usize| {
            let (a, b) = (i as f64 / mf, j as f64 / mf);
            [c[0] + a * e1[0] + b * e2[0], c[1] + a * e1[1] + b * e2[1]]
        };
        let tri_area = 0.5 * (e1[0] * e2[1] - e1[1] * e2[0]) / (mf * mf);
        if tri_area <= 0.0 {
            continue;
        }
        for i in 0..m {
            for j in 0..m - i {
                let up = [node(i, j), node(i + 1, j), node(i, j + 1)];
                let ids = up.map(|v| index(v, &mut nodes));
                tris.push(Triangle { nodes: ids, area: tri_area });
                if i + j + 1 < m {
                    let down = [node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)];
                    let ids = down.map(|v| index(v, &mut nodes));
                    tris.push(Triangle { nodes: ids, area: tri_area });
                }
            }
        }
    }
    (nodes, tris)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::sat::separation;

    fn cube(min: Vec3, size: Vec3) -> ConvexBlock {
        ConvexBlock::cuboid(min, min + size).unwrap()
    }

    #[test]
    fn stacked_boxes_share_the_overlap_rectangle() {
        let a = cube(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.2, 0.1, 0.05));
        let b = cube(Vec3::new(0.05, 0.0, 0.05), Vec3::new(0.2, 0.1, 0.05));
        let s = crate::dem::params::SolverParams::default().patch();
        let p = block_block(&a, &b, &s).unwrap();
        assert_eq!(p.kind, PatchKind::Face);
        assert!((p.normal - Vec3::z()).norm() < 1e-12);
        assert!(p.gap.abs() < 1e-12);
        assert!((p.area - 0.15 * 0.1).abs() < 1e-12, "{p:?}");
        for q in &p.nodes {
            assert!((q.on_a.z - 0.05).abs() < 1e-12 && (q.on_b.z - 0.05).abs() < 1e-12);
        }
    }

    #[test]
    fn subdivision_tiles_the_polygon() {
        let poly = vec![[0.0, 0.0], [0.3, 0.0], [0.3, 0.1], [0.0, 0.1]];
        for (fan, per) in [(Fan::Centroid, 4), (Fan::Vertex, 2)] {
            for m in 1..6 {
                let (nodes, tris) = subdivide_polygon(&poly, m, fan);
                assert_eq!(tris.len(), per * m * m);
                let a: f64 = tris.iter().map(|t| t.area).sum();
                assert!((a - 0.03).abs() < 1e-14);
                // Each triangle's stored area equals its geometric area, counter-clockwise.
                for t in &tris {
                    let [p, q, r] = t.nodes.map(|i| nodes[i as usize]);
                    let ga = 0.5 * ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
                    assert!((ga - t.area).abs() < 1e-15);
                }
                // Euler: V − E + F = 1 for a triangulated disc; with E = (3F + boundary)/2.
                let boundary = 4 * m;
                let e = (3 * tris.len() + boundary) / 2;
                assert_eq!(nodes.len() + tris.len(), e + 1);
            }
        }
    }

    /// A triangular joint is never a single sub-contact under the penalty DEM's fan: its
    /// three fan triangles from the centroid put a shear spring on each side of every
    /// axis through the centroid, so the joint resists twist; a quadrilateral keeps the
    /// vertex fan. The non-smooth solver's fan keeps the corners alone.
    #[test]
    fn a_triangle_gets_three_shear_points_under_the_penalty_fan() {
        let tri = vec![[0.0, 0.0], [0.3, 0.0], [0.1, 0.2]];
        let (_, shear) = subdivide_polygon(&tri, 1, Fan::Shear);
        assert_eq!(shear.len(), 3);
        let (nodes, plain) = subdivide_polygon(&tri, 1, Fan::Vertex);
        assert_eq!((plain.len(), nodes.len()), (1, 3));
        let quad = vec![[0.0, 0.0], [0.3, 0.0], [0.3, 0.1], [0.0, 0.1]];
        assert_eq!(subdivide_polygon(&quad, 1, Fan::Shear), subdivide_polygon(&quad, 1, Fan::Vertex));
        let a: f64 = shear.iter().map(|t| t.area).sum();
        assert!((a - 0.03).abs() < 1e-15);
    }

    #[test]
    fn tipped_block_on_table_is_a_face_contact_with_graded_gaps() {
        let b = cube(Vec3::new(0.0, -0.05, 0.0), Vec3::new(0.3, 0.1, 0.3));
        let r = nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), -0.01);
        let toe = Vec3::new(0.0, 0.05, 0.0);
        let bt = b.transformed(|v| toe + r * (v - toe), r.matrix());
        let p = table_block(&bt, &crate::dem::params::SolverParams::default().patch()).unwrap();
        assert_eq!(p.kind, PatchKind::Face);
        let gaps: Vec<f64> = p.nodes.iter().map(|q| q.on_b.z - q.on_a.z).collect();
        let max = gaps.iter().cloned().fold(0.0, f64::max);
        assert!((max - 0.1 * 0.01f64.sin()).abs() < 1e-6, "{max}");
        assert!(gaps.iter().all(|g| *g > -1e-12));
    }

    /// Two stacked blocks pressed 50 µm into each other and leaning by tens of µrad, the
    /// upper shifted along the bed so that the patch's corners are its own: every node's
    /// normal gap is the distance between the two bed faces' planes along the normal (the
    /// faces are planar), and the joint is closed at every node. A side face almost
    /// parallel to the normal must not set a node's surface point.
    #[test]
    fn leaning_stacked_blocks_give_every_node_the_gap_between_the_bed_planes() {
        let s = crate::dem::params::SolverParams::default().patch();
        let mut worst: f64 = 0.0;
        for (k, (ta, tb)) in [(6e-5, 2e-5), (-4e-5, 9e-5), (1.1e-4, 0.0), (3e-5, -7e-5)].into_iter().enumerate() {
            for shift in [0.1, 0.0489, 0.1 + 1e-7 * k as f64] {
                let ra = nalgebra::Rotation3::from_axis_angle(&Vec3::y_axis(), ta);
                let rb = nalgebra::Rotation3::from_axis_angle(&Vec3::y_axis(), tb);
                let a0 = cube(Vec3::new(0.8, -0.1, 0.0), Vec3::new(0.2, 0.2, 0.15));
                let b0 = cube(Vec3::new(0.8 + shift, -0.1, 0.15 - 5e-5), Vec3::new(0.2, 0.2, 0.15));
                let ca = Vec3::new(0.9, 0.0, 0.075);
                let cb = Vec3::new(0.9 + shift, 0.0, 0.225);
                let a = a0.transformed(|v| ca + ra * (v - ca), ra.matrix());
                let b = b0.transformed(|v| cb + rb * (v - cb), rb.matrix());
                let p = block_block(&a, &b, &s).unwrap();
                assert_eq!(p.kind, PatchKind::Face);
                // The bed planes: A's top (normal ra z through ra's image of a top point), B's
                // bottom (normal −rb z).
                let (na, da) = (ra * Vec3::z(), (ra * Vec3::z()).dot(&(ca + ra * (Vec3::new(0.9, 0.0, 0.15) - ca))));
                let (nb, db) = (
                    rb * Vec3::z(),
                    (rb * Vec3::z()).dot(&(cb + rb * (Vec3::new(0.9 + shift, 0.0, 0.15 - 5e-5) - cb))),
                );
                let n = p.normal;
                for q in &p.nodes {
                    let x = 0.5 * (q.on_a + q.on_b);
                    let gap = (q.on_b - q.on_a).dot(&n);
                    let expected = (db - nb.dot(&x)) / nb.dot(&n) - (da - na.dot(&x)) / na.dot(&n);
                    assert!(gap < 0.0, "tilts {ta} {tb}, shift {shift}: an open node {gap} in a closed joint");
                    worst = worst.max((gap - expected).abs());
                }
            }
        }
        assert!(worst < 1e-12, "{worst}");
    }

    #[test]
    fn separated_and_overlapping_pairs() {
        let a = cube(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0));
        let b = cube(Vec3::new(1.5, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0));
        let s = separation(&a, &b);
        assert!((s.distance - 0.5).abs() < 1e-12);
        assert!((s.normal - Vec3::x()).norm() < 1e-12);
        let c = cube(Vec3::new(0.9, 0.2, 0.2), Vec3::new(1.0, 0.5, 0.5));
        assert!((separation(&a, &c).distance + 0.1).abs() < 1e-12);
    }
}
