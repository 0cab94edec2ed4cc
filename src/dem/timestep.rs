//! Critical time step of the explicit scheme.
//!
//! Every sub-contact node carries three springs (open or closed): normal `Kn·A/3` and two
//! shear `Ks·A/3` per sub-contact it belongs to, of area `A`. A spring of direction `d`
//! between the material points at arms `r_A`, `r_B` from the two centroids has the
//! generalized directions `g_B = (d, r_B × d)` and `g_A = −(d, r_A × d)`, and adds
//! `k g gᵀ` to the assembled stiffness `K` (6 dofs per body: translation, then rotation;
//! table frame). The step is set by the highest frequency of `K` against the mass matrix
//! `M = diag(s m, s m, s m, s R I Rᵀ)` (density scaling factor `s`, 1 without it; a body's
//! 6 × 6 block mass instead under block scaling, [`block_masses`]),
//! `ω_max² = λ_max(M^{-1/2} K M^{-1/2})` ([`Stiffness::max_eigenvalue`], Lanczos), and the
//! local damping α ([`step_for`]):
//!
//! ```text
//! Δt = safety × 2 / (ω_max √(1 + α))        (safety 0.95 by default)
//! ```
//!
//! Central differences alone are stable for `ω Δt < 2`; local damping multiplies a force
//! that opposes the velocity by `1 + α`, which lowers the limit of the highest mode to
//! `2/√(1 + α)` (1.49 for α = 0.8; a test integrates one body either side of it). The
//! Lanczos value over-estimates `ω_max²` slightly (its residual bound), and the arms change
//! by under a millimetre between detections: the 5 % margin covers both.
//!
//! The per-body eigenvalues (each body against its neighbours held,
//! [`Stiffness::body_eigenvalues`]) set the density scaling and give the classical bound
//! `ω_max² ≤ 2 max_body λ_body` (each spring joins two bodies), which caps the Lanczos
//! estimate. A step from the body bound without the damping factor, `0.8 × 2 / √(2 λ_body)`,
//! would put the highest mode of the SBL wall (assembled `ω_max²` 1.65 times the scaled body
//! eigenvalue) at 97–98 % of the damped limit, and a layout with a ratio above 1.75 (a column
//! of blocks tends to 2) past it.
//!
//! A joint's normal stiffness is the bound of its closure law's tangent
//! ([`crate::dem::contact::law::JointParams::kn_bound`]: `Kn` for the linear law), except for
//! a law whose tangent grows far past its initial stiffness (the hyperbolic law's reaches
//! `25 Kni` at its cap): each sub-contact then takes the bound over a window of the closure
//! from its nodes' largest ([`set_closure_windows`],
//! [`crate::closure::ClosureLaw::tangent_window`]), and the contact pass asks for a new step
//! as soon as a node closes past its window, as the ropes' bound is taken over a window of
//! their deflection ([`Stiffness::add_restraints`]).
//!
//! The three springs of a node sum to `w C₀` with `C₀ = Ks I + (Kn − Ks) n nᵀ` (`w` the
//! node's area), so a contact's blocks follow from the moments `Σ w`, `Σ w r` and
//! `Σ w r_p r_qᵀ` of its nodes (see [`Stiffness::new`]) instead of three outer products
//! per node and side.

use super::contact::types::Contact;
use super::rope::{stiffness_bound, RopeLoad};
use super::state::Body;
use crate::layout::EndRestraint;
use crate::math::{Mat3, Vec3};
use nalgebra::{DMatrix, Matrix6, Vector6};

/// `[a]×`, the cross-product matrix: `[a]× b = a × b`.
fn skew(a: &Vec3) -> Mat3 {
    Mat3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// The 6 × 6 block coupling side `p` to side `q` of one contact's springs:
/// `Σ_nodes Σ_dirs k g_p g_qᵀ` without the signs, from the node moments `w = Σ w`,
/// `sp = Σ w r_p`, `sq = Σ w r_q`, `rpq = Σ w r_p r_qᵀ` (N/m, N, N·m), for `C₀` with the
/// stiffnesses `ks`, `beta = Kn − Ks` (Pa/m) and the unit normal `n`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn block(c0: &Mat3, n: &Vec3, ks: f64, beta: f64, w: f64, sp: &Vec3, sq: &Vec3, rpq: &Mat3) -> Matrix6<f64> {
    let mut k = Matrix6::zeros();
    // TT: Σ w C₀;  TR: Σ w C₀ [r_q]×ᵀ;  RT: Σ w [r_p]× C₀;
    // RR: Σ w [r_p]× C₀ [r_q]×ᵀ = Ks (tr(R) I − Rᵀ) + (Kn − Ks) [n]× R [n]×ᵀ, R = Σ w r_p r_qᵀ
    // (from [a]×[b]×ᵀ = (a·b) I − b aᵀ and [r]× n = −[n]× r).
    let nx = skew(n);
    k.fixed_view_mut::<3, 3>(0, 0).copy_from(&(c0 * w));
    k.fixed_view_mut::<3, 3>(0, 3).copy_from(&(c0 * skew(sq).transpose()));
    k.fixed_view_mut::<3, 3>(3, 0).copy_from(&(skew(sp) * c0));
    let rr = (Mat3::identity() * rpq.trace() - rpq.transpose()) * ks + nx * rpq * nx.transpose() * beta;
    k.fixed_view_mut::<3, 3>(3, 3).copy_from(&rr);
    k
}

/// The assembled stiffness of every sub-contact spring, table frame: a 6 × 6 diagonal block
/// per body and one off-diagonal block per contact between two free bodies (N/m, N, N·m;
/// dofs: translation in m, rotation in rad).
#[derive(Debug, Clone)]
pub struct Stiffness {
    /// `K_ii` per body (zero for fixed bodies and bodies without contacts).
    diag: Vec<Matrix6<f64>>,
    /// Whether a body has any spring.
    touched: Vec<bool>,
    /// `(a, b, K_ab)`: the coupling of free bodies `a` and `b` (`K_ba = K_abᵀ`).
    off: Vec<(usize, usize, Matrix6<f64>)>,
    /// Largest eigenvalue of each diagonal block against the body's true mass, rad²/s².
    body_lambdas: Vec<f64>,
}

/// The moments of a contact's nodes for [`block`] under the node weights `w_i` (m² or
/// N/m): `w = Σ w_i`, `sa = Σ w_i r_A`, `sb = Σ w_i r_B`, `raa = Σ w_i r_A r_Aᵀ`,
/// `rab = Σ w_i r_A r_Bᵀ`, `rbb = Σ w_i r_B r_Bᵀ`, arms in the table frame (zero on A's side
/// for the table).
struct NodeMoments {
    w: f64,
    sa: Vec3,
    sb: Vec3,
    raa: Mat3,
    rab: Mat3,
    rbb: Mat3,
}

impl NodeMoments {
    fn of(c: &Contact, weight: &[f64], ra_mat: Option<&Mat3>, rb_mat: &Mat3) -> NodeMoments {
        let (mut w, mut sa, mut sb) = (0.0, Vec3::zeros(), Vec3::zeros());
        let (mut raa, mut rab, mut rbb) = (Mat3::zeros(), Mat3::zeros(), Mat3::zeros());
        for (nd, &wi) in c.nodes.iter().zip(weight) {
            if wi == 0.0 {
                continue;
            }
            let rb = rb_mat * nd.on_b;
            w += wi;
            sb += rb * wi;
            rbb += rb * rb.transpose() * wi;
            if let Some(m) = ra_mat {
                let ra = m * nd.on_a;
                sa += ra * wi;
                raa += ra * ra.transpose() * wi;
                rab += ra * rb.transpose() * wi;
            }
        }
        NodeMoments { w, sa, sb, raa, rab, rbb }
    }
}

/// Takes each sub-contact's window of its closure law's tangent at the current poses
/// ([`crate::closure::ClosureLaw::tangent_window`], from the largest closure of its three
/// nodes): what [`Stiffness::new`] then reads as the sub-contact's normal stiffness, and
/// what the contact pass watches ([`super::contact::types::SubContact::window_cap_m`]).
/// Contacts whose law has no windows are left as they are. Closures as in the contact
/// pass: the nodes' overlap along the mean of the two bodies' detection normals.
pub fn set_closure_windows(bodies: &[Body], contacts: &mut [Contact]) {
    for c in contacts.iter_mut().filter(|c| c.joint.closure.is_windowed()) {
        let bb = &bodies[c.b];
        let (pa_of, n) = match c.a {
            None => ((Mat3::identity(), Vec3::zeros()), (c.normal_a + bb.rot_mat * c.normal_b).normalize()),
            Some(i) => {
                let a = &bodies[i];
                ((a.rot_mat, a.pos), (a.rot_mat * c.normal_a + bb.rot_mat * c.normal_b).normalize())
            }
        };
        let closure = |k: u32| {
            let nd = &c.nodes[k as usize];
            let pa = pa_of.1 + pa_of.0 * nd.on_a;
            let pb = bb.pos + bb.rot_mat * nd.on_b;
            -(pb - pa).dot(&n)
        };
        let (kn, law) = (c.joint.kn, c.joint.closure);
        let mut windows = Vec::with_capacity(c.subs.len());
        for s in &c.subs {
            let u = s.nodes.iter().map(|&k| closure(k)).fold(f64::NEG_INFINITY, f64::max);
            windows.push(law.tangent_window(kn, u).unwrap_or((f64::INFINITY, c.joint.kn_bound())));
        }
        for (s, (cap, k)) in c.subs.iter_mut().zip(windows) {
            s.window_cap_m = cap;
            s.window_kn = k;
        }
    }
}

impl Stiffness {
    /// Assembles the springs of `contacts` at the current poses of `bodies` (normal from
    /// the mean of the two bodies' detection normals, as in the contact pass; node arms
    /// from each body's own material point).
    pub fn new(bodies: &[Body], contacts: &[Contact]) -> Stiffness {
        let nb = bodies.len();
        let mut diag = vec![Matrix6::zeros(); nb];
        let mut touched = vec![false; nb];
        let mut off = Vec::new();
        let mut weight = Vec::new();
        let mut normal_weight = Vec::new();
        for c in contacts {
            let rb_mat = &bodies[c.b].rot_mat;
            let ra_mat = c.a.map(|i| bodies[i].rot_mat);
            let na = match &ra_mat {
                None => c.normal_a,
                Some(m) => m * c.normal_a,
            };
            let n = (na + rb_mat * c.normal_b).normalize();
            let ks = c.joint.ks;
            // Node areas: a third of every sub-contact the node belongs to.
            weight.clear();
            weight.resize(c.nodes.len(), 0.0);
            for s in &c.subs {
                for &i in &s.nodes {
                    weight[i as usize] += s.area / 3.0;
                }
            }
            let m = NodeMoments::of(c, &weight, ra_mat.as_ref(), rb_mat);
            if m.w == 0.0 {
                continue;
            }
            // The blocks: one normal stiffness for the whole contact (the law's bound), or,
            // for a law with tangent windows, each sub-contact's window bound on its nodes
            // (`Ks I` over the areas plus `(k_s − Ks) n nᵀ` over the areas so weighted: a
            // sub-contact's tangent is at most its window's anywhere on it, so the nodes'
            // sum bounds the law's stiffness as the vertex rule bounds the linear one's).
            let blocks = |p: &Vec3, q: &Vec3, r: &Mat3, nm: Option<(&NodeMoments, &Vec3, &Vec3, &Mat3)>| match nm {
                None => {
                    let kn = c.joint.kn_bound();
                    let c0 = Mat3::identity() * ks + n * n.transpose() * (kn - ks);
                    block(&c0, &n, ks, kn - ks, m.w, p, q, r)
                }
                Some((nw, np, nq, nr)) => {
                    block(&(Mat3::identity() * ks), &n, ks, 0.0, m.w, p, q, r)
                        + block(&(n * n.transpose()), &n, 0.0, 1.0, nw.w, np, nq, nr)
                }
            };
            let nm = c.joint.closure.is_windowed().then(|| {
                normal_weight.clear();
                normal_weight.resize(c.nodes.len(), 0.0);
                for s in &c.subs {
                    for &i in &s.nodes {
                        normal_weight[i as usize] += (s.window_kn - ks) * s.area / 3.0;
                    }
                }
                NodeMoments::of(c, &normal_weight, ra_mat.as_ref(), rb_mat)
            });
            let free_b = !bodies[c.b].fixed();
            let free_a = c.a.filter(|&i| !bodies[i].fixed());
            if free_b {
                diag[c.b] += blocks(&m.sb, &m.sb, &m.rbb, nm.as_ref().map(|x| (x, &x.sb, &x.sb, &x.rbb)));
                touched[c.b] = true;
            }
            if let Some(a) = free_a {
                diag[a] += blocks(&m.sa, &m.sa, &m.raa, nm.as_ref().map(|x| (x, &x.sa, &x.sa, &x.raa)));
                touched[a] = true;
                if free_b {
                    // g_A = −(d, r_A × d): the coupling carries a minus sign.
                    off.push((a, c.b, -blocks(&m.sa, &m.sb, &m.rab, nm.as_ref().map(|x| (x, &x.sa, &x.sb, &x.rab)))));
                }
            }
        }
        let mut k = Stiffness { diag, touched, off, body_lambdas: Vec::new() };
        k.body_lambdas = k.diagonal_eigenvalues(bodies);
        k
    }

    /// Adds the restraints' springs to the diagonal blocks of the bodies they hold, at the
    /// current poses: a spring end restraint of stiffness `k` (N/m) on the body's y
    /// translation, and for each rope a spring in y at each bearer's point `p_b` (arm
    /// `r_b` from the centroid; generalized direction `(ŷ, r_b × ŷ)`) of stiffness
    /// `w_b K`, with `w_b = h_b / Σ h` the bearer's share of the band and `K` the rope's
    /// tangent stiffness bound over the deflections `[δ̄ − reach, δ̄ + reach]`
    /// ([`super::rope::stiffness_bound`]; `reach`, m, the motion allowed before the next
    /// update). A lone bearer gets the rope's whole `dF/dδ̄`; the coupling of several
    /// bearers through their shared tension (rank one, at most `w_b` times the axial
    /// term) is left to the step's margin. Without the springs the step of a layout
    /// whose restraints are stiffer than its contacts is unstable: a rope of 1e6 N over
    /// 0.1 m legs adds `2 T₀ / s` = 2e7 N/m. Rigid end restraints hold the dof and add
    /// nothing. `reach_m` ≥ 0.
    pub fn add_restraints(
        &mut self,
        bodies: &[Body],
        restraint: &[Option<EndRestraint>],
        ropes: &[RopeLoad],
        reach_m: f64,
    ) {
        // The bodies whose diagonal block a restraint changes: only their eigenvalues are
        // taken again (the others' blocks, and so their eigenvalues, stand).
        let mut changed = vec![false; bodies.len()];
        for (k, r) in restraint.iter().enumerate() {
            if let (Some(EndRestraint::Spring(ky)), false) = (r, bodies[k].fixed()) {
                self.diag[k][(1, 1)] += ky;
                self.touched[k] = true;
                changed[k] = true;
            }
        }
        for rope in ropes {
            if rope.covered <= 0.0 {
                continue;
            }
            let d = rope.deflection(bodies);
            let kr = stiffness_bound(&rope.rope, (d - reach_m).max(0.0), d + reach_m);
            for b in &rope.bearers {
                if bodies[b.body].fixed() || !(kr > 0.0) {
                    continue;
                }
                let m = rope.arm(b, bodies).cross(&Vec3::y());
                let g = Vector6::new(0.0, 1.0, 0.0, m.x, m.y, m.z);
                self.diag[b.body] += g * g.transpose() * (kr * b.height / rope.covered);
                self.touched[b.body] = true;
                changed[b.body] = true;
            }
        }
        for (i, b) in bodies.iter().enumerate() {
            if changed[i] {
                self.body_lambdas[i] = self.body_eigenvalue(i, b);
            }
        }
    }

    /// `M^{-1/2}` of a body's inertial mass (6 × 6, table frame): with `scaled`, as the
    /// integrator uses it, its block mass (`Q diag(λ^{-1/2}) Qᵀ`) if it has one, else
    /// `diag(1/√(s m), (s R I Rᵀ)^{-1/2})`; without, the true mass (`s = 1`).
    fn mass_root(b: &Body, scaled: bool) -> Matrix6<f64> {
        if let (true, Some(bm)) = (scaled, &b.block_mass) {
            return bm.q * Matrix6::from_diagonal(&bm.inv_lambda.map(f64::sqrt)) * bm.q.transpose();
        }
        let r = if scaled { b.inertia_scale_inv.sqrt() } else { 1.0 };
        let mut s = Matrix6::zeros();
        for k in 0..3 {
            s[(k, k)] = r / b.mass.sqrt();
        }
        s.fixed_view_mut::<3, 3>(3, 3).copy_from(&(b.rot_mat * b.inv_sqrt_inertia * b.rot_mat.transpose() * r));
        s
    }

    /// `λ_max(S K_ii S)` for the mass root `S` of body `i`.
    fn block_eigenvalue(&self, i: usize, s: &Matrix6<f64>) -> f64 {
        (s * self.diag[i] * s).symmetric_eigenvalues().iter().cloned().fold(0.0, f64::max)
    }

    /// The largest eigenvalue `λ = ω²` (rad²/s²) of each body's diagonal block against its
    /// true (unscaled) mass matrix: the body's highest frequency with its neighbours held;
    /// 0 for fixed bodies and bodies without contacts. Length: one per body.
    pub fn body_eigenvalues(&self) -> &[f64] {
        &self.body_lambdas
    }

    fn diagonal_eigenvalues(&self, bodies: &[Body]) -> Vec<f64> {
        bodies.iter().enumerate().map(|(i, b)| self.body_eigenvalue(i, b)).collect()
    }

    /// Body `i`'s entry of [`Stiffness::body_eigenvalues`].
    fn body_eigenvalue(&self, i: usize, b: &Body) -> f64 {
        if b.fixed() || !self.touched[i] {
            0.0
        } else {
            self.block_eigenvalue(i, &Self::mass_root(b, false))
        }
    }

    /// The largest eigenvalue `λ = ω²` (rad²/s²) of the whole assembly against the
    /// density-scaled mass matrix (each body's `inertia_scale_inv`); 0 if no free body has
    /// a spring.
    ///
    /// Lanczos iteration with full re-orthogonalization (Golub & Van Loan, *Matrix
    /// Computations*, 4th ed., §10.1) for at most 16 steps from a fixed pseudo-random start
    /// vector (so the result is deterministic), on the block-sparse product. The value is
    /// the largest Ritz value plus its residual bound `β_m |s_m|`, an over-estimate of
    /// the top eigenvalue once the iteration has found it (16 steps: within 0.6 % above the
    /// dense eigenvalue on the SBL wall), capped by the bound `2 max λ_body` (scaled).
    pub fn max_eigenvalue(&self, bodies: &[Body]) -> f64 {
        const LANCZOS_STEPS: usize = 16;
        let free: Vec<usize> = (0..bodies.len()).filter(|&i| self.touched[i] && !bodies[i].fixed()).collect();
        if free.is_empty() {
            return 0.0;
        }
        let roots: Vec<Matrix6<f64>> = bodies.iter().map(|b| Self::mass_root(b, true)).collect();
        // Bound: each spring joins two bodies, so ω_max² ≤ 2 max_i λ_max(S_i K_ii S_i); for a
        // scalar-scaled body that is its true-mass eigenvalue over s.
        let bound = 2.0
            * free
                .iter()
                .map(|&i| match bodies[i].block_mass {
                    None => self.body_lambdas[i] * bodies[i].inertia_scale_inv,
                    Some(_) => self.block_eigenvalue(i, &roots[i]),
                })
                .fold(0.0, f64::max);
        let nb = bodies.len();
        let n = 6 * nb;
        let scale = |x: &[f64], y: &mut [f64]| {
            for i in 0..nb {
                let r = roots[i] * Vector6::from_column_slice(&x[6 * i..6 * i + 6]);
                y[6 * i..6 * i + 6].copy_from_slice(r.as_slice());
            }
        };
        let six = |x: &[f64], i: usize| Vector6::from_column_slice(&x[6 * i..6 * i + 6]);
        let mut u = vec![0.0; n];
        let mut v = vec![0.0; n];
        let mut apply = |x: &[f64], y: &mut [f64]| {
            scale(x, &mut u);
            v.iter_mut().for_each(|e| *e = 0.0);
            for &i in &free {
                let r = self.diag[i] * six(&u, i);
                v[6 * i..6 * i + 6].copy_from_slice(r.as_slice());
            }
            for (a, b, k) in &self.off {
                let ra = k * six(&u, *b);
                let rb = k.tr_mul(&six(&u, *a));
                for j in 0..6 {
                    v[6 * a + j] += ra[j];
                    v[6 * b + j] += rb[j];
                }
            }
            scale(&v, y);
        };
        // Fixed pseudo-random start on the free bodies' dofs (a 64-bit LCG with Knuth's
        // MMIX constants).
        let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut q = vec![0.0; n];
        for &i in &free {
            for j in 0..6 {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                q[6 * i + j] = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            }
        }
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let q0 = dot(&q, &q).sqrt();
        q.iter_mut().for_each(|e| *e /= q0);
        let steps = LANCZOS_STEPS.min(6 * free.len());
        let mut basis: Vec<Vec<f64>> = Vec::with_capacity(steps);
        let (mut alpha, mut beta) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
        let mut w = vec![0.0; n];
        for _ in 0..steps {
            apply(&q, &mut w);
            let a = dot(&w, &q);
            basis.push(std::mem::take(&mut q));
            // Full re-orthogonalization against the basis, twice ("twice is enough").
            for _ in 0..2 {
                for b in &basis {
                    let c = dot(&w, b);
                    w.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
                }
            }
            alpha.push(a);
            let b = dot(&w, &w).sqrt();
            beta.push(b);
            if b <= 1e-12 * a.abs() {
                break; // an invariant subspace: the Ritz values are exact
            }
            q = w.iter().map(|x| x / b).collect();
        }
        let m = alpha.len();
        let t = DMatrix::from_fn(m, m, |i, j| {
            if i == j {
                alpha[i]
            } else if i.abs_diff(j) == 1 {
                beta[i.min(j)]
            } else {
                0.0
            }
        });
        let e = t.symmetric_eigen();
        let top = (0..m).fold(0, |k, i| if e.eigenvalues[i] > e.eigenvalues[k] { i } else { k });
        let estimate = e.eigenvalues[top] + beta[m - 1] * e.eigenvectors[(m - 1, top)].abs();
        estimate.min(bound)
    }
}

/// Block-Jacobi density scaling (the block form of [`density_scaling`]; block-diagonal
/// preconditioning of dynamic relaxation): each free body with contacts gets the inertial
/// mass `M_i = K_ii / λ_target + ε s_i M_i⁰` (6 × 6, table frame), with `K_ii` its diagonal
/// stiffness block, `λ_target` the scalar target (the median body eigenvalue), `s_i` its
/// scalar factor (bodies' `inertia_scale_inv` must be set), `M_i⁰ = diag(m, m, m, R I Rᵀ)`
/// its true mass and `ε = floor` (`DensityScaling::Block::mass_floor`). As `ε` → 0 every
/// direction of every body has the frequency `√λ_target` against its held neighbours (the
/// scalar scaling equalises only the stiffest direction): on the SBL wall the condition
/// number of the assembled system falls from about 2,700 to about 550 (eigenvalues floored
/// at 1e-3 of each block's largest). The `ε s M⁰` term keeps the mass positive definite in
/// directions no contact stiffens (a block on an edge) and, at `ε = 1`, never lighter than
/// under scalar scaling. A body with its y translation `held`
/// (rigid end restraint) has that direction decoupled from the others. `None` for fixed
/// bodies and bodies without contacts (they keep their scalar scaling). One per body.
pub fn block_masses(
    stiffness: &Stiffness,
    bodies: &[Body],
    target: f64,
    floor: f64,
    held: &[bool],
) -> Vec<Option<super::state::BlockMass>> {
    bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            if b.fixed() || !stiffness.touched[i] || target <= 0.0 {
                return None;
            }
            let s = 1.0 / b.inertia_scale_inv;
            let mut m = stiffness.diag[i] / target;
            for k in 0..3 {
                m[(k, k)] += floor * s * b.mass;
            }
            let iw = b.rot_mat * b.inertia * b.rot_mat.transpose() * (floor * s);
            let mut rr = m.fixed_view_mut::<3, 3>(3, 3);
            rr += iw;
            if held[i] {
                for k in 0..6 {
                    if k != 1 {
                        m[(1, k)] = 0.0;
                        m[(k, 1)] = 0.0;
                    }
                }
            }
            let m = (m + m.transpose()) * 0.5;
            let e = m.symmetric_eigen();
            if e.eigenvalues.iter().any(|&l| l.is_nan() || l <= 0.0 || !l.is_finite()) {
                return None;
            }
            Some(super::state::BlockMass { q: e.eigenvectors, inv_lambda: e.eigenvalues.map(|l| 1.0 / l) })
        })
        .collect()
}

/// The time step, s, for the largest eigenvalue `λ` (rad²/s²) of the assembly under local
/// damping `alpha`: `safety × 2 / (√λ √(1 + α))`; `None` if `λ` is 0.
///
/// Local damping scales a component's force by `1 + α` while the force opposes the
/// velocity, so the undamped limit `ω Δt < 2` becomes `ω √(1 + α) Δt < 2` (a single
/// oscillator with α = 0.8 diverges from `ω Δt ≈ 1.49`; `tests/suite/timestep.rs`).
pub fn step_for(lambda: f64, safety: f64, alpha: f64) -> Option<f64> {
    (lambda > 0.0).then(|| safety * 2.0 / (lambda.sqrt() * (1.0 + alpha).sqrt()))
}

/// Density scaling for static solutions (3DEC's density scaling; Itasca 3DEC manual,
/// "static analysis"; Underwood's dynamic relaxation): every body in contact gets its
/// inertial mass and inertia multiplied by `s = λ/λ_target` so that all of them have the same
/// critical step, the one of the target `λ_target` = the median of the bodies' eigenvalues.
/// Stiff bodies (small wedges, slivers) get `s > 1` and no longer limit the step; soft ones
/// (large stones on few contacts) get `s < 1` and no longer lag behind: the scaled system is
/// the Jacobi-preconditioned one, whose slowest mode converges in the fewest steps. Bodies
/// without contacts keep `s = 1`. Returns the target and the factors. Equilibrium states do
/// not depend on inertia; only the path to them does.
pub fn density_scaling(lambdas: &[f64]) -> (f64, Vec<f64>) {
    let mut v: Vec<f64> = lambdas.iter().copied().filter(|l| *l > 0.0).collect();
    if v.is_empty() {
        return (0.0, vec![1.0; lambdas.len()]);
    }
    v.sort_by(f64::total_cmp);
    let target = v[(v.len() - 1) / 2];
    (target, lambdas.iter().map(|&l| if l > 0.0 { l / target } else { 1.0 }).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `k g_p g_qᵀ` summed over the three springs (normal, two shear) of every node: the
    /// reference the moment form of [`block`] must reproduce.
    fn explicit(n: &Vec3, kn: f64, ks: f64, nodes: &[(f64, Vec3, Vec3)]) -> Matrix6<f64> {
        let (t1, t2) = crate::geometry::polygon::plane_basis(n);
        let mut k6 = Matrix6::zeros();
        for (w, rp, rq) in nodes {
            for (k, d) in [(kn * w, *n), (ks * w, t1), (ks * w, t2)] {
                let (mp, mq) = (rp.cross(&d), rq.cross(&d));
                let gp = Vector6::new(d.x, d.y, d.z, mp.x, mp.y, mp.z);
                let gq = Vector6::new(d.x, d.y, d.z, mq.x, mq.y, mq.z);
                k6 += gp * gq.transpose() * k;
            }
        }
        k6
    }

    #[test]
    fn the_moment_form_of_a_contact_block_is_the_sum_of_its_springs() {
        let n = Vec3::new(0.2, -0.3, 0.9).normalize();
        let (kn, ks) = (3.0e9, 1.1e9);
        let nodes: Vec<(f64, Vec3, Vec3)> = (0..5)
            .map(|i| {
                let f = i as f64;
                (
                    0.01 + 0.003 * f,
                    Vec3::new(0.1 * f, -0.05, 0.2 - 0.03 * f),
                    Vec3::new(-0.07, 0.04 * f, -0.1 + 0.01 * f),
                )
            })
            .collect();
        let c0 = Mat3::identity() * ks + n * n.transpose() * (kn - ks);
        let w: f64 = nodes.iter().map(|x| x.0).sum();
        let sp = nodes.iter().fold(Vec3::zeros(), |a, x| a + x.1 * x.0);
        let sq = nodes.iter().fold(Vec3::zeros(), |a, x| a + x.2 * x.0);
        let rpq = nodes.iter().fold(Mat3::zeros(), |a, x| a + x.1 * x.2.transpose() * x.0);
        let got = block(&c0, &n, ks, kn - ks, w, &sp, &sq, &rpq);
        let want = explicit(&n, kn, ks, &nodes);
        let err = (got - want).abs().max();
        assert!(err <= 1e-12 * want.abs().max(), "{err:e} of {:e}", want.abs().max());
    }

    #[test]
    fn single_spring_frequency_is_recovered() {
        // A mass on one normal spring through its centroid: λ = k/m exactly.
        let k6 = explicit(&Vec3::z(), 100.0, 0.0, &[(1.0, Vec3::zeros(), Vec3::zeros())]);
        let m: f64 = 4.0;
        let s = Matrix6::from_diagonal(&Vector6::new(1.0 / m.sqrt(), 1.0 / m.sqrt(), 1.0 / m.sqrt(), 1.0, 1.0, 1.0));
        let l = (s * k6 * s).symmetric_eigenvalues().iter().cloned().fold(0.0, f64::max);
        assert!((l - 25.0).abs() < 1e-12);
        let i = crate::math::Mat3::from_diagonal(&Vec3::new(4.0, 9.0, 16.0));
        let r = crate::math::inv_sqrt(&i);
        assert!((r[(1, 1)] - 1.0 / 3.0).abs() < 1e-14);
    }
}
