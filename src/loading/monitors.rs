//! Monitor points (the out-of-plane displacement of points on the wall) and measures of
//! block motion between two states, shared by the loading protocols.

use crate::dem::Simulation;
use crate::layout::Layout;
use crate::Vec3;

/// Pose of one body: centroid (m, table frame) and orientation.
pub type BodyPose = (Vec3, nalgebra::UnitQuaternion<f64>);

/// Monitor points of a simulation: name, body index, point in the body frame, reference
/// position in the table frame.
#[derive(Debug, Clone)]
pub(crate) struct MonitorPoint {
    pub(crate) name: String,
    pub(crate) body: usize,
    pub(crate) local: Vec3,
}

/// The monitor points of `layout` in `sim`: the layout's own, or else `top_left`, `top_centre`
/// and `top_right`, on the top face of the highest movable block at 5 %, 50 % and 95 % of the
/// layout's length.
pub(crate) fn monitor_points(layout: &Layout, sim: &Simulation) -> Vec<MonitorPoint> {
    if !layout.monitors.is_empty() {
        return layout
            .monitors
            .iter()
            .map(|m| MonitorPoint {
                name: m.name.clone(),
                body: m.block,
                local: sim.state.bodies[m.block].to_body(&m.point),
            })
            .collect();
    }
    let all = layout.bounds();
    let (x0, x1) = (all.min.x, all.max.x);
    let len = x1 - x0;
    let targets = [("top_left", x0 + 0.05 * len), ("top_centre", 0.5 * (x0 + x1)), ("top_right", x1 - 0.05 * len)];
    targets
        .iter()
        .filter_map(|&(name, x)| {
            let (bi, b) = layout
                .blocks
                .iter()
                .enumerate()
                .filter(|(_, b)| {
                    let bb = b.shape.aabb();
                    bb.min.x <= x && x <= bb.max.x && !b.fixed
                })
                .max_by(|(i, a), (j, b)| a.shape.aabb().max.z.total_cmp(&b.shape.aabb().max.z).then(j.cmp(i)))?;
            let bb = b.shape.aabb();
            let p = Vec3::new(x, 0.5 * (bb.min.y + bb.max.y), bb.max.z);
            Some(MonitorPoint { name: name.into(), body: bi, local: sim.state.bodies[bi].to_body(&p) })
        })
        .collect()
}

/// Out-of-plane (y) displacement of each monitor point from its `reference` position, m.
pub(crate) fn monitor_displacements(sim: &Simulation, monitors: &[MonitorPoint], reference: &[Vec3]) -> Vec<f64> {
    monitors.iter().zip(reference).map(|(m, r)| (sim.state.bodies[m.body].to_world(&m.local) - r).y).collect()
}

/// How far a body of radius `radius` (m) moved between two poses (centroid, orientation),
/// m: centroid displacement plus rotation angle times the radius (a bound on the motion of
/// its farthest point).
pub(crate) fn body_motion(from: &BodyPose, to: &BodyPose, radius: f64) -> f64 {
    (to.0 - from.0).norm() + rotation_angle(&(to.1 * from.1.inverse())) * radius
}

/// The angle of a rotation, rad, in [0, π]: `2 atan2(|v|, |w|)` for the quaternion (w, v),
/// exact to rounding near zero, where the `2 acos(w)` of `UnitQuaternion::angle` reads one
/// rounding error of w as a rotation of about 3e-8 rad.
fn rotation_angle(q: &nalgebra::UnitQuaternion<f64>) -> f64 {
    2.0 * q.imag().norm().atan2(q.scalar().abs())
}

/// The largest motion of a movable block since `start` (its position and orientation per
/// body), m: centroid displacement plus rotation angle times the block's radius. The
/// per-increment collapse criterion compares it with a fraction of the wall width.
pub fn largest_motion(sim: &Simulation, start: &[BodyPose]) -> f64 {
    sim.state
        .bodies
        .iter()
        .zip(start)
        .filter(|(b, _)| !b.fixed)
        .map(|(b, from)| body_motion(from, &(b.pos, b.rot), b.radius))
        .fold(0.0, f64::max)
}
