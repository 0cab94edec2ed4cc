//! Per-degree-of-freedom constraints of a body: which of its six degrees of freedom are
//! held, and where a held translation acts.
//!
//! What holds a body is its [`Hold`] ([`super::state::Body::hold`]): nothing
//! ([`Hold::Free`]), every degree of freedom at its reference pose ([`Hold::Fixed`]: the
//! tilting table's base, a layout's fixed block), or some of them by a [`DofConstraint`]
//! ([`Hold::Dof`]):
//!
//! * a **held translation** along a table axis i holds the table coordinate i of one
//!   body-frame point `p` (the *anchor*) at a target value `x_i`: the reaction `R_i` is
//!   whatever cancels the body's out-of-balance force along i, and it acts at the anchor, so
//!   it adds the moment `(R p) × R_i e_i` about the centroid (R the body's rotation). An
//!   **imposed displacement** is a held translation whose target a protocol moves between
//!   static solves ([`DofConstraint::set_target`]); a held translation with the anchor at
//!   the centroid is the classic roller.
//! * a **held rotation** about a table axis j keeps the body's angular velocity about j at
//!   zero; its reaction is whatever moment cancels the out-of-balance moment about j.
//! * a **rig's moment** ([`RigMoment`]) about a free rotation, linear in the body's motion
//!   since a reference pose (a vertical load applied off the centroid, or at a point that
//!   lags the body; a rotational spring), is added to the out-of-balance moment in the load
//!   stage with the reactions;
//! * an **applied force** is not a constraint: it is the body's external force
//!   ([`super::WallState::external_force`], at the centroid) and its external torque.
//!
//! A test rig combines them: a loading beam, say, with one translation held at the
//! actuator's point and moved step by step, another free under a constant applied force and
//! the rest held by the rig's guides; each loading protocol's module states its rig's
//! degrees of freedom.
//!
//! The engine applies a constraint in its load stage (the held components leave the
//! out-of-balance force, so that the unbalanced-force ratio measures only what can move,
//! and the reaction's moment is added) and in its integration (the held velocities are
//! zeroed and the anchor is put back on its target after the rotation of the step); the body
//! turns with its inertia about the anchor (the centroid's plus the parallel-axis term of
//! the held translations, `integrator::constrained_inertia`), since the hold carries its
//! centroid round the anchor: with the centroid's alone, an anchor far from the centroid
//! (the in-plane beam at a large shear span) made the rotation outrun the time step. A
//! constrained body moves by its scalar inertial mass: the block density scaling's 6 × 6
//! mass matrix couples held and free degrees of freedom, so a protocol that constrains a
//! body runs scalar density scaling ([`super::DensityScaling::without_block`]). Every stage
//! of the static cascade ([`super::solve_static`]) holds them: the implicit iteration's
//! stiffness leaves the held degrees of freedom out (a held translation taken at the
//! centroid), and its jumps, like those of the secant acceleration, are
//! [`super::Simulation::predict`]'s, which zero the held components and put the anchor back
//! on its target.

pub use super::hold::{DofConstraint, Hold, RigMoment};
use super::state::Body;
use crate::math::Vec3;

impl DofConstraint {
    /// Holds the translation along table axis `axis` (0 x, 1 y, 2 z) with the anchor where
    /// it is now on `body`.
    ///
    /// # Panics
    /// If `axis > 2`.
    pub fn hold_translation(mut self, body: &Body, axis: usize) -> DofConstraint {
        self.translation[axis] = Some(self.anchor_world(body)[axis]);
        self
    }

    /// The anchor of `body` in the table frame, m.
    pub fn anchor_world(&self, body: &Body) -> Vec3 {
        body.pos + body.rot_mat * self.anchor
    }

    /// Takes the held components out of the out-of-balance force `f` and moment `t` of
    /// `body` (N, N·m about the centroid, table frame) and adds the moment of the held
    /// translations' reaction about the centroid; returns the reaction force (N).
    #[inline]
    pub fn react(&self, body: &Body, f: &mut Vec3, t: &mut Vec3) -> Vec3 {
        let mut reaction = Vec3::zeros();
        for i in 0..3 {
            if self.translation[i].is_some() {
                reaction[i] = -f[i];
                f[i] = 0.0;
            }
        }
        *t += (body.rot_mat * self.anchor).cross(&reaction);
        if let Some(m) = &self.moment {
            t[m.axis] += m.moment_nm(&body.pos, &body.rot);
        }
        for j in 0..3 {
            if self.rotation[j] {
                t[j] = 0.0;
            }
        }
        reaction
    }

    /// Puts the anchor of `body` back on its targets (moving the centroid along the held
    /// axes only).
    #[inline]
    pub fn place(&self, body: &mut Body) {
        let a = body.rot_mat * self.anchor;
        for i in 0..3 {
            if let Some(x) = self.translation[i] {
                body.pos[i] = x - a[i];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ConvexBlock;

    fn body() -> Body {
        let v: Vec<Vec3> = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]
            .iter()
            .flat_map(|p| [Vec3::new(p[0], p[1], p[2]), Vec3::new(p[0], p[1], 1.0)])
            .collect();
        let shape = ConvexBlock::from_vertices(&v).unwrap();
        Body::new("b".into(), &shape, 1000.0, 0, false)
    }

    /// A held translation anchored above the centroid turns the held force into a moment
    /// `r × R` (the lever of the actuator), and a held rotation takes that moment.
    #[test]
    fn a_held_translation_acts_at_its_anchor() {
        let b = body();
        let c = DofConstraint { anchor: Vec3::new(0.0, 0.0, 0.5), ..DofConstraint::free() }.hold_translation(&b, 0);
        let (mut f, mut t) = (Vec3::new(3.0, 1.0, -2.0), Vec3::zeros());
        let r = c.react(&b, &mut f, &mut t);
        assert_eq!(r, Vec3::new(-3.0, 0.0, 0.0));
        assert_eq!(f, Vec3::new(0.0, 1.0, -2.0));
        // (0, 0, 0.5) × (−3, 0, 0) = (0, −1.5, 0).
        assert!((t - Vec3::new(0.0, -1.5, 0.0)).norm() < 1e-15, "{t}");
        let c = c.hold_rotation(1);
        let (mut f, mut t) = (Vec3::new(3.0, 1.0, -2.0), Vec3::new(0.2, 0.4, 0.0));
        c.react(&b, &mut f, &mut t);
        assert_eq!(t, Vec3::new(0.2, 0.0, 0.0));
    }

    /// Placing the body keeps the anchor on its target whatever the rotation.
    #[test]
    fn placing_keeps_the_anchor_on_target() {
        let mut b = body();
        let mut c = DofConstraint { anchor: Vec3::new(0.0, 0.0, 0.5), ..DofConstraint::free() }.hold_translation(&b, 0);
        c.set_target(0, 0.75);
        b.rotate(Vec3::new(0.0, 0.1, 0.0));
        c.place(&mut b);
        assert!((c.anchor_world(&b).x - 0.75).abs() < 1e-15);
    }
}
