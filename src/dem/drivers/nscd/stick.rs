//! The stick-set correction of the NSGS iteration: a global solve over the contact points
//! that stick, between Gauss–Seidel sweeps.
//!
//! Gauss–Seidel removes the error of the impulses contact by contact: a correction travels
//! one contact per sweep, so the smooth part of the error (a course, or the upper half of
//! the wall, moving as a whole on contacts that should hold it; a heavy stone on a light
//! wedge) takes hundreds of sweeps on a wall of a few hundred blocks, and a sweep that
//! changes little says little about what is left. The correction removes that part in one
//! linear solve, as the coarse level of a two-level method does, and the sweeps that follow
//! (the smoother) restore the Signorini–Coulomb conditions it may break.
//!
//! # The solve
//!
//! With the statuses the sweeps have reached, each point α that carries a normal impulse
//! either sticks (its impulse inside the Coulomb cone: all three components of its
//! relative velocity `u_α` should vanish) or slips (on the cone: the normal component
//! should). The correction finds the body velocity change Δv (six per free body) and
//! impulse changes Δr_α that cancel those velocities in the least-squares sense of a stiff
//! regularization:
//!
//! ```text
//! (M + Σ_α H_αᵀ K_α H_α) Δv = −Σ_α H_αᵀ K_α u_α,      Δr_α = −K_α (u_α + H_α Δv)
//! ```
//!
//! with `K_α = κ W_αα⁻¹` for a sticking point (its three rows) and `κ / (W_αα)ₙₙ` on the
//! normal row of a slipping one (κ [`super::NscdParams::stick_stiffness`], dimensionless:
//! the velocity left at a point is `1/κ` of what its own correction would cancel), `M` the
//! bodies' mass and inertia, `H_α` the point's rows (`super::delassus`), `u_α` the point's
//! velocity (a point with a Signorini term `b ≠ 0`, open or closing within the step, is
//! left to the sweeps: the velocity it asks for may contradict its neighbours'). The normal equations give `M Δv = Σ H_αᵀ Δr_α`: the change is a
//! set of impulses, applied to the bodies point by point as a sweep applies them. Among
//! the many impulse sets that hold a statically indeterminate wall the regularization picks
//! the one of least `Σ Δr_αᵀ K_α⁻¹ Δr_α`: it spreads the load over the points of a polygon
//! instead of piling it on one. This is the compliance form of a constraint solve (as
//! the implicit step of a stiff spring model, with κ → ∞ the exact constraint); it is a
//! correction of the iterate, not a different model: the sweeps decide the final impulses.
//!
//! The matrix is assembled per body pair and factorized by faer's sparse Cholesky (an
//! approximate minimum degree ordering, simplicial, sequential), its pattern (every pair in
//! contact, whatever its status) analysed once per contact detection.

use super::contacts::ContactPoint;
use super::delassus::{PointRows, TABLE};
use crate::math::{Mat3, Vec3};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par, Side};
use nalgebra::{Matrix3x6, Matrix6};
use std::sync::Arc;

/// The symbolic factorization of the pattern of the last detection (cached).
#[derive(Clone, Default)]
pub(crate) struct StickSolver {
    symbolic: Option<(Vec<usize>, Vec<usize>, Arc<SymbolicCholesky<usize>>)>,
}

impl std::fmt::Debug for StickSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("StickSolver")
    }
}

/// The bodies as the correction sees them: mass per axis and world inertia of each free
/// body, `None` for the table side of a contact and fixed blocks.
pub(crate) struct Masses<'a> {
    /// Inverse mass per axis (0: held on that axis, or fixed), 1/kg.
    pub inv_m: &'a [Vec3],
    /// Inverse inertia in the table frame (zeros: fixed), 1/(kg·m²).
    pub inv_i: &'a [Mat3],
}

/// The point's rows on one of its bodies: `u = H_B v_B + H_A v_A` with `H_B = [Eᵀ C_Bᵀ]`,
/// `H_A = −[Eᵀ C_Aᵀ]`.
fn rows_of(rows: &PointRows, on_b: bool) -> Matrix3x6<f64> {
    let (e, c, s) = if on_b { (rows.frame, rows.c_b, 1.0) } else { (rows.frame, rows.c_a, -1.0) };
    let mut h = Matrix3x6::zeros();
    h.fixed_view_mut::<3, 3>(0, 0).copy_from(&(e.transpose() * s));
    h.fixed_view_mut::<3, 3>(0, 3).copy_from(&(c.transpose() * s));
    h
}

impl StickSolver {
    /// Forgets the cached pattern (after a detection).
    pub(crate) fn reset(&mut self) {
        self.symbolic = None;
    }

    /// Applies the correction (see the module doc) to the impulses of `points` and the
    /// velocities `vel`, `angvel`; `kappa` is κ. Returns false, changing nothing, when no
    /// point carries an impulse or the factorization fails (the sweeps then go on alone).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn correct(
        &mut self,
        points: &mut [ContactPoint],
        rows: &[PointRows],
        masses: &Masses<'_>,
        vel: &mut [Vec3],
        angvel: &mut [Vec3],
        kappa: f64,
    ) -> bool {
        let nb = vel.len();
        // Unknowns: six per body that can move (an axis held by a restraint keeps a row
        // with a unit diagonal and no coupling).
        let mut first = vec![usize::MAX; nb];
        let mut n = 0;
        for k in 0..nb {
            if masses.inv_m[k] != Vec3::zeros() || masses.inv_i[k] != Mat3::zeros() {
                first[k] = n;
                n += 6;
            }
        }
        if n == 0 {
            return false;
        }
        let held = |k: usize, r: usize| r < 3 && masses.inv_m[k][r] == 0.0;
        // Diagonal blocks (the mass), then each point's contributions per body pair.
        let mut diag = vec![Matrix6::<f64>::zeros(); nb];
        for k in (0..nb).filter(|&k| first[k] != usize::MAX) {
            for r in 0..3 {
                if !held(k, r) {
                    diag[k][(r, r)] = 1.0 / masses.inv_m[k][r];
                }
            }
            let inertia = masses.inv_i[k].try_inverse().unwrap_or_else(Mat3::zeros);
            diag[k].fixed_view_mut::<3, 3>(3, 3).copy_from(&inertia);
        }
        let mut rhs = Mat::<f64>::zeros(n, 1);
        let mut off: Vec<((usize, usize), Matrix6<f64>)> = Vec::new();
        let mut gains: Vec<Option<Mat3>> = vec![None; points.len()];
        let mut any = false;
        for (k, (c, rw)) in points.iter().zip(rows).enumerate() {
            let r = c.impulse;
            let pair_index = (rw.a, rw.b);
            // A point that may close within the step (its Signorini term b is not zero) asks
            // for a velocity of its own, which the others' may contradict: left to the sweeps.
            let gain = if r.x <= 0.0 || rw.bias != 0.0 {
                None
            } else if r.y * r.y + r.z * r.z < c.mu * c.mu * r.x * r.x * (1.0 - 1e-9) {
                Some(rw.w_inv * kappa)
            } else if rw.w[(0, 0)] > 0.0 {
                let mut g = Mat3::zeros();
                g[(0, 0)] = kappa / rw.w[(0, 0)];
                Some(g)
            } else {
                None
            };
            // Every pair in contact enters the pattern, whatever its status.
            if rw.a != TABLE
                && first[rw.a] != usize::MAX
                && first[rw.b] != usize::MAX
                && off.last().map(|(p, _)| *p) != Some(pair_index)
            {
                off.push((pair_index, Matrix6::zeros()));
            }
            let Some(g) = gain else { continue };
            any = true;
            gains[k] = Some(g);
            let u = rw.velocity(vel, angvel);
            let hb = rows_of(rw, true);
            let ku = g * u;
            if first[rw.b] != usize::MAX {
                diag[rw.b] += hb.transpose() * g * hb;
                let f = -(hb.transpose() * ku);
                for i in 0..6 {
                    rhs[(first[rw.b] + i, 0)] += f[i];
                }
            }
            if rw.a != TABLE && first[rw.a] != usize::MAX {
                let ha = rows_of(rw, false);
                diag[rw.a] += ha.transpose() * g * ha;
                let f = -(ha.transpose() * ku);
                for i in 0..6 {
                    rhs[(first[rw.a] + i, 0)] += f[i];
                }
                if first[rw.b] != usize::MAX {
                    // Block (b, a): H_Bᵀ K H_A.
                    if let Some(last) = off.last_mut() {
                        last.1 += hb.transpose() * g * ha;
                    }
                }
            }
        }
        if !any {
            return false;
        }
        let mut entries = Vec::with_capacity(21 * nb + 36 * off.len());
        for k in (0..nb).filter(|&k| first[k] != usize::MAX) {
            let f0 = first[k];
            for r in 0..6 {
                if held(k, r) {
                    entries.push(Triplet::new(f0 + r, f0 + r, 1.0));
                    rhs[(f0 + r, 0)] = 0.0;
                    continue;
                }
                entries.push(Triplet::new(f0 + r, f0 + r, diag[k][(r, r)]));
                for cc in 0..r {
                    if !held(k, cc) {
                        entries.push(Triplet::new(f0 + r, f0 + cc, diag[k][(r, cc)]));
                    }
                }
            }
        }
        for ((a, b), kba) in &off {
            // Block (b, a) = H_Bᵀ K H_A: rows of b, columns of a; keep the lower triangle.
            let (fa, fb) = (first[*a], first[*b]);
            for r in 0..6 {
                for cc in 0..6 {
                    let (row, col, v, hr, hc) = if fb > fa {
                        (fb + r, fa + cc, kba[(r, cc)], held(*b, r), held(*a, cc))
                    } else {
                        (fa + cc, fb + r, kba[(r, cc)], held(*a, cc), held(*b, r))
                    };
                    if !(hr || hc) {
                        entries.push(Triplet::new(row, col, v));
                    }
                }
            }
        }
        let Ok(a) = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &entries) else { return false };
        let Some(symbolic) = self.symbolic_of(&a) else { return false };
        let mut values = vec![0.0f64; symbolic.len_val()];
        let Ok(mut mem) =
            MemBuffer::try_new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()))
        else {
            return false;
        };
        if symbolic
            .factorize_numeric_llt(
                &mut values,
                a.as_ref(),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .is_err()
        {
            return false;
        }
        let llt = LltRef::new(&symbolic, &values);
        let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        llt.solve_in_place_with_conj(Conj::No, rhs.as_mut(), Par::Seq, MemStack::new(&mut mem));
        if !(0..n).all(|i| rhs[(i, 0)].is_finite()) {
            return false;
        }
        // Δr_α = −K_α (u_α + H_α Δv), from the velocities before any change.
        let dv = |k: usize| -> nalgebra::Vector6<f64> {
            let f0 = first[k];
            if f0 == usize::MAX {
                return nalgebra::Vector6::zeros();
            }
            nalgebra::Vector6::from_fn(|i, _| rhs[(f0 + i, 0)])
        };
        let mut changes = Vec::with_capacity(points.len());
        for (k, rw) in rows.iter().enumerate() {
            let Some(g) = gains[k] else { continue };
            let u = rw.velocity(vel, angvel);
            let mut hu = rows_of(rw, true) * dv(rw.b);
            if rw.a != TABLE {
                hu += rows_of(rw, false) * dv(rw.a);
            }
            changes.push((k, -(g * (u + hu))));
        }
        for (k, dr) in changes {
            rows[k].apply(&dr, vel, angvel);
            points[k].impulse += dr;
        }
        true
    }

    fn symbolic_of(&mut self, a: &SparseColMat<usize, f64>) -> Option<Arc<SymbolicCholesky<usize>>> {
        let (cp, ri) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
        if let Some((p, r, s)) = &self.symbolic {
            if p.as_slice() == cp && r.as_slice() == ri {
                return Some(Arc::clone(s));
            }
        }
        let s = Arc::new(
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
        self.symbolic = Some((cp.to_vec(), ri.to_vec(), Arc::clone(&s)));
        Some(s)
    }
}
