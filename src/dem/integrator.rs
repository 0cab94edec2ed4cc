//! Central-difference (leapfrog) integration of the Newton–Euler equations with Cundall's
//! local non-viscous damping.
//!
//! Velocities live at half steps, positions at whole steps (Cundall & Strack 1979):
//!
//! ```text
//! F_d   = F − α |F| sign(v^{n−½})            per component (local damping, α ∈ [0, 1))
//! v^{n+½} = v^{n−½} + Δt F_d / m
//! x^{n+1} = x^n + Δt v^{n+½}
//! ω^{n+½} = ω^{n−½} + Δt I_w⁻¹ (T_d − ω^{n−½} × I_w ω^{n−½})   (full inertia tensor, I_w = R I Rᵀ)
//! q^{n+1} = exp(Δt ω^{n+½}) q^n
//! ```
//!
//! With density scaling (static solutions only) a body's inertial mass and inertia are
//! `s m`, `s I` (`s > 0`, see [`super::timestep`]) while its weight stays `m g`.
//!
//! Local damping (Cundall 1987; the default 0.8 of 3DEC and YADE's NewtonIntegrator) removes
//! kinetic energy in proportion to the unbalanced force and vanishes at equilibrium: it is a
//! device for static solutions, not physical damping.

use super::constraint::DofConstraint;
use super::state::Body;
use crate::math::Vec3;

/// Constraint on a body's y translation (end restraints).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum YConstraint {
    /// Free.
    Free,
    /// y translation held (rigid end restraint).
    Held,
}

#[inline]
fn damp(f: Vec3, v: &Vec3, alpha: f64) -> Vec3 {
    if alpha == 0.0 {
        return f;
    }
    Vec3::new(
        f.x - alpha * f.x.abs() * v.x.signum_or_zero(),
        f.y - alpha * f.y.abs() * v.y.signum_or_zero(),
        f.z - alpha * f.z.abs() * v.z.signum_or_zero(),
    )
}

trait SignumOrZero {
    fn signum_or_zero(self) -> f64;
}

impl SignumOrZero for f64 {
    #[inline]
    fn signum_or_zero(self) -> f64 {
        if self > 0.0 {
            1.0
        } else if self < 0.0 {
            -1.0
        } else {
            0.0
        }
    }
}

/// Advances one body by one step. `force` (N) and `torque` (N·m, about the centroid) are in
/// the table frame and include every load. Fixed bodies do not move.
#[inline(always)]
pub fn advance(b: &mut Body, force: Vec3, torque: Vec3, dt: f64, damping: f64, y: YConstraint) {
    if b.fixed() {
        b.vel = Vec3::zeros();
        b.angvel = Vec3::zeros();
        return;
    }
    if let Some(bm) = &b.block_mass {
        (b.vel, b.angvel) = block_velocities(b.vel, b.angvel, bm, force, torque, dt, damping, y);
        b.pos += b.vel * dt;
        b.rotate(b.angvel * dt);
        return;
    }
    let mut f = damp(force, &b.vel, damping);
    if y == YConstraint::Held {
        f.y = 0.0;
        b.vel.y = 0.0;
    }
    b.vel += f * (dt * b.inertia_scale_inv / b.mass);
    b.pos += b.vel * dt;
    let t = damp(torque, &b.angvel, damping);
    let r = b.rot_mat;
    // I_w ω = R I Rᵀ ω and I_w⁻¹ x = R I⁻¹ Rᵀ x, as matrix–vector products.
    let iw_w = r * (b.inertia * (r.tr_mul(&b.angvel)));
    let gyro = b.angvel.cross(&iw_w);
    // With density scaling s the inertia is s·I: ω̇ = I⁻¹(T/s − ω × Iω).
    b.angvel += r * (b.inv_inertia * r.tr_mul(&(t * b.inertia_scale_inv - gyro))) * dt;
    b.rotate(b.angvel * dt);
}

/// Advances one body with per-degree-of-freedom constraints by one step
/// ([`super::constraint`]): `force` and `torque` are the out-of-balance loads with the
/// held components already taken out and the reaction's moment added
/// ([`DofConstraint::react`]), that is the moment about the anchor. The scalar inertial
/// mass is used (block density scaling does not apply to a constrained body); the body
/// turns about the anchor, whose held coordinates do not move, so its rotational inertia
/// is the one about the anchor ([`constrained_inertia`]: the centroid's plus the parallel
/// axis term of the held translations, `m |r|²` for an anchor at a lever `r` above the
/// centroid of a horizontal hold), the mass's share carried along by the rotation; the
/// held velocities are zeroed before the pose is updated, and the anchor is put back on
/// its targets after the rotation; the held translations' velocities are then those of
/// that placement, so that the joints see the imposed motion.
#[inline(always)]
pub fn advance_constrained(b: &mut Body, force: Vec3, torque: Vec3, dt: f64, damping: f64, c: &DofConstraint) {
    if b.fixed() {
        b.vel = Vec3::zeros();
        b.angvel = Vec3::zeros();
        return;
    }
    let f = damp(force, &b.vel, damping);
    b.vel += f * (dt * b.inertia_scale_inv / b.mass);
    let t = damp(torque, &b.angvel, damping);
    let r = b.rot_mat;
    let iw_w = r * (b.inertia * (r.tr_mul(&b.angvel)));
    let gyro = b.angvel.cross(&iw_w);
    let rhs = t * b.inertia_scale_inv - gyro;
    // An anchor at the centroid to rounding (the in-plane beam whose centroid is the
    // actuator's point) adds nothing: the centroid's inertia, as for a free body.
    let lever2 = c.anchor.norm_squared();
    if b.mass * lever2 <= 1e-12 * b.inertia.diagonal().max() || c.translation.iter().all(Option::is_none) {
        b.angvel += r * (b.inv_inertia * r.tr_mul(&rhs)) * dt;
    } else {
        b.angvel += constrained_inertia(b, c).solve(&rhs) * dt;
    }
    c.hold_velocities(&mut b.vel, &mut b.angvel);
    let before = b.pos;
    b.pos += b.vel * dt;
    b.rotate(b.angvel * dt);
    c.place(b);
    // The held axes' velocities are those of the anchor's placement (a moved target, the
    // rotation's lever): the contact pass reads the joints' shear increments as `v Δt`.
    for i in 0..3 {
        if c.translation[i].is_some() {
            b.vel[i] = (b.pos[i] - before[i]) / dt;
        }
    }
}

/// The rotational inertia (table frame, kg·m², unscaled) of a body whose held
/// translations act at an anchor off its centroid ([`DofConstraint`]): the anchor's held
/// coordinates do not accelerate, `P (a + α × r) = 0` (r the anchor's lever from the
/// centroid, table frame; P the projection on the held axes), so the held reaction
/// `m P (r × α)` that keeps them there adds to the inertia about the centroid `I` the
/// parallel-axis term
/// `m [r]ₓᵀ P [r]ₓ`: `I + m (|r|² − r rᵀ)` with every translation held, `I_yy + m r_z²` for
/// a horizontal (x) hold at a lever r_z above the centroid. Held rotations keep their row
/// and column of the centroid's inertia (their velocities are zeroed after).
pub fn constrained_inertia(b: &Body, c: &DofConstraint) -> ConstrainedInertia {
    let r = b.rot_mat;
    let lever = r * c.anchor;
    let skew = lever.cross_matrix();
    let mut held = crate::math::Mat3::zeros();
    for i in 0..3 {
        if c.translation[i].is_some() {
            held[(i, i)] = 1.0;
        }
    }
    let inertia = r * b.inertia * r.transpose() + b.mass * (skew.transpose() * held * skew);
    ConstrainedInertia(inertia)
}

/// The inertia of [`constrained_inertia`], to solve for the angular acceleration.
#[derive(Debug, Clone, Copy)]
pub struct ConstrainedInertia(pub crate::math::Mat3);

impl ConstrainedInertia {
    /// The angular acceleration (rad/s², table frame) under the moment `t` (N·m, table
    /// frame, about the centroid with the held reaction's moment in it: about the anchor).
    #[inline]
    pub fn solve(&self, t: &Vec3) -> Vec3 {
        self.0.try_inverse().map_or(Vec3::zeros(), |inv| inv * t)
    }
}

/// The new velocities `(v, ω)` of a body with block density scaling: the force and torque
/// `(F, T)` and the velocities in the eigenbasis `Q` of the block mass, local damping per
/// component there (so that damping and mass commute and each mass-normalized direction
/// is damped as a single oscillator), `Δ = Q diag(1/λ) (damped Qᵀ(F, T)) Δt`. No gyroscopic
/// term: the scaled inertia is a device for static solutions, not a rigid body's.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn block_velocities(
    vel: Vec3,
    angvel: Vec3,
    bm: &super::state::BlockMass,
    mut force: Vec3,
    torque: Vec3,
    dt: f64,
    damping: f64,
    y: YConstraint,
) -> (Vec3, Vec3) {
    let mut v = vel;
    if y == YConstraint::Held {
        force.y = 0.0;
        v.y = 0.0;
    }
    let f6 = nalgebra::Vector6::new(force.x, force.y, force.z, torque.x, torque.y, torque.z);
    let v6 = nalgebra::Vector6::new(v.x, v.y, v.z, angvel.x, angvel.y, angvel.z);
    // Qᵀ(F, T) and Qᵀ(v, ω) column by column, then v + Q Δ: written out so that they are
    // inlined into the dispatched step (nalgebra's generic `tr_mul` was a call, 4 % of a
    // step).
    let q = bm.q.as_slice(); // column-major: column k is q[6k..6k + 6]
    let mut out = v6;
    for k in 0..6 {
        let col = &q[6 * k..6 * k + 6];
        let (mut fk, mut vk) = (0.0, 0.0);
        for i in 0..6 {
            fk += col[i] * f6[i];
            vk += col[i] * v6[i];
        }
        if damping != 0.0 {
            fk -= damping * fk.abs() * vk.signum_or_zero();
        }
        let dk = fk * bm.inv_lambda[k] * dt;
        for i in 0..6 {
            out[i] += col[i] * dk;
        }
    }
    let mut vel = Vec3::new(out[0], out[1], out[2]);
    if y == YConstraint::Held {
        vel.y = 0.0;
    }
    (vel, Vec3::new(out[3], out[4], out[5]))
}

#[cfg(test)]
mod tests {
    use super::super::state::rotation_increment;
    use super::*;
    use nalgebra::UnitQuaternion;

    /// The series agrees with the trigonometric form to rounding over the range it covers,
    /// and the two forms meet at the switch.
    #[test]
    fn rotation_increment_matches_the_exponential_map() {
        for &theta in &[0.0, 1e-12, 1e-8, 1e-6, 1e-4, 5e-4, 9.99e-4, 1.001e-3, 0.1, 1.0] {
            for axis in [Vec3::x(), Vec3::new(1.0, -2.0, 0.5).normalize()] {
                let phi = axis * theta;
                let q = rotation_increment(phi);
                let r = UnitQuaternion::from_scaled_axis(phi);
                let d = (q.coords - r.coords).norm();
                assert!(d <= 4.0 * f64::EPSILON, "θ = {theta}: {d:e}");
                assert!((q.coords.norm() - 1.0).abs() <= 4.0 * f64::EPSILON);
            }
        }
    }
}
