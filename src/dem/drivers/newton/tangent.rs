//! The consistent tangent of the contact forces of one state (its sparse LU solve in
//! `lu.rs`; see the parent module).

use crate::dem::contact::law::{normal, JointParams, Quadrature, SubContactState, TensionCutoff};
use crate::dem::drivers::implicit::PoseIncrement;
use crate::dem::engine::Simulation;
use crate::layout::EndRestraint;
use crate::math::{Mat3, Vec3};
use nalgebra::{Matrix6, Vector6};
use std::collections::BTreeMap;

/// Relative size of the diagonal floor: every diagonal entry of the tangent gets this
/// fraction of the largest translational (rotational) diagonal entry added. Where the
/// tangent is regular this changes the Newton step by about this fraction; where it is
/// singular (a body without a closed contact, a sliding or rocking mechanism) it bounds the
/// step, which the line search then cuts to what reduces the out-of-balance force.
pub const FLOOR: f64 = 1e-8;

/// `[a]×`, the cross-product matrix: `[a]× b = a × b`.
fn skew(a: &Vec3) -> Mat3 {
    Mat3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// `J(r)ᵀ v = [v; r × v]`: the generalized force (N, N·m) of the force `v` at the arm `r`.
fn jt(r: &Vec3, v: &Vec3) -> Vector6<f64> {
    let m = r.cross(v);
    Vector6::new(v.x, v.y, v.z, m.x, m.y, m.z)
}

/// `J(r)ᵀ = [I; [r]×]` (6 × 3): the generalized force (N, N·m) of a force at the arm `r`.
fn jt_mat(r: &Vec3) -> nalgebra::Matrix6x3<f64> {
    let mut m = nalgebra::Matrix6x3::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&Mat3::identity());
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&skew(r));
    m
}

/// The blocks of the tangent: per body its diagonal block and per ordered pair of free
/// bodies `(a, b)` the block of `a`'s rows and `b`'s columns (N/m, N, N·m; table frame;
/// dofs: centroid translation in m, rotation vector in rad).
pub(super) struct Blocks {
    pub(super) diag: Vec<Matrix6<f64>>,
    off: BTreeMap<(usize, usize), Matrix6<f64>>,
    free: Vec<bool>,
}

impl Blocks {
    /// Adds the stiffness of a force on B (`−C δ`-like, given as the four products) to
    /// the blocks: `kbb` to B's diagonal, `kaa` to A's, `kab` (A's rows, B's columns) and
    /// `kba` to the couplings, each only where its bodies are free.
    fn add(
        &mut self,
        a: Option<usize>,
        b: usize,
        kbb: Matrix6<f64>,
        kba: Matrix6<f64>,
        kab: Matrix6<f64>,
        kaa: Matrix6<f64>,
    ) {
        let a = a.filter(|&i| self.free[i]);
        if self.free[b] {
            self.diag[b] += kbb;
        }
        if let Some(a) = a {
            self.diag[a] += kaa;
            if self.free[b] {
                *self.off.entry((b, a)).or_insert_with(Matrix6::zeros) += kba;
                *self.off.entry((a, b)).or_insert_with(Matrix6::zeros) += kab;
            }
        }
    }
}

/// The point of application of a sub-contact's shear force, barycentric, as the law puts
/// it (`contact::law::evaluate`): from the area centroid of the compressed part to the
/// pressure centroid, linearly in the mobilised fraction `|Fs| / (c A + Fn tan φ)` (1 at
/// slip, 0 for a joint held against slip), for the nodal closures `u` (m) and the shear
/// force's magnitude `fs` (N).
fn shear_point(
    j: &JointParams,
    quad: Quadrature,
    st: &SubContactState,
    tension: bool,
    u: [f64; 3],
    area: f64,
    fs: f64,
) -> [f64; 3] {
    let nr = normal::integrate(&j.normal(), quad, u, area, tension);
    let fnorm = nr.moments[0] + nr.moments[1] + nr.moments[2];
    let at = if fnorm.abs() > 0.0 { nr.moments.map(|m| m / fnorm) } else { [1.0 / 3.0; 3] };
    let w = if !j.can_slip {
        0.0
    } else if st.slipping {
        1.0
    } else {
        let limit = if st.bonded { j.cohesion * area } else { 0.0 } + fnorm.max(0.0) * j.tan_phi;
        if limit <= 0.0 {
            1.0
        } else {
            (fs / limit).min(1.0)
        }
    };
    let c = nr.area_centroid;
    [(1.0 - w) * c[0] + w * at[0], (1.0 - w) * c[1] + w * at[1], (1.0 - w) * c[2] + w * at[2]]
}

/// The derivatives of [`shear_point`] in closed form where the pressure is linear over the
/// whole triangle (the linear closure law with every node closed, or a joint carrying
/// tension): `(∂λ_i/∂u_j` as `[j][i]`, 1/m; `∂λ_i/∂fs`, 1/N`), the same arguments. With
/// `S = Σu` the normal force is `Kn A S / 3` and the pressure centroid `λ_i = (u_i + S) /
/// (4S)` under the exact rule (`u_i / S` under the vertex rule), the area centroid the
/// triangle's; the shear point moves between them with the mobilised fraction `w = fs /
/// (c A + Fn tan φ)` (`contact::law::evaluate`). `None` elsewhere (a triangle cut by the
/// zero-closure line, a nonlinear closure law), where the caller differentiates
/// numerically.
fn shear_point_jacobian(
    j: &JointParams,
    quad: Quadrature,
    st: &SubContactState,
    tension: bool,
    u: [f64; 3],
    area: f64,
    fs: f64,
) -> Option<([[f64; 3]; 3], [f64; 3])> {
    if j.closure != crate::closure::Closure::Linear || !(tension || u.iter().all(|&v| v > 0.0)) {
        return None;
    }
    let s = u[0] + u[1] + u[2];
    if s <= 0.0 {
        return None;
    }
    let exact = quad == Quadrature::Exact;
    let at: [f64; 3] = if exact { u.map(|v| (v + s) / (4.0 * s)) } else { u.map(|v| v / s) };
    // ∂at_i/∂u_k.
    let scale = if exact { 4.0 } else { 1.0 };
    let dat = |i: usize, k: usize| (if i == k { 1.0 } else { 0.0 }) / (scale * s) - u[i] / (scale * s * s);
    let fnorm = j.kn * area * s / 3.0;
    let (w, dw_du, dw_dfs) = if !j.can_slip {
        (0.0, 0.0, 0.0)
    } else if st.slipping {
        (1.0, 0.0, 0.0)
    } else {
        let limit = if st.bonded { j.cohesion * area } else { 0.0 } + fnorm * j.tan_phi;
        if limit <= 0.0 || fs >= limit {
            (1.0, 0.0, 0.0)
        } else {
            (fs / limit, -fs / (limit * limit) * j.tan_phi * j.kn * area / 3.0, 1.0 / limit)
        }
    };
    let mut du = [[0.0; 3]; 3];
    for (k, col) in du.iter_mut().enumerate() {
        for (i, v) in col.iter_mut().enumerate() {
            *v = dw_du * (at[i] - 1.0 / 3.0) + w * dat(i, k);
        }
    }
    Some((du, at.map(|a| dw_dfs * (a - 1.0 / 3.0))))
}

/// A node of a contact at the current poses: the arms of its material points from A's
/// centroid and from B's (m, table frame), its closure `u = (p_a − p_b)·n` (m) and the
/// offset `o = p_a − p_b` of its two points (m).
#[derive(Clone, Copy)]
struct Arm {
    ra: Vec3,
    rb: Vec3,
    u: f64,
    o: Vec3,
}

/// Adds the four blocks of a force on B (B's diagonal, B's rows and A's columns, A's rows
/// and B's columns, A's diagonal) to a contact's blocks.
fn add(local: &mut [Matrix6<f64>; 4], kbb: Matrix6<f64>, kba: Matrix6<f64>, kab: Matrix6<f64>, kaa: Matrix6<f64>) {
    local[0] += kbb;
    local[1] += kba;
    local[2] += kab;
    local[3] += kaa;
}

/// The compressed part of a sub-contact triangle with nodal closures `u` (m): its pieces,
/// each three barycentric points and the piece's area as a fraction of the triangle's. A
/// node at zero closure counts as closed (a block placed touching its neighbours, every
/// gap zero, gets the stiffness of the joints it is about to close rather than none).
fn compressed_pieces(u: [f64; 3]) -> Vec<([[f64; 3]; 3], f64)> {
    let pos = u.iter().filter(|&&v| v >= 0.0).count();
    let unit = |i: usize| {
        let mut b = [0.0; 3];
        b[i] = 1.0;
        b
    };
    match pos {
        0 => Vec::new(),
        3 => vec![([unit(0), unit(1), unit(2)], 1.0)],
        _ => {
            let mut poly: Vec<[f64; 3]> = Vec::with_capacity(4);
            for i in 0..3 {
                let j = (i + 1) % 3;
                if u[i] >= 0.0 {
                    poly.push(unit(i));
                }
                if (u[i] >= 0.0) != (u[j] >= 0.0) {
                    let t = u[i] / (u[i] - u[j]);
                    let mut b = [0.0; 3];
                    b[i] = 1.0 - t;
                    b[j] = t;
                    poly.push(b);
                }
            }
            // Area fraction of a barycentric triangle: |det| of two of its edge vectors in
            // the (λ₁, λ₂) plane.
            let det = |a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]| {
                ((b[1] - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (b[2] - a[2])).abs()
            };
            (1..poly.len() - 1)
                .map(|k| ([poly[0], poly[k], poly[k + 1]], det(&poly[0], &poly[k], &poly[k + 1])))
                .collect()
        }
    }
}

/// The left Jacobian of the rotation vector, `J(w) = Σ_k [w]×^k / (k+1)!` (–): a jump by
/// `exp(w + δw)` turns a body by `exp(J(w) δw) exp(w)` to first order (Chirikjian 2011,
/// *Stochastic Models, Information Theory, and Lie Groups* vol. 2, § 10.6).
fn left_jacobian(w: &Vec3) -> Mat3 {
    let t2 = w.norm_squared();
    let wx = skew(w);
    let (a, b) = if t2 < 1e-8 {
        (0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0)
    } else {
        let t = t2.sqrt();
        ((1.0 - t.cos()) / t2, (t - t.sin()) / (t2 * t))
    };
    Mat3::identity() + wx * a + wx * wx * b
}

/// The tangent blocks of the contact forces of `sim`'s state (its last assessment: the
/// closures at the current poses, each sub-contact's shear force, slip state and return
/// factor), the end-restraint springs and the rigs' moments, with respect to the jump `x`
/// of the Newton iteration (per body: translation, m, and rotation vector, rad, table
/// frame) that led from the increment's start to `sim`'s poses.
///
/// The derivative of the law as `contact::forces` and `contact::law` code it (3DEC's
/// contact update, Itasca, *3DEC Theory and Background*, "contact mechanics"; Cundall
/// 1988, *Int. J. Rock Mech. Min. Sci.* 25, 107), for a force `F` on B at the mid-point
/// `x_m = ½ (p_a + p_b)` of a node pair (moment `(x_m − x_b) × F` on B, the opposite about
/// `x_a` on A):
///
/// * the springs: the normal springs on `δu = n·(δp_a − δp_b)` at the material points and
///   the shear spring `Ks A` on the shear increment at the sub-contact's centroid, through
///   the radial return where it slips (Alart & Curnier 1991, *Comput. Methods Appl. Mech.
///   Eng.* 92, 353; Simo & Hughes 1998, ch. 3);
/// * the arms: `δ(x_m − x_b) = ½ (δx_a − δx_b) + ½ (δθ_a × r_a + δθ_b × r_b)`, so that a
///   rigid motion of the pair turns the moments with it;
/// * the normal `n = m/|m|`, `m = R_a n_a + R_b n_b`: `δn = N_a δθ_a + N_b δθ_b`,
///   `N = −(I − n nᵀ) [R n]× / |m|` (both bodies turn it: a rigid turn of the pair turns
///   it with them). With it turn the normal force (`Fn δn`), every closure (`u = (p_a −
///   p_b)·n` changes by `(p_a − p_b)·δn`, the offset of the node's two points along the
///   joint: zero on a rigid turn) and the trial shear force: the law projects the stored
///   force onto the current plane and adds `−Ks A (I − n nᵀ) r`, so `δT = −n (δn·T) +
///   Ks A (n·r) δn − Ks A (I − n nᵀ) δr`, and through the return `δFs = Ret δT` with
///   `Ret n = n limit/|T|`: `δFs ⊇ (−n Fsᵀ + Ks A (n·r) Ret) δn`. The stored force is not
///   turned about the normal (the law keeps its direction in the plane), and neither is it
///   here;
/// * the shear increment of the jump `r = Δx_b + w_b × (x_c − x_b) − Δx_a − w_a × (x_c −
///   x_a)` (the jump's translation and rotation vector as one step's velocities times the
///   step) depends on `w` directly and through the centroid's arms;
/// * the point of application of the shear force moves with the closures (including their
///   change as `n` turns) and with `|Fs|`;
/// * the rotation columns are with respect to the jump's rotation vector `w`, which turns a
///   body by `exp(w) R₀`: `δθ = J(w) δw` ([`left_jacobian`]).
///
/// What the tangent holds fixed for the step: each sub-contact's stick/slip state and its
/// open or closed nodes (the semi-smooth part), and the magnitude-preserving rescaling of
/// the stored force (second order in the tilt of the plane since the increment's start).
pub(super) fn tangent_blocks(sim: &Simulation, x: &PoseIncrement) -> Blocks {
    let nb = sim.state.bodies.len();
    let free: Vec<bool> = sim.state.bodies.iter().map(|b| !b.fixed()).collect();
    let mut blocks = Blocks { diag: vec![Matrix6::zeros(); nb], off: BTreeMap::new(), free };
    let quad = sim.params().quadrature;
    let mut arms: Vec<Arm> = Vec::new();
    for c in &sim.state.contacts {
        // This contact's blocks: B's, (B, A), (A, B), A's.
        let mut local = [Matrix6::zeros(); 4];
        let n = sim.state.contact_normal(c);
        let nn = n * n.transpose();
        let pt = Mat3::identity() - nn;
        let np = c.joint.normal();
        let rb_mat = &sim.state.bodies[c.b].rot_mat;
        let ra_mat = c.a.map(|i| sim.state.bodies[i].rot_mat);
        // The normal n = m/|m|, m = R_a n_a + R_b n_b (`contact_normal`), turns with either
        // body: δn = N_a δθ_a + N_b δθ_b, N = −(I − n nᵀ) [R n]× / |m|.
        let (na_w, nb_w) = (ra_mat.map_or(c.normal_a, |m| m * c.normal_a), rb_mat * c.normal_b);
        let inv_m = 1.0 / (na_w + nb_w).norm();
        let (dn_a, dn_b) = (-(pt * skew(&na_w)) * inv_m, -(pt * skew(&nb_w)) * inv_m);
        // The columns of a force's change `G δn` on B's rotation and on A's.
        let turn_cols = |g: Mat3, arm: &Vec3| {
            let (mut kb, mut ka) = (Matrix6::zeros(), Matrix6::zeros());
            kb.fixed_view_mut::<6, 3>(0, 3).copy_from(&(jt_mat(arm) * g * dn_b));
            ka.fixed_view_mut::<6, 3>(0, 3).copy_from(&(jt_mat(arm) * g * dn_a));
            (kb, ka)
        };
        // The jump of each body from the increment's start (translation, rotation vector).
        let (xb_pos, (db, wb)) = (sim.state.bodies[c.b].pos, (x.0[c.b], x.1[c.b]));
        let (xa_pos, (da, wa)) = match c.a {
            Some(i) => (sim.state.bodies[i].pos, (x.0[i], x.1[i])),
            None => (Vec3::zeros(), (Vec3::zeros(), Vec3::zeros())),
        };
        arms.clear();
        for nd in &c.nodes {
            let (pa, pb) = sim.state.node_points(c, nd);
            let rb = rb_mat * nd.on_b;
            let ra = ra_mat.map_or(Vec3::zeros(), |m| m * nd.on_a);
            arms.push(Arm { ra, rb, u: (pa - pb).dot(&n), o: pa - pb });
        }
        // Moments of the normal springs over the contact (as `timestep::block` takes them):
        // rows at the mid-points (`_m`), columns at the material points.
        let (mut w, mut sa_m, mut sb_m, mut sa, mut sb) =
            (0.0, Vec3::zeros(), Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
        let (mut raa, mut rab, mut rba, mut rbb) = (Mat3::zeros(), Mat3::zeros(), Mat3::zeros(), Mat3::zeros());
        for s in &c.subs {
            let node = s.nodes.map(|k| arms[k as usize]);
            let u = node.map(|v| v.u);
            let tension = c.joint.tension != TensionCutoff::NoTension && s.state.bonded;
            // Normal springs: the quadrature points of the compressed part, weight × tangent.
            let mut points: Vec<([f64; 3], f64)> = Vec::with_capacity(8);
            match quad {
                Quadrature::Vertex => {
                    for i in 0..3 {
                        if tension || u[i] > 0.0 {
                            let mut l = [0.0; 3];
                            l[i] = 1.0;
                            points.push((l, s.area / 3.0));
                        }
                    }
                }
                Quadrature::Exact => {
                    let pieces = if tension { compressed_pieces([1.0; 3]) } else { compressed_pieces(u) };
                    for (p, frac) in pieces {
                        let a = s.area * frac;
                        let mut cen = [0.0; 3];
                        for v in &p {
                            for i in 0..3 {
                                cen[i] += v[i] / 3.0;
                            }
                            points.push((*v, a / 12.0));
                        }
                        points.push((cen, 0.75 * a));
                    }
                }
            }
            // The arms at barycentric `l`: A's and B's material points, and the mid-point's
            // arm from A's centroid and from B's (where the law applies the forces).
            let at_l = |l: &[f64; 3]| {
                let mix = |f: &dyn Fn(&Arm) -> Vec3| f(&node[0]) * l[0] + f(&node[1]) * l[1] + f(&node[2]) * l[2];
                let (ra, rb, o) = (mix(&|a| a.ra), mix(&|a| a.rb), mix(&|a| a.o));
                (ra, rb, ra - o * 0.5, rb + o * 0.5, o)
            };
            // Σ c_p [n; r_p × n] on each side: the normal force's gradient (for the slip
            // coupling); the closure u = (p_a − p_b)·n also changes as n turns, by
            // (p_a − p_b)·δn (the offset of the two material points along the joint): its
            // Σ c_p (p_a − p_b) and the moments on each side.
            let (mut ga, mut gb) = (Vector6::zeros(), Vector6::zeros());
            let (mut so, mut moa, mut mob) =
                (Vec3::zeros(), nalgebra::Matrix6x3::zeros(), nalgebra::Matrix6x3::zeros());
            for (l, wt) in &points {
                let (ra, rb, ram, rbm, o) = at_l(l);
                let uu = u[0] * l[0] + u[1] * l[1] + u[2] * l[2];
                let k = wt * np.tangent(uu);
                if k == 0.0 {
                    continue;
                }
                so += o * k;
                moa += jt(&ram, &n) * o.transpose() * k;
                mob += jt(&rbm, &n) * o.transpose() * k;
                w += k;
                sa_m += ram * k;
                sb_m += rbm * k;
                sa += ra * k;
                sb += rb * k;
                raa += ram * ra.transpose() * k;
                rab += ram * rb.transpose() * k;
                rba += rbm * ra.transpose() * k;
                rbb += rbm * rb.transpose() * k;
                ga += jt(&ra, &n) * k;
                gb += jt(&rb, &n) * k;
            }
            // δFn on B along n = Σ c_p o_pᵀ δn: B's rows −, A's rows +.
            {
                let cols = |m: &nalgebra::Matrix6x3<f64>, dn: &Mat3| {
                    let mut k = Matrix6::zeros();
                    k.fixed_view_mut::<6, 3>(0, 3).copy_from(&(m * dn));
                    k
                };
                add(&mut local, -cols(&mob, &dn_b), -cols(&mob, &dn_a), cols(&moa, &dn_b), cols(&moa, &dn_a));
            }
            // The normal force's gradient on each side's dofs: δFn = dfa·q_a + dfb·q_b.
            let (mut dfa, mut dfb) = (ga, -gb);
            {
                let (ta, tb) = (dn_a.transpose() * so, dn_b.transpose() * so);
                for i in 0..3 {
                    dfa[3 + i] += ta[i];
                    dfb[3 + i] += tb[i];
                }
            }
            // The shear spring at the sub-contact's centroid, where the law takes the shear
            // increment; nothing where the law gives the sub-contact no force (no compression
            // and no tension carried: `contact::law::evaluate`), whatever shear it stores (a
            // sub-contact wholly open keeps the history it had when it opened).
            let st = &s.state;
            if st.normal <= 0.0 && !tension {
                continue;
            }
            let third = [1.0 / 3.0; 3];
            let (rac, rbc, rac_m, rbc_m, _) = at_l(&third);
            let ksa = c.joint.ks * s.area;
            let mag = st.shear.norm();
            let e = if mag > 0.0 { st.shear / mag } else { Vec3::zeros() };
            // Where the shear force acts, and how that point moves with the closures and
            // the shear force's magnitude (central differences of the law's rule).
            let point = |u: [f64; 3], fs: f64| shear_point(&c.joint, quad, st, tension, u, s.area, fs);
            let lam = point(u, mag);
            let (ras, rbs, ras_m, rbs_m, _) = at_l(&lam);
            // Geometric stiffness of a force F on B at a mid-point x_m (node arms r_a, r_b):
            // the arms move with the mid-point, δ(x_m − x_b) = ½ (δx_a − δx_b) + ½ (δθ_a ×
            // r_a + δθ_b × r_b) and δ(x_m − x_a) = ½ (δx_b − δx_a) + the same turn, so the
            // moment (x_m − x_b) × F on B changes by −[F]× of that, and A's by its opposite.
            let arm_turn = |f: &Vec3, ra: &Vec3, rb: &Vec3| {
                let fx = skew(f);
                let half = Mat3::identity() * 0.5;
                let mut h = [Matrix6::zeros(); 4];
                // B's rows: B's columns, A's columns; A's rows: B's columns, A's columns.
                let blocks3 = [(-half, -skew(rb) * 0.5), (half, -skew(ra) * 0.5)];
                for (k, (t, r)) in blocks3.iter().enumerate() {
                    // k = 0: B's columns, 1: A's columns (for B's rows: δ(x_m − x_b)).
                    h[k].fixed_view_mut::<3, 3>(3, 0).copy_from(&(fx * t));
                    h[k].fixed_view_mut::<3, 3>(3, 3).copy_from(&(fx * r));
                    // A's rows: δ(x_m − x_a) has the opposite translation parts, −[F]× × −1.
                    h[2 + k].fixed_view_mut::<3, 3>(3, 0).copy_from(&(fx * t));
                    h[2 + k].fixed_view_mut::<3, 3>(3, 3).copy_from(&(-(fx * r)));
                }
                h
            };
            let nr = normal::integrate(&np, quad, u, s.area, tension);
            let fnorm = nr.moments[0] + nr.moments[1] + nr.moments[2];
            if fnorm != 0.0 || mag > 0.0 {
                let at = if fnorm.abs() > 0.0 { nr.moments.map(|m| m / fnorm) } else { [1.0 / 3.0; 3] };
                let (raa_t, rba_t, raa_m, rba_m, _) = at_l(&at);
                let fnv = n * fnorm;
                for (f, ra, rb) in [(fnv, raa_t, rba_t), (st.shear, ras, rbs)] {
                    let [bb, ba, ab, aa] = arm_turn(&f, &ra, &rb);
                    add(&mut local, bb, ba, ab, aa);
                }
                // The normal force turns with n: δ(Fn n) = Fn δn on B.
                let g = Mat3::identity() * fnorm;
                let ((bb, ba), (ab, aa)) = (turn_cols(g, &rba_m), turn_cols(g, &raa_m));
                add(&mut local, -bb, -ba, ab, aa);
            }
            let ret = if st.slipping {
                // Radial return: d Fs = (limit/|T|) (I − e eᵀ) dT + tan φ e dFn.
                let coupling = c.joint.tan_phi;
                if mag > 0.0 && coupling > 0.0 {
                    let (eb, ea) = (jt(&rbs_m, &e) * coupling, jt(&ras_m, &e) * coupling);
                    add(
                        &mut local,
                        -(eb * dfb.transpose()),
                        -(eb * dfa.transpose()),
                        ea * dfb.transpose(),
                        ea * dfa.transpose(),
                    );
                }
                (Mat3::identity() - e * e.transpose()) * st.return_scale
            } else {
                Mat3::identity()
            };
            let cs = ret * pt * ksa;
            // The shear increment of the jump, r = Δx_b + w_b × (x_c − x_b) − Δx_a − w_a ×
            // (x_c − x_a) at the mid-plane centroid x_c (`contact::forces`), changes with the
            // arms as well as with the motion (x_c moves as x_m above), so
            // δr = J_b q_b − J_a q_a with J_b = [I − ½ [w_a + w_b]× | −[x_c − x_b]× −
            // ½ [w_b − w_a]× [r_b]×] and J_a = [I − ½ [w_a + w_b]× | −[x_c − x_a]× +
            // ½ [w_b − w_a]× [r_a]×].
            let xc = xb_pos + rbc_m;
            let r_jump = db + wb.cross(&(xc - xb_pos)) - da - wa.cross(&(xc - xa_pos));
            let (wsum, wdiff) = (skew(&(wa + wb)) * 0.5, skew(&(wb - wa)) * 0.5);
            // The jump's own rotation vector w enters r directly (not through the body's
            // turn δθ = J(w) δw the columns are mapped by below): that column is
            // −[x_c − x]× J(w)⁻¹ before the mapping.
            let jmat = |r_m: &Vec3, r: &Vec3, w: &Vec3, sgn: f64| {
                let mut j = nalgebra::Matrix3x6::<f64>::zeros();
                let direct = left_jacobian(w).try_inverse().unwrap_or_else(Mat3::identity);
                j.fixed_view_mut::<3, 3>(0, 0).copy_from(&(Mat3::identity() - wsum));
                j.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-skew(r_m) * direct - wdiff * skew(r) * sgn));
                j
            };
            let (jb, ja) = (jmat(&rbc_m, &rbc, &wb, 1.0), jmat(&rac_m, &rac, &wa, -1.0));
            let spring = |rf: &Vec3, jd: &nalgebra::Matrix3x6<f64>| jt_mat(rf) * cs * jd;
            add(&mut local, spring(&rbs_m, &jb), -spring(&rbs_m, &ja), -spring(&ras_m, &jb), spring(&ras_m, &ja));
            // The trial force turns with n (`slip::shear`: the stored force projected onto
            // the current plane, the increment −Ks A (I − n nᵀ) r): δT ⊇ −n (δn·T) +
            // Ks A (n·r) δn, through the return: δFs ⊇ (−n Fsᵀ + Ks A (n·r) Ret) δn.
            let g = -(n * st.shear.transpose()) + ret * (ksa * n.dot(&r_jump));
            let ((bb, ba), (ab, aa)) = (turn_cols(g, &rbs_m), turn_cols(g, &ras_m));
            add(&mut local, -bb, -ba, ab, aa);
            if mag > 0.0 {
                // The moment of the shear force as its point moves by v = V_b q_b − V_a q_a
                // (the arm's change, the same from either centroid): v × Fs on B.
                let scale = u.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
                let (mut vb, mut va) = (nalgebra::Matrix3x6::<f64>::zeros(), nalgebra::Matrix3x6::<f64>::zeros());
                let closed = shear_point_jacobian(&c.joint, quad, st, tension, u, s.area, mag);
                let lever_of = |dl: [f64; 3]| at_l(&dl).3;
                for i in 0..3 {
                    let dl: [f64; 3] = match &closed {
                        Some((du, _)) => du[i],
                        None => {
                            let h = 1e-6 * scale;
                            let (mut up, mut um) = (u, u);
                            up[i] += h;
                            um[i] -= h;
                            let (lp, lm) = (point(up, mag), point(um, mag));
                            [0, 1, 2].map(|j| (lp[j] - lm[j]) / (2.0 * h))
                        }
                    };
                    let lever = lever_of(dl);
                    // du_i = −g_bᵢᵀ q_b + g_aᵢᵀ q_a + o_iᵀ (N_a δθ_a + N_b δθ_b).
                    vb -= lever * jt(&node[i].rb, &n).transpose();
                    va -= lever * jt(&node[i].ra, &n).transpose();
                    let (ob, oa) = (node[i].o.transpose() * dn_b, node[i].o.transpose() * dn_a);
                    let mut rot_b = vb.fixed_view_mut::<3, 3>(0, 3);
                    rot_b += lever * ob;
                    let mut rot_a = va.fixed_view_mut::<3, 3>(0, 3);
                    rot_a -= lever * oa;
                }
                if !st.slipping && c.joint.can_slip {
                    let dl: [f64; 3] = match &closed {
                        Some((_, dfs)) => *dfs,
                        None => {
                            let h = 1e-6 * mag;
                            let (lp, lm) = (point(u, mag + h), point(u, mag - h));
                            [0, 1, 2].map(|j| (lp[j] - lm[j]) / (2.0 * h))
                        }
                    };
                    let lever = lever_of(dl);
                    // d|Fs| = eᵀ dFs = −Ks A eᵀ (J_b q_b − J_a q_a) + Ks A (n·r) eᵀ δn while
                    // sticking.
                    vb -= lever * (e.transpose() * jb) * ksa;
                    va -= lever * (e.transpose() * ja) * ksa;
                    let tilt = ksa * n.dot(&r_jump);
                    let mut rot_b = vb.fixed_view_mut::<3, 3>(0, 3);
                    rot_b += lever * (e.transpose() * dn_b) * tilt;
                    let mut rot_a = va.fixed_view_mut::<3, 3>(0, 3);
                    rot_a -= lever * (e.transpose() * dn_a) * tilt;
                }
                let fx = skew(&st.shear);
                let lift = |m: nalgebra::Matrix3x6<f64>| {
                    let mut k = Matrix6::zeros();
                    k.fixed_view_mut::<3, 6>(3, 0).copy_from(&(fx * m));
                    k
                };
                add(&mut local, lift(vb), -lift(va), -lift(vb), lift(va));
            }
        }
        if w != 0.0 {
            let normal =
                |sp: &Vec3, sq: &Vec3, rpq: &Mat3| crate::dem::timestep::block(&nn, &n, 0.0, 1.0, w, sp, sq, rpq);
            add(
                &mut local,
                normal(&sb_m, &sb, &rbb),
                -normal(&sb_m, &sa, &rba),
                -normal(&sa_m, &sb, &rab),
                normal(&sa_m, &sa, &raa),
            );
        }
        // Every contact between free bodies has its coupling blocks, zero or not, so that
        // the pattern changes only with the contacts.
        let [kbb, kba, kab, kaa] = local;
        blocks.add(c.a, c.b, kbb, kba, kab, kaa);
    }
    // The rotation columns with respect to the jump's rotation vector: δθ = J(w) δw.
    let jl: Vec<Mat3> = x.1.iter().map(left_jacobian).collect();
    let right = |m: &mut Matrix6<f64>, j: &Mat3| {
        let cols = m.fixed_view::<6, 3>(0, 3) * j;
        m.fixed_view_mut::<6, 3>(0, 3).copy_from(&cols);
    };
    for (k, d) in blocks.diag.iter_mut().enumerate() {
        right(d, &jl[k]);
    }
    for ((_, b), m) in blocks.off.iter_mut() {
        right(m, &jl[*b]);
    }
    for (k, b) in sim.state.bodies.iter().enumerate() {
        if b.fixed() {
            continue;
        }
        if let Some(EndRestraint::Spring(ky)) = sim.state.restraint[k] {
            blocks.diag[k][(1, 1)] += ky;
        }
        if let Some(m) = b.hold.dof().and_then(|c| c.moment.as_ref()) {
            // M = m0 + k_u x_along + k_θ θ_axis acts on the body: its stiffness is −dM.
            blocks.diag[k][(3 + m.axis, m.along)] -= m.per_displacement_n;
            blocks.diag[k][(3 + m.axis, 3 + m.axis)] -= m.per_rotation_nm;
        }
    }
    blocks
}

mod lu;

pub(super) use lu::newton_step;

#[cfg(test)]
mod tests;
