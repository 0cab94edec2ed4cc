//! The collapse mechanism read from the motion between the last stable and the collapsed
//! state of a test: the failing joints, the groups of blocks they cut loose, and whether
//! each joint slid or opened.

use super::monitors::body_motion;
use crate::dem::Simulation;
use serde::{Deserialize, Serialize};

/// Failure mode of a joint or of the wall.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MechanismKind {
    /// Relative sliding along the failing joints.
    Sliding,
    /// Rotation about an edge, the failing joints opening.
    Toppling,
    /// Some failing joints slide, others open.
    Mixed,
    /// No collapse.
    None,
}

/// The collapse mechanism.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mechanism {
    /// Overall kind.
    pub kind: MechanismKind,
    /// The governing joint: the lowest failing joint, named `table/ID` or `ID_A/ID_B`.
    pub joint: String,
    /// Every joint between a moving and a resting body, with its kind, lowest first.
    pub joints: Vec<(String, MechanismKind)>,
    /// Ids of the blocks that moved.
    pub blocks: Vec<String>,
}

/// Share of the largest motion above which a joint counts as failing (its relative motion)
/// or a group of blocks as moving (its largest body motion) in [`mechanism`].
pub const MECHANISM_SHARE: f64 = 0.25;

/// The collapse mechanism from the motion between a stable and a failed state of the same
/// simulation.
///
/// Read from the joints, not from the blocks one by one (a block at the foot of a toppling
/// stack rotates with it but moves less than a third as far as the top):
/// 1. every joint that carries force in the stable state gets its relative motion, the
///    largest over its nodes of the change of the B − A node separation (m);
/// 2. a joint *fails* if that motion exceeds [`MECHANISM_SHARE`] of the largest one;
/// 3. the blocks joined by intact joints form rigid groups; a group *rests* if it holds a
///    fixed body or is held by the table through an intact joint, or if no block of it
///    moved (centroid motion plus rotation times radius) more than [`MECHANISM_SHARE`] of
///    the largest block motion (e.g. an end-restrained group); the others *move*; nothing
///    moves if no block moved more than 1e-9 of the largest block radius (rounding);
/// 4. the mechanism's joints are those between a moving and a resting group, each sliding
///    if its largest tangential relative motion exceeds its largest opening, else toppling;
///    the governing joint is the lowest (mean node height in the stable state).
pub fn mechanism(stable: &Simulation, failed: &Simulation) -> Mechanism {
    let nb = stable.state.bodies.len();
    let moved: Vec<f64> = stable
        .state
        .bodies
        .iter()
        .zip(&failed.state.bodies)
        .map(|(s, f)| body_motion(&(s.pos, s.rot), &(f.pos, f.rot), s.radius))
        .collect();
    // Motion below a nanometre per metre of block size is rounding, not a mechanism.
    let max_radius = stable.state.bodies.iter().map(|b| b.radius).fold(0.0, f64::max);
    let max_moved = moved.iter().cloned().fold(0.0, f64::max);
    let max_moved = if max_moved > 1e-9 * max_radius { max_moved } else { 0.0 };
    // Relative motion, largest opening and slip, and mean node height of every
    // load-carrying joint.
    struct JointMotion {
        contact: usize,
        relative: f64,
        open: f64,
        slip: f64,
        z: f64,
    }
    let mut motions = Vec::new();
    for (ci, c) in stable.state.contacts.iter().enumerate() {
        if c.force.norm() == 0.0 {
            continue; // not a load-carrying joint in the stable state
        }
        let (mut relative, mut open, mut slip, mut z) = (0.0f64, 0.0f64, 0.0f64, 0.0);
        let n = failed.state.contact_normal(c);
        for nd in &c.nodes {
            let (a0, b0) = stable.state.node_points(c, nd);
            let (a1, b1) = failed.state.node_points(c, nd);
            let dd = (b1 - a1) - (b0 - a0);
            let dn = dd.dot(&n);
            relative = relative.max(dd.norm());
            open = open.max(dn);
            slip = slip.max((dd - n * dn).norm());
            z += 0.5 * (a0.z + b0.z) / c.nodes.len() as f64;
        }
        motions.push(JointMotion { contact: ci, relative, open, slip, z });
    }
    let max_relative = motions.iter().map(|m| m.relative).fold(0.0, f64::max);
    // Rigid groups: union-find over the bodies and the ground (index nb) through intact joints.
    let mut parent: Vec<usize> = (0..=nb).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    fn join(parent: &mut [usize], i: usize, j: usize) {
        let (ri, rj) = (root(parent, i), root(parent, j));
        if ri != rj {
            parent[ri.max(rj)] = ri.min(rj);
        }
    }
    for (k, b) in stable.state.bodies.iter().enumerate() {
        if b.fixed {
            join(&mut parent, k, nb);
        }
    }
    for m in &motions {
        if m.relative <= MECHANISM_SHARE * max_relative {
            let c = &stable.state.contacts[m.contact];
            join(&mut parent, c.a.unwrap_or(nb), c.b);
        }
    }
    let mut group_motion = vec![0.0f64; nb + 1];
    for (k, &d) in moved.iter().enumerate() {
        let r = root(&mut parent, k);
        group_motion[r] = group_motion[r].max(d);
    }
    let ground = root(&mut parent, nb);
    let moving: Vec<bool> = (0..nb)
        .map(|k| {
            let r = root(&mut parent, k);
            let cut_off = r != ground && group_motion[r] > MECHANISM_SHARE * max_moved;
            max_moved > 0.0 && (cut_off || moved[k] > MECHANISM_SHARE * max_moved)
        })
        .collect();
    let is_moving = |i: Option<usize>| i.is_some_and(|i| moving[i]);
    let mut joints: Vec<(f64, String, MechanismKind)> = motions
        .iter()
        .filter(|m| {
            let c = &stable.state.contacts[m.contact];
            is_moving(c.a) != is_moving(Some(c.b))
        })
        .map(|m| {
            let kind = if m.slip > m.open { MechanismKind::Sliding } else { MechanismKind::Toppling };
            (m.z, stable.state.joint_name(&stable.state.contacts[m.contact]), kind)
        })
        .collect();
    joints.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let kind = if joints.is_empty() {
        MechanismKind::None
    } else if joints.iter().all(|j| j.2 == MechanismKind::Sliding) {
        MechanismKind::Sliding
    } else if joints.iter().all(|j| j.2 == MechanismKind::Toppling) {
        MechanismKind::Toppling
    } else {
        MechanismKind::Mixed
    };
    Mechanism {
        kind,
        joint: joints.first().map(|j| j.1.clone()).unwrap_or_default(),
        joints: joints.into_iter().map(|j| (j.1, j.2)).collect(),
        blocks: stable.state.bodies.iter().zip(&moving).filter(|(_, m)| **m).map(|(b, _)| b.id.clone()).collect(),
    }
}
