//! The separating-axis test between two convex blocks (Gottschalk, Lin & Manocha 1996;
//! Ericson, *Real-Time Collision Detection*, §4.4): candidate axes are the face normals of
//! both blocks and the cross products of their edges; the axis of largest separation gives
//! the common-plane normal from A to B. Face axes win ties; edge axes must beat the faces
//! clearly.

use super::ConvexBlock;
use crate::Vec3;

/// Which axis separated the blocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// Face `k` of A.
    FaceA(usize),
    /// Face `k` of B.
    FaceB(usize),
    /// Edge `i` of A × edge `j` of B.
    Edges(usize, usize),
}

/// Result of the separating-axis test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Separation {
    /// Separation along the best axis, m: positive apart, negative interpenetration depth.
    pub distance: f64,
    /// Unit normal from A to B.
    pub normal: Vec3,
    /// The axis.
    pub axis: Axis,
}

/// The smallest and largest of `n · v` over the vertices of a block. (Plain comparisons:
/// the vertices are finite, and which zero is returned on a ±0 tie changes no comparison
/// made with the result.)
#[inline]
fn min_max_along(blk: &ConvexBlock, n: &Vec3) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in &blk.vertices {
        let x = n.dot(v);
        if x < lo {
            lo = x;
        }
        if x > hi {
            hi = x;
        }
    }
    (lo, hi)
}

/// The smallest of `n · v` over the vertices of a block (see [`min_max_along`]).
#[inline]
fn min_along(blk: &ConvexBlock, n: &Vec3) -> f64 {
    let mut lo = f64::INFINITY;
    for v in &blk.vertices {
        let x = n.dot(v);
        if x < lo {
            lo = x;
        }
    }
    lo
}

/// Separating-axis test between two convex blocks in the same frame.
pub fn separation(a: &ConvexBlock, b: &ConvexBlock) -> Separation {
    let size = a.aabb().extent().norm().max(b.aabb().extent().norm());
    let tie = 1e-9 * size;
    let mut best = Separation { distance: f64::NEG_INFINITY, normal: Vec3::z(), axis: Axis::FaceA(0) };
    for (k, f) in a.faces.iter().enumerate() {
        let d = min_along(b, &f.normal) - f.offset;
        if d > best.distance + tie {
            best = Separation { distance: d, normal: f.normal, axis: Axis::FaceA(k) };
        }
    }
    for (k, f) in b.faces.iter().enumerate() {
        let d = min_along(a, &f.normal) - f.offset;
        if d > best.distance + tie {
            best = Separation { distance: d, normal: -f.normal, axis: Axis::FaceB(k) };
        }
    }
    let face_best = best.distance;
    let b_edges: Vec<(Vec3, f64)> = b
        .edges
        .iter()
        .map(|&(b0, b1)| {
            let eb = b.vertices[b1] - b.vertices[b0];
            (eb, eb.norm())
        })
        .collect();
    for (i, &(a0, a1)) in a.edges.iter().enumerate() {
        let ea = a.vertices[a1] - a.vertices[a0];
        let ea_norm = ea.norm();
        for (j, &(eb, eb_norm)) in b_edges.iter().enumerate() {
            let c = ea.cross(&eb);
            let cn = c.norm();
            if cn <= 1e-6 * ea_norm * eb_norm {
                continue;
            }
            let mut n = c / cn;
            // One pass per block for both orientations: (−n)·v is exactly −(n·v), so the
            // extremes along −n are the negated extremes along n.
            let (amin, amax) = min_max_along(a, &n);
            let (bmin, bmax) = min_max_along(b, &n);
            let mut d = bmin - amax;
            let d2 = -bmax - -amin;
            if d2 > d {
                d = d2;
                n = -n;
            }
            // Edge axes must beat the faces clearly (Box2D/Bullet practice).
            if d > face_best + 1e-6 * size && d > best.distance {
                best = Separation { distance: d, normal: n, axis: Axis::Edges(i, j) };
            }
        }
    }
    best
}
