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

use super::state::Body;
use crate::Vec3;
use nalgebra::UnitQuaternion;

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
#[inline]
pub fn advance(b: &mut Body, force: Vec3, torque: Vec3, dt: f64, damping: f64, y: YConstraint) {
    if b.fixed {
        b.vel = Vec3::zeros();
        b.angvel = Vec3::zeros();
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
    let dq = UnitQuaternion::from_scaled_axis(b.angvel * dt);
    b.rot = dq * b.rot;
    b.rot.renormalize_fast();
    b.rot_mat = *b.rot.to_rotation_matrix().matrix();
}
