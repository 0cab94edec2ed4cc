//! The model state of one simulation: what the wall is at an instant (bodies with their
//! poses and velocities, contacts with their sub-contacts' joint history, the loads, the
//! time), and the geometric questions it answers. The engine's derived data (forces,
//! masses, time step, detection cache) live in its workspace ([`super::Simulation`]); the
//! parameters in [`super::SolverParams`].

use super::contact::forces::unit;
use super::contact::law;
use super::contact::types::{Contact, ContactNode, SubContact};
use super::rope::RopeLoad;
use super::state::Body;
use crate::layout::{EndRestraint, Layout};
use crate::math::Vec3;

/// The model state of one simulation. Every vector indexed by body is in layout order.
#[derive(Debug, Clone)]
pub struct WallState {
    /// Bodies, in layout order.
    pub bodies: Vec<Body>,
    /// Contacts, sorted by (A, B) with the table first, each with its sub-contacts' joint
    /// history.
    pub contacts: Vec<Contact>,
    /// Gravity, m/s², table frame (`g (0, sin α, −cos α)` at tilt α).
    pub gravity: Vec3,
    /// Magnitude of gravity, m/s² (the layout's `gravity`).
    pub gravity_magnitude: f64,
    /// External force per body at its centroid, N, table frame (lateral loads).
    pub external_force: Vec<Vec3>,
    /// External torque per body about its centroid, N·m, table frame.
    pub external_torque: Vec<Vec3>,
    /// End restraint per body.
    pub restraint: Vec<Option<EndRestraint>>,
    /// The layout's rope restraints with the blocks each bears on ([`super::rope`]).
    pub ropes: Vec<RopeLoad>,
    /// Simulated time, s.
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
}

impl WallState {
    /// The state of a checked layout at rest, gravity straight down (table level), no
    /// contacts yet (the engine detects them).
    pub fn new(layout: &Layout) -> WallState {
        let bodies = crate::dem::state::bodies_of(layout);
        let n = bodies.len();
        let mut restraint = vec![None; n];
        for &(i, r) in &layout.end_restraints {
            restraint[i] = Some(r);
        }
        let ropes = RopeLoad::of_layout(layout, &bodies);
        WallState {
            ropes,
            bodies,
            contacts: Vec::new(),
            gravity: Vec3::new(0.0, 0.0, -layout.gravity),
            gravity_magnitude: layout.gravity,
            external_force: vec![Vec3::zeros(); n],
            external_torque: vec![Vec3::zeros(); n],
            restraint,
            time: 0.0,
            steps: 0,
        }
    }

    /// Whether some body has a per-degree-of-freedom constraint.
    pub fn constrained(&self) -> bool {
        self.bodies.iter().any(|b| b.hold.dof().is_some())
    }

    /// Sets the table tilt α (rad): gravity becomes `g (0, sin α, −cos α)` in the table
    /// frame (the out-of-plane load is `W sin α`; Santa-Cruz et al. 2021, Eq. 1 with sine
    /// and cosine in their places).
    pub fn set_tilt(&mut self, alpha: f64) {
        self.gravity = Vec3::new(0.0, alpha.sin(), -alpha.cos()) * self.gravity_magnitude;
    }

    /// B's pose relative to A (the table for `None`): B's centroid in A's body frame and
    /// B's rotation relative to A's.
    pub fn relative_pose(&self, a: Option<usize>, b: usize) -> (Vec3, nalgebra::UnitQuaternion<f64>) {
        let bb = &self.bodies[b];
        match a {
            None => (bb.pos, bb.rot),
            Some(i) => {
                let ba = &self.bodies[i];
                (ba.to_body(&bb.pos), ba.rot.inverse() * bb.rot)
            }
        }
    }

    /// Table-frame positions of a node's two material points (on A, on B), m.
    pub fn node_points(&self, c: &Contact, nd: &ContactNode) -> (Vec3, Vec3) {
        let pa = match c.a {
            None => nd.on_a,
            Some(i) => self.bodies[i].to_world(&nd.on_a),
        };
        (pa, self.bodies[c.b].to_world(&nd.on_b))
    }

    /// Table-frame centroid of a sub-contact (mid-plane), m.
    pub fn sub_centroid(&self, c: &Contact, s: &SubContact) -> Vec3 {
        s.nodes.iter().fold(Vec3::zeros(), |acc, &k| {
            let (pa, pb) = self.node_points(c, &c.nodes[k as usize]);
            acc + (pa + pb) / 6.0
        })
    }

    /// Normal gaps (m) at the three nodes of a sub-contact, along the current normal
    /// (positive: open).
    pub fn sub_gaps(&self, c: &Contact, s: &SubContact) -> [f64; 3] {
        let n = self.contact_normal(c);
        s.nodes.map(|k| {
            let (pa, pb) = self.node_points(c, &c.nodes[k as usize]);
            (pb - pa).dot(&n)
        })
    }

    /// Current unit normal of a contact (A → B, table frame): the mean of the detection
    /// normal carried by each body.
    pub fn contact_normal(&self, c: &Contact) -> Vec3 {
        let na = match c.a {
            None => c.normal_a,
            Some(i) => self.bodies[i].rot_mat * c.normal_a,
        };
        unit(na + self.bodies[c.b].rot_mat * c.normal_b)
    }

    /// Total energy bookkeeping: (kinetic, gravitational potential relative to the
    /// reference configuration, elastic energy stored in the joints), J. The energy
    /// stored in rope restraints is not counted.
    pub fn energies(&self) -> (f64, f64, f64) {
        let ke: f64 = self.bodies.iter().map(|b| b.kinetic_energy()).sum();
        let pe: f64 = self.bodies.iter().map(|b| -b.mass * self.gravity.dot(&(b.pos - b.pos0))).sum();
        let el: f64 = self
            .contacts
            .iter()
            .flat_map(|c| {
                c.subs.iter().map(move |s| {
                    law::normal_energy(&c.joint, self.sub_gaps(c, s), s.area)
                        + law::shear_energy(&c.joint, &s.state, s.area)
                })
            })
            .sum();
        (ke, pe, el)
    }

    /// Name of a contact's joint: `table/ID` or `ID_A/ID_B`.
    pub fn joint_name(&self, c: &Contact) -> String {
        match c.a {
            None => format!("table/{}", self.bodies[c.b].id),
            Some(i) => format!("{}/{}", self.bodies[i].id, self.bodies[c.b].id),
        }
    }

    /// The current contact of the pair, if its bodies have moved relative to each other by
    /// less than `tol` (m, at B's extremities) since its patch was made.
    pub(crate) fn reusable(&self, a: Option<usize>, b: usize, tol: f64) -> Option<Contact> {
        if tol <= 0.0 {
            return None;
        }
        let key = (a.map_or(0, |i| i + 1), b);
        let k = self.contacts.binary_search_by_key(&key, |o| o.key()).ok()?;
        let c = &self.contacts[k];
        let (t, q) = self.relative_pose(a, b);
        let dt = (t - c.made_at.0).norm();
        // Rotation angle θ from the quaternion dot product, |q·q₀| = cos(θ/2) (as in the
        // engine's re-detection test, an upper bound for small θ).
        let dot = q.coords.dot(&c.made_at.1.coords).abs().min(1.0);
        let dr = 2.0 * (2.0 * (1.0 - dot)).sqrt() * self.bodies[b].radius;
        (dt + dr < tol).then(|| c.clone())
    }

    /// Carries the joint history of the current contacts over to `new` (the same pairs
    /// detected afresh): each new sub-contact takes the bond and the shear force (scaled
    /// by the area ratio) of the nearest old sub-contact of its pair.
    pub(crate) fn transfer_history(&self, new: &mut [Contact]) {
        let old = &self.contacts;
        for c in new.iter_mut() {
            let Ok(k) = old.binary_search_by_key(&c.key(), |o| o.key()) else { continue };
            let o = &old[k];
            let old_pts: Vec<Vec3> = o.subs.iter().map(|s| self.sub_centroid(o, s)).collect();
            let mut fresh = Vec::with_capacity(c.subs.len());
            for s in &c.subs {
                let x = self.sub_centroid(c, s);
                let nearest = old_pts
                    .iter()
                    .enumerate()
                    .min_by(|(_, p), (_, q)| (*p - x).norm_squared().total_cmp(&(*q - x).norm_squared()))
                    .map(|(i, _)| i);
                let mut st = s.state;
                if let Some(i) = nearest {
                    let os = &o.subs[i];
                    st.bonded = os.state.bonded;
                    st.shear = os.state.shear * (s.area / os.area.max(1e-300));
                }
                fresh.push(st);
            }
            for (s, st) in c.subs.iter_mut().zip(fresh) {
                s.state = st;
            }
        }
    }
}
