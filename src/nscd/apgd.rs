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
//! [`SHIFT_EVERY`] iterations (relaxed by [`SHIFT_RELAXATION`] once the residual has
//! risen), and at a fixed point the natural map of Coulomb's law vanishes. `W r` is never
//! formed: the impulses are summed into each body's impulse and moment (`Hᵀ r`), which
//! give its velocity change and `½ rᵀ W r` (the kinetic energy of that change); the
//! relative velocities follow point by point.
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
//!
//! # The work of an iteration
//!
//! Two passes over the points: the first projects the step from `y` and sums the
//! candidate's impulses per body (`Hᵀ r`; again for each doubling of L), the second reads
//! the candidate's relative velocities (`H v`) and, when due, its residual and the new
//! shift. `W r` is linear in `r`, so the relative velocities and the bodies' sums of the
//! next `y = r_{k+1} + β (r_{k+1} − r_k)` are the same combination of the candidate's and
//! the last iterate's, and `f_s(y)` follows from them: no pass evaluates `y`. The passes
//! read a compact copy of each point's rows (frame, lever arms, bodies, μ, the Signorini
//! term, `w̄_α`), so that the SBL wall's 2,424 points and the iteration's vectors stay in
//! a core's second-level cache; the residual reads the Delassus block from the rows, with
//! the same operations as [`super::nsgs::natural_residual`] (bit for bit the same value).
//! L starts each step where the last step's ended.

use super::delassus::{PointRows, TABLE};
use super::local;
use super::nsgs::{BodyState, NaturalSum, SweepOutcome};
use crate::math::{Mat3, Vec3};

/// Iterations between two readings of the natural-map residual and two updates of the
/// shift `s_α = μ ‖u_{t,α}‖`.
pub const SHIFT_EVERY: u32 = 5;

/// The relaxation of the shift's update once a step's residual has risen:
/// `s_α ← s_α + ω (μ ‖u_{t,α}‖ − s_α)`, ω = 0.4.
///
/// The shift's fixed point `s = μ ‖u_t(s)‖` is not a contraction where blocks slide past
/// each other while they rock (docs/nscd.md, "The steps the gradient leaves at its
/// limit"): there the plain update (ω = 1) overshoots, and the residual, down to 1–4e-4
/// within about 100 iterations, wanders about the tolerance. A step updates its shift
/// plainly until a reading of the residual (every [`SHIFT_EVERY`] iterations) is above the
/// one before, and relaxed from then to its end: where the fixed point contracts (a block
/// on a joint of high friction, whose shift is many times its slip velocity) the plain
/// update converges sooner, and the relaxed one has the same fixed point, so a step still
/// ends only when the natural-map residual of its impulses and velocities meets the
/// tolerance (docs/nscd.md, "The shift's relaxed update").
pub const SHIFT_RELAXATION: f64 = 0.4;

/// Scratch of the iteration, kept across steps to avoid allocations.
#[derive(Debug, Clone, Default)]
pub struct ApgdScratch {
    vfree: Vec<Vec3>,
    wfree: Vec<Vec3>,
    /// The points' rows as the iteration reads them (compact: the passes stay in cache).
    points: Vec<Point>,
    /// Relative velocity of every point in the free motion, with Signorini's term.
    uf: Vec<Vec3>,
    /// De Saxcé's shift of every point, m/s.
    shift: Vec<f64>,
    /// The extrapolated point y, the candidate, the last iterate and the best (impulses).
    y: Vec<Vec3>,
    candidate: Vec<Vec3>,
    last: Vec<Vec3>,
    best: Vec<Vec3>,
    /// The relative velocities (with Signorini's term) of y and of the last iterate.
    u_y: Vec<Vec3>,
    u_last: Vec<Vec3>,
    /// The bodies' impulses and moments of impulse (`Hᵀ r`, table frame) of y, of the
    /// candidate and of the last iterate.
    body_y: BodySums,
    body_c: BodySums,
    body_last: BodySums,
    /// The step length's L where the last step ended (the next step starts from it).
    lipschitz: f64,
}

/// A contact point as the iteration reads it: [`PointRows`] without the Delassus block
/// and its inverse (the residual reads them from the rows).
#[derive(Debug, Clone, Copy)]
struct Point {
    frame: Mat3,
    r_a: Vec3,
    r_b: Vec3,
    /// Body A ([`u32::MAX`] for the table) and body B.
    a: u32,
    b: u32,
    mu: f64,
    bias: f64,
    /// `w̄_α = tr W_αα / 3`, s/kg, and its inverse.
    wbar: f64,
    inv_wbar: f64,
    /// `1 / (1 + μ²)`, for the projection on the cone.
    inv_cone: f64,
}

/// No body: the table side of a [`Point`].
const NO_BODY: u32 = u32::MAX;

impl Point {
    fn of(row: &PointRows) -> Point {
        let index = |k: usize| u32::try_from(k).expect("fewer than 2^32 - 1 bodies");
        let wbar = (row.w.trace() / 3.0).max(f64::MIN_POSITIVE);
        Point {
            frame: row.frame,
            r_a: row.r_a,
            r_b: row.r_b,
            a: if row.a == TABLE { NO_BODY } else { index(row.a) },
            b: index(row.b),
            mu: row.mu,
            bias: row.bias,
            wbar,
            inv_wbar: 1.0 / wbar,
            inv_cone: 1.0 / (1.0 + row.mu * row.mu),
        }
    }

    /// The projection of `r` on the point's Coulomb cone (as [`local::project`], with the
    /// point's constants).
    #[inline(always)]
    fn project(&self, r: &Vec3) -> Vec3 {
        // The two cases without the root compared in squares (the cone and its polar).
        let (t2, n2) = (r.y * r.y + r.z * r.z, r.x * r.x);
        let mu2 = self.mu * self.mu;
        if r.x >= 0.0 && t2 <= mu2 * n2 {
            *r
        } else if r.x <= 0.0 && mu2 * t2 <= n2 {
            Vec3::zeros()
        } else {
            let t = t2.sqrt();
            let rn = (r.x + self.mu * t) * self.inv_cone;
            let f = self.mu * rn / t;
            Vec3::new(rn, f * r.y, f * r.z)
        }
    }

    /// The relative velocity at the bodies' velocities with Signorini's term (m/s, local
    /// frame): the same operations as [`PointRows::velocity`] and the bias added.
    #[inline(always)]
    fn relative(&self, vel: &[Vec3], angvel: &[Vec3]) -> Vec3 {
        let b = self.b as usize;
        let mut d = vel[b] + angvel[b].cross(&self.r_b);
        if self.a != NO_BODY {
            let a = self.a as usize;
            d -= vel[a] + angvel[a].cross(&self.r_a);
        }
        let mut u = self.frame.tr_mul(&d);
        u.x += self.bias;
        u
    }
}

/// The impulses and moments of impulse summed per body (`Hᵀ r`), table frame.
#[derive(Debug, Clone, Default)]
struct BodySums {
    impulse: Vec<Vec3>,
    moment: Vec<Vec3>,
}

impl BodySums {
    /// Zeros for `n` bodies.
    fn clear(&mut self, n: usize) {
        self.impulse.clear();
        self.impulse.resize(n, Vec3::zeros());
        self.moment.clear();
        self.moment.resize(n, Vec3::zeros());
    }

    /// Adds the impulse `r` (local frame) of the point `p`.
    #[inline(always)]
    fn add(&mut self, p: &Point, r: &Vec3) {
        let pw = p.frame * r;
        let b = p.b as usize;
        self.impulse[b] += pw;
        self.moment[b] += p.r_b.cross(&pw);
        if p.a != NO_BODY {
            let a = p.a as usize;
            self.impulse[a] -= pw;
            self.moment[a] -= p.r_a.cross(&pw);
        }
    }

    /// `Hᵀ r` of the impulses `r`.
    fn of(&mut self, points: &[Point], r: &[Vec3], n: usize) {
        self.clear(n);
        for (p, ri) in points.iter().zip(r) {
            self.add(p, ri);
        }
    }

    /// `½ rᵀ W r`, J: the kinetic energy of the velocity change `M⁻¹ Hᵀ r`.
    fn energy(&self, b: &BodyState<'_>) -> f64 {
        let mut twice = 0.0;
        for k in 0..self.impulse.len() {
            let mut dv = b.inv_m[k].component_mul(&self.impulse[k]);
            let mut dw = b.inv_i[k] * self.moment[k];
            if let Some(h) = &b.held[k] {
                let (hv, hw) = h.apply(&self.impulse[k], &self.moment[k]);
                dv += hv;
                dw += hw;
            }
            twice += self.impulse[k].dot(&dv) + self.moment[k].dot(&dw);
        }
        0.5 * twice
    }

    /// Sets the bodies' velocities to the free ones plus `M⁻¹ Hᵀ r`.
    fn velocities(&self, b: &mut BodyState<'_>, vfree: &[Vec3], wfree: &[Vec3]) {
        for k in 0..self.impulse.len() {
            b.vel[k] = vfree[k] + b.inv_m[k].component_mul(&self.impulse[k]);
            b.angvel[k] = wfree[k] + b.inv_i[k] * self.moment[k];
            if let Some(h) = &b.held[k] {
                let (hv, hw) = h.apply(&self.impulse[k], &self.moment[k]);
                b.vel[k] += hv;
                b.angvel[k] += hw;
            }
        }
    }

    /// `self + beta (self − other)`, into `out` (the sums are linear in the impulses).
    fn extrapolate(&self, other: &BodySums, beta: f64, out: &mut BodySums) {
        out.impulse.clear();
        out.impulse.extend(self.impulse.iter().zip(&other.impulse).map(|(a, b)| a + beta * (a - b)));
        out.moment.clear();
        out.moment.extend(self.moment.iter().zip(&other.moment).map(|(a, b)| a + beta * (a - b)));
    }
}

/// De Saxcé's shift `μ ‖u_t‖` of a point at relative velocity `u` (local frame, m/s).
#[inline]
pub(super) fn shift_of(u: &Vec3, mu: f64) -> f64 {
    mu * (u.y * u.y + u.z * u.z).sqrt()
}

/// APGD on the step's contact problem from the impulses `impulse` (local frames, N·s; the
/// warm start, already applied to `bodies`' velocities), until the natural-map residual is
/// at most `tolerance` or `max_iterations` iterations; `gh` is g h (m/s). The impulses and
/// velocities left are the last iterate's when it converged, else those of least residual.
/// `SweepOutcome::sweeps` counts iterations; `SweepOutcome::quad` is the natural-map residual.
///
/// Each iteration passes twice over the points: once to project the step from y and sum
/// the candidate's impulses per body (`Hᵀ r`, again for each doubling of L), once to read
/// the candidate's relative velocities (`H v`), with the residual and the shift when they
/// are due. The next y, its relative velocities and its bodies' sums are combinations of
/// the candidate's and the last iterate's (all linear in the impulses). L starts where the
/// last step's ended.
pub fn solve(
    rows: &[PointRows],
    impulse: &mut [Vec3],
    b: &mut BodyState<'_>,
    tolerance: f64,
    max_iterations: u32,
    gh: f64,
    st: &mut ApgdScratch,
) -> SweepOutcome {
    let (m, n) = (rows.len(), b.vel.len());
    // The free velocities: the warm start taken back out.
    st.vfree.clear();
    st.vfree.extend_from_slice(b.vel);
    st.wfree.clear();
    st.wfree.extend_from_slice(b.angvel);
    for (row, r) in rows.iter().zip(impulse.iter()) {
        if *r != Vec3::zeros() {
            row.apply(&-r, &mut st.vfree, &mut st.wfree, b.inv_m, b.inv_i, b.held);
        }
    }
    st.points.clear();
    st.points.extend(rows.iter().map(Point::of));
    st.uf.clear();
    st.uf.extend(st.points.iter().map(|p| p.relative(&st.vfree, &st.wfree)));
    st.last.clear();
    st.last.extend(rows.iter().zip(impulse.iter()).map(|(row, r)| local::project(r, row.mu)));
    st.body_last.of(&st.points, &st.last, n);
    st.body_last.velocities(b, &st.vfree, &st.wfree);
    st.u_last.clear();
    st.shift.clear();
    let mut sum = NaturalSum::default();
    for ((row, p), r) in rows.iter().zip(&st.points).zip(&st.last) {
        let u = p.relative(b.vel, b.angvel);
        sum.add(row, r, &u);
        st.shift.push(shift_of(&u, p.mu));
        st.u_last.push(u);
    }
    let mut residual = sum.residual(gh);
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
    st.u_y.clone_from(&st.u_last);
    st.body_y.clone_from(&st.body_last);
    st.candidate.resize(m, Vec3::zeros());
    // Whether the shift's update is relaxed: from the first reading of the residual above
    // the one before (the plain update overshooting), to the step's end.
    let mut relaxed = false;
    let mut last_reading = residual;
    let mut theta = 1.0f64;
    let mut lipschitz = if st.lipschitz > 0.0 { st.lipschitz } else { 1.0 };
    for it in 1..=max_iterations {
        // The projected step from y along the gradient `u_y + s e_n`, L doubled until the
        // quadratic bound holds.
        let energy_y = st.body_y.energy(b);
        let mut linear_y = 0.0;
        let mut uphill = 0.0;
        for attempt in 0..60 {
            let step = 1.0 / lipschitz;
            st.body_c.clear(n);
            let (mut g_d, mut d_d, mut linear_c) = (0.0, 0.0, 0.0);
            uphill = 0.0;
            for k in 0..m {
                let (p, y, s) = (&st.points[k], st.y[k], st.shift[k]);
                let mut g = st.u_y[k];
                g.x += s;
                let c = p.project(&(y - g * (step * p.inv_wbar)));
                let d = c - y;
                g_d += g.dot(&d);
                d_d += p.wbar * d.norm_squared();
                uphill += g.dot(&(c - st.last[k]));
                let uf = st.uf[k];
                linear_c += uf.dot(&c) + s * c.x;
                if attempt == 0 {
                    linear_y += uf.dot(&y) + s * y.x;
                }
                st.candidate[k] = c;
                st.body_c.add(p, &c);
            }
            let (f_y, f_c) = (energy_y + linear_y, st.body_c.energy(b) + linear_c);
            if f_c <= f_y + g_d + 0.5 * lipschitz * d_d + 1e-14 * f_y.abs() {
                break;
            }
            lipschitz *= 2.0;
        }
        // Nesterov's extrapolation, restarted when the step goes uphill.
        let restart = uphill > 0.0;
        let theta_next = 0.5 * theta * ((theta * theta + 4.0).sqrt() - theta);
        let beta = if restart { 0.0 } else { theta * (1.0 - theta) / (theta * theta + theta_next) };
        theta = if restart { 1.0 } else { theta_next };
        // The candidate's velocities, its residual and shift when due, and the next y.
        st.body_c.velocities(b, &st.vfree, &st.wfree);
        let read = it % SHIFT_EVERY == 0 || it == max_iterations;
        let omega = if relaxed { SHIFT_RELAXATION } else { 1.0 };
        let mut sum = NaturalSum::default();
        for k in 0..m {
            let p = &st.points[k];
            let c = st.candidate[k];
            let u = p.relative(b.vel, b.angvel);
            if read {
                sum.add(&rows[k], &c, &u);
                st.shift[k] += omega * (shift_of(&u, p.mu) - st.shift[k]);
            }
            if restart {
                st.y[k] = c;
                st.u_y[k] = u;
            } else {
                st.y[k] = c + beta * (c - st.last[k]);
                st.u_y[k] = u + beta * (u - st.u_last[k]);
            }
            st.last[k] = c;
            st.u_last[k] = u;
        }
        if restart {
            st.body_y.clone_from(&st.body_c);
        } else {
            st.body_c.extrapolate(&st.body_last, beta, &mut st.body_y);
        }
        std::mem::swap(&mut st.body_last, &mut st.body_c);
        lipschitz *= 0.9;
        if read {
            // The bodies' velocities are the candidate's, now the last iterate.
            residual = sum.residual(gh);
            relaxed |= residual > last_reading;
            last_reading = residual;
            if residual <= tolerance {
                st.lipschitz = lipschitz;
                return finish(st, impulse, it, true, residual);
            }
            if residual < best {
                best = residual;
                st.best.copy_from_slice(&st.last);
            }
        }
    }
    st.lipschitz = lipschitz;
    st.body_c.of(&st.points, &st.best, n);
    st.body_c.velocities(b, &st.vfree, &st.wfree);
    finish(st, impulse, max_iterations, false, best)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nscd::nsgs::natural_residual;

    /// Two boxes stacked on the table (four points each), the top one thrown sideways and
    /// both falling: the gradient's reported residual is [`natural_residual`] of the
    /// impulses and velocities it leaves, bit for bit, and those velocities are the free
    /// ones plus the impulses' (the fused passes never report a residual of another state).
    #[test]
    fn the_reported_residual_is_that_of_the_state_left() {
        let x = [Vec3::new(0.0, 0.0, 0.1), Vec3::new(0.02, 0.0, 0.3)];
        let inv_m = [Vec3::repeat(1.0 / 8.0), Vec3::repeat(1.0 / 2.0)];
        let inv_i =
            [Mat3::from_diagonal(&Vec3::new(30.0, 25.0, 40.0)), Mat3::from_diagonal(&Vec3::new(120.0, 90.0, 150.0))];
        let up = Vec3::z();
        let mut rows = Vec::new();
        for (a, b, z, half) in [(TABLE, 0, 0.0, 0.15), (0, 1, 0.2, 0.08)] {
            for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = Vec3::new(sx * half, sy * 0.6 * half, z);
                rows.push(PointRows::new(a, b, p, up, &x, &inv_m, &inv_i, 0.6));
            }
        }
        let gh = 9.81e-3;
        let vfree = [Vec3::new(0.0, 0.0, -gh), Vec3::new(0.4, 0.1, -gh)];
        let wfree = [Vec3::zeros(), Vec3::new(0.0, 0.5, 0.0)];
        for tolerance in [1e-4, 1e-8] {
            let (mut vel, mut angvel) = (vfree.to_vec(), wfree.to_vec());
            let radius = [0.2, 0.1];
            let held = [None, None];
            let mut b = BodyState {
                vel: &mut vel,
                angvel: &mut angvel,
                inv_m: &inv_m,
                inv_i: &inv_i,
                held: &held,
                radius: &radius,
            };
            let mut impulse = vec![Vec3::zeros(); rows.len()];
            let mut st = ApgdScratch::default();
            let out = solve(&rows, &mut impulse, &mut b, tolerance, 2000, gh, &mut st);
            assert!(out.converged, "tolerance {tolerance:e}: residual {:e} after {}", out.quad, out.sweeps);
            let again = natural_residual(&rows, &impulse, b.vel, b.angvel, gh);
            assert_eq!(out.quad.to_bits(), again.to_bits(), "reported {:e}, recomputed {again:e}", out.quad);
            assert!(again <= tolerance);
            let (mut v, mut w) = (vfree.to_vec(), wfree.to_vec());
            for (row, r) in rows.iter().zip(&impulse) {
                row.apply(r, &mut v, &mut w, &inv_m, &inv_i, &[None, None]);
            }
            for k in 0..2 {
                assert!((v[k] - b.vel[k]).norm() + (w[k] - b.angvel[k]).norm() < 1e-12, "body {k}");
            }
        }
    }
}
