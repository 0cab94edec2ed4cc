//! The collapse mechanism of a limit analysis, read from the dual variables of the block
//! equations: the virtual velocity (translation and rotation) of every block at collapse,
//! and from it the relative velocity of the two sides of every contact point, which tells
//! which joints open, slide or hinge (Livesley 1978; Gilbert, Casapulla & Ahmed 2006, §2:
//! the dual of the equilibrium problem is the kinematic problem).

use super::model::Model;
use crate::loading::mechanism::{read_mechanism, BlockMotion, Mechanism, MechanismKind};
use crate::math::Vec3;
use serde::{Deserialize, Serialize};

/// Share of the largest block motion (or joint relative motion) above which a block moves
/// (or a joint fails) in the mechanism. An interior-point dual is exact to about 1e-8 of
/// its scale; where two mechanisms tie, it is a blend of both, and a lower share would
/// read the weaker one's traces as motion.
pub const VELOCITY_SHARE: f64 = 0.01;

/// How a joint moves in the collapse mechanism.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointMode {
    /// Relative sliding along the joint (its tangential relative velocity exceeds half of
    /// the largest relative velocity at its points; with associative friction it comes with
    /// a dilatancy of tan φ).
    Slide,
    /// Rotation about a line of the joint: some points stay closed (opening below 10 % of
    /// the joint's largest), the others open.
    Hinge,
    /// Every point of the joint opens: the blocks separate.
    Open,
}

/// A failing joint of the mechanism.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LimitJoint {
    /// `table/ID` or `ID_A/ID_B`.
    pub joint: String,
    /// Its mode.
    pub mode: JointMode,
    /// Largest opening velocity at its points (relative velocity along the normal A → B),
    /// per unit of the largest block motion of the mechanism.
    pub opening: f64,
    /// Largest sliding velocity at its points, per unit of the largest block motion.
    pub slip: f64,
    /// Mean height of its points, m.
    pub z_m: f64,
}

/// Virtual velocity of a block: translation of its centroid and rotation, table frame, per
/// unit of the largest block motion (|v| + |ω| r over the blocks).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BlockVelocity {
    /// Translation velocity of the centroid.
    pub translation: Vec3,
    /// Angular velocity, rad per unit (times the block radius it is a velocity).
    pub rotation: Vec3,
}

/// The mechanism of a solution's velocities: the DEM's [`Mechanism`] (kind, the lowest
/// failing joint, the failing joints with their kind, the moving blocks), every failing
/// joint with its mode, and the normalised block velocities.
///
/// Unlike the DEM's reading (joints between a moving and a resting group), the joints here
/// are all those with relative motion, internal cracks included.
pub(crate) fn read(model: &Model, velocity: &[(Vec3, Vec3)]) -> (Mechanism, Vec<LimitJoint>, Vec<BlockVelocity>) {
    let motion: Vec<f64> = velocity.iter().zip(&model.radius).map(|((v, w), r)| v.norm() + w.norm() * r).collect();
    let max_motion = motion.iter().cloned().fold(0.0, f64::max);
    let scale = if max_motion > 0.0 { 1.0 / max_motion } else { 0.0 };
    let at = |k: Option<usize>, x: &Vec3| -> Vec3 {
        match k {
            Some(k) => {
                let (v, w) = velocity[k];
                v + w.cross(&(x - model.centroid[k]))
            }
            None => Vec3::zeros(),
        }
    };
    struct Motion {
        relative: f64,
        open_max: f64,
        open_min: f64,
        slip: f64,
    }
    let motions: Vec<Motion> = model
        .joints
        .iter()
        .map(|j| {
            let n = j.frame[0];
            let mut m = Motion { relative: 0.0, open_max: f64::NEG_INFINITY, open_min: f64::INFINITY, slip: 0.0 };
            for p in j.points.clone() {
                let x = model.points[p].x;
                let du = (at(Some(j.b), &x) - at(j.a, &x)) * scale;
                let dn = du.dot(&n);
                m.relative = m.relative.max(du.norm());
                m.open_max = m.open_max.max(dn);
                m.open_min = m.open_min.min(dn);
                m.slip = m.slip.max((du - n * dn).norm());
            }
            m
        })
        .collect();
    let max_relative = motions.iter().map(|m| m.relative).fold(0.0, f64::max);
    let mut joints: Vec<LimitJoint> = model
        .joints
        .iter()
        .zip(&motions)
        .filter(|(_, m)| max_relative > 0.0 && m.relative > VELOCITY_SHARE * max_relative)
        .map(|(j, m)| {
            let mode = if m.slip > 0.5 * m.relative {
                JointMode::Slide
            } else if m.open_min < 0.1 * m.open_max {
                JointMode::Hinge
            } else {
                JointMode::Open
            };
            LimitJoint { joint: j.name.clone(), mode, opening: m.open_max.max(0.0), slip: m.slip, z_m: j.z }
        })
        .collect();
    joints.sort_by(|a, b| a.z_m.total_cmp(&b.z_m).then(a.joint.cmp(&b.joint)));
    let kind_of = |m: JointMode| match m {
        JointMode::Slide => MechanismKind::Sliding,
        JointMode::Hinge | JointMode::Open => MechanismKind::Toppling,
    };
    let kind = if joints.is_empty() {
        MechanismKind::None
    } else if joints.iter().all(|j| j.mode == JointMode::Slide) {
        MechanismKind::Sliding
    } else if joints.iter().all(|j| j.mode != JointMode::Slide) {
        MechanismKind::Toppling
    } else {
        MechanismKind::Mixed
    };
    let moving: Vec<bool> = motion.iter().map(|m| max_motion > 0.0 && *m > VELOCITY_SHARE * max_motion).collect();
    let seen: Vec<BlockMotion> = model
        .extents
        .iter()
        .zip(&motion)
        .zip(&moving)
        .map(|(((x, z, fixed), m), mv)| BlockMotion { x: *x, z: *z, moved: m * scale, moving: *mv, fixed: *fixed })
        .collect();
    let mechanism = Mechanism {
        reading: read_mechanism(&seen, kind),
        kind,
        joint: joints.first().map(|j| j.joint.clone()).unwrap_or_default(),
        joints: joints.iter().map(|j| (j.joint.clone(), kind_of(j.mode))).collect(),
        blocks: model
            .ids
            .iter()
            .zip(&motion)
            .filter(|(_, m)| max_motion > 0.0 && **m > VELOCITY_SHARE * max_motion)
            .map(|(id, _)| id.clone())
            .collect(),
    };
    let blocks = velocity.iter().map(|(v, w)| BlockVelocity { translation: v * scale, rotation: w * scale }).collect();
    (mechanism, joints, blocks)
}
