//! The geometric checks of a layout: convex blocks, no overlaps.

use super::{Block, LayoutError, OVERLAP_TOLERANCE_M};
use crate::geometry::ConvexBlock;
use crate::math::Vec3;

/// Refuses a block whose given vertices are not all vertices of their convex hull (a vertex
/// strictly inside the hull or on one of its faces or edges: a non-convex block, which the
/// hull would silently replace), duplicates within 1e-9 of the block's size aside.
pub(super) fn check_convex(id: &str, given: &[Vec3], shape: &ConvexBlock) -> Result<(), LayoutError> {
    let size = shape.aabb().extent().norm();
    let tol = 1e-9 * size;
    for (i, v) in given.iter().enumerate() {
        if !shape.vertices.iter().any(|h| (h - v).norm() <= tol) {
            return Err(LayoutError::NotConvex { id: id.to_owned(), index: i, vertex: [v.x, v.y, v.z] });
        }
    }
    Ok(())
}

/// Rejects blocks below the table or interpenetrating each other beyond the tolerance.
/// Uses the DEM's own narrow phase (separating-axis test) after a bounding-box sweep.
pub(super) fn check_overlaps(blocks: &[Block]) -> Result<(), LayoutError> {
    for b in blocks {
        let zmin = b.shape.vertices.iter().map(|v| v.z).fold(f64::INFINITY, f64::min);
        if zmin < -OVERLAP_TOLERANCE_M {
            return Err(LayoutError::Overlap { a: b.id.clone(), b: "table".into(), depth_m: -zmin });
        }
    }
    let boxes: Vec<_> = blocks.iter().map(|b| b.shape.aabb()).collect();
    for (i, j) in crate::geometry::sweep::sweep_pairs(&boxes, 0.0) {
        let sep = crate::geometry::sat::separation(&blocks[i].shape, &blocks[j].shape);
        if sep.distance < -OVERLAP_TOLERANCE_M {
            return Err(LayoutError::Overlap {
                a: blocks[i].id.clone(),
                b: blocks[j].id.clone(),
                depth_m: -sep.distance,
            });
        }
    }
    Ok(())
}
