//! The preconditioner of the implicit iteration: the stiffness `K` of every sub-contact
//! spring (see the parent module), its assembly per body pair and its sparse Cholesky
//! factorization.

use super::PoseIncrement;
use crate::dem::engine::Simulation;
use crate::dem::timestep::block;
use crate::layout::EndRestraint;
use crate::math::{Mat3, Vec3};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::utils::{permute_self_adjoint_scratch, permute_self_adjoint_to_unsorted};
use faer::sparse::{Argsort, Pair, SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, Mat, Par, Side};
use nalgebra::Matrix6;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;

/// The numbering of the unknowns: six per free body (translation, rotation), in body order.
pub(in crate::dem::drivers) struct Dofs {
    /// First unknown of each body (`usize::MAX` for a fixed body).
    pub(in crate::dem::drivers) first: Vec<usize>,
    /// Which of a body's six degrees of freedom (x, y, z translation of the centroid, then
    /// rotation about x, y, z; table frame) are held: the y translation of a rigid end
    /// restraint, and the held translations and rotations of a per-degree-of-freedom
    /// constraint ([`crate::dem::DofConstraint`]; a held translation anchored off the
    /// centroid is taken as held at the centroid, the jumps put the anchor back).
    pub(in crate::dem::drivers) held: Vec<[bool; 6]>,
    /// Number of unknowns.
    pub(in crate::dem::drivers) n: usize,
}

impl Dofs {
    /// The out-of-balance force and moment of every free body of `sim` (its last
    /// assessment; N, N·m about the centroid, table frame) as one column in this numbering,
    /// zero at the held degrees of freedom: the right-hand side of both static solves.
    pub(in crate::dem::drivers) fn out_of_balance(&self, sim: &Simulation) -> Mat<f64> {
        let mut rhs = Mat::<f64>::zeros(self.n, 1);
        for (k, &f0) in self.first.iter().enumerate() {
            if f0 == usize::MAX {
                continue;
            }
            let (f, t) = sim.unbalanced(k);
            for r in 0..3 {
                rhs[(f0 + r, 0)] = f[r];
                rhs[(f0 + 3 + r, 0)] = t[r];
            }
            for (r, &held) in self.held[k].iter().enumerate() {
                if held {
                    rhs[(f0 + r, 0)] = 0.0;
                }
            }
        }
        rhs
    }

    /// A column in this numbering as a pose increment per body (m, rad; zero for fixed
    /// bodies).
    pub(in crate::dem::drivers) fn pose_increment(&self, x: &Mat<f64>) -> PoseIncrement {
        let nb = self.first.len();
        let mut step = (vec![Vec3::zeros(); nb], vec![Vec3::zeros(); nb]);
        for (k, &f0) in self.first.iter().enumerate() {
            if f0 == usize::MAX {
                continue;
            }
            step.0[k] = Vec3::new(x[(f0, 0)], x[(f0 + 1, 0)], x[(f0 + 2, 0)]);
            step.1[k] = Vec3::new(x[(f0 + 3, 0)], x[(f0 + 4, 0)], x[(f0 + 5, 0)]);
        }
        step
    }

    pub(in crate::dem::drivers) fn new(sim: &Simulation) -> Dofs {
        let mut n = 0;
        let first = sim
            .state
            .bodies
            .iter()
            .map(|b| {
                if b.fixed() {
                    usize::MAX
                } else {
                    n += 6;
                    n - 6
                }
            })
            .collect();
        let held = sim
            .state
            .restraint
            .iter()
            .zip(&sim.state.bodies)
            .map(|(r, b)| {
                let mut h = [false; 6];
                h[1] = *r == Some(EndRestraint::Rigid);
                if let Some(c) = b.hold.dof() {
                    for i in 0..3 {
                        h[i] |= c.translation[i].is_some();
                        h[i + 3] |= c.rotation[i];
                    }
                }
                h
            })
            .collect();
        Dofs { first, held, n }
    }
}

/// The factorized stiffness `K` of a state (sparse Cholesky, simplicial, approximate
/// minimum degree ordering, sequential).
pub(super) struct Factor {
    symbolic: Rc<SymbolicCholesky<usize>>,
    values: Vec<f64>,
}

/// The assembly pattern of `K` on this thread: the (row, column) of every entry in the
/// order the assembly lists them, the compressed sparse column pattern they make with the
/// order to read the values in ([`Argsort`]: duplicates summed in list order, as
/// [`SparseColMat::try_new_from_triplets`] sums them), and the pattern's symbolic Cholesky
/// factorization. The pattern changes only when contacts are re-detected; a hit gives
/// the same matrix and the same ordering as a fresh analysis, bit for bit, so the results
/// never depend on it.
struct Pattern {
    entries: Vec<Pair<usize, usize>>,
    matrix: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    cholesky: Rc<SymbolicCholesky<usize>>,
    /// The numeric factorization's schedule for this pattern (`None`: faer's own numeric
    /// factorization, for a symbolic factorization other than a permuted simplicial one).
    schedule: Option<Schedule>,
}

/// What faer's simplicial up-looking numeric Cholesky factorization derives from the
/// pattern alone and recomputes at every factorization, computed once per pattern: the
/// upper triangle of the permuted matrix `P A Pᵀ` (column pointers and row indices in the
/// order faer's permutation lists them, and for each entry the index of its value in
/// `A`'s compressed values), and each row's elimination reach (the columns `j < k` with
/// `L_kj ≠ 0`, in the topological order faer's `ereach` visits them). With these,
/// [`Schedule::factorize`] performs faer's floating-point operations in faer's order: the
/// factor is the same bit for bit.
struct Schedule {
    /// Column pointers of the permuted upper triangle, `n + 1`.
    a_ptr: Vec<usize>,
    /// Row index (permuted) of each entry of the permuted upper triangle.
    a_row: Vec<usize>,
    /// Index in `A`'s compressed values of each entry of the permuted upper triangle.
    a_src: Vec<usize>,
    /// Row `k`'s reach is `reach[reach_ptr[k]..reach_ptr[k + 1]]`.
    reach_ptr: Vec<usize>,
    reach: Vec<usize>,
    /// Column pointers (`n + 1`) and row indices of `L` (faer's simplicial symbolic factor:
    /// the diagonal first, then the rows in increasing order).
    l_ptr: Vec<usize>,
    l_row: Vec<usize>,
}

impl Schedule {
    /// The schedule of the pattern `matrix` (lower triangle) under `cholesky`; `None`
    /// unless `cholesky` is simplicial with a fill-reducing permutation.
    fn new(matrix: &SymbolicSparseColMat<usize>, cholesky: &SymbolicCholesky<usize>) -> Option<Schedule> {
        let (SymbolicCholeskyRaw::Simplicial(simplicial), Some(perm)) = (cholesky.raw(), cholesky.perm()) else {
            return None;
        };
        let n = matrix.nrows();
        let nnz = matrix.row_idx().len();
        // The permutation of faer's numeric factorization applied to the values 0, 1, 2, …:
        // each permuted entry carries the index of its source (exact in f64 below 2⁵³).
        let index: Vec<f64> = (0..nnz).map(|i| i as f64).collect();
        let (mut src, mut a_ptr, mut a_row) = (vec![0.0; nnz], vec![0usize; n + 1], vec![0usize; nnz]);
        let mut mem = MemBuffer::new(permute_self_adjoint_scratch::<usize>(n));
        let permuted = permute_self_adjoint_to_unsorted(
            &mut src,
            &mut a_ptr,
            &mut a_row,
            SparseColMatRef::new(matrix.as_ref(), &index),
            perm,
            Side::Lower,
            Side::Upper,
            MemStack::new(&mut mem),
        );
        let a_nnz = permuted.compute_nnz();
        let a_src: Vec<usize> = src[..a_nnz].iter().map(|&v| v as usize).collect();
        a_row.truncate(a_nnz);
        let (l_ptr, l_row) = (simplicial.col_ptr().to_vec(), simplicial.row_idx().to_vec());
        // The elimination tree: a column's parent is its first row below the diagonal.
        let parent: Vec<usize> =
            (0..n).map(|j| if l_ptr[j + 1] > l_ptr[j] + 1 { l_row[l_ptr[j] + 1] } else { usize::MAX }).collect();
        // faer's `ereach`, row by row.
        let (mut reach_ptr, mut reach) = (vec![0usize; n + 1], Vec::with_capacity(l_row.len() - n));
        let mut visited = vec![usize::MAX; n];
        let mut stack = vec![0usize; n];
        for k in 0..n {
            let mut top = n;
            visited[k] = k;
            for &i0 in &a_row[a_ptr[k]..a_ptr[k + 1]] {
                if i0 >= k {
                    continue;
                }
                let (mut i, mut len) = (i0, 0);
                while visited[i] != k {
                    stack[len] = i;
                    len += 1;
                    visited[i] = k;
                    i = parent[i];
                }
                stack.copy_within(..len, top - len);
                top -= len;
            }
            reach.extend_from_slice(&stack[top..]);
            reach_ptr[k + 1] = reach.len();
        }
        Some(Schedule { a_ptr, a_row, a_src, reach_ptr, reach, l_ptr, l_row })
    }

    /// The values of `L` for the compressed values `a` of `A`: faer's
    /// `factorize_simplicial_numeric_llt` (no regularization) on the permuted matrix,
    /// operation for operation.
    ///
    /// # Errors
    /// A pivot not positive, as faer reports it (`NonPositivePivot { index }`, 1-based).
    fn factorize(&self, a: &[f64]) -> Result<Vec<f64>, String> {
        let n = self.a_ptr.len() - 1;
        let (lp, lr) = (&self.l_ptr, &self.l_row);
        let mut l = vec![0.0f64; lr.len()];
        let mut x = vec![0.0f64; n];
        // The next free position of each column of `L`, less one.
        let mut cur: Vec<usize> = lp[..n].to_vec();
        for k in 0..n {
            for p in self.a_ptr[k]..self.a_ptr[k + 1] {
                x[self.a_row[p]] += a[self.a_src[p]];
            }
            let mut d = x[k];
            x[k] = 0.0;
            for &j in &self.reach[self.reach_ptr[k]..self.reach_ptr[k + 1]] {
                let j_start = lp[j];
                cur[j] += 1;
                let at = cur[j];
                let xj = x[j];
                x[j] = 0.0;
                let lkj = xj * (1.0 / l[j_start]);
                for (&i, &lij) in lr[j_start + 1..at].iter().zip(&l[j_start + 1..at]) {
                    x[i] -= lij * lkj;
                }
                d -= lkj * lkj;
                l[at] = lkj;
            }
            if !(d > 0.0) {
                return Err(format!("NonPositivePivot {{ index: {} }}", k + 1));
            }
            l[lp[k]] = d.sqrt();
        }
        Ok(l)
    }
}

thread_local! {
    /// The last pattern factorized on this thread.
    static PATTERN: RefCell<Option<Rc<Pattern>>> = const { RefCell::new(None) };
}

/// The pattern of the entries listed, from the thread's cache when it is the last one.
fn pattern_of(n: usize, entries: &[Pair<usize, usize>]) -> Result<Rc<Pattern>, String> {
    if let Some(hit) = PATTERN.with_borrow(|c| c.as_ref().filter(|p| p.entries == entries).map(Rc::clone)) {
        return Ok(hit);
    }
    let (matrix, argsort) =
        SymbolicSparseColMat::try_new_from_indices(n, n, entries).map_err(|e| format!("assembly: {e:?}"))?;
    let cholesky = Rc::new(
        factorize_symbolic_cholesky(
            matrix.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .map_err(|e| format!("symbolic Cholesky factorization: {e:?}"))?,
    );
    let schedule = Schedule::new(&matrix, &cholesky);
    let pattern = Rc::new(Pattern { entries: entries.to_vec(), matrix, argsort, cholesky, schedule });
    PATTERN.with_borrow_mut(|c| *c = Some(Rc::clone(&pattern)));
    Ok(pattern)
}

impl Factor {
    /// Assembles and factorizes `K` at `sim`'s state.
    ///
    /// # Errors
    /// No spring stiffens the free bodies, or faer's error from the assembly, the symbolic
    /// or the numeric factorization (`K` not positive definite), as text.
    pub(super) fn new(sim: &Simulation, dofs: &Dofs) -> Result<Factor, String> {
        let (diag, off) = spring_stiffness(sim);
        let nb = sim.state.bodies.len();
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
            return Err(format!(
                "no stiffness on the free bodies (largest diagonal entries {tmax:e} N/m, {rmax:e} N·m)"
            ));
        }
        let is_held = |k: usize, r: usize| dofs.held[k][r];
        let cap = 21 * nb + 36 * off.len();
        let (mut entries, mut vals) = (Vec::with_capacity(cap), Vec::with_capacity(cap));
        let mut push = |row: usize, col: usize, v: f64| {
            entries.push(Pair { row, col });
            vals.push(v);
        };
        for k in 0..nb {
            let f0 = dofs.first[k];
            if f0 == usize::MAX {
                continue;
            }
            let mut kk = diag[k];
            if let Some(EndRestraint::Spring(ky)) = sim.state.restraint[k] {
                kk[(1, 1)] += ky;
            }
            for r in 0..6 {
                if is_held(k, r) {
                    push(f0 + r, f0 + r, 1.0);
                    continue;
                }
                let floor = if r < 3 { tmax } else { rmax } * 1e-9;
                push(f0 + r, f0 + r, kk[(r, r)] * (1.0 + 1e-6) + floor);
                for c in 0..r {
                    if !is_held(k, c) {
                        push(f0 + r, f0 + c, kk[(r, c)]);
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
                        push(row, col, v);
                    }
                }
            }
        }
        let pattern = pattern_of(dofs.n, &entries)?;
        let a = SparseColMat::new_from_argsort(pattern.matrix.clone(), &pattern.argsort, &vals)
            .map_err(|e| format!("assembly: {e:?}"))?;
        let symbolic = Rc::clone(&pattern.cholesky);
        if let Some(schedule) = &pattern.schedule {
            let values = schedule.factorize(a.val()).map_err(|e| format!("numeric Cholesky factorization: {e}"))?;
            return Ok(Factor { symbolic, values });
        }
        let mut values = vec![0.0f64; symbolic.len_val()];
        let mut mem = MemBuffer::try_new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()))
            .map_err(|e| format!("workspace: {e:?}"))?;
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
            .map_err(|e| format!("numeric Cholesky factorization: {e:?}"))?;
        Ok(Factor { symbolic, values })
    }

    /// `K⁻¹ R` for the out-of-balance loads `R` of `sim` (its last assessment), per body.
    pub(super) fn solve(&self, sim: &Simulation, dofs: &Dofs) -> PoseIncrement {
        let mut rhs = dofs.out_of_balance(sim);
        let llt = LltRef::new(&self.symbolic, &self.values);
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        llt.solve_in_place_with_conj(Conj::No, rhs.as_mut(), Par::Seq, MemStack::new(&mut mem));
        dofs.pose_increment(&rhs)
    }
}

/// Per-body diagonal blocks and per-pair coupling blocks (`(a, b) → K_ab`, rows of `a`)
/// of the stiffness `K` of every sub-contact spring of `sim` (N/m, N, N·m; table frame; see
/// the module doc). Couplings with a fixed body are left out.
fn spring_stiffness(sim: &Simulation) -> (Vec<Matrix6<f64>>, BTreeMap<(usize, usize), Matrix6<f64>>) {
    let nb = sim.state.bodies.len();
    let mut diag = vec![Matrix6::zeros(); nb];
    let mut off: BTreeMap<(usize, usize), Matrix6<f64>> = BTreeMap::new();
    // Spring points of one contact: arm from A's centroid (m), arm from B's centroid (m),
    // normal and shear stiffness (N/m).
    let mut points: Vec<(Vec3, Vec3, f64, f64)> = Vec::new();
    let mut arms: Vec<(Vec3, Vec3, f64)> = Vec::new();
    for c in &sim.state.contacts {
        let n = sim.state.contact_normal(c);
        let np = c.joint.normal();
        // `tangent` is Kn for an open node (u ≤ 0).
        let stiffness = |u: f64| np.tangent(u).max(np.kn);
        let rb_mat = &sim.state.bodies[c.b].rot_mat;
        let ra_mat = c.a.map(|i| sim.state.bodies[i].rot_mat);
        // Node arms and closures.
        arms.clear();
        for nd in &c.nodes {
            let (pa, pb) = sim.state.node_points(c, nd);
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
        let free_b = !sim.state.bodies[c.b].fixed();
        let free_a = c.a.filter(|&i| !sim.state.bodies[i].fixed());
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
    use crate::dem::{RunToEquilibrium, SolverParams};
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
        let (diag, _) = spring_stiffness(&sim);
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
}
