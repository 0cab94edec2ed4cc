//! The consistent tangent of the contact forces of one state and its sparse LU
//! factorization (see the parent module).

use crate::dem::contact::law::{normal, JointParams, Quadrature, SubContactState, TensionCutoff};
use crate::dem::drivers::implicit::stiffness::Dofs;
use crate::dem::drivers::implicit::PoseIncrement;
use crate::dem::engine::Simulation;
use crate::layout::EndRestraint;
use crate::math::{Mat3, Vec3};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams, NumericLu, SymbolicLu};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Conj, Par};
use nalgebra::{Matrix6, Vector6};
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;

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

/// `J(rf)ᵀ C J(rd)` with `J(r) = [I | −[r]×]` (3 × 6): the 6 × 6 stiffness between a force
/// `−C δ` acting at the arm `rf` and the relative displacement `δ` at the arm `rd` (m).
fn jtcj(rf: &Vec3, c: &Mat3, rd: &Vec3) -> Matrix6<f64> {
    let (sf, sd) = (skew(rf), skew(rd));
    let mut k = Matrix6::zeros();
    k.fixed_view_mut::<3, 3>(0, 0).copy_from(c);
    k.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-(c * sd)));
    k.fixed_view_mut::<3, 3>(3, 0).copy_from(&(sf * c));
    k.fixed_view_mut::<3, 3>(3, 3).copy_from(&(-(sf * c * sd)));
    k
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

/// The tangent blocks of the contact forces of `sim`'s state (its last assessment: the
/// closures at the current poses, each sub-contact's shear force, slip state and return
/// factor), the end-restraint springs and the rigs' moments.
pub(super) fn tangent_blocks(sim: &Simulation) -> Blocks {
    let nb = sim.state.bodies.len();
    let free: Vec<bool> = sim.state.bodies.iter().map(|b| !b.fixed()).collect();
    let mut blocks = Blocks { diag: vec![Matrix6::zeros(); nb], off: BTreeMap::new(), free };
    let quad = sim.params().quadrature;
    let mut arms: Vec<(Vec3, Vec3, f64)> = Vec::new();
    for c in &sim.state.contacts {
        // This contact's blocks: B's, (B, A), (A, B), A's.
        let mut local = [Matrix6::zeros(); 4];
        let n = sim.state.contact_normal(c);
        let nn = n * n.transpose();
        let pt = Mat3::identity() - nn;
        let np = c.joint.normal();
        let rb_mat = &sim.state.bodies[c.b].rot_mat;
        let ra_mat = c.a.map(|i| sim.state.bodies[i].rot_mat);
        arms.clear();
        for nd in &c.nodes {
            let (pa, pb) = sim.state.node_points(c, nd);
            let rb = rb_mat * nd.on_b;
            let ra = ra_mat.map_or(Vec3::zeros(), |m| m * nd.on_a);
            arms.push((ra, rb, (pa - pb).dot(&n)));
        }
        // Moments of the normal springs over the contact (as `timestep::block` takes them).
        let (mut w, mut sa, mut sb) = (0.0, Vec3::zeros(), Vec3::zeros());
        let (mut raa, mut rab, mut rba, mut rbb) = (Mat3::zeros(), Mat3::zeros(), Mat3::zeros(), Mat3::zeros());
        for s in &c.subs {
            let node = s.nodes.map(|k| arms[k as usize]);
            let u = node.map(|v| v.2);
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
            // Σ c_p [n; r_p × n] on each side: the normal force's gradient (for the slip
            // coupling).
            let (mut ga, mut gb) = (Vector6::zeros(), Vector6::zeros());
            for (l, wt) in &points {
                let ra = node[0].0 * l[0] + node[1].0 * l[1] + node[2].0 * l[2];
                let rb = node[0].1 * l[0] + node[1].1 * l[1] + node[2].1 * l[2];
                let uu = u[0] * l[0] + u[1] * l[1] + u[2] * l[2];
                let k = wt * np.tangent(uu);
                if k == 0.0 {
                    continue;
                }
                w += k;
                sa += ra * k;
                sb += rb * k;
                raa += ra * ra.transpose() * k;
                rab += ra * rb.transpose() * k;
                rba += rb * ra.transpose() * k;
                rbb += rb * rb.transpose() * k;
                ga += jt(&ra, &n) * k;
                gb += jt(&rb, &n) * k;
            }
            // The shear spring at the sub-contact's centroid, where the law takes the shear
            // increment; nothing where the sub-contact carries no force.
            let st = &s.state;
            if st.normal == 0.0 && st.shear == Vec3::zeros() {
                continue;
            }
            let rac = (node[0].0 + node[1].0 + node[2].0) / 3.0;
            let rbc = (node[0].1 + node[1].1 + node[2].1) / 3.0;
            let ksa = c.joint.ks * s.area;
            let mag = st.shear.norm();
            let e = if mag > 0.0 { st.shear / mag } else { Vec3::zeros() };
            // Where the shear force acts, and how that point moves with the closures and
            // the shear force's magnitude (central differences of the law's rule).
            let point = |u: [f64; 3], fs: f64| shear_point(&c.joint, quad, st, tension, u, s.area, fs);
            let lam = point(u, mag);
            let bary = |l: [f64; 3], side: usize| {
                let r = |i: usize| if side == 0 { node[i].0 } else { node[i].1 };
                r(0) * l[0] + r(1) * l[1] + r(2) * l[2]
            };
            let (ras, rbs) = (bary(lam, 0), bary(lam, 1));
            // Geometric stiffness: the arms turn with their bodies (a force f at the arm r
            // of B gives δ(r × f) = [f]× [r]× δθ_b), and the normal force turns with the
            // contact normal, half of the pair's relative rotation (δn = ½ (δθ_b − δθ_a) × n).
            let nr = normal::integrate(&np, quad, u, s.area, tension);
            let fnorm = nr.moments[0] + nr.moments[1] + nr.moments[2];
            if fnorm != 0.0 || mag > 0.0 {
                let at = if fnorm.abs() > 0.0 { nr.moments.map(|m| m / fnorm) } else { [1.0 / 3.0; 3] };
                let (raa_t, rba_t) = (bary(at, 0), bary(at, 1));
                let fnv = n * fnorm;
                let turn = |f: &Vec3, r: &Vec3| {
                    let mut k = Matrix6::zeros();
                    k.fixed_view_mut::<3, 3>(3, 3).copy_from(&(skew(f) * skew(r)));
                    k
                };
                let kbb = -(turn(&fnv, &rba_t) + turn(&st.shear, &rbs));
                let kaa = turn(&fnv, &raa_t) + turn(&st.shear, &ras);
                add(&mut local, kbb, Matrix6::zeros(), Matrix6::zeros(), kaa);
                let half = skew(&n) * (0.5 * fnorm);
                let rot_cols = |r: &Vec3| {
                    let mut k = Matrix6::zeros();
                    k.fixed_view_mut::<6, 3>(0, 3).copy_from(&(jt_mat(r) * half));
                    k
                };
                let (kb, ka) = (rot_cols(&rba_t), rot_cols(&raa_t));
                add(&mut local, kb, -kb, -ka, ka);
            }
            let cs = if st.slipping {
                // Radial return: d Fs = (limit/|T|) (I − e eᵀ) dT + tan φ e dFn.
                let coupling = c.joint.tan_phi;
                if mag > 0.0 && coupling > 0.0 {
                    let (eb, ea) = (jt(&rbs, &e) * coupling, jt(&ras, &e) * coupling);
                    add(
                        &mut local,
                        eb * gb.transpose(),
                        -(eb * ga.transpose()),
                        -(ea * gb.transpose()),
                        ea * ga.transpose(),
                    );
                }
                (pt - e * e.transpose()) * (ksa * st.return_scale)
            } else {
                pt * ksa
            };
            add(
                &mut local,
                jtcj(&rbs, &cs, &rbc),
                -jtcj(&rbs, &cs, &rac),
                -jtcj(&ras, &cs, &rbc),
                jtcj(&ras, &cs, &rac),
            );
            if mag > 0.0 {
                // The moment of the shear force as its point moves by v = V_b q_b − V_a q_a
                // (the arm's change, the same from either centroid): v × Fs on B.
                let scale = u.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
                let (mut vb, mut va) = (nalgebra::Matrix3x6::<f64>::zeros(), nalgebra::Matrix3x6::<f64>::zeros());
                let closed = shear_point_jacobian(&c.joint, quad, st, tension, u, s.area, mag);
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
                    let lever = bary(dl, 1);
                    // du_i = −g_bᵢᵀ q_b + g_aᵢᵀ q_a.
                    vb -= lever * jt(&node[i].1, &n).transpose();
                    va -= lever * jt(&node[i].0, &n).transpose();
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
                    let lever = bary(dl, 1);
                    // d|Fs| = eᵀ dFs = −Ks A (eᵀ J(r_b) q_b − eᵀ J(r_a) q_a) while sticking.
                    vb -= lever * jt(&rbc, &e).transpose() * ksa;
                    va -= lever * jt(&rac, &e).transpose() * ksa;
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
                normal(&sb, &sb, &rbb),
                -normal(&sb, &sa, &rba),
                -normal(&sa, &sb, &rab),
                normal(&sa, &sa, &raa),
            );
        }
        // Every contact between free bodies has its coupling blocks, zero or not, so that
        // the pattern changes only with the contacts.
        let [kbb, kba, kab, kaa] = local;
        blocks.add(c.a, c.b, kbb, kba, kab, kaa);
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
pub(super) fn newton_step(sim: &Simulation, dofs: &Dofs) -> Result<PoseIncrement, String> {
    {
        let blocks = tangent_blocks(sim);
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
