//! The Newton step: the tangent's blocks reduced to the free degrees of freedom and
//! solved by faer's sparse LU, its symbolic factorization kept while the pattern holds.

use super::{skew, tangent_blocks, FLOOR};
use crate::dem::drivers::implicit::stiffness::Dofs;
use crate::dem::drivers::implicit::PoseIncrement;
use crate::dem::engine::Simulation;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams, NumericLu, SymbolicLu};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Conj, Par};
use nalgebra::Matrix6;
use std::cell::RefCell;
use std::rc::Rc;

/// The map `E` (6 × 6) from a body's free degrees of freedom to its motion: the identity
/// on the free ones, zero columns for the held ones, and for a translation held at an
/// anchor off the centroid the centroid's motion that keeps the anchor on its target as
/// the body turns (`δx_i = ([a]× δθ)_i`, `a` the anchor's arm, table frame).
fn reduction(sim: &Simulation, dofs: &Dofs, k: usize) -> Matrix6<f64> {
    let mut e = Matrix6::identity();
    let held = dofs.held[k];
    for (i, &h) in held.iter().enumerate() {
        if h {
            e[(i, i)] = 0.0;
        }
    }
    let b = &sim.state.bodies[k];
    if let Some(c) = b.hold.dof() {
        let ax = skew(&(b.rot_mat * c.anchor));
        for i in 0..3 {
            if c.translation[i].is_some() {
                for j in 0..3 {
                    if !held[3 + j] {
                        e[(i, 3 + j)] = ax[(i, j)];
                    }
                }
            }
        }
    }
    e
}

/// The assembly pattern of the tangent on this thread: the (row, column) of every entry in
/// the order the assembly lists them, the compressed sparse column pattern they make with
/// the order to read the values in, and the pattern's symbolic LU factorization (COLAMD
/// column ordering). The pattern changes only when contacts are re-detected; a hit gives
/// the same matrix and ordering as a fresh analysis, so the results never depend on it.
struct Pattern {
    entries: Vec<Pair<usize, usize>>,
    matrix: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    lu: SymbolicLu<usize>,
}

/// The numeric LU factorization's storage and the scratch space of its factorization and
/// solve, kept between the iterations that factorize the same pattern (their sizes depend
/// on the pattern alone; every factorization overwrites them).
struct Workspace {
    pattern: Rc<Pattern>,
    numeric: NumericLu<usize, f64>,
    factor: MemBuffer,
    solve: MemBuffer,
}

thread_local! {
    /// The workspace of the last pattern factorized on this thread.
    static WORKSPACE: RefCell<Option<Workspace>> = const { RefCell::new(None) };
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
    let lu = factorize_symbolic_lu(
        matrix.as_ref(),
        LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        },
    )
    .map_err(|e| format!("symbolic LU factorization: {e:?}"))?;
    let pattern = Rc::new(Pattern { entries: entries.to_vec(), matrix, argsort, lu });
    PATTERN.with_borrow_mut(|c| *c = Some(Rc::clone(&pattern)));
    Ok(pattern)
}

/// The Newton step of a state: `K⁻¹ R` for the tangent `K` and the out-of-balance loads
/// `R` of `sim`'s state (its last assessment), per body: translation (m) and rotation
/// vector (rad), table frame; zero for the held degrees of freedom (the jump puts a held
/// anchor back itself). `K` is assembled and factorized by faer's sparse LU with partial
/// pivoting (supernodal, COLAMD column ordering, sequential).
///
/// # Errors
/// No stiffness on the free bodies, or faer's error from the assembly or the
/// factorization, as text.
pub(in crate::dem::drivers::newton) fn newton_step(
    sim: &Simulation,
    x: &PoseIncrement,
    dofs: &Dofs,
) -> Result<PoseIncrement, String> {
    {
        let blocks = tangent_blocks(sim, x);
        let nb = sim.state.bodies.len();
        let e: Vec<Matrix6<f64>> = (0..nb)
            .map(|k| if dofs.first[k] == usize::MAX { Matrix6::zeros() } else { reduction(sim, dofs, k) })
            .collect();
        let (mut tmax, mut rmax) = (0.0f64, 0.0f64);
        let mut diag = Vec::with_capacity(nb);
        for k in 0..nb {
            let d = e[k].transpose() * blocks.diag[k] * e[k];
            if dofs.first[k] != usize::MAX {
                for r in 0..3 {
                    tmax = tmax.max(d[(r, r)].abs());
                    rmax = rmax.max(d[(r + 3, r + 3)].abs());
                }
            }
            diag.push(d);
        }
        if !(tmax > 0.0 && rmax > 0.0) {
            return Err(format!(
                "no stiffness on the free bodies (largest diagonal entries {tmax:e} N/m, {rmax:e} N·m)"
            ));
        }
        let cap = 36 * (nb + blocks.off.len());
        let (mut entries, mut vals) = (Vec::with_capacity(cap), Vec::with_capacity(cap));
        let mut push = |row: usize, col: usize, v: f64| {
            entries.push(Pair { row, col });
            vals.push(v);
        };
        for (k, d) in diag.iter().enumerate() {
            let f0 = dofs.first[k];
            if f0 == usize::MAX {
                continue;
            }
            for r in 0..6 {
                if dofs.held[k][r] {
                    push(f0 + r, f0 + r, 1.0);
                    continue;
                }
                for c in 0..6 {
                    if dofs.held[k][c] {
                        continue;
                    }
                    let mut v = d[(r, c)];
                    if r == c {
                        v += FLOOR * if r < 3 { tmax } else { rmax };
                    }
                    push(f0 + r, f0 + c, v);
                }
            }
        }
        for ((a, b), kab) in &blocks.off {
            let (fa, fb) = (dofs.first[*a], dofs.first[*b]);
            let m = e[*a].transpose() * kab * e[*b];
            for r in 0..6 {
                if dofs.held[*a][r] {
                    continue;
                }
                for c in 0..6 {
                    if !dofs.held[*b][c] {
                        push(fa + r, fb + c, m[(r, c)]);
                    }
                }
            }
        }
        let pattern = pattern_of(dofs.n, &entries)?;
        let a = SparseColMat::new_from_argsort(pattern.matrix.clone(), &pattern.argsort, &vals)
            .map_err(|e| format!("assembly: {e:?}"))?;
        let symbolic = &pattern.lu;
        let mut rhs = dofs.out_of_balance(sim);
        WORKSPACE.with_borrow_mut(|cache| -> Result<(), String> {
            if cache.as_ref().is_none_or(|w| !Rc::ptr_eq(&w.pattern, &pattern)) {
                let factor =
                    MemBuffer::try_new(symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()))
                        .map_err(|e| format!("workspace: {e:?}"))?;
                let solve = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
                    .map_err(|e| format!("workspace: {e:?}"))?;
                *cache = Some(Workspace { pattern: Rc::clone(&pattern), numeric: NumericLu::new(), factor, solve });
            }
            let w = cache.as_mut().expect("set above");
            let lu = symbolic
                .factorize_numeric_lu(
                    &mut w.numeric,
                    a.as_ref(),
                    Par::Seq,
                    MemStack::new(&mut w.factor),
                    Default::default(),
                )
                .map_err(|e| format!("numeric LU factorization: {e:?}"))?;
            lu.solve_in_place_with_conj(Conj::No, rhs.as_mut(), Par::Seq, MemStack::new(&mut w.solve));
            Ok(())
        })?;
        let step = dofs.pose_increment(&rhs);
        if step.0.iter().chain(&step.1).any(|v| !v.iter().all(|x| x.is_finite())) {
            return Err("the LU solve gave a non-finite step".into());
        }
        Ok(step)
    }
}
