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
    // The hull's vertices by x: only those within `tol` in x can be within `tol` of a given
    // vertex (the window is twice that, clear of rounding), so each is looked up in
    // O(log V) rather than against every hull vertex.
    let mut by_x: Vec<&Vec3> = shape.vertices.iter().collect();
    by_x.sort_unstable_by(|a, b| a.x.total_cmp(&b.x));
    for (i, v) in given.iter().enumerate() {
        let from = by_x.partition_point(|h| h.x < v.x - 2.0 * tol);
        let near = by_x[from..].iter().take_while(|h| h.x <= v.x + 2.0 * tol);
        if !near.into_iter().any(|h| (*h - v).norm() <= tol) {
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

/// Checks a block's own mass properties against its hull ([`super::OwnMassSpec`]) and
/// returns them at unit density.
///
/// # Errors
/// [`LayoutError::Invalid`] naming `blocks[ID].own_mass.KEY`: a value that is not finite, a
/// volume not positive or larger than the hull's by more than
/// [`super::SIMPLIFIED_HULL_VOLUME_TOLERANCE`] of itself, a centroid outside the hull, an inertia
/// that is not symmetric or whose principal moments are not positive or break the triangle
/// inequality.
pub(super) fn check_own_mass(
    id: &str,
    m: &super::OwnMassSpec,
    shape: &ConvexBlock,
) -> Result<crate::geometry::MassProperties, LayoutError> {
    let key = |k: &str| format!("blocks[{id}].own_mass.{k}");
    let hull = shape.volume();
    if !(m.volume_m3.is_finite() && m.volume_m3 > 0.0) {
        return Err(super::invalid(key("volume_m3"), m.volume_m3, "must be a finite number > 0"));
    }
    if m.volume_m3 * (1.0 - super::SIMPLIFIED_HULL_VOLUME_TOLERANCE) > hull * (1.0 + 1e-9) {
        let reason = format!(
            "exceeds the volume of the block's convex hull, {hull:e} m³, by more than {} % of itself: a solid lies \
             inside its hull (up to what a simplified hull leaves out)",
            100.0 * super::SIMPLIFIED_HULL_VOLUME_TOLERANCE
        );
        return Err(super::invalid(key("volume_m3"), m.volume_m3, &reason));
    }
    let c = Vec3::from(m.centroid_m);
    let size = shape.aabb().extent().norm();
    if !c.iter().all(|x| x.is_finite()) || shape.signed_distance(&c) < -1e-9 * size {
        return Err(super::invalid(
            key("centroid_m"),
            format!("{:?}", m.centroid_m),
            "must lie inside the block's convex hull (table frame, m)",
        ));
    }
    let i = &m.inertia_m5;
    let scale = (0..3).map(|k| i[k][k].abs()).fold(0.0, f64::max);
    let inertia = format!("{i:?}");
    if !i.iter().flatten().all(|x| x.is_finite()) {
        return Err(super::invalid(key("inertia_m5"), inertia, "every entry must be a finite number"));
    }
    if (0..3).any(|r| (0..3).any(|c| (i[r][c] - i[c][r]).abs() > 1e-9 * scale)) {
        return Err(super::invalid(key("inertia_m5"), inertia, "must be symmetric"));
    }
    let mp = m.unit_density();
    let mut ev: Vec<f64> = mp.inertia.symmetric_eigenvalues().iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    if !(ev[0] > 0.0) || ev[2] > (ev[0] + ev[1]) * (1.0 + 1e-9) {
        let reason = format!(
            "principal moments {:.4e}, {:.4e}, {:.4e} m⁵: a solid's are positive and each at most the sum of the \
             other two",
            ev[0], ev[1], ev[2]
        );
        return Err(super::invalid(key("inertia_m5"), inertia, &reason));
    }
    Ok(mp)
}
