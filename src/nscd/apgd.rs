//! The accelerated projected gradient (APGD) of a step of motion: Nesterov's method on the
//! step's contact problem, with De Saxcé's shift for Coulomb's non-associated friction,
//! stopped by the natural-map residual ([`super::nsgs::natural_residual`]).
//!
//! # Why
//!
//! Gauss–Seidel ([`super::nsgs`]) solves one contact point at a time with its neighbours
//! held, so a correction travels one contact per sweep: on a wall of hundreds of blocks
//! what is left after tens of sweeps is smooth (a course moving as a whole, a stone on a
//! light wedge) and the natural-map residual falls only as about 1/k (docs/nscd.md, "What
//! the sweeps leave on a large wall"). A gradient step moves every impulse at once, and
//! Nesterov's momentum turns the 1/k of a plain gradient into 1/k² on a convex problem:
//! the smooth error that Gauss–Seidel carries one contact at a time is what momentum
//! removes. After Mazhar, Heyn, Negrut & Tasora (ACM TOG 34(3), 2015; Project Chrono's
//! `ChSolverAPGD`), here with a diagonal preconditioner and the residual of the Coulomb
//! problem itself as the stopping rule.
//!
//! # The problem
//!
//! With `u_f` the relative velocities of the free motion (with Signorini's term) and `W`
//! the Delassus operator, the step's impulses `r` (one per contact point, local frames)
//! satisfy Signorini–Coulomb at `u = W r + u_f`. With the shift `s_α = μ ‖u_{t,α}‖` held,
//! that is the optimality condition of the convex cone program
//!
//! ```text
//! min  f_s(r) = ½ rᵀ W r + Σ_α (u_{f,α} + s_α e_n) · r_α      over r_α ∈ K_μ (Coulomb's cone)
//! ```
//!
//! (De Saxcé & Feng 1998: the bipotential's fixed point; Acary, Brémond & Huber 2018).
//! APGD minimizes it; the shift is updated from the iterate every
//! [`SHIFT_EVERY`] iterations, and at a fixed point the natural map of Coulomb's law
//! vanishes. `W r` is never formed: the impulses are summed into each body's impulse and
//! moment (`Hᵀ r`), which give its velocity change and `½ rᵀ W r` (the kinetic energy of
//! that change); the relative velocities follow point by point.
//!
//! # The iteration
//!
//! Preconditioned by `N = diag(1 / w̄_α)` (`w̄_α = tr W_αα / 3`: a light wedge's point
//! moves as far as a heavy stone's per unit of its own velocity), from the warm start `r₀`:
//!
//! ```text
//! g = ∇f_s(y_k);  r_{k+1} = Π_K(y_k − N g / L)   (L doubled until f_s(r_{k+1}) ≤ f_s(y_k) + g·d + ½ L ‖d‖²_{N⁻¹})
//! θ_{k+1} = θ_k (√(θ_k² + 4) − θ_k) / 2,  β = θ_k (1 − θ_k) / (θ_k² + θ_{k+1})
//! y_{k+1} = r_{k+1} + β (r_{k+1} − r_k)    (restart y = r, θ = 1 when g · (r_{k+1} − r_k) > 0)
//! L ← 0.9 L
//! ```
//!
//! The natural-map residual is read every [`SHIFT_EVERY`] iterations; the step ends when
//! it is at most [`super::NscdParams::natural_tolerance`], or keeps the iterate of least
//! residual when the budget runs out.

use super::delassus::{PointRows, TABLE};
use super::local;
use super::nsgs::{natural_residual, BodyState, SweepOutcome};
use crate::math::Vec3;

/// Iterations between two readings of the natural-map residual and two updates of the
/// shift `s_α = μ ‖u_{t,α}‖`.
pub const SHIFT_EVERY: u32 = 5;

/// Scratch of the iteration, kept across steps to avoid allocations.
#[derive(Debug, Clone, Default)]
pub struct ApgdScratch {
    vfree: Vec<Vec3>,
    wfree: Vec<Vec3>,
    /// Relative velocity of every point in the free motion, with Signorini's term.
    uf: Vec<Vec3>,
    /// De Saxcé's shift of every point, m/s.
    shift: Vec<f64>,
    /// `w̄_α`, s/kg.
    wbar: Vec<f64>,
    /// Bodies' impulses and moments of impulse (table frame).
    impulse_sum: Vec<Vec3>,
    moment_sum: Vec<Vec3>,
    /// The extrapolated point y, the gradient, the candidate, the last iterate and the best.
    y: Vec<Vec3>,
    grad: Vec<Vec3>,
    candidate: Vec<Vec3>,
    last: Vec<Vec3>,
    best: Vec<Vec3>,
}

/// De Saxcé's shift `μ ‖u_t‖` of a point at relative velocity `u` (local frame, m/s).
#[inline]
pub(super) fn shift_of(u: &Vec3, mu: f64) -> f64 {
    mu * (u.y * u.y + u.z * u.z).sqrt()
}

impl ApgdScratch {
    /// Sets the bodies' velocities to those of the impulses `r` (the free velocities plus
    /// `M⁻¹ Hᵀ r`) and returns `½ rᵀ W r`, J (the kinetic energy of the velocity change).
    fn velocities(&mut self, rows: &[PointRows], r: &[Vec3], b: &mut BodyState<'_>) -> f64 {
        let n = b.vel.len();
        self.impulse_sum.clear();
        self.impulse_sum.resize(n, Vec3::zeros());
        self.moment_sum.clear();
        self.moment_sum.resize(n, Vec3::zeros());
        for (row, ri) in rows.iter().zip(r) {
            let pw = row.frame * ri;
            self.impulse_sum[row.b] += pw;
            self.moment_sum[row.b] += row.r_b.cross(&pw);
            if row.a != TABLE {
                self.impulse_sum[row.a] -= pw;
                self.moment_sum[row.a] -= row.r_a.cross(&pw);
            }
        }
        let mut twice = 0.0;
        for k in 0..n {
            let dv = b.inv_m[k].component_mul(&self.impulse_sum[k]);
            let dw = b.inv_i[k] * self.moment_sum[k];
            twice += self.impulse_sum[k].dot(&dv) + self.moment_sum[k].dot(&dw);
            b.vel[k] = self.vfree[k] + dv;
            b.angvel[k] = self.wfree[k] + dw;
        }
        0.5 * twice
    }

    /// The linear part of `f_s` at `r`.
    fn linear(&self, r: &[Vec3]) -> f64 {
        r.iter().zip(&self.uf).zip(&self.shift).map(|((ri, u), s)| u.dot(ri) + s * ri.x).sum()
    }

    /// Updates the shift from the bodies' velocities (those of the iterate).
    fn update_shift(&mut self, rows: &[PointRows], b: &BodyState<'_>) {
        for (s, row) in self.shift.iter_mut().zip(rows) {
            *s = shift_of(&row.velocity(b.vel, b.angvel), row.mu);
        }
    }
}

/// APGD on the step's contact problem from the impulses `impulse` (local frames, N·s; the
/// warm start, already applied to `bodies`' velocities), until the natural-map residual is
/// at most `tolerance` or `max_iterations` iterations; `gh` is g h (m/s). The impulses and
/// velocities left are the last iterate's when it converged, else those of least residual.
/// `SweepOutcome::sweeps` counts iterations; `SweepOutcome::quad` is the natural-map residual.
pub fn solve(
    rows: &[PointRows],
    impulse: &mut [Vec3],
    b: &mut BodyState<'_>,
    tolerance: f64,
    max_iterations: u32,
    gh: f64,
    st: &mut ApgdScratch,
) -> SweepOutcome {
    let m = rows.len();
    // The free velocities: the warm start taken back out.
    st.vfree.clear();
    st.vfree.extend_from_slice(b.vel);
    st.wfree.clear();
    st.wfree.extend_from_slice(b.angvel);
    for (row, r) in rows.iter().zip(impulse.iter()) {
        if *r != Vec3::zeros() {
            row.apply(&-r, &mut st.vfree, &mut st.wfree, b.inv_m, b.inv_i);
        }
    }
    st.uf.clear();
    st.wbar.clear();
    for row in rows {
        let mut u = row.velocity(&st.vfree, &st.wfree);
        u.x += row.bias;
        st.uf.push(u);
        st.wbar.push((row.w.trace() / 3.0).max(f64::MIN_POSITIVE));
    }
    st.last.clear();
    st.last.extend(rows.iter().zip(impulse.iter()).map(|(row, r)| local::project(r, row.mu)));
    let last = std::mem::take(&mut st.last);
    st.velocities(rows, &last, b);
    st.last = last;
    st.shift.clear();
    st.shift.resize(m, 0.0);
    st.update_shift(rows, b);
    let mut residual = natural_residual(rows, &st.last, b.vel, b.angvel, gh);
    let mut best = residual;
    st.best.clone_from(&st.last);
    let finish = |st: &ApgdScratch, impulse: &mut [Vec3], sweeps: u32, converged: bool, residual: f64| {
        impulse.copy_from_slice(if converged { &st.last } else { &st.best });
        SweepOutcome { sweeps, converged, residual_m_per_s: 0.0, quad: residual }
    };
    if residual <= tolerance {
        return finish(st, impulse, 0, true, residual);
    }
    st.y.clone_from(&st.last);
    let (mut theta, mut lipschitz) = (1.0f64, 1.0f64);
    for it in 1..=max_iterations {
        // The gradient at y: its relative velocities with the shift.
        let y = std::mem::take(&mut st.y);
        let f_y = st.velocities(rows, &y, b) + st.linear(&y);
        st.grad.clear();
        for (k, row) in rows.iter().enumerate() {
            let mut u = row.velocity(b.vel, b.angvel);
            u.x += row.bias + st.shift[k];
            st.grad.push(u);
        }
        // The projected step, L doubled until the quadratic bound holds.
        let mut candidate = std::mem::take(&mut st.candidate);
        for _ in 0..60 {
            candidate.clear();
            let (mut g_d, mut d_d) = (0.0, 0.0);
            for k in 0..m {
                let c = local::project(&(y[k] - st.grad[k] / (lipschitz * st.wbar[k])), rows[k].mu);
                let d = c - y[k];
                g_d += st.grad[k].dot(&d);
                d_d += st.wbar[k] * d.norm_squared();
                candidate.push(c);
            }
            let f_c = st.velocities(rows, &candidate, b) + st.linear(&candidate);
            if f_c <= f_y + g_d + 0.5 * lipschitz * d_d + 1e-14 * f_y.abs() {
                break;
            }
            lipschitz *= 2.0;
        }
        // Nesterov's extrapolation, restarted when the step goes uphill.
        let theta_next = 0.5 * theta * ((theta * theta + 4.0).sqrt() - theta);
        let beta = theta * (1.0 - theta) / (theta * theta + theta_next);
        let uphill: f64 = (0..m).map(|k| st.grad[k].dot(&(candidate[k] - st.last[k]))).sum();
        let mut y = y;
        if uphill > 0.0 {
            y.copy_from_slice(&candidate);
            theta = 1.0;
        } else {
            for k in 0..m {
                y[k] = candidate[k] + beta * (candidate[k] - st.last[k]);
            }
            theta = theta_next;
        }
        st.y = y;
        st.last.copy_from_slice(&candidate);
        st.candidate = candidate;
        lipschitz *= 0.9;
        if it % SHIFT_EVERY == 0 || it == max_iterations {
            // The bodies' velocities are the candidate's (the last evaluation).
            residual = natural_residual(rows, &st.last, b.vel, b.angvel, gh);
            if residual <= tolerance {
                return finish(st, impulse, it, true, residual);
            }
            if residual < best {
                best = residual;
                st.best.copy_from_slice(&st.last);
            }
            st.update_shift(rows, b);
        }
    }
    let best_impulse = std::mem::take(&mut st.best);
    st.velocities(rows, &best_impulse, b);
    st.best = best_impulse;
    finish(st, impulse, max_iterations, false, best)
}
