//! Implicit relaxation of the static increments: an iteration preconditioned by the
//! factorized stiffness of the contact springs and accelerated by Anderson mixing, with
//! dynamic relaxation ([`super::relax`]) taking over where it does not converge (near
//! collapse).
//!
//! # The iteration
//!
//! Dynamic relaxation needs hundreds of steps per increment because its explicit steps
//! see the stiffness one body at a time (the condition number of the SBL wall's assembled
//! stiffness is about 550 even after block density scaling). Here each iteration applies
//! the whole assembled stiffness at once. With `R_k` the out-of-balance force and moment of
//! every free body (N, N·m about its centroid, table frame) at iterate `k`, and `K` the
//! stiffness below,
//!
//! ```text
//! f_k = K⁻¹ R_k                                   (sparse Cholesky solve)
//! γ   = argmin ‖f_k − ΔF γ‖                       (the last m differences of f)
//! Δx_k = f_k − (ΔX + ΔF) γ                        (Anderson type II, mixing 1)
//! ```
//!
//! (Anderson 1965, *J. ACM* 12, 547; Walker & Ni 2011, *SIAM J. Numer. Anal.* 49, 1715: on a
//! linear problem the iterates are those of GMRES preconditioned by `K`). Rotations enter
//! the least squares times the body radius, so that both halves are lengths.
//!
//! Every iterate is one jump of [`Simulation::predict`] from the one before: the joints
//! take the iterate's relative motion as their shear increment, the Coulomb limit and the
//! no-tension closure act on it as they act on a step of dynamic relaxation, and the
//! joints' history follows the iterates' path. The iteration is therefore dynamic
//! relaxation with the stiffness matrix for a mass matrix (each elastic mode then takes
//! one iteration) and Anderson mixing for damping.
//!
//! `K` is the stiffness of every sub-contact spring, open or closed, as the critical time
//! step sees it ([`super::timestep`]), but with the springs where the joint law acts:
//! normal springs integrated exactly over each triangle (weights `A/12` at the nodes and
//! `3A/4` at the centroid, the rule exact for the quadratic integrand) with the stiffness
//! `max(dq/du, Kn)` of the closure law at each point
//! ([`crate::dem::contact::law::NormalParams::tangent`]), and the shear spring `Ks A` at the
//! centroid, where the law takes the shear increment. It bounds the true tangent from
//! above (an open, slipping or softening joint is stiffer in `K` than it is), so no mode
//! is over-corrected; the modes it over-stiffens (slip, opening joints, rocking) are what
//! the Anderson mixing resolves. It is factorized once per increment, after every
//! re-detection of contacts and every [`ImplicitSolve::refactor_every`] iterations.
//!
//! The iteration ends at equilibrium (unbalanced-force ratio below the tolerance), when
//! the protocol's check stops it (a collapse criterion), when the ratio grows tenfold
//! (the state is then put back where the iteration started), or after
//! [`ImplicitSolve::max_iterations`].
//!
//! The sparse factorization is faer's simplicial Cholesky with an approximate minimum
//! degree ordering, run sequentially; the simplicial factorization and the sparse
//! triangular solves are scalar code (no runtime choice of SIMD kernels), so a test gives
//! the same bits on any number of threads and any x86-64 machine, as the explicit step
//! does.

use super::engine::Simulation;
use super::timestep::block;
use crate::layout::EndRestraint;
use crate::{Mat3, Vec3};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par, Side};
use nalgebra::{DMatrix, DVector, Matrix6};
use serde::{Deserialize, Serialize};
use std::cell::RefCell;
use std::collections::{BTreeMap, VecDeque};
use std::rc::Rc;

/// Settings of the implicit iteration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ImplicitSolve {
    /// Iterations at most before dynamic relaxation takes over (default 1000).
    pub max_iterations: u32,
    /// Differences kept by the Anderson mixing, m (default 4; 0: the plain preconditioned
    /// iteration `Δx = K⁻¹ R`).
    pub anderson_depth: u32,
    /// Iterations between two factorizations of the stiffness when no contact is
    /// re-detected (default 32).
    pub refactor_every: u32,
}

impl Default for ImplicitSolve {
    fn default() -> Self {
        ImplicitSolve { max_iterations: 1000, anderson_depth: 4, refactor_every: 32 }
    }
}

impl ImplicitSolve {
    /// Checks the settings.
    ///
    /// # Errors
    /// The first key out of range, by name.
    pub fn validate(&self) -> Result<(), crate::range::OutOfRange> {
        crate::range::check_ranges(&[
            (
                "implicit_solve.max_iterations",
                self.max_iterations as f64,
                (1..=1_000_000).contains(&self.max_iterations),
                "in [1, 1000000]",
            ),
            ("implicit_solve.anderson_depth", self.anderson_depth as f64, self.anderson_depth <= 50, "in [0, 50]"),
            ("implicit_solve.refactor_every", self.refactor_every as f64, self.refactor_every >= 1, ">= 1"),
        ])
    }
}

/// How an implicit relaxation ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Solved<R> {
    /// The unbalanced-force ratio fell below the tolerance after this many iterations.
    Equilibrium(u32),
    /// The stop check returned its reason after this many iterations.
    Stopped(R, u32),
    /// No equilibrium within the iterations (the state is the last iterate), or the
    /// stiffness could not be factorized (the state is the last iterate), or the
    /// unbalanced-force ratio grew tenfold above where it started or turned non-finite (the
    /// state is put back where the iteration started), after this many iterations.
    Unsolved(u32),
}

/// A pose increment: per body, translation (m) and rotation vector (rad), table frame.
pub type PoseIncrement = (Vec<Vec3>, Vec<Vec3>);

/// Relaxes `sim` (its load set, its state placed) towards an unbalanced-force ratio below
/// `tol` by the preconditioned, Anderson-mixed iteration of the module doc, calling `check`
/// after every iteration; a reason from `check` stops it. Every iterate is a jump of
/// [`Simulation::predict`] from the one before (the bodies end at rest), so the joints'
/// history follows the iterates' path as it follows the steps of dynamic relaxation. The
/// inertial masses and the time step are brought up to date at the end if contacts were
/// re-detected meanwhile, so dynamic relaxation can go on from the state.
pub fn relax<R>(
    sim: &mut Simulation,
    tol: f64,
    settings: &ImplicitSolve,
    check: impl FnMut(&Simulation) -> Option<R>,
) -> Solved<R> {
    sim.defer_step_updates();
    let out = relax_deferred(sim, tol, settings, check);
    sim.end_deferral();
    out
}

/// [`relax`] with the time-step updates of re-detections deferred.
fn relax_deferred<R>(
    sim: &mut Simulation,
    tol: f64,
    settings: &ImplicitSolve,
    mut check: impl FnMut(&Simulation) -> Option<R>,
) -> Solved<R> {
    let nb = sim.bodies.len();
    let dofs = Dofs::new(sim);
    if dofs.n == 0 {
        return Solved::Unsolved(0);
    }
    let zeros = vec![Vec3::zeros(); nb];
    sim.predict(&zeros, &zeros);
    sim.assess_predicted();
    let start = sim.clone();
    let limit = 10.0 * sim.stats.unbalanced_ratio.max(tol);
    let depth = settings.anderson_depth as usize;
    let mut mixing = Anderson::new(depth);
    let mut factor: Option<Factor> = None;
    let mut since = 0;
    let mut detections = sim.detections;
    for it in 0..settings.max_iterations {
        let ratio = sim.stats.unbalanced_ratio;
        if !(ratio <= limit) {
            *sim = start;
            return Solved::Unsolved(it);
        }
        if ratio < tol {
            return Solved::Equilibrium(it);
        }
        if factor.is_none() || since >= settings.refactor_every || sim.detections != detections {
            factor = Factor::new(sim, &dofs);
            since = 0;
            detections = sim.detections;
            // Differences taken under another preconditioner do not mix.
            mixing = Anderson::new(depth);
        }
        let Some(f) = &factor else {
            return Solved::Unsolved(it);
        };
        since += 1;
        let fk = flatten(&f.solve(sim, &dofs), sim);
        let step = unflatten(&mixing.next(fk), sim);
        sim.predict(&step.0, &step.1);
        sim.assess_predicted();
        if let Some(r) = check(sim) {
            return Solved::Stopped(r, it + 1);
        }
    }
    if sim.stats.unbalanced_ratio < tol {
        Solved::Equilibrium(settings.max_iterations)
    } else {
        Solved::Unsolved(settings.max_iterations)
    }
}

/// Anderson mixing (type II, mixing parameter 1) over the last `depth` iterates.
struct Anderson {
    depth: usize,
    /// `(Δx_i, f_{i+1} − f_i)` of the last iterations, oldest first.
    history: VecDeque<(Vec<f64>, Vec<f64>)>,
    /// The last preconditioned residual and the step taken from it.
    last: Option<(Vec<f64>, Vec<f64>)>,
}

impl Anderson {
    fn new(depth: usize) -> Anderson {
        Anderson { depth, history: VecDeque::new(), last: None }
    }

    /// The step from the preconditioned residual `f` (flattened, m).
    fn next(&mut self, f: Vec<f64>) -> Vec<f64> {
        if let Some((lf, dx)) = self.last.take() {
            if self.depth > 0 {
                let df: Vec<f64> = f.iter().zip(&lf).map(|(a, b)| a - b).collect();
                self.history.push_back((dx, df));
                if self.history.len() > self.depth {
                    self.history.pop_front();
                }
            }
        }
        let mut step = f.clone();
        let m = self.history.len();
        if m > 0 {
            // Normal equations of min ‖f − ΔF γ‖, with a relative ridge of 1e-10 against
            // (near-)collinear differences.
            let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
            let mut a = DMatrix::<f64>::zeros(m, m);
            let mut b = DVector::<f64>::zeros(m);
            for i in 0..m {
                for j in 0..=i {
                    let v = dot(&self.history[i].1, &self.history[j].1);
                    a[(i, j)] = v;
                    a[(j, i)] = v;
                }
                b[i] = dot(&self.history[i].1, &f);
            }
            let ridge = 1e-10 * (0..m).map(|i| a[(i, i)]).fold(0.0, f64::max);
            for i in 0..m {
                a[(i, i)] += ridge;
            }
            if let Some(g) = a.lu().solve(&b) {
                for (gi, (dx, df)) in g.iter().zip(&self.history) {
                    for ((s, x), y) in step.iter_mut().zip(dx).zip(df) {
                        *s -= gi * (x + y);
                    }
                }
            }
        }
        self.last = Some((f, step.clone()));
        step
    }
}

/// A pose increment as one vector, rotations times the body radius (m).
fn flatten(d: &PoseIncrement, sim: &Simulation) -> Vec<f64> {
    let mut v = Vec::with_capacity(6 * d.0.len());
    for (k, b) in sim.bodies.iter().enumerate() {
        v.extend_from_slice(d.0[k].as_slice());
        v.extend((d.1[k] * b.radius).iter());
    }
    v
}

/// The inverse of [`flatten`].
fn unflatten(v: &[f64], sim: &Simulation) -> PoseIncrement {
    sim.bodies
        .iter()
        .enumerate()
        .map(|(k, b)| {
            (
                Vec3::new(v[6 * k], v[6 * k + 1], v[6 * k + 2]),
                Vec3::new(v[6 * k + 3], v[6 * k + 4], v[6 * k + 5]) / b.radius,
            )
        })
        .unzip()
}

/// The numbering of the unknowns: six per free body (translation, rotation), in body order.
struct Dofs {
    /// First unknown of each body (`usize::MAX` for a fixed body).
    first: Vec<usize>,
    /// Whether a body's y translation is held (rigid end restraint).
    held: Vec<bool>,
    /// Number of unknowns.
    n: usize,
}

impl Dofs {
    fn new(sim: &Simulation) -> Dofs {
        let mut n = 0;
        let first = sim
            .bodies
            .iter()
            .map(|b| {
                if b.fixed {
                    usize::MAX
                } else {
                    n += 6;
                    n - 6
                }
            })
            .collect();
        let held = sim.restraint.iter().map(|r| *r == Some(EndRestraint::Rigid)).collect();
        Dofs { first, held, n }
    }
}

/// The factorized tangent stiffness of a state (sparse Cholesky, simplicial, approximate
/// minimum degree ordering, sequential).
struct Factor {
    symbolic: Rc<SymbolicCholesky<usize>>,
    values: Vec<f64>,
}

thread_local! {
    /// The symbolic factorization of the last sparsity pattern factorized on this thread
    /// (column pointers, row indices): the pattern changes only when contacts are
    /// re-detected. A cache hit gives the same ordering as a fresh analysis, so the results
    /// never depend on it.
    static SYMBOLIC: RefCell<Option<(Vec<usize>, Vec<usize>, Rc<SymbolicCholesky<usize>>)>> =
        const { RefCell::new(None) };
}

/// The symbolic Cholesky factorization (approximate minimum degree ordering, simplicial) of
/// the pattern of `a`, from the thread's cache when the pattern is the last one.
fn symbolic_of(a: &SparseColMat<usize, f64>) -> Option<Rc<SymbolicCholesky<usize>>> {
    let (cp, ri) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
    if let Some(hit) = SYMBOLIC.with_borrow(|c| {
        c.as_ref().filter(|(p, r, _)| p.as_slice() == cp && r.as_slice() == ri).map(|(_, _, s)| Rc::clone(s))
    }) {
        return Some(hit);
    }
    let symbolic = Rc::new(
        factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .ok()?,
    );
    SYMBOLIC.with_borrow_mut(|c| *c = Some((cp.to_vec(), ri.to_vec(), Rc::clone(&symbolic))));
    Some(symbolic)
}

impl Factor {
    /// Assembles and factorizes the tangent at `sim`'s state; `None` if it is not positive
    /// definite.
    fn new(sim: &Simulation, dofs: &Dofs) -> Option<Factor> {
        let (diag, off) = tangent(sim);
        let nb = sim.bodies.len();
        // Regularization: a millionth of each diagonal entry plus a floor of a billionth of
        // the largest translational (rotational) diagonal entry, so that a direction no
        // spring stiffens gets a large but finite stiffness.
        let (mut tmax, mut rmax) = (0.0f64, 0.0f64);
        for k in (0..nb).filter(|&k| dofs.first[k] != usize::MAX) {
            for r in 0..3 {
                tmax = tmax.max(diag[k][(r, r)]);
                rmax = rmax.max(diag[k][(r + 3, r + 3)]);
            }
        }
        if !(tmax > 0.0 && rmax > 0.0) {
            return None;
        }
        let is_held = |k: usize, r: usize| dofs.held[k] && r == 1;
        let mut entries = Vec::with_capacity(21 * nb + 36 * off.len());
        for k in 0..nb {
            let f0 = dofs.first[k];
            if f0 == usize::MAX {
                continue;
            }
            let mut kk = diag[k];
            if let Some(EndRestraint::Spring(ky)) = sim.restraint[k] {
                kk[(1, 1)] += ky;
            }
            for r in 0..6 {
                if is_held(k, r) {
                    entries.push(Triplet::new(f0 + r, f0 + r, 1.0));
                    continue;
                }
                let floor = if r < 3 { tmax } else { rmax } * 1e-9;
                entries.push(Triplet::new(f0 + r, f0 + r, kk[(r, r)] * (1.0 + 1e-6) + floor));
                for c in 0..r {
                    if !is_held(k, c) {
                        entries.push(Triplet::new(f0 + r, f0 + c, kk[(r, c)]));
                    }
                }
            }
        }
        for ((a, b), kab) in &off {
            let (fa, fb) = (dofs.first[*a], dofs.first[*b]);
            // Lower triangle: rows of the later body.
            for r in 0..6 {
                for c in 0..6 {
                    let (row, col, v, hr, hc) = if fa > fb {
                        (fa + r, fb + c, kab[(r, c)], is_held(*a, r), is_held(*b, c))
                    } else {
                        (fb + r, fa + c, kab[(c, r)], is_held(*b, r), is_held(*a, c))
                    };
                    if !(hr || hc) {
                        entries.push(Triplet::new(row, col, v));
                    }
                }
            }
        }
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(dofs.n, dofs.n, &entries).ok()?;
        let symbolic = symbolic_of(&a)?;
        let mut values = vec![0.0f64; symbolic.len_val()];
        let mut mem =
            MemBuffer::try_new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())).ok()?;
        symbolic
            .factorize_numeric_llt(
                &mut values,
                a.as_ref(),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .ok()?;
        Some(Factor { symbolic, values })
    }

    /// `K⁻¹ R` for the out-of-balance loads `R` of `sim` (its last assessment), per body.
    fn solve(&self, sim: &Simulation, dofs: &Dofs) -> PoseIncrement {
        let nb = sim.bodies.len();
        let mut rhs = Mat::<f64>::zeros(dofs.n, 1);
        for k in 0..nb {
            let f0 = dofs.first[k];
            if f0 == usize::MAX {
                continue;
            }
            let (f, t) = sim.unbalanced(k);
            for r in 0..3 {
                rhs[(f0 + r, 0)] = f[r];
                rhs[(f0 + 3 + r, 0)] = t[r];
            }
            if dofs.held[k] {
                rhs[(f0 + 1, 0)] = 0.0;
            }
        }
        let llt = LltRef::new(&self.symbolic, &self.values);
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        llt.solve_in_place_with_conj(Conj::No, rhs.as_mut(), Par::Seq, MemStack::new(&mut mem));
        let mut step = (vec![Vec3::zeros(); nb], vec![Vec3::zeros(); nb]);
        for k in 0..nb {
            let f0 = dofs.first[k];
            if f0 == usize::MAX {
                continue;
            }
            step.0[k] = Vec3::new(rhs[(f0, 0)], rhs[(f0 + 1, 0)], rhs[(f0 + 2, 0)]);
            step.1[k] = Vec3::new(rhs[(f0 + 3, 0)], rhs[(f0 + 4, 0)], rhs[(f0 + 5, 0)]);
        }
        step
    }
}

/// Per-body diagonal blocks and per-pair coupling blocks (`(a, b) → K_ab`, rows of `a`)
/// of the stiffness `K` of every sub-contact spring of `sim` (N/m, N, N·m; table frame; see
/// the module doc). Couplings with a fixed body are left out.
fn tangent(sim: &Simulation) -> (Vec<Matrix6<f64>>, BTreeMap<(usize, usize), Matrix6<f64>>) {
    let nb = sim.bodies.len();
    let mut diag = vec![Matrix6::zeros(); nb];
    let mut off: BTreeMap<(usize, usize), Matrix6<f64>> = BTreeMap::new();
    // Spring points of one contact: arm from A's centroid (m), arm from B's centroid (m),
    // normal and shear stiffness (N/m).
    let mut points: Vec<(Vec3, Vec3, f64, f64)> = Vec::new();
    let mut arms: Vec<(Vec3, Vec3, f64)> = Vec::new();
    for c in &sim.contacts {
        let n = sim.contact_normal(c);
        let np = c.joint.normal();
        let stiffness = |u: f64| if u > 0.0 { np.tangent(u).max(c.joint.kn) } else { c.joint.kn };
        let rb_mat = &sim.bodies[c.b].rot_mat;
        let ra_mat = c.a.map(|i| sim.bodies[i].rot_mat);
        // Node arms and closures.
        arms.clear();
        for nd in &c.nodes {
            let (pa, pb) = sim.node_points(c, nd);
            let rb = rb_mat * nd.on_b;
            let ra = ra_mat.map_or(Vec3::zeros(), |m| m * nd.on_a);
            arms.push((ra, rb, (pa - pb).dot(&n)));
        }
        points.clear();
        for s in &c.subs {
            let a = s.area;
            let (mut ra_c, mut rb_c, mut u_c) = (Vec3::zeros(), Vec3::zeros(), 0.0);
            for &k in &s.nodes {
                let (ra, rb, u) = arms[k as usize];
                ra_c += ra / 3.0;
                rb_c += rb / 3.0;
                u_c += u / 3.0;
                points.push((ra, rb, a / 12.0 * stiffness(u), 0.0));
            }
            points.push((ra_c, rb_c, 0.75 * a * stiffness(u_c), c.joint.ks * a));
        }
        if points.is_empty() {
            continue;
        }
        let nn = n * n.transpose();
        let free_b = !sim.bodies[c.b].fixed;
        let free_a = c.a.filter(|&i| !sim.bodies[i].fixed);
        // The normal springs (C₀ = n nᵀ) and the shear springs (C₀ = I − n nᵀ).
        for (part, c0, ks, beta) in [(0, nn, 0.0, 1.0), (1, Mat3::identity() - nn, 1.0, -1.0)] {
            let (mut wsum, mut sa, mut sb) = (0.0, Vec3::zeros(), Vec3::zeros());
            let (mut raa, mut rab, mut rbb) = (Mat3::zeros(), Mat3::zeros(), Mat3::zeros());
            for &(ra, rb, wn, ws) in &points {
                let wi = if part == 0 { wn } else { ws };
                if wi == 0.0 {
                    continue;
                }
                wsum += wi;
                sb += rb * wi;
                rbb += rb * rb.transpose() * wi;
                sa += ra * wi;
                raa += ra * ra.transpose() * wi;
                rab += ra * rb.transpose() * wi;
            }
            if wsum == 0.0 {
                continue;
            }
            if free_b {
                diag[c.b] += block(&c0, &n, ks, beta, wsum, &sb, &sb, &rbb);
            }
            if let Some(a) = free_a {
                diag[a] += block(&c0, &n, ks, beta, wsum, &sa, &sa, &raa);
                if free_b {
                    *off.entry((a, c.b)).or_insert_with(Matrix6::zeros) -=
                        block(&c0, &n, ks, beta, wsum, &sa, &sb, &rab);
                }
            }
        }
    }
    (diag, off)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::SolverParams;
    use crate::layout::Layout;

    /// On a block settled flat on the table (every node closed, nothing slipping) `K` is
    /// the tangent of the joint law: each column equals the change of the out-of-balance
    /// load under a small motion of that degree of freedom (central differences of the
    /// contact pass), to 1 % of the column's largest entry.
    #[test]
    fn the_stiffness_is_the_tangent_of_a_closed_sticking_joint() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/layouts/single_block.json");
        let mut sim = Simulation::new(&Layout::from_file(&path).unwrap(), SolverParams::default());
        assert!(sim.run_to_equilibrium(1e-8, 200_000).unwrap());
        sim.set_tilt(0.05);
        let (diag, _) = tangent(&sim);
        let load = |d: &PoseIncrement| {
            let mut s = sim.clone();
            s.predict(&d.0, &d.1);
            s.assess_predicted();
            let (f, t) = s.unbalanced(0);
            [f.x, f.y, f.z, t.x, t.y, t.z]
        };
        for dof in 0..6 {
            let eps = if dof < 3 { 1e-8 } else { 1e-7 };
            let mut plus = (vec![Vec3::zeros()], vec![Vec3::zeros()]);
            let mut minus = plus.clone();
            if dof < 3 {
                plus.0[0][dof] = eps;
                minus.0[0][dof] = -eps;
            } else {
                plus.1[0][dof - 3] = eps;
                minus.1[0][dof - 3] = -eps;
            }
            let (lp, lm) = (load(&plus), load(&minus));
            let column: Vec<f64> = (0..6).map(|i| diag[0][(i, dof)]).collect();
            let scale = column.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for i in 0..6 {
                let fd = -(lp[i] - lm[i]) / (2.0 * eps);
                assert!((fd - column[i]).abs() <= 0.01 * scale, "K[{i}][{dof}] = {} against {fd}", column[i]);
            }
        }
    }

    /// Anderson mixing of depth m solves a linear fixed-point problem `x = x + f(x)`,
    /// `f(x) = b − A x` with A symmetric positive definite of dimension m + 1 or less in at
    /// most m + 2 iterations (it is GMRES), where the plain iteration needs hundreds.
    #[test]
    fn anderson_mixing_solves_a_small_linear_problem_like_gmres() {
        let a = nalgebra::Matrix3::new(1.0, 0.2, 0.0, 0.2, 0.05, 0.01, 0.0, 0.01, 0.002);
        let b = nalgebra::Vector3::new(1.0, -1.0, 0.5);
        let exact = a.try_inverse().unwrap() * b;
        let run = |depth: usize| {
            let mut mixing = Anderson::new(depth);
            let mut x = nalgebra::Vector3::zeros();
            for it in 0..2000 {
                let f = b - a * x;
                if (x - exact).norm() < 1e-9 * exact.norm() {
                    return it;
                }
                let step = mixing.next(f.as_slice().to_vec());
                x += nalgebra::Vector3::from_column_slice(&step);
            }
            2000
        };
        assert!(run(3) <= 5, "{}", run(3));
        assert!(run(0) > 100, "{}", run(0));
    }
}
