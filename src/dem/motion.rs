//! Measures of body motion between two states: the pose of a body, how far a body moved,
//! the largest motion of any movable body. The static solvers' collapse and probe
//! distances and the protocols' collapse criteria are all measured with these.

use crate::dem::Simulation;
use crate::math::Vec3;

/// Pose of one body: centroid (m, table frame) and orientation.
pub type BodyPose = (Vec3, nalgebra::UnitQuaternion<f64>);

/// The pose of every body of `sim`, in body order.
pub fn poses(sim: &Simulation) -> Vec<BodyPose> {
    sim.state.bodies.iter().map(|b| (b.pos, b.rot)).collect()
}

/// How far a body of radius `radius` (m) moved between two poses (centroid, orientation),
/// m: centroid displacement plus rotation angle times the radius (a bound on the motion of
/// its farthest point).
pub fn body_motion(from: &BodyPose, to: &BodyPose, radius: f64) -> f64 {
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
        .filter(|(b, _)| !b.fixed())
        .map(|(b, from)| body_motion(from, &(b.pos, b.rot), b.radius))
        .fold(0.0, f64::max)
}
