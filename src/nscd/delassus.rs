//! The Delassus operator `W = H M⁻¹ Hᵀ` of rigid bodies, point by point.
//!
//! At a contact point p between bodies A and B, with local frame `E = [n t₁ t₂]` (columns,
//! table frame) and lever arms `r_A = p − x_A`, `r_B = p − x_B` (m), the relative velocity
//! in the local frame is
//!
//! ```text
//! u = Eᵀ (v_B − v_A) + C_Bᵀ ω_B − C_Aᵀ ω_A,     C_X = [r_X × n, r_X × t₁, r_X × t₂]
//! ```
//!
//! (the rows `H` of the point), and an impulse `r` (local, on B; −r on A) changes the
//! velocities by `Δv_B = M_B⁻¹ E r`, `Δω_B = I_B⁻¹ C_B r` (and the opposite, with A's
//! inverses, for A). The diagonal block of the point is therefore
//!
//! ```text
//! W = Eᵀ (M_A⁻¹ + M_B⁻¹) E + C_Aᵀ I_A⁻¹ C_A + C_Bᵀ I_B⁻¹ C_B      (3 × 3, s/kg)
//! ```
//!
//! with `M⁻¹` the diagonal of inverse masses per axis (0 on an axis a restraint holds, 0
//! for the table and fixed blocks) and `I⁻¹` the inverse inertia in the table frame. The
//! off-diagonal blocks of W are never formed: the Gauss–Seidel loop keeps the bodies'
//! velocities up to date instead (each point reads `u` from them and writes its impulse
//! change back), which is the same iteration on `W` at the cost of the points only.

use super::held::Held;
use crate::math::{Mat3, Vec3};

/// No body: the table side of a table contact.
pub const TABLE: usize = usize::MAX;

/// The rows of one contact point for one step: frame, lever arms and the diagonal
/// Delassus block with its inverse. The inverse masses and inertias are the bodies'
/// (passed to [`Self::apply`]), so that a point is small.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointRows {
    /// Body A, or [`TABLE`].
    pub a: usize,
    /// Body B.
    pub b: usize,
    /// Local frame `E = [n t₁ t₂]`, columns, table frame.
    pub frame: Mat3,
    /// Lever arm `r_A = p − x_A`, m (zero for the table).
    pub r_a: Vec3,
    /// Lever arm `r_B = p − x_B`, m.
    pub r_b: Vec3,
    /// The diagonal Delassus block W, s/kg (velocity per impulse).
    pub w: Mat3,
    /// W⁻¹ (zeros if W is singular).
    pub w_inv: Mat3,
    /// Friction coefficient μ ([`super::contacts::HELD_FRICTION`] at a held point).
    pub mu: f64,
    /// Normal term b of Signorini's condition `uₙ + b ≥ 0`, m/s.
    pub bias: f64,
}

impl PointRows {
    /// The rows of a point at `p` (table frame, m) with unit normal `n`, between body `a`
    /// ([`TABLE`] for the table) and `b`, from the bodies' centroids `x`, inverse masses per
    /// axis `inv_m` and inverse inertias in the table frame `inv_i`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(a: usize, b: usize, p: Vec3, n: Vec3, x: &[Vec3], inv_m: &[Vec3], inv_i: &[Mat3], mu: f64) -> PointRows {
        let (t1, t2) = crate::geometry::polygon::plane_basis(&n);
        let frame = Mat3::from_columns(&[n, t1, t2]);
        let side = |k: usize| {
            if k == TABLE {
                (Vec3::zeros(), Mat3::zeros(), Mat3::zeros(), Mat3::zeros())
            } else {
                let r = p - x[k];
                let c = Mat3::from_columns(&[r.cross(&n), r.cross(&t1), r.cross(&t2)]);
                (r, c, Mat3::from_diagonal(&inv_m[k]) * frame, inv_i[k] * c)
            }
        };
        let (r_a, c_a, m_a, i_a) = side(a);
        let (r_b, c_b, m_b, i_b) = side(b);
        let w = frame.transpose() * (m_a + m_b) + c_a.transpose() * i_a + c_b.transpose() * i_b;
        let w = 0.5 * (w + w.transpose());
        let w_inv = w.try_inverse().unwrap_or_else(Mat3::zeros);
        PointRows { a, b, frame, r_a, r_b, w, w_inv, mu, bias: 0.0 }
    }

    /// The relative velocity of B with respect to A at the point, local frame, m/s:
    /// `Eᵀ((v_B + ω_B × r_B) − (v_A + ω_A × r_A))`.
    #[inline(always)]
    pub fn velocity(&self, vel: &[Vec3], angvel: &[Vec3]) -> Vec3 {
        let mut d = vel[self.b] + angvel[self.b].cross(&self.r_b);
        if self.a != TABLE {
            d -= vel[self.a] + angvel[self.a].cross(&self.r_a);
        }
        self.frame.tr_mul(&d)
    }

    /// Adds to the diagonal block the terms of a constrained body on either side (its
    /// mobility `K` in `held`, [`Held::block`]; its `inv_m` and `inv_i` are zero, so that
    /// [`Self::new`] left it out) and inverts it again. A point between free bodies is left
    /// as it is.
    pub fn couple(&mut self, held: &[Option<Held>]) {
        let mut w = self.w;
        let mut changed = false;
        if let Some(h) = &held[self.b] {
            w += h.block(&self.frame, &self.r_b);
            changed = true;
        }
        if self.a != TABLE {
            if let Some(h) = &held[self.a] {
                w += h.block(&self.frame, &self.r_a);
                changed = true;
            }
        }
        if changed {
            self.w = 0.5 * (w + w.transpose());
            self.w_inv = self.w.try_inverse().unwrap_or_else(Mat3::zeros);
        }
    }

    /// Applies the impulse `dr` (local, on B; −dr on A) to the bodies' velocities, with
    /// their inverse masses per axis `inv_m` (1/kg) and inverse inertias `inv_i` (table
    /// frame, 1/(kg·m²)): `Δv_B = M_B⁻¹ E dr`, `Δω_B = I_B⁻¹ (r_B × E dr)`; a constrained
    /// body (`held`, [`super::held`]) moves by its mobility `K` instead.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn apply(
        &self,
        dr: &Vec3,
        vel: &mut [Vec3],
        angvel: &mut [Vec3],
        inv_m: &[Vec3],
        inv_i: &[Mat3],
        held: &[Option<Held>],
    ) {
        let pw = self.frame * dr;
        vel[self.b] += inv_m[self.b].component_mul(&pw);
        angvel[self.b] += inv_i[self.b] * self.r_b.cross(&pw);
        if let Some(h) = &held[self.b] {
            let (dv, dw) = h.apply(&pw, &self.r_b.cross(&pw));
            vel[self.b] += dv;
            angvel[self.b] += dw;
        }
        if self.a != TABLE {
            vel[self.a] -= inv_m[self.a].component_mul(&pw);
            angvel[self.a] -= inv_i[self.a] * self.r_a.cross(&pw);
            if let Some(h) = &held[self.a] {
                let (dv, dw) = h.apply(&pw, &self.r_a.cross(&pw));
                vel[self.a] -= dv;
                angvel[self.a] -= dw;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// W of a point on a free body equals the velocity change per unit impulse computed
    /// directly from Newton–Euler, column by column.
    #[test]
    fn the_delassus_block_is_the_velocity_response_to_a_unit_impulse() {
        let x = [Vec3::new(0.1, -0.2, 0.3)];
        let inv_m = [Vec3::repeat(0.5)];
        let i = Mat3::new(2.0, 0.1, 0.0, 0.1, 3.0, 0.2, 0.0, 0.2, 4.0);
        let inv_i = [i.try_inverse().unwrap()];
        let p = Vec3::new(0.4, 0.1, -0.1);
        let n = Vec3::new(0.2, 0.3, 0.9).normalize();
        let rows = PointRows::new(TABLE, 0, p, n, &x, &inv_m, &inv_i, 0.5);
        for k in 0..3 {
            let mut e = Vec3::zeros();
            e[k] = 1.0;
            let (mut v, mut w) = ([Vec3::zeros()], [Vec3::zeros()]);
            rows.apply(&e, &mut v, &mut w, &inv_m, &inv_i, &[None]);
            let u = rows.velocity(&v, &w);
            // Direct: impulse P = E e at p on the body.
            let pw = rows.frame * e;
            let dv = pw * 0.5;
            let dw = inv_i[0] * (p - x[0]).cross(&pw);
            let direct = rows.frame.transpose() * (dv + dw.cross(&(p - x[0])));
            assert!((u - direct).norm() < 1e-14, "{u} {direct}");
            assert!((rows.w.column(k) - direct).norm() < 1e-14);
        }
    }
}
