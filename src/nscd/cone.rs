//! The step as one cone program: the finisher of a step of motion that the gradient
//! ([`super::apgd`]) leaves at its iteration limit.
//!
//! # Why
//!
//! On the SBL walls rocking near their capacity, a few steps in a thousand stall under the
//! gradient at a natural-map residual of 1–3e-4 (tolerance 1e-4): the residual reaches
//! about 2e-4 within 200 iterations, then wanders (docs/nscd.md, "The steps left at the
//! limit"). Two errors add up there: the convex problem with De Saxcé's shift held is
//! ill-conditioned (light wedges beside heavy stones, redundant points of a face), so the
//! gradient solves it slowly; and the shift's fixed point `s = μ ‖u_t(s)‖` is not a
//! contraction on head joints sliding while the wall rocks, so updating the shift from the
//! iterate oscillates. This module removes both: each convex problem is solved exactly by
//! an interior-point method, and the shift is updated by Anderson's acceleration.
//!
//! # The program
//!
//! With the shift `s` held, the step's impulses are the multipliers of the cone program in
//! the bodies' velocity changes `δ = v − v_f` (Nodargi & Bisegna, CMAME 2024, one cone
//! program per step; Acary, Brémond & Huber 2018 for the shift):
//!
//! ```text
//! min ½ δᵀ M δ
//! s.t. (uₙ + b + s_α, μ u_t) ∈ K_SOC          every point (second-order cone of dimension 3)
//! ```
//!
//! with `u = u_f + H δ` the point's relative velocity and `M` the bodies' masses and
//! inertias (table frame). The multipliers `z` of the cones give the impulses:
//! `r = (z₀, μ z₁, μ z₂)` (the dual of the scaled cone is Coulomb's cone). A point held
//! against slip is a Coulomb point at [`super::contacts::HELD_FRICTION`].
//!
//! Solved by Clarabel (Goulart & Chen 2024; the interior point of [`crate::limit`]),
//! built once per step; each update of the shift only rewrites `b`.
//!
//! # The shift
//!
//! `G(s) = μ ‖u_t‖` of the program's solution at shift `s`: the step's Coulomb problem is
//! the fixed point `s = G(s)` (De Saxcé & Feng 1998). Plain iteration oscillates on the
//! stalled steps (natural residual 1–4e-4 after 8 updates); Anderson's acceleration
//! (type II, memory [`SHIFT_MEMORY`]; Walker & Ni, SIAM J. Numer. Anal. 49, 2011) takes
//! the combination of the last updates whose residual `G(s) − s` is least. The finisher
//! stops when the natural-map residual ([`super::nsgs::natural_residual`]) is at most the
//! tolerance, or when it stalls: [`STALL_PROGRAMS`] programs in a row without a least
//! residual at least [`PROGRESS`] below the last one. It keeps the impulses of least
//! residual (the incoming ones when no program improved on them). There is no fixed
//! number of programs: near the tolerance the residual of successive programs wanders
//! (1.1–1.8e-4 over 25 programs on one SBL step at 1.0 g) and a new least residual can
//! come 8 programs after the last, so a step is handed back unconverged only once the
//! shift has stopped making progress. The rule ends every step: each new least residual
//! is below `(1 − PROGRESS)` times the last, so at most `ln(r₀ / tol) / −ln(1 − PROGRESS)`
//! of them can come before the tolerance, each within [`STALL_PROGRAMS`] programs.
//!
//! # Measured
//!
//! The SBL preset wall (seed 20210917, realization 0) under `data/motions/synthetic_10s.csv`
//! at 0.9 g and at its own 1.0 g: docs/nscd.md, "The steps left at the limit".

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::{DMatrix, DVector};

use super::apgd::shift_of;
use super::delassus::{PointRows, TABLE};
use super::nsgs::{natural_residual, BodyState, SweepOutcome};
use crate::math::Vec3;

/// Anderson's memory: the number of past shift updates combined.
pub const SHIFT_MEMORY: usize = 5;

/// The finisher stalls after this many cone programs (shift updates) in a row without
/// progress ([`PROGRESS`]).
pub const STALL_PROGRAMS: u32 = 16;

/// Progress: a program's natural-map residual below `(1 − PROGRESS)` times the least so
/// far (a relative fall of 1 %).
pub const PROGRESS: f64 = 0.01;

/// The interior point's iteration limit for one program.
const IPM_ITERATIONS: u32 = 100;

/// The interior point's tolerances (gap, absolute and relative; feasibility).
const IPM_TOLERANCE: f64 = 1e-8;

/// Not used: no free body, or the interior point could not be set up.
fn unchanged(best: f64, tolerance: f64) -> SweepOutcome {
    SweepOutcome { sweeps: 0, converged: best <= tolerance, residual_m_per_s: 0.0, quad: best }
}

/// Finishes a step from the impulses `impulse` (local frames, N·s; already applied to
/// `b`'s velocities) by cone programs with the shift updated by Anderson's acceleration,
/// until the natural-map residual is at most `tolerance` or the shift stalls
/// ([`STALL_PROGRAMS`] programs without [`PROGRESS`]); `gh` is g h (m/s). Leaves the impulses and velocities of least residual.
/// `SweepOutcome::sweeps` counts programs; `SweepOutcome::quad` is the natural-map
/// residual left.
pub fn solve(rows: &[PointRows], impulse: &mut [Vec3], b: &mut BodyState<'_>, tolerance: f64, gh: f64) -> SweepOutcome {
    let incoming = natural_residual(rows, impulse, b.vel, b.angvel, gh);
    if incoming <= tolerance || rows.is_empty() {
        return unchanged(incoming, tolerance);
    }
    let Some(program) = Program::new(rows, impulse, b) else { return unchanged(incoming, tolerance) };
    let mut shift: Vec<f64> = rows.iter().map(|row| shift_of(&row.velocity(b.vel, b.angvel), row.mu)).collect();
    let mut solver = None;
    let mut anderson = Anderson::new(SHIFT_MEMORY);
    let (mut best, mut programs) = (incoming, 0);
    let (mut best_r, mut best_v, mut best_w) = (impulse.to_vec(), b.vel.to_vec(), b.angvel.to_vec());
    let mut stall = Stall::default();
    while !stall.stalled() {
        programs += 1;
        let rhs = program.rhs(rows, &shift);
        let Some(z) = program.solve(&mut solver, &rhs) else { break };
        program.impulses(rows, &z, impulse, b);
        let residual = natural_residual(rows, impulse, b.vel, b.angvel, gh);
        stall.read(residual);
        if residual < best {
            best = residual;
            best_r.copy_from_slice(impulse);
            best_v.copy_from_slice(b.vel);
            best_w.copy_from_slice(b.angvel);
        }
        if residual <= tolerance {
            break;
        }
        let g: Vec<f64> = rows.iter().map(|row| shift_of(&row.velocity(b.vel, b.angvel), row.mu)).collect();
        shift = anderson.next(&shift, &g);
        for s in &mut shift {
            *s = s.max(0.0);
        }
    }
    impulse.copy_from_slice(&best_r);
    b.vel.copy_from_slice(&best_v);
    b.angvel.copy_from_slice(&best_w);
    SweepOutcome { sweeps: programs, converged: best <= tolerance, residual_m_per_s: 0.0, quad: best }
}

/// The finisher's stopping rule short of the tolerance: the least residual of the
/// programs so far and the programs since it last fell by [`PROGRESS`].
#[derive(Debug, Clone, Copy)]
struct Stall {
    least: f64,
    since: u32,
}

impl Default for Stall {
    fn default() -> Stall {
        Stall { least: f64::INFINITY, since: 0 }
    }
}

impl Stall {
    /// Reads a program's natural-map residual.
    fn read(&mut self, residual: f64) {
        if residual < (1.0 - PROGRESS) * self.least {
            self.least = residual;
            self.since = 0;
        } else {
            self.since += 1;
        }
    }

    /// [`STALL_PROGRAMS`] programs in a row without progress.
    fn stalled(&self) -> bool {
        self.since >= STALL_PROGRAMS
    }
}

/// The program of one step: `P`, `A` and the cones (fixed), the free velocities and the
/// free relative velocities of the points (the right-hand side's parts).
struct Program {
    p: CscMatrix<f64>,
    a: CscMatrix<f64>,
    cones: Vec<SupportedConeT<f64>>,
    /// Free velocities (the incoming impulses taken back out).
    vfree: Vec<Vec3>,
    wfree: Vec<Vec3>,
    /// Each point's free relative velocity with Signorini's term, local frame.
    uf: Vec<Vec3>,
    /// The equality rows of the constrained bodies' held degrees of freedom (after the
    /// points' rows).
    equalities: usize,
}

impl Program {
    /// Assembles the program, or `None` without a free degree of freedom. A body
    /// constrained per degree of freedom ([`super::held`]) has its six velocity changes as
    /// unknowns, its whole mass matrix in `P` and its held degrees of freedom as equality
    /// rows `G δ = 0` (a zero cone): the program's optimum is then the velocity change
    /// `K Hᵀ r` of its mobility `K` (Acary & Brogliato 2008, §10.1).
    fn new(rows: &[PointRows], impulse: &[Vec3], b: &BodyState<'_>) -> Option<Program> {
        let mut vfree = b.vel.to_vec();
        let mut wfree = b.angvel.to_vec();
        for (row, r) in rows.iter().zip(impulse) {
            row.apply(&-r, &mut vfree, &mut wfree, b.inv_m, b.inv_i, b.held);
        }
        let uf = rows
            .iter()
            .map(|row| {
                let mut u = row.velocity(&vfree, &wfree);
                u.x += row.bias;
                u
            })
            .collect();
        // Columns: the free axes of each body (translation per axis, rotation as a whole).
        let mut col = vec![[usize::MAX; 6]; b.vel.len()];
        let mut n = 0;
        for (k, c) in col.iter_mut().enumerate() {
            if b.held[k].is_some() {
                for slot in c.iter_mut() {
                    *slot = n;
                    n += 1;
                }
                continue;
            }
            for i in 0..3 {
                if b.inv_m[k][i] > 0.0 {
                    c[i] = n;
                    n += 1;
                }
            }
            if b.inv_i[k].iter().any(|x| *x != 0.0) {
                for slot in c.iter_mut().skip(3) {
                    *slot = n;
                    n += 1;
                }
            }
        }
        if n == 0 {
            return None;
        }
        let (mut pi, mut pj, mut pv) = (Vec::new(), Vec::new(), Vec::new());
        for (k, c) in col.iter().enumerate() {
            if let Some(h) = &b.held[k] {
                let m = h.mass();
                for i in 0..6 {
                    for j in i..6 {
                        if m[(i, j)] != 0.0 || m[(j, i)] != 0.0 {
                            pi.push(c[i]);
                            pj.push(c[j]);
                            pv.push(0.5 * (m[(i, j)] + m[(j, i)]));
                        }
                    }
                }
                continue;
            }
            for i in 0..3 {
                if c[i] != usize::MAX {
                    pi.push(c[i]);
                    pj.push(c[i]);
                    pv.push(1.0 / b.inv_m[k][i]);
                }
            }
            if c[3] != usize::MAX {
                let inertia = b.inv_i[k].try_inverse()?;
                for i in 0..3 {
                    for j in i..3 {
                        pi.push(c[3 + i]);
                        pj.push(c[3 + j]);
                        pv.push(0.5 * (inertia[(i, j)] + inertia[(j, i)]));
                    }
                }
            }
        }
        let (mut ai, mut aj, mut av) = (Vec::new(), Vec::new(), Vec::new());
        let mut cones = Vec::with_capacity(rows.len());
        for (k, row) in rows.iter().enumerate() {
            // A point's three rows, one second-order cone.
            let scale = [1.0, row.mu, row.mu];
            for c in 0..3 {
                let line = 3 * k + c;
                let e = row.frame.column(c).into_owned();
                let sides = [(row.b, row.r_b, 1.0), (row.a, row.r_a, -1.0)];
                for &(body, arm, sign) in sides.iter().take(if row.a == TABLE { 1 } else { 2 }) {
                    let rx = arm.cross(&e);
                    let h = [e.x, e.y, e.z, rx.x, rx.y, rx.z];
                    for (dof, hv) in h.iter().enumerate() {
                        if col[body][dof] != usize::MAX && *hv != 0.0 {
                            ai.push(line);
                            aj.push(col[body][dof]);
                            av.push(-scale[c] * sign * hv);
                        }
                    }
                }
            }
            cones.push(SupportedConeT::SecondOrderConeT(3));
        }
        // The held degrees of freedom: G δ = 0, one zero cone after the points' cones.
        let mut line = 3 * rows.len();
        for (k, h) in b.held.iter().enumerate() {
            let Some(h) = h else { continue };
            for g in h.rows() {
                for (dof, gv) in g.iter().enumerate() {
                    if *gv != 0.0 {
                        ai.push(line);
                        aj.push(col[k][dof]);
                        av.push(*gv);
                    }
                }
                line += 1;
            }
        }
        let equalities = line - 3 * rows.len();
        if equalities > 0 {
            cones.push(SupportedConeT::ZeroConeT(equalities));
        }
        let p = CscMatrix::new_from_triplets(n, n, pi, pj, pv);
        let a = CscMatrix::new_from_triplets(line, n, ai, aj, av);
        Some(Program { p, a, cones, vfree, wfree, uf, equalities })
    }

    /// The right-hand side `b` (Clarabel's `A x + s = b`) at the shift `shift` (m/s).
    fn rhs(&self, rows: &[PointRows], shift: &[f64]) -> Vec<f64> {
        let mut out = Vec::with_capacity(3 * rows.len() + self.equalities);
        for ((row, u), s) in rows.iter().zip(&self.uf).zip(shift) {
            out.extend([u.x + s, row.mu * u.y, row.mu * u.z]);
        }
        out.resize(3 * rows.len() + self.equalities, 0.0);
        out
    }

    /// Solves at the right-hand side `rhs`, set up on the first call and updated after;
    /// the cones' multipliers, or `None` when the interior point did not solve it.
    fn solve(&self, solver: &mut Option<DefaultSolver<f64>>, rhs: &[f64]) -> Option<Vec<f64>> {
        match solver {
            Some(s) => s.update_b(&rhs.to_vec()).ok()?,
            None => {
                let settings = DefaultSettings {
                    verbose: false,
                    max_iter: IPM_ITERATIONS,
                    max_threads: 1,
                    presolve_enable: false,
                    input_sparse_dropzeros: false,
                    tol_gap_abs: IPM_TOLERANCE,
                    tol_gap_rel: IPM_TOLERANCE,
                    tol_feas: IPM_TOLERANCE,
                    ..DefaultSettings::default()
                };
                let q = vec![0.0; self.p.n];
                *solver = Some(DefaultSolver::new(&self.p, &q, &self.a, rhs, &self.cones, settings).ok()?);
            }
        }
        let s = solver.as_mut()?;
        s.solve();
        matches!(s.solution.status, SolverStatus::Solved | SolverStatus::AlmostSolved).then(|| s.solution.z.clone())
    }

    /// The impulses of the multipliers `z` into `impulse`, and the bodies' velocities
    /// those impulses give (the free velocities plus `M⁻¹ Hᵀ r`) into `b`.
    fn impulses(&self, rows: &[PointRows], z: &[f64], impulse: &mut [Vec3], b: &mut BodyState<'_>) {
        for (k, row) in rows.iter().enumerate() {
            let z = &z[3 * k..3 * k + 3];
            impulse[k] = Vec3::new(z[0], row.mu * z[1], row.mu * z[2]);
        }
        b.vel.copy_from_slice(&self.vfree);
        b.angvel.copy_from_slice(&self.wfree);
        for (row, r) in rows.iter().zip(impulse.iter()) {
            row.apply(r, b.vel, b.angvel, b.inv_m, b.inv_i, b.held);
        }
    }
}

/// Anderson's acceleration (type II) of a fixed-point iteration `x = G(x)` with memory
/// `m`: from the differences of the last `m` iterates' values `ΔG` and residuals
/// `ΔF` (`F = G(x) − x`), the next iterate is `G(x_k) − ΔG γ` with `γ` the least-squares
/// solution of `ΔF γ ≈ F(x_k)` (Walker & Ni 2011). With `m = 0` it is the plain iteration.
#[derive(Debug, Clone)]
pub struct Anderson {
    memory: usize,
    last: Option<(Vec<f64>, Vec<f64>)>,
    dg: Vec<Vec<f64>>,
    df: Vec<Vec<f64>>,
}

impl Anderson {
    /// An empty history of memory `memory`.
    pub fn new(memory: usize) -> Anderson {
        Anderson { memory, last: None, dg: Vec::new(), df: Vec::new() }
    }

    /// The next iterate from the current one `x` and its image `g = G(x)` (same length).
    pub fn next(&mut self, x: &[f64], g: &[f64]) -> Vec<f64> {
        let f: Vec<f64> = g.iter().zip(x).map(|(g, x)| g - x).collect();
        if let Some((lg, lf)) = &self.last {
            if self.memory > 0 {
                self.dg.push(g.iter().zip(lg).map(|(a, b)| a - b).collect());
                self.df.push(f.iter().zip(lf).map(|(a, b)| a - b).collect());
                if self.df.len() > self.memory {
                    self.dg.remove(0);
                    self.df.remove(0);
                }
            }
        }
        let m = self.df.len();
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        let gram = DMatrix::from_fn(m, m, |i, j| dot(&self.df[i], &self.df[j]));
        let rhs = DVector::from_fn(m, |i, _| dot(&self.df[i], &f));
        // A relative ridge keeps the normal equations solvable when two updates are alike.
        let ridge = 1e-10 * (0..m).map(|i| gram[(i, i)]).fold(0.0, f64::max);
        let gamma =
            (gram + DMatrix::identity(m, m) * ridge).cholesky().map_or_else(|| DVector::zeros(m), |c| c.solve(&rhs));
        let mut next = g.to_vec();
        for (i, dg) in self.dg.iter().enumerate() {
            for (n, d) in next.iter_mut().zip(dg) {
                *n -= gamma[i] * d;
            }
        }
        self.last = Some((g.to_vec(), f));
        next
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a linear map `G(x) = A x + c` of dimension 3 (contraction factor 0.95, so the
    /// plain iteration needs hundreds of steps), Anderson's acceleration with memory 3
    /// reaches the exact fixed point `(I − A)⁻¹ c` (a closed form) within a few steps, as
    /// GMRES would.
    #[test]
    fn anderson_solves_a_slow_linear_fixed_point() {
        let a = nalgebra::Matrix3::new(0.95, 0.02, 0.0, -0.01, 0.9, 0.03, 0.0, 0.04, -0.5);
        let c = nalgebra::Vector3::new(1.0, -2.0, 0.5);
        let exact = (nalgebra::Matrix3::identity() - a).try_inverse().unwrap() * c;
        let map = |x: &[f64]| {
            let y = a * nalgebra::Vector3::new(x[0], x[1], x[2]) + c;
            vec![y.x, y.y, y.z]
        };
        let mut anderson = Anderson::new(3);
        let mut x = vec![0.0; 3];
        for _ in 0..6 {
            let g = map(&x);
            x = anderson.next(&x, &g);
        }
        let err = (nalgebra::Vector3::new(x[0], x[1], x[2]) - exact).norm();
        assert!(err < 1e-8 * exact.norm(), "Anderson after 6 steps: error {err:e}");
        let mut plain = vec![0.0; 3];
        for _ in 0..6 {
            plain = map(&plain);
        }
        let err_plain = (nalgebra::Vector3::new(plain[0], plain[1], plain[2]) - exact).norm();
        assert!(err_plain > 0.1 * exact.norm(), "the plain iteration after 6 steps: {err_plain:e}");
    }

    /// Memory 0 is the plain iteration.
    /// The natural-map residuals (1e-4 units) of the 26 programs of the SBL preset wall's
    /// step at 2.759 s under `data/motions/synthetic_10s.csv` at 1.0 g (seed 20210917,
    /// read from a run of the finisher; tolerance 1.0): the rule goes on past the 16th
    /// program, where the residual is still 1.18, to the 26th, which meets the tolerance;
    /// the last new least residuals come 7 and 8 programs apart.
    #[test]
    fn the_finisher_goes_on_while_the_residual_still_falls() {
        let recorded = [
            4.281, 3.055, 2.499, 1.913, 1.754, 1.451, 1.243, 1.227, 1.264, 1.268, 1.182, 1.715, 1.494, 1.414, 1.459,
            1.791, 1.228, 1.108, 1.199, 1.201, 1.113, 1.509, 1.423, 1.321, 1.115, 0.945,
        ];
        let mut stall = Stall::default();
        for (k, r) in recorded.iter().enumerate() {
            assert!(!stall.stalled(), "stalled before program {}", k + 1);
            stall.read(*r);
        }
        assert!(recorded[25] <= 1.0 && recorded[..25].iter().all(|r| *r > 1.0));
    }

    /// Residuals that never fall by 1 % below the first stop the finisher after exactly
    /// [`STALL_PROGRAMS`] more programs; one that falls restarts the count.
    #[test]
    fn the_finisher_stops_once_the_residual_no_longer_falls() {
        let mut stall = Stall::default();
        stall.read(2.0);
        for k in 0..STALL_PROGRAMS {
            assert!(!stall.stalled(), "stalled after {k} programs without progress");
            stall.read(2.0 - 0.005 * f64::from(k % 3));
        }
        assert!(stall.stalled());
        let mut stall = Stall::default();
        stall.read(2.0);
        for _ in 0..STALL_PROGRAMS - 1 {
            stall.read(2.5);
        }
        stall.read(1.9);
        assert!(!stall.stalled());
        assert_eq!(stall.since, 0);
    }

    #[test]
    fn anderson_without_memory_is_the_plain_iteration() {
        let mut anderson = Anderson::new(0);
        let x = anderson.next(&[1.0, 2.0], &[3.0, 5.0]);
        assert_eq!(x, vec![3.0, 5.0]);
        let x = anderson.next(&x, &[4.0, 4.5]);
        assert_eq!(x, vec![4.0, 4.5]);
    }
}
