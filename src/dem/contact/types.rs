//! Contact types: a contact between two bodies (or the table and a body), its sub-contact
//! mesh and the joint history of every sub-contact (parry's `ContactManifold` with its
//! per-contact data, in the 3DEC manner).

use super::law::{JointParams, SubContactState};
use crate::math::Vec3;

/// A node of a contact's sub-contact mesh: a material point on each body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactNode {
    /// Point on A, A's body frame (table frame for the table), m.
    pub on_a: Vec3,
    /// Point on B, B's body frame, m.
    pub on_b: Vec3,
}

/// One sub-contact: a triangle of the contact polygon and its joint history.
#[derive(Debug, Clone, PartialEq)]
pub struct SubContact {
    /// Node indices into [`Contact::nodes`].
    pub nodes: [u32; 3],
    /// Area, m².
    pub area: f64,
    /// Joint history.
    pub state: SubContactState,
    /// The time step's window of the closure law ([`crate::closure::ClosureLaw::tangent_window`]):
    /// the closure up to which `window_kn` bounds the tangent, m. Infinite for a law
    /// without windows (its bound holds everywhere); `−∞` until the first update of the
    /// step, so that a node closing ahead of it asks for one.
    pub window_cap_m: f64,
    /// The normal tangent bound within the window, Pa/m (the law's bound for a law
    /// without windows): the stiffness the time step takes for this sub-contact.
    pub window_kn: f64,
}

impl SubContact {
    /// A sub-contact of the joint `joint` at rest, its window not yet taken.
    pub fn new(nodes: [u32; 3], area: f64, joint: &JointParams, bonded: bool) -> SubContact {
        let windowed = joint.closure.is_windowed();
        SubContact {
            nodes,
            area,
            state: SubContactState::new(bonded),
            window_cap_m: if windowed { f64::NEG_INFINITY } else { f64::INFINITY },
            window_kn: joint.kn_bound(),
        }
    }
}

/// A contact between body A (or the table) and body B.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// Body A; `None` is the table.
    pub a: Option<usize>,
    /// Body B.
    pub b: usize,
    /// Joint parameters.
    pub joint: JointParams,
    /// Contact normal at detection, in A's body frame (table frame for the table).
    pub normal_a: Vec3,
    /// Contact normal at detection, in B's body frame.
    pub normal_b: Vec3,
    /// Nodes of the sub-contact mesh.
    pub nodes: Vec<ContactNode>,
    /// Sub-contacts (triangles).
    pub subs: Vec<SubContact>,
    /// Resultant force on B at the last step, N, table frame.
    pub force: Vec3,
    /// B's pose relative to A when the patch was made: B's centroid in A's body frame (the
    /// table frame for the table), m, and B's rotation relative to A's. A re-detection
    /// keeps the patch while the pair has moved less than
    /// [`crate::dem::SolverParams::patch_reuse_fraction`] of the re-detection distance
    /// relative to it (the nodes are material points of the two bodies, so the patch moves
    /// with the pair).
    pub made_at: (Vec3, nalgebra::UnitQuaternion<f64>),
}

impl Contact {
    /// The sort key of a contact: the table first, then by (A, B).
    pub(crate) fn key(&self) -> (usize, usize) {
        (self.a.map_or(0, |i| i + 1), self.b)
    }
}
