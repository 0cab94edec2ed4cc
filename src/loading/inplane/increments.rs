//! The increments of the penalty DEM's path ([`Stepper`]): the displacement reached, the
//! size of the next increment, the predictor of its motion from the last one's (a block
//! that walked alone carried by the body that presses on it hardest, [`carry_with`]), and
//! the restart of an increment that failed from its start.

use super::{InPlaneParams, Rig};
use crate::dem::motion::BodyPose;
use crate::dem::Simulation;
use crate::loading::excursion::JointNeighbours;
use crate::math::Vec3;

/// The increments along the path: the displacement reached, the size of the next
/// increment, the predictor of its motion, and the restarts of those that failed.
pub(super) struct Stepper {
    /// The secant predictor: each increment starts from the last one's motion scaled to its
    /// own (the first from a motion growing linearly with height), so that the joints are
    /// not made to slip by the jump of the beam alone (a joint's shear law is incremental:
    /// a jump of the beam's target alone would be one step's shear increment at its joints).
    pub(super) last: Option<(Vec<Vec3>, Vec<Vec3>, f64)>,
    /// The bodies that walked alone in the last increment (moved from every joint
    /// neighbour), each with the body that pressed on it hardest (`None`: the table or a
    /// fixed block): the predictor carries such a body with that one instead of repeating
    /// its own motion. A body that walked alone slipped on its joints, and a slip is
    /// plastic: repeated by the predictor it is imposed as one step's shear increment at
    /// the joints, beyond what their friction can hold, and the friction then keeps it. A
    /// loose block (one the beam has lifted off) is in neutral equilibrium along its bed and
    /// a loaded one is held by friction: either way the solve leaves a predicted slip where
    /// the predictor put it, and a block walks out of the wall an increment at a time (on
    /// joints ten times as stiff as the granite wall's, a predictor that carried the loose
    /// blocks only walked a base-course end block 4 cm and threw a top-course block from
    /// the wall in a cyclic run to 3 % at 0.5 MPa). The solve finds a slip that the load
    /// truly drives from the carried prediction.
    carriers: Vec<Option<Option<usize>>>,
    /// The actuator's displacement reached, m.
    pub(super) u_prev: f64,
    /// The first increment, and the first after a reversal, are a quarter of the smallest
    /// slip displacement of the joints under the vertical stress (μ σ0 / Ks), so that a
    /// predictor that is not yet the path's own does not make a joint slip; each converged
    /// increment doubles the next, up to the path's.
    pub(super) first: f64,
    /// The largest next increment, m.
    pub(super) allowed: f64,
    /// The path's increment, mm ([`InPlaneParams::step_mm`]).
    step_mm: f64,
    /// Increments solved again from their start.
    pub(super) retried: usize,
    /// Whether the increment being solved is one thrown off the path solved again from its
    /// start (it is not solved a third time).
    pub(super) from_start: bool,
}

impl Stepper {
    /// At the start of the path of `params` on the rig `rig`, of `n_bodies` bodies.
    pub(super) fn new(rig: &Rig, params: &InPlaneParams, n_bodies: usize) -> Stepper {
        let first = 0.25
            * rig
                .layout
                .materials
                .iter()
                .map(|m| m.friction.tan().max(1e-3) * params.sigma0_mpa * 1e6 / m.ks)
                .fold(f64::INFINITY, f64::min);
        Stepper {
            last: None,
            carriers: vec![None; n_bodies],
            u_prev: 0.0,
            first,
            allowed: first,
            step_mm: params.step_mm,
            retried: 0,
            from_start: false,
        }
    }

    /// The next increment towards the path's point `u` (m), its end now the displacement
    /// reached; `None` at a reversal (the next is sized from the first again).
    pub(super) fn next(&mut self, u: f64) -> Option<f64> {
        let du = (u - self.u_prev).clamp(-self.allowed, self.allowed);
        if self.last.as_ref().is_some_and(|l| l.2 * du < 0.0) {
            // A reversal: the last motion is no predictor of the unloading.
            self.last = None;
            self.allowed = self.first;
            return None;
        }
        self.u_prev = if (u - self.u_prev).abs() <= self.allowed { u } else { self.u_prev + du };
        self.allowed = (2.0 * self.allowed).min(self.step_mm * 1e-3);
        Some(du)
    }

    /// The predicted motion of the bodies of `sim` over the increment `du` (m): centroid
    /// translations and rotation vectors, the last increment's scaled (the bodies that
    /// walked alone carried by their carriers, [`carry_with`]), or, with none, a motion growing linearly
    /// with height up to the anchor's `anchor_z_m` (m).
    pub(super) fn predict(&self, du: f64, sim: &Simulation, anchor_z_m: f64) -> (Vec<Vec3>, Vec<Vec3>) {
        match &self.last {
            Some((dp, dr, d0)) if *d0 != 0.0 => {
                // No body is predicted to move more than the beam's increment (the
                // last solve's relaxation left no creep to extrapolate).
                let k = du / d0;
                let cap = du.abs();
                let clip = |v: Vec3, r: f64| if v.norm() * r > cap { v * (cap / (v.norm() * r)) } else { v };
                let mut p: Vec<Vec3> = dp.iter().map(|v| clip(v * k, 1.0)).collect();
                let mut r: Vec<Vec3> = dr.iter().zip(&sim.state.bodies).map(|(v, b)| clip(v * k, b.radius)).collect();
                carry_with(&mut p, &mut r, &self.carriers, sim);
                (p, r)
            }
            _ => sim
                .state
                .bodies
                .iter()
                .map(|b| (Vec3::new(du * (b.pos.z / anchor_z_m).clamp(0.0, 1.0), 0.0, 0.0), Vec3::zeros()))
                .unzip(),
        }
    }

    /// Whether the increment `du` (m) is the smallest one with no predictor: the warm-up's
    /// first, which is not solved again from its start.
    pub(super) fn is_warm_up(&self, du: f64) -> bool {
        self.last.is_none() && du.abs() <= self.first
    }

    /// Puts `sim` back to `before`, the state the increment `du` (m) was solved from, the
    /// beam's target with it (body `beam`, the anchor at `anchor_x0` m at the start), to
    /// solve the increment again from its start, warming up from the smallest one;
    /// `off_path`: the increment threw a block off the path (it is not solved a third time).
    pub(super) fn restart(
        &mut self,
        sim: &mut Simulation,
        before: Simulation,
        du: f64,
        off_path: bool,
        beam: usize,
        anchor_x0: f64,
    ) {
        self.from_start |= off_path;
        *sim = before;
        self.u_prev -= du;
        if let Some(c) = sim.state.bodies[beam].hold.dof_mut() {
            c.set_target(0, anchor_x0 + self.u_prev);
        }
        self.last = None;
        self.allowed = self.first;
        self.retried += 1;
    }

    /// Learns the predictor of the next increment from the increment `du` (m) solved from
    /// the poses `start` to `now`: its motion, and the bodies that walked alone in it with
    /// their carriers ([`hardest_pressing`]; the beam, body `beam`, never).
    pub(super) fn learn(
        &mut self,
        neighbours: &JointNeighbours,
        start: &[BodyPose],
        now: &[BodyPose],
        du: f64,
        sim: &Simulation,
        beam: usize,
    ) {
        let alone = neighbours.walked_alone(start, now, (WALK_SHARE * du.abs()).max(WALK_FLOOR_M));
        self.carriers =
            alone.iter().enumerate().map(|(k, &a)| (a && k != beam).then(|| hardest_pressing(sim, k))).collect();
        self.carriers.resize(sim.state.bodies.len(), None);
        self.last = Some((
            now.iter().zip(start).map(|(a, b)| a.0 - b.0).collect(),
            now.iter().zip(start).map(|(a, b)| (a.1 * b.1.inverse()).scaled_axis()).collect(),
            du,
        ));
    }
}

/// The share of an increment's beam displacement by which a body must move from every
/// joint neighbour to have walked alone \[0.1\] (a body moving with a neighbour departs from
/// it by the joint's deformation only, orders of magnitude less).
const WALK_SHARE: f64 = 0.1;

/// The least relative motion that counts as walking alone, m \[10 µm\]: above the elastic
/// deformation of a joint in one increment.
const WALK_FLOOR_M: f64 = 1e-5;

/// The body that presses on body `k` hardest (the largest contact force between the two;
/// `None`: the table or a fixed block, or no contact).
fn hardest_pressing(sim: &Simulation, k: usize) -> Option<usize> {
    let mut best: (f64, Option<usize>) = (0.0, None);
    let mut by: std::collections::BTreeMap<Option<usize>, f64> = std::collections::BTreeMap::new();
    for c in &sim.state.contacts {
        let other = if c.b == k {
            c.a
        } else if c.a == Some(k) {
            Some(c.b)
        } else {
            continue;
        };
        let other = other.filter(|&j| !sim.state.bodies[j].fixed());
        *by.entry(other).or_default() += c.force.norm();
    }
    for (other, f) in by {
        if f > best.0 {
            best = (f, other);
        }
    }
    best.1
}

/// Replaces the predicted motion (`dpos`, `drot`: centroid translation, rotation vector) of
/// each body that has a carrier (`carriers[k] = Some(c)`) by its carrier's predicted rigid
/// motion applied to it (`c = None`: no motion).
fn carry_with(dpos: &mut [Vec3], drot: &mut [Vec3], carriers: &[Option<Option<usize>>], sim: &Simulation) {
    let (p0, r0) = (dpos.to_vec(), drot.to_vec());
    for (k, c) in carriers.iter().enumerate() {
        match c {
            None => {}
            Some(None) => {
                dpos[k] = Vec3::zeros();
                drot[k] = Vec3::zeros();
            }
            Some(Some(j)) => {
                let arm = sim.state.bodies[k].pos - sim.state.bodies[*j].pos;
                let q = nalgebra::UnitQuaternion::from_scaled_axis(r0[*j]);
                dpos[k] = p0[*j] + (q * arm - arm);
                drot[k] = r0[*j];
            }
        }
    }
}
