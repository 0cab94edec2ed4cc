//! Per-degree-of-freedom constraints of a body in the contact dynamics
//! ([`crate::dem::constraint::DofConstraint`]): held translations at an anchor, an imposed
//! displacement, held rotations.
//!
//! # Elimination of the held degrees of freedom
//!
//! A constrained body's velocity `q = (v, ω)` (centroid velocity, m/s; angular velocity,
//! rad/s; table frame) lies on the affine set `G q = g` of its constraint: one row
//! `e_iᵀ v + (a × e_i)ᵀ ω = u̇_i` per held translation i (the anchor's velocity along i, `a`
//! the anchor from the centroid in the table frame, m), one row `e_jᵀ ω = 0` per held
//! rotation j. Its free velocities are `q = q_p + N z`: `q_p` the imposed velocity (`v_i =
//! u̇_i` on the held axes, nothing else) and the columns of `N` a basis of `G q = 0`, one per
//! free degree of freedom:
//!
//! * a free translation i: `(e_i, 0)`;
//! * a free rotation j: `ω = e_j` and, on each held translation axis i, `v_i = −(e_j × a)_i`
//!   (the rotation about the anchor, which leaves it in place along the held axes).
//!
//! Newton–Euler over the step projected on the free directions, `Nᵀ M (q⁺ − q⁻) = Nᵀ (h F +
//! Hᵀ r)` (M = diag(m I, I_c) the mass matrix, F the smooth load, `Hᵀ r` the contact
//! impulses), gives
//!
//! ```text
//! q⁺ = q_p + K M (q⁻ − q_p) + K (h F + Hᵀ r),      K = N (Nᵀ M N)⁻¹ Nᵀ   (6 × 6, PSD)
//! ```
//!
//! `K` is the body's mobility in place of `M⁻¹`: the Delassus operator is built on the free
//! directions only (`W = H K Hᵀ`), the held directions carry no contact impulse, and the
//! imposed velocity enters as a known term of the free velocity (as a prescribed degree of
//! freedom is eliminated from the velocity unknowns: Acary & Brogliato 2008, §10.1; the
//! "driven" degrees of freedom of LMGC90's rigid bodies, Dubois et al. 2018, are the case
//! of an anchor at the centroid). `K M` is the M-orthogonal projector on the free
//! directions, so that a velocity carried from the last step (whose anchor has turned) is
//! put back on the constraint.
//!
//! An imposed displacement is a held translation whose target the driver moves
//! ([`DofConstraint::set_target`]): each step imposes the anchor's velocity `u̇_i = (x_i −
//! anchor_i) / h` that brings it to the target over the step, and the anchor is put back
//! on its target after the step ([`DofConstraint::place`]), so that the rotation of the
//! anchor within a step does not drift the held coordinate.

use crate::dem::constraint::DofConstraint;
use crate::dem::state::Body;
use crate::math::{Mat3, Vec3};
use nalgebra::{DMatrix, Matrix6, Vector6};

/// The mobility of a constrained body over one step (see the module doc): `K` as its 3 × 3
/// blocks and the imposed velocity `q_p`. Table frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Held {
    /// `K_vv`: centroid velocity per impulse, 1/kg.
    pub vv: Mat3,
    /// `K_vω`: centroid velocity per angular impulse, 1/(kg·m); `K_ωv = K_vωᵀ`.
    pub vw: Mat3,
    /// `K_ωω`: angular velocity per angular impulse, 1/(kg·m²).
    pub ww: Mat3,
    /// The imposed centroid velocity `q_p`'s translation, m/s (its rotation is zero).
    pub imposed: Vec3,
    /// The body's mass matrix `M = diag(m I, I_c)`, table frame (kg, kg·m²).
    mass: Matrix6<f64>,
    /// The rows `G` of the constraint on a velocity change `δq = (δv, δω)`, `G δq = 0`:
    /// `(e_i, a × e_i)` per held translation i (the anchor's velocity along i), `(0, e_j)`
    /// per held rotation j; the first [`Self::held_rows`] are set.
    rows: [Vector6<f64>; 6],
    /// The number of held degrees of freedom.
    held_rows: usize,
}

impl Held {
    /// The mobility of `body` (at its current pose) under `constraint` for a step of length
    /// `h` (s, > 0).
    pub fn new(constraint: &DofConstraint, body: &Body, h: f64) -> Held {
        let a = body.rot_mat * constraint.anchor;
        let anchor = body.pos + a;
        let mut columns: Vec<Vector6<f64>> = Vec::with_capacity(6);
        let mut imposed = Vec3::zeros();
        let (mut rows, mut held_rows) = ([Vector6::zeros(); 6], 0);
        for i in 0..3 {
            if constraint.translation[i].is_some() {
                let e = Vec3::ith(i, 1.0);
                let m = a.cross(&e);
                rows[held_rows] = Vector6::new(e.x, e.y, e.z, m.x, m.y, m.z);
                held_rows += 1;
            }
        }
        for j in 0..3 {
            if constraint.rotation[j] {
                rows[held_rows][3 + j] = 1.0;
                held_rows += 1;
            }
        }
        for i in 0..3 {
            match constraint.translation[i] {
                None => {
                    let mut n = Vector6::zeros();
                    n[i] = 1.0;
                    columns.push(n);
                }
                Some(x) => imposed[i] = (x - anchor[i]) / h,
            }
        }
        for j in 0..3 {
            if constraint.rotation[j] {
                continue;
            }
            let mut n = Vector6::zeros();
            n[3 + j] = 1.0;
            let e = Vec3::ith(j, 1.0);
            let turn = -e.cross(&a);
            for i in 0..3 {
                if constraint.translation[i].is_some() {
                    n[i] = turn[i];
                }
            }
            columns.push(n);
        }
        let inertia = body.rot_mat * body.inertia * body.rot_mat.transpose();
        let mut mass = Matrix6::zeros();
        for i in 0..3 {
            mass[(i, i)] = body.mass;
        }
        mass.fixed_view_mut::<3, 3>(3, 3).copy_from(&inertia);
        let k = if columns.is_empty() {
            Matrix6::zeros()
        } else {
            let r = columns.len();
            let n: DMatrix<f64> = DMatrix::from_fn(6, r, |i, j| columns[j][i]);
            let m: DMatrix<f64> = DMatrix::from_fn(6, 6, |i, j| mass[(i, j)]);
            let reduced = n.transpose() * m * &n;
            let inv = reduced.cholesky().map_or_else(|| DMatrix::zeros(r, r), |c| c.inverse());
            let k: DMatrix<f64> = &n * inv * n.transpose();
            Matrix6::from_fn(|i, j| 0.5 * (k[(i, j)] + k[(j, i)]))
        };
        Held {
            vv: k.fixed_view::<3, 3>(0, 0).into_owned(),
            vw: k.fixed_view::<3, 3>(0, 3).into_owned(),
            ww: k.fixed_view::<3, 3>(3, 3).into_owned(),
            imposed,
            mass,
            rows,
            held_rows,
        }
    }

    /// The body's mass matrix `M = diag(m I, I_c)`, table frame (kg, kg·m²).
    pub fn mass(&self) -> &Matrix6<f64> {
        &self.mass
    }

    /// The constraint's rows `G` (`G δq = 0` for every velocity change the constraint
    /// allows, `δq = (δv, δω)` in m/s and rad/s, table frame): one per held degree of
    /// freedom.
    pub fn rows(&self) -> &[Vector6<f64>] {
        &self.rows[..self.held_rows]
    }

    /// The velocity change `K (p, m)` of an impulse `p` (N·s, at the centroid) and an
    /// angular impulse `m` (N·m·s, about it): (Δv m/s, Δω rad/s).
    #[inline]
    pub fn apply(&self, p: &Vec3, m: &Vec3) -> (Vec3, Vec3) {
        (self.vv * p + self.vw * m, self.vw.tr_mul(p) + self.ww * m)
    }

    /// The velocity `q_p + K M (q − q_p)` of the start of a step: the velocity `(v, w)`
    /// (m/s, rad/s) carried from the last step put on the step's constraint.
    pub fn project(&self, v: &Vec3, w: &Vec3) -> (Vec3, Vec3) {
        let d = Vector6::new(v.x - self.imposed.x, v.y - self.imposed.y, v.z - self.imposed.z, w.x, w.y, w.z);
        let md = self.mass * d;
        let (dv, dw) = self.apply(&md.fixed_rows::<3>(0).into_owned(), &md.fixed_rows::<3>(3).into_owned());
        (self.imposed + dv, dw)
    }

    /// The diagonal Delassus block `Jᵀ K J` of a contact point on this body, with the
    /// point's frame `e` (columns n, t₁, t₂) and lever arm `r` (m): `J = [E; C]`, `C = [r × n,
    /// r × t₁, r × t₂]`; s/kg.
    pub fn block(&self, e: &Mat3, r: &Vec3) -> Mat3 {
        let c = Mat3::from_columns(&[r.cross(&e.column(0)), r.cross(&e.column(1)), r.cross(&e.column(2))]);
        let ev = e.transpose() * (self.vv * e + self.vw * c);
        let cw = c.transpose() * (self.vw.transpose() * e + self.ww * c);
        ev + cw
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ConvexBlock;

    fn body() -> Body {
        let v: Vec<Vec3> = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 0.4, 0.0], [0.0, 0.4, 0.0]]
            .iter()
            .flat_map(|p| [Vec3::new(p[0], p[1], p[2]), Vec3::new(p[0], p[1], 0.3)])
            .collect();
        let shape = ConvexBlock::from_vertices(&v).unwrap();
        let mut b = Body::new("beam".into(), &shape, 2000.0, 0, false);
        b.rotate(Vec3::new(0.02, -0.05, 0.01));
        b
    }

    /// Whatever the impulse, the velocity change leaves the anchor still along the held
    /// axes and the held rotations at zero; and a free body's mobility is `M⁻¹`.
    #[test]
    fn an_impulse_does_not_move_the_held_degrees_of_freedom() {
        let b = body();
        let anchor = Vec3::new(0.1, 0.0, 0.6);
        let c = DofConstraint { anchor, ..DofConstraint::free() }
            .hold_translation(&b, 0)
            .hold_translation(&b, 1)
            .hold_rotation(0)
            .hold_rotation(2);
        let held = Held::new(&c, &b, 1e-3);
        let a = b.rot_mat * anchor;
        for (p, m) in [(Vec3::new(3.0, -1.0, 2.0), Vec3::new(0.5, 0.7, -0.2)), (Vec3::x(), Vec3::zeros())] {
            let (dv, dw) = held.apply(&p, &m);
            let at_anchor = dv + dw.cross(&a);
            assert!(at_anchor.x.abs() < 1e-15 && at_anchor.y.abs() < 1e-15, "{at_anchor}");
            assert!(dw.x.abs() < 1e-15 && dw.z.abs() < 1e-15, "{dw}");
        }
        let free = Held::new(&DofConstraint::free(), &b, 1e-3);
        let inv_i = b.rot_mat * b.inv_inertia * b.rot_mat.transpose();
        assert!((free.vv - Mat3::identity() / b.mass).norm() < 1e-12 / b.mass);
        assert!((free.ww - inv_i).norm() < 1e-9 * inv_i.norm());
        assert!(free.vw.norm() < 1e-12 * inv_i.norm());
    }

    /// The projection of a velocity puts the anchor at the imposed velocity along the held
    /// axes, and keeps a velocity already on the constraint.
    #[test]
    fn the_projection_imposes_the_anchor_velocity() {
        let b = body();
        let anchor = Vec3::new(0.0, 0.0, 0.6);
        let mut c = DofConstraint { anchor, ..DofConstraint::free() }.hold_translation(&b, 0).hold_rotation(2);
        let x0 = c.anchor_world(&b).x;
        c.set_target(0, x0 + 2e-6);
        let held = Held::new(&c, &b, 1e-3);
        let a = b.rot_mat * anchor;
        let (v, w) = held.project(&Vec3::new(0.3, 0.1, -0.2), &Vec3::new(0.1, 0.4, 0.3));
        assert!(((v + w.cross(&a)).x - 2e-3).abs() < 1e-12, "{v} {w}");
        assert!(w.z.abs() < 1e-15);
        let (v2, w2) = held.project(&v, &w);
        assert!((v2 - v).norm() < 1e-14 && (w2 - w).norm() < 1e-14);
    }
}
