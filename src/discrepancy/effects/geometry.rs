//! Layout-stage effects: transformations of a checked layout's block geometry.
//!
//! Each keeps every block a convex polyhedron and never makes two blocks overlap: the
//! shear and the bed tilt are continuous maps of the whole layout (shared faces stay
//! shared), the chamfer only removes material.

use crate::geometry::{ConvexBlock, GeometryError};
use crate::layout::Layout;
use crate::Vec3;
use parry3d_f64::math::Vector as PVec;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// A failed block: its id and the reason.
pub type BlockFailure = (String, GeometryError);

/// The convex block spanned by `points` (the hull; points inside it are dropped).
fn hull(points: &[Vec3]) -> Result<ConvexBlock, GeometryError> {
    let pts: Vec<PVec> = points.iter().map(|v| PVec::new(v.x, v.y, v.z)).collect();
    let (hv, _) =
        parry3d_f64::transformation::try_convex_hull(&pts).map_err(|e| GeometryError::Hull(format!("{e:?}")))?;
    let hv: Vec<Vec3> = hv.iter().map(|p| Vec3::new(p.x, p.y, p.z)).collect();
    ConvexBlock::from_vertices(&hv)
}

/// Applies `f` to every vertex of every block and to every monitor point, and rebuilds the
/// blocks as the hulls of the moved vertices.
fn map_layout(layout: &mut Layout, f: impl Fn(&Vec3) -> Vec3) -> Result<(), BlockFailure> {
    for b in &mut layout.blocks {
        let moved: Vec<Vec3> = b.shape.vertices.iter().map(&f).collect();
        b.shape = hull(&moved).map_err(|e| (b.id.clone(), e))?;
    }
    for m in &mut layout.monitors {
        m.point = f(&m.point);
    }
    Ok(())
}

/// `initial_lean`: the wall built out of plumb by `psi` (rad) towards +y (the side it falls
/// to), course by course: every point moves by `z tan ψ` in y (a shear; the base stays on
/// the table). A rigid block of width b and height h then tips at `tan α = b/h − tan ψ`.
///
/// # Errors
/// The block that could not be rebuilt.
pub fn shear_out_of_plumb(layout: &mut Layout, psi: f64) -> Result<(), BlockFailure> {
    if psi == 0.0 {
        return Ok(());
    }
    let t = psi.tan();
    map_layout(layout, |p| Vec3::new(p.x, p.y + p.z * t, p.z))
}

/// `edge_rounding`: every block edge running along the wall (within 30° of x, the pivots
/// of out-of-plane rocking) is cut by a chamfer plane through the points `r` (m) from the
/// edge on both adjacent faces, so every such pivot moves `r` inwards. `r` is capped at
/// 40 % of the narrower adjacent face's extent across the edge. A rigid rectangular block
/// of width b and height h then tips at `tan α = (b/2 − r)/(h/2)`.
///
/// # Errors
/// The block that could not be rebuilt.
pub fn chamfer_pivot_edges(layout: &mut Layout, r: f64) -> Result<(), BlockFailure> {
    if r <= 0.0 {
        return Ok(());
    }
    for b in &mut layout.blocks {
        let planes = chamfer_planes(&b.shape, r);
        for (m, c) in planes {
            b.shape = cut(&b.shape, &m, c).map_err(|e| (b.id.clone(), e))?;
        }
    }
    Ok(())
}

/// The chamfer planes `m · x ≤ c` of a block's pivot edges (computed on the original block
/// so that the order of the cuts does not matter).
fn chamfer_planes(s: &ConvexBlock, r: f64) -> Vec<(Vec3, f64)> {
    let cos_edge = 30f64.to_radians().cos();
    let mut planes = Vec::new();
    for &(i, j) in &s.edges {
        let (a, b) = (s.vertices[i], s.vertices[j]);
        let d = (b - a).normalize();
        if d.x.abs() < cos_edge {
            continue;
        }
        let adj: Vec<usize> = (0..s.faces.len())
            .filter(|&f| s.faces[f].vertices.contains(&i) && s.faces[f].vertices.contains(&j))
            .collect();
        if adj.len() != 2 {
            continue;
        }
        let (f1, f2) = (&s.faces[adj[0]], &s.faces[adj[1]]);
        if f1.normal.dot(&f2.normal) > 20f64.to_radians().cos() {
            continue; // nearly flat: no pivot
        }
        // In-face directions perpendicular to the edge, pointing into each face, and the
        // extent of each face across the edge.
        let inward = |f: &crate::geometry::Face| {
            let mut t = f.normal.cross(&d).normalize();
            let c: Vec3 = f.vertices.iter().map(|&k| s.vertices[k]).sum::<Vec3>() / f.vertices.len() as f64;
            if t.dot(&(c - a)) < 0.0 {
                t = -t;
            }
            let extent = f.vertices.iter().map(|&k| (s.vertices[k] - a).dot(&t)).fold(0.0, f64::max);
            (t, extent)
        };
        let ((t1, e1), (t2, e2)) = (inward(f1), inward(f2));
        let rr = r.min(0.4 * e1.min(e2));
        if rr <= 0.0 {
            continue;
        }
        let (p1, p2) = (a + t1 * rr, a + t2 * rr);
        let mut m = (p2 - p1).cross(&d).normalize();
        if m.dot(&(f1.normal + f2.normal)) < 0.0 {
            m = -m;
        }
        planes.push((m, m.dot(&p1)));
    }
    planes
}

/// The part of a convex block with `m · x ≤ c`.
fn cut(s: &ConvexBlock, m: &Vec3, c: f64) -> Result<ConvexBlock, GeometryError> {
    let side: Vec<f64> = s.vertices.iter().map(|v| m.dot(v) - c).collect();
    let mut pts: Vec<Vec3> = s.vertices.iter().zip(&side).filter(|(_, &d)| d <= 0.0).map(|(v, _)| *v).collect();
    for &(i, j) in &s.edges {
        let (di, dj) = (side[i], side[j]);
        if (di < 0.0 && dj > 0.0) || (di > 0.0 && dj < 0.0) {
            let t = di / (di - dj);
            pts.push(s.vertices[i] + (s.vertices[j] - s.vertices[i]) * t);
        }
    }
    hull(&pts)
}

/// `transverse_dip`: every bed joint between two courses dips across the wall's thickness
/// by its own angle, uniform in `[−δ, δ]` (`max_dip` in rad), drawn in course order from
/// `rng`. A point on the bed joint at nominal height `Zₖ` (`course_tops_m`, the tops of the
/// courses, m) moves by `(y − y_c) tan δₖ` in z, with `y_c` the wall's centre line; a point
/// is on the bed joint nearest to it. The table and the wall's crest stay level. Bed
/// faces and vertical head joints stay plane; the shared faces of neighbours move
/// together, so no overlap is made.
///
/// # Errors
/// The block that could not be rebuilt.
pub fn tilt_beds_across(
    layout: &mut Layout,
    max_dip: f64,
    course_tops_m: &[f64],
    rng: &mut ChaCha8Rng,
) -> Result<(), BlockFailure> {
    if max_dip <= 0.0 || course_tops_m.len() < 2 {
        return Ok(());
    }
    let n = course_tops_m.len();
    // Interfaces: the table (level), the joints between courses, the crest (level).
    let mut levels = vec![(0.0, 0.0)];
    for &z in &course_tops_m[..n - 1] {
        let dip: f64 = rng.random_range(-max_dip..=max_dip);
        levels.push((z, dip.tan()));
    }
    levels.push((course_tops_m[n - 1], 0.0));
    let bounds = layout.bounds();
    let yc = 0.5 * (bounds.min.y + bounds.max.y);
    map_layout(layout, |p| {
        let (_, t) =
            levels.iter().min_by(|a, b| (a.0 - p.z).abs().total_cmp(&(b.0 - p.z).abs())).copied().unwrap_or((0.0, 0.0));
        Vec3::new(p.x, p.y, p.z + (p.y - yc) * t)
    })
}
