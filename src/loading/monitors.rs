//! Monitor points (the out-of-plane displacement of points on the wall) and measures of
//! block motion between two states, shared by the loading protocols.

use crate::dem::Simulation;
use crate::layout::Layout;
use crate::math::Vec3;

pub use crate::dem::motion::{body_motion, largest_motion, BodyPose};

/// The default monitor points of a wall without monitors of its own: points on the top
/// face of the highest movable block at 5 %, 50 % and 95 % of the layout's length (x),
/// where the paper's tilting-table walls carried their displacement transducers (§2.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TopMonitor {
    /// At 5 % of the length from the left end (x min).
    TopLeft,
    /// At mid-length.
    TopCentre,
    /// At 5 % of the length from the right end (x max).
    TopRight,
}

impl TopMonitor {
    /// The three default monitors, left to right.
    pub const ALL: [TopMonitor; 3] = [TopMonitor::TopLeft, TopMonitor::TopCentre, TopMonitor::TopRight];

    /// The name in results, tables and layout files (`top_left`, `top_centre`, `top_right`).
    pub fn name(self) -> &'static str {
        match self {
            TopMonitor::TopLeft => "top_left",
            TopMonitor::TopCentre => "top_centre",
            TopMonitor::TopRight => "top_right",
        }
    }

    /// The monitor of a name, if it is one of the defaults.
    pub fn from_name(name: &str) -> Option<TopMonitor> {
        TopMonitor::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Where along the length it sits, as a fraction of the length from the left end.
    pub fn length_fraction(self) -> f64 {
        match self {
            TopMonitor::TopLeft => 0.05,
            TopMonitor::TopCentre => 0.5,
            TopMonitor::TopRight => 0.95,
        }
    }

    /// The position of this monitor in a result's list of monitor names, if present.
    pub fn index_in<S: AsRef<str>>(self, names: &[S]) -> Option<usize> {
        names.iter().position(|n| n.as_ref() == self.name())
    }
}

/// TopMonitor points of a simulation: name, body index, point in the body frame, reference
/// position in the table frame.
#[derive(Debug, Clone)]
pub(crate) struct MonitorPoint {
    pub(crate) name: String,
    pub(crate) body: usize,
    pub(crate) local: Vec3,
}

/// The monitor points of `layout` in `sim`: the layout's own, or else the default
/// [`TopMonitor`]s.
pub(crate) fn monitor_points(layout: &Layout, sim: &Simulation) -> Vec<MonitorPoint> {
    monitor_points_of(layout, &sim.state.bodies)
}

/// [`monitor_points`] for the bodies of any solver (the layout's blocks, in layout order).
pub(crate) fn monitor_points_of(layout: &Layout, bodies: &[crate::dem::state::Body]) -> Vec<MonitorPoint> {
    if !layout.monitors.is_empty() {
        return layout
            .monitors
            .iter()
            .map(|m| MonitorPoint { name: m.name.clone(), body: m.block, local: bodies[m.block].to_body(&m.point) })
            .collect();
    }
    let all = layout.bounds();
    let (x0, x1) = (all.min.x, all.max.x);
    let len = x1 - x0;
    // Written out per monitor (not x0 + f·len for all three) so the points are the same
    // bits as they have always been.
    let at = |m: TopMonitor| match m {
        TopMonitor::TopLeft => x0 + 0.05 * len,
        TopMonitor::TopCentre => 0.5 * (x0 + x1),
        TopMonitor::TopRight => x1 - 0.05 * len,
    };
    TopMonitor::ALL
        .iter()
        .map(|&m| (m.name(), at(m)))
        .filter_map(|(name, x)| {
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
            Some(MonitorPoint { name: name.into(), body: bi, local: bodies[bi].to_body(&p) })
        })
        .collect()
}

/// Out-of-plane (y) displacement of each monitor point from its `reference` position, m.
pub(crate) fn monitor_displacements(sim: &Simulation, monitors: &[MonitorPoint], reference: &[Vec3]) -> Vec<f64> {
    monitors.iter().zip(reference).map(|(m, r)| (sim.state.bodies[m.body].to_world(&m.local) - r).y).collect()
}
