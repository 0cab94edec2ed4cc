//! Normal closure sub-models: the joint pressure as a function of the closure, and its
//! integral over a sub-contact triangle.
//!
//! A sub-contact is a triangle of area `A` (m²). The closure `u` (m, positive when the two
//! faces overlap, `u = −gap`) is known at its three nodes and varies linearly over it. A
//! closure law gives the normal pressure `q(u)` (Pa, compression positive) for `u > 0`; the
//! kernel returns the pressure moments `∫ q λᵢ dA` (N) for the barycentric coordinates
//! `λᵢ` of the nodes, whose sum is the normal force and whose ratios place it, and the area
//! centroid of the compressed part (where the elastic shear acts).
//!
//! The laws are [`crate::closure`]'s, one file each. The linear law (`q = Kn u`) is
//! integrated exactly: the triangle is clipped at `u = 0` and the linear pressure
//! integrated in closed form over the compressed part. A nonlinear law is integrated over
//! the compressed part along the closure gradient: the triangle is cut at its middle nodal
//! closure into two pieces on which the integral is one dimensional, evaluated with
//! 8-point Gauss–Legendre between the law's kinks (relative error below 1e-10 for the
//! hyperbolic law; exact for the quadratic seating law).
//!
//! A joint that carries tension (see [`super::tension`]) has `q = Kn u` (`Kni u`) for `u < 0`
//! with either law, over the whole triangle.

use crate::closure::Closure;

/// Parameters of the normal closure sub-model (plain data).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalParams {
    /// Normal stiffness Kn (linear) or initial normal stiffness Kni (hyperbolic), Pa/m.
    pub kn: f64,
    /// The closure law.
    pub closure: Closure,
}

impl NormalParams {
    /// Pressure at closure `u` (m), Pa; compression positive. Negative `u` gives the
    /// tensile branch `Kn u` (used only while a joint carries tension).
    #[inline(always)]
    pub fn pressure(&self, u: f64) -> f64 {
        self.closure.pressure(self.kn, u)
    }

    /// Largest tangent stiffness `dq/du` the law reaches, Pa/m (the stiffness the critical
    /// time step must be taken from): `Kn` (linear), `25 Kni` (hyperbolic, at its cap).
    pub fn stiffness_bound(&self) -> f64 {
        self.closure.stiffness_bound(self.kn)
    }

    /// Tangent stiffness `dq/du` at closure `u` (m), Pa/m: `Kn` in tension, the law's
    /// tangent in compression. The consistent tangent of the implicit increments
    /// ([`crate::dem::drivers::implicit`]).
    pub fn tangent(&self, u: f64) -> f64 {
        self.closure.tangent(self.kn, u)
    }

    /// Strain energy per unit area stored at closure `u`, J/m²: `∫₀ᵘ q ds`.
    pub fn energy_density(&self, u: f64) -> f64 {
        self.closure.energy_density(self.kn, u)
    }
}

/// How the pressure is integrated over a sub-contact triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quadrature {
    /// Integral over the compressed part of the triangle (exact for the linear law).
    #[default]
    Exact,
    /// One third of the area at each node (3DEC vertex sub-contacts).
    Vertex,
}

/// What the normal kernel returns for one sub-contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalResult {
    /// `∫ q λᵢ dA` per node, N; their sum is the normal force on B (compression positive).
    pub moments: [f64; 3],
    /// Area centroid of the compressed part, barycentric (the triangle's centroid when all
    /// or none of it is compressed).
    pub area_centroid: [f64; 3],
}

/// The normal kernel: pressure moments of one sub-contact triangle of area `area` (m²) with
/// nodal closures `u` (m). `tension`: the joint carries tension, so the whole triangle is
/// integrated with the tensile branch where `u < 0`.
#[inline(always)]
pub fn integrate(p: &NormalParams, quad: Quadrature, u: [f64; 3], area: f64, tension: bool) -> NormalResult {
    match p.closure {
        Closure::Linear => {
            let q = [p.kn * u[0], p.kn * u[1], p.kn * u[2]];
            linear_moments(q, area, quad, tension)
        }
        Closure::Seating(s) if quad == Quadrature::Exact => seating_moments(p.kn, s.max_gap_m, u, area, tension),
        _ => match quad {
            Quadrature::Exact => nonlinear_moments(p, u, area, tension),
            Quadrature::Vertex => linear_moments(u.map(|v| p.pressure(v)), area, Quadrature::Vertex, tension),
        },
    }
}

/// Moments of a pressure linear over the triangle with nodal values `q`.
#[inline(always)]
fn linear_moments(q: [f64; 3], area: f64, quad: Quadrature, tension: bool) -> NormalResult {
    let (moments, area_centroid) = match (quad, tension) {
        (Quadrature::Exact, true) => (moments_full(q, area), [1.0 / 3.0; 3]),
        (Quadrature::Exact, false) => compressed_moments_centroid(q, area),
        (Quadrature::Vertex, true) => (q.map(|v| v * area / 3.0), [1.0 / 3.0; 3]),
        (Quadrature::Vertex, false) => {
            let c = q.iter().filter(|&&v| v > 0.0).count().max(1) as f64;
            (q.map(|v| v.max(0.0) * area / 3.0), q.map(|v| if v > 0.0 { 1.0 / c } else { 0.0 }))
        }
    };
    NormalResult { moments, area_centroid }
}

/// ∫ q λᵢ dA over a triangle with linear q (nodal values `q`), area `area`:
/// `A/12 (qᵢ + Σq)` for each barycentric coordinate λᵢ.
#[inline(always)]
pub(crate) fn moments_full(q: [f64; 3], area: f64) -> [f64; 3] {
    let s = q[0] + q[1] + q[2];
    let a12 = area * (1.0 / 12.0);
    [a12 * (q[0] + s), a12 * (q[1] + s), a12 * (q[2] + s)]
}

/// ∫ max(q, 0) λᵢ dA over a triangle with linear q: the triangle is clipped at q = 0 and
/// the compressed part (a triangle or a quadrilateral) integrated exactly.
#[inline]
pub fn compressed_moments(q: [f64; 3], area: f64) -> [f64; 3] {
    compressed_moments_centroid(q, area).0
}

/// [`compressed_moments`] and, from the same clipping, the area centroid of the compressed
/// part in barycentric coordinates (the triangle's centroid when all or none of it is
/// compressed).
///
/// Dispatches on the sign pattern of `q` to a clipping compiled once per pattern, so that
/// its branches and index arithmetic fold away (the floating-point operations, and so the
/// results, are those of the generic algorithm).
#[inline(always)]
pub fn compressed_moments_centroid(q: [f64; 3], area: f64) -> ([f64; 3], [f64; 3]) {
    match sign_mask(q) {
        0 => ([0.0; 3], [1.0 / 3.0; 3]),
        7 => (moments_full(q, area), [1.0 / 3.0; 3]),
        1 => clipped_moments::<1>(q, area),
        2 => clipped_moments::<2>(q, area),
        3 => clipped_moments::<3>(q, area),
        4 => clipped_moments::<4>(q, area),
        5 => clipped_moments::<5>(q, area),
        _ => clipped_moments::<6>(q, area),
    }
}

#[inline(always)]
fn sign_mask(q: [f64; 3]) -> u8 {
    (q[0] > 0.0) as u8 | ((q[1] > 0.0) as u8) << 1 | ((q[2] > 0.0) as u8) << 2
}

/// The compressed part of a triangle whose nodes with `q > 0` are the set bits of `MASK`:
/// up to four vertices in barycentric coordinates, with their `q`.
#[inline(always)]
fn clip<const MASK: u8>(q: [f64; 3]) -> ([([f64; 3], f64); 4], usize) {
    let positive = |i: usize| MASK & (1 << i) != 0;
    let mut poly: [([f64; 3], f64); 4] = [([0.0; 3], 0.0); 4];
    let mut n = 0;
    for i in 0..3 {
        let j = (i + 1) % 3;
        let mut bi = [0.0; 3];
        bi[i] = 1.0;
        if positive(i) {
            poly[n] = (bi, q[i]);
            n += 1;
        }
        if positive(i) != positive(j) {
            let t = q[i] / (q[i] - q[j]);
            let mut b = [0.0; 3];
            b[i] = 1.0 - t;
            b[j] = t;
            poly[n] = (b, 0.0);
            n += 1;
        }
    }
    (poly, n)
}

/// Area ratio of the sub-triangle (a, b, c) in barycentric coordinates.
#[inline(always)]
fn det(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    let (u1, v1) = (b[1] - a[1], b[2] - a[2]);
    let (u2, v2) = (c[1] - a[1], c[2] - a[2]);
    (u1 * v2 - u2 * v1).abs()
}

/// [`compressed_moments`] for a partly compressed triangle whose nodes with `q > 0` are the
/// set bits of `MASK` (1 to 6).
#[inline(always)]
fn clipped_moments<const MASK: u8>(q: [f64; 3], area: f64) -> ([f64; 3], [f64; 3]) {
    let (poly, n) = clip::<MASK>(q);
    let mut m = [0.0; 3];
    let (mut centroid, mut total) = ([0.0; 3], 0.0);
    for k in 1..n - 1 {
        let (a, qa) = poly[0];
        let (b, qb) = poly[k];
        let (c, qc) = poly[k + 1];
        let w = det(&a, &b, &c);
        let sub = area * w;
        let mm = moments_full([qa, qb, qc], sub);
        total += w;
        for i in 0..3 {
            m[i] += mm[0] * a[i] + mm[1] * b[i] + mm[2] * c[i];
            centroid[i] += w * (a[i] + b[i] + c[i]);
        }
    }
    let centroid = if total > 0.0 {
        let inv = 1.0 / (3.0 * total);
        centroid.map(|v| v * inv)
    } else {
        [1.0 / 3.0; 3]
    };
    (m, centroid)
}

/// Gauss–Legendre nodes on [−1, 1] and weights, 8 points (exact to degree 15).
const GAUSS8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_2, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_2, 0.101_228_536_290_376_26),
];

/// What [`level_integrals`] returns.
struct LevelIntegrals {
    /// `∫ g(u) λᵢ dA` per node.
    moments: [f64; 3],
    /// Area of the part, m².
    area: f64,
    /// Area centroid of the part, barycentric.
    centroid: [f64; 3],
}

/// Integrals over the part of a triangle where `u > lower`, for a closure `u` linear over
/// the triangle (nodal values `u`, area `area`): `∫ g(u) λᵢ dA` per node, the area of the
/// part and its area centroid.
///
/// The triangle is cut at its middle nodal value into two pieces whose level lines
/// `u = const` are segments of length linear in `u`; on each piece the integral is one
/// dimensional, `∫ g(u) λ̄ᵢ(u) (dA/du) du` with `λ̄` (the mean of λ on the level segment) and
/// `dA/du` of degree ≤ 1 in `u`, evaluated with 8-point Gauss–Legendre on every interval
/// between `breaks` (the kinks of `g`).
fn level_integrals(u: [f64; 3], area: f64, lower: f64, breaks: &[f64], g: impl Fn(f64) -> f64) -> LevelIntegrals {
    let mut out = LevelIntegrals { moments: [0.0; 3], area: 0.0, centroid: [1.0 / 3.0; 3] };
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&i, &j| u[i].total_cmp(&u[j]));
    let [ia, ib, ic] = idx;
    let (ua, ub, uc) = (u[ia], u[ib], u[ic]);
    let span = uc - ua;
    if span <= 1e-12 * (ua.abs() + uc.abs()) {
        if ua > lower {
            out.moments = [g(ua) * area / 3.0; 3];
            out.area = area;
        }
        return out;
    }
    // Sums per node in the sorted order (node `idx[k]` is entry `k`), each taking the same
    // terms in the same order as the node's own sum would.
    let (mut moments, mut sorted_centroid) = ([0.0; 3], [0.0; 3]);
    // One piece from `lo` to `hi` with its density `dA/du` and mean barycentrics `λ̄(u)`
    // (closures of their own types, so each evaluation is inlined).
    macro_rules! piece {
        ($lo:expr, $hi:expr, $density:expr, $lam:expr) => {{
            let (density, lam) = ($density, $lam);
            let (lo, hi): (f64, f64) = (f64::max($lo, lower), $hi);
            if hi > lo {
                // The intervals between `lo`, the kinks inside and `hi`, in that order.
                let inside = breaks.iter().copied().filter(|&b| b > lo && b < hi);
                let mut from = lo;
                for to in inside.chain(std::iter::once(hi)) {
                    let (mid, half) = (0.5 * (from + to), 0.5 * (to - from));
                    from = to;
                    for (x, wt) in GAUSS8 {
                        let v = mid + half * x;
                        let d_area = wt * half * density(v);
                        let (gv, l): (f64, [f64; 3]) = (g(v) * d_area, lam(v));
                        for k in 0..3 {
                            moments[k] += gv * l[k];
                            sorted_centroid[k] += d_area * l[k];
                        }
                        out.area += d_area;
                    }
                }
            }
        }};
    }
    let a_low = area * (ub - ua) / span;
    if ub > ua {
        let db = ub - ua;
        piece!(ua, ub, |v: f64| 2.0 * a_low * (v - ua) / (db * db), |v: f64| {
            let (s, t) = ((v - ua) / db, (v - ua) / span);
            [1.0 - 0.5 * (s + t), 0.5 * s, 0.5 * t]
        });
    }
    if uc > ub {
        let (dc, a_up) = (uc - ub, area - a_low);
        piece!(ub, uc, |v: f64| 2.0 * a_up * (uc - v) / (dc * dc), |v: f64| {
            let (r, t) = ((v - ub) / dc, (v - ua) / span);
            [0.5 * (1.0 - t), 0.5 * (1.0 - r), 0.5 * (r + t)]
        });
    }
    let mut centroid = [0.0; 3];
    for k in 0..3 {
        out.moments[idx[k]] = moments[k];
        centroid[idx[k]] = sorted_centroid[k];
    }
    if out.area > 0.0 {
        out.centroid = centroid.map(|c| c / out.area);
    }
    out
}

/// The kinks of a law's pressure (the hyperbolic cap), closures in m.
fn breaks(p: &NormalParams) -> [f64; 1] {
    [p.closure.kink(p.kn)]
}

/// `∫ q(u) λᵢ dA` over the compressed part (the whole triangle when the joint carries
/// tension) by [`level_integrals`]: relative error below 1e-10 for the hyperbolic law.
fn nonlinear_moments(p: &NormalParams, u: [f64; 3], area: f64, tension: bool) -> NormalResult {
    let lower = if tension { f64::NEG_INFINITY } else { 0.0 };
    let li = level_integrals(u, area, lower, &breaks(p), |v| p.pressure(v));
    let whole = tension || u.iter().all(|&v| v > 0.0);
    NormalResult { moments: li.moments, area_centroid: if whole { [1.0 / 3.0; 3] } else { li.centroid } }
}

/// `∫ q(u) λᵢ dA` of the seating law ([`crate::closure::Seating`], largest gap `g`, m) in
/// closed form: `q = Kn/(2g) (u₊² − (u − g)₊²)` (the quadratic branch while the gaps close,
/// `Kn (u − g/2)` past them), so the moments are `Kn/(2g)` times the difference of
/// [`squared_positive_moments`] of `u` and of `u − g`; a triangle closed past `g` at every
/// node is the linear pressure `Kn (u − g/2)` integrated at once. Exact, as the 8-point
/// quadrature of [`nonlinear_moments`] is for this law, at a fraction of its cost. With
/// tension the tensile branch `Kn u` is added over the part where `u < 0`. The area
/// centroid is that of the part with `u > 0` (the triangle's when the joint carries
/// tension or the whole triangle is closed).
fn seating_moments(kn: f64, g: f64, u: [f64; 3], area: f64, tension: bool) -> NormalResult {
    let centroid = if tension { [1.0 / 3.0; 3] } else { compressed_moments_centroid(u, area).1 };
    let past = u.map(|v| v - g);
    let mut moments = if past.iter().all(|&v| v > 0.0) {
        moments_full(u.map(|v| kn * (v - 0.5 * g)), area)
    } else {
        let (a, b) = (squared_positive_moments(u, area), squared_positive_moments(past, area));
        let c = kn / (2.0 * g);
        [c * (a[0] - b[0]), c * (a[1] - b[1]), c * (a[2] - b[2])]
    };
    if tension && u.iter().any(|&v| v < 0.0) {
        // The tensile branch over u < 0: the whole linear integral less its compressed part.
        let q = u.map(|v| kn * v);
        let (full, pos) = (moments_full(q, area), compressed_moments(q, area));
        for i in 0..3 {
            moments[i] += full[i] - pos[i];
        }
    }
    NormalResult { moments, area_centroid: centroid }
}

/// `∫ v₊² λᵢ dA` per node over a triangle of area `area` with `v` linear (nodal values `v`):
/// the triangle is clipped at `v = 0` ([`clip`]), the part fanned into triangles, and on each
/// the cubic `v² λᵢ` integrated exactly by `∫ L₁^a L₂^b L₃^c dA = 2A a! b! c! / (a+b+c+2)!`
/// (A/10, A/30, A/60 for the three kinds of cubic monomial).
fn squared_positive_moments(v: [f64; 3], area: f64) -> [f64; 3] {
    let (poly, n) = match sign_mask(v) {
        0 => return [0.0; 3],
        7 => {
            let e = |i: usize| {
                let mut b = [0.0; 3];
                b[i] = 1.0;
                (b, v[i])
            };
            ([e(0), e(1), e(2), ([0.0; 3], 0.0)], 3)
        }
        1 => clip::<1>(v),
        2 => clip::<2>(v),
        3 => clip::<3>(v),
        4 => clip::<4>(v),
        5 => clip::<5>(v),
        _ => clip::<6>(v),
    };
    let mut m = [0.0; 3];
    for k in 1..n - 1 {
        let (a, va) = poly[0];
        let (b, vb) = poly[k];
        let (c, vc) = poly[k + 1];
        let sub = area * det(&a, &b, &c);
        let vals = [va, vb, vc];
        // w_l = Σ_ij v_i v_j m(i, j, l), m = 6 (i = j = l), 2 (two equal), 1 (all differ):
        // ∫ v² h dA = A/60 Σ_l h_l w_l for h linear with nodal values h_l.
        let mut w = [0.0; 3];
        for (l, wl) in w.iter_mut().enumerate() {
            for i in 0..3 {
                for j in 0..3 {
                    let mult = if i == j && j == l {
                        6.0
                    } else if i == j || j == l || i == l {
                        2.0
                    } else {
                        1.0
                    };
                    *wl += mult * vals[i] * vals[j];
                }
            }
        }
        let s = sub / 60.0;
        for i in 0..3 {
            m[i] += s * (a[i] * w[0] + b[i] * w[1] + c[i] * w[2]);
        }
    }
    m
}

/// Elastic energy stored in the normal closure of a sub-contact, J: `∫ W(u₊) dA` over the
/// compressed part, with `W` the law's energy density ([`NormalParams::energy_density`]).
/// Exact for the linear law (`∫ q₊² / (2 Kn) dA`); by `level_integrals` otherwise.
pub fn energy(p: &NormalParams, u: [f64; 3], area: f64) -> f64 {
    match p.closure {
        Closure::Linear => squared_compressed(u.map(|v| p.kn * v), area) / (2.0 * p.kn),
        _ => level_integrals(u, area, 0.0, &breaks(p), |v| p.energy_density(v)).moments.iter().sum(),
    }
}

/// ∫ q₊² dA over a triangle with linear q: the compressed part is sub-triangulated and
/// `∫ q² dA = A/12 (Σqᵢ² + (Σqᵢ)²)` applied to each piece.
fn squared_compressed(q: [f64; 3], area: f64) -> f64 {
    let full = |a: f64, b: f64, c: f64, ar: f64| ar / 12.0 * (a * a + b * b + c * c + (a + b + c).powi(2));
    let unit = |i: usize| {
        let mut b = [0.0; 3];
        b[i] = 1.0;
        b
    };
    let pos: Vec<usize> = (0..3).filter(|&i| q[i] > 0.0).collect();
    match pos.len() {
        0 => 0.0,
        1 => {
            let i = pos[0];
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let tj = q[i] / (q[i] - q[j]);
            let tk = q[i] / (q[i] - q[k]);
            full(q[i], 0.0, 0.0, area * tj * tk)
        }
        2 => {
            let k = (0..3).find(|&v| q[v] <= 0.0).unwrap_or(0);
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let ti = q[k] / (q[k] - q[i]);
            let tj = q[k] / (q[k] - q[j]);
            // The compressed quadrilateral as two triangles (i, j, Pj) and (i, Pj, Pi), with
            // P the cut points on the edges from k.
            let mut pi = [0.0; 3];
            pi[k] = 1.0 - ti;
            pi[i] = ti;
            let mut pj = [0.0; 3];
            pj[k] = 1.0 - tj;
            pj[j] = tj;
            let (ei, ej) = (unit(i), unit(j));
            full(q[i], q[j], 0.0, area * det(&ei, &ej, &pj)) + full(q[i], 0.0, 0.0, area * det(&ei, &pj, &pi))
        }
        _ => full(q[0], q[1], q[2], area),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::closure::Seating;

    /// The seating law's closed form against the 8-point quadrature along the closure
    /// gradient (exact for a quadratic, an independent algorithm): every sign pattern of
    /// `u` and of `u − g`, with and without tension, and the area centroid; and a dense
    /// midpoint rule over the triangle, which splits at no kink, for the tensile cases.
    #[test]
    fn the_seating_laws_closed_form_is_its_quadrature() {
        let (kn, g) = (2e10, 1.5e-4);
        let p = NormalParams { kn, closure: Closure::Seating(Seating { max_gap_m: g }) };
        let mut cases = 0;
        for a in [-2e-4, -3e-5, 0.0, 4e-5, 1.4e-4, 1.5e-4, 2.6e-4, 6e-4] {
            for b in [-1e-4, 2e-5, 1e-4, 3e-4] {
                for c in [-5e-5, 7e-5, 1.6e-4, 5e-4] {
                    for tension in [false, true] {
                        let u = [a, b, c];
                        let area = 0.013;
                        let closed = seating_moments(kn, g, u, area, tension);
                        // The quadrature splits at the law's kink g, not at 0, where the
                        // tensile branch meets the quadratic one: with tension the
                        // reference is its compressed part plus the tensile branch's own
                        // closed form over u < 0 (the linear law's clipping).
                        let mut quad = nonlinear_moments(&p, u, area, false);
                        if tension {
                            let q = u.map(|v| kn * v);
                            let (full, pos) = (moments_full(q, area), compressed_moments(q, area));
                            for i in 0..3 {
                                quad.moments[i] += full[i] - pos[i];
                            }
                            quad.area_centroid = [1.0 / 3.0; 3];
                        }
                        let scale = quad.moments.iter().map(|m| m.abs()).sum::<f64>().max(1e-9 * kn * g * area);
                        for i in 0..3 {
                            assert!(
                                (closed.moments[i] - quad.moments[i]).abs() <= 1e-11 * scale,
                                "u {u:?}, tension {tension}: node {i} {:e} vs {:e}",
                                closed.moments[i],
                                quad.moments[i]
                            );
                            assert!(
                                (closed.area_centroid[i] - quad.area_centroid[i]).abs() < 1e-9,
                                "u {u:?}, tension {tension}: centroid {:?} vs {:?}",
                                closed.area_centroid,
                                quad.area_centroid
                            );
                        }
                        cases += 1;
                    }
                }
            }
        }
        assert_eq!(cases, 256);
        // Tension, against 3 × 400² midpoint samples (error of the order 1e-5 at the kinks).
        let n = 400;
        for u in [[-2e-4, -1e-4, 7e-5], [-3e-5, 1e-4, 5e-4], [4e-5, -1e-4, 1.6e-4]] {
            let area = 0.013;
            let closed = seating_moments(kn, g, u, area, true);
            let mut m = [0.0; 3];
            let h = 1.0 / n as f64;
            for i in 0..n {
                for j in 0..n - i {
                    // The two sub-triangles of the cell (i, j) of the barycentric grid.
                    let mut tri = vec![[(i as f64 + 1.0 / 3.0) * h, (j as f64 + 1.0 / 3.0) * h]];
                    if i + j + 1 < n {
                        tri.push([(i as f64 + 2.0 / 3.0) * h, (j as f64 + 2.0 / 3.0) * h]);
                    }
                    for [l1, l2] in tri {
                        let l = [l1, l2, 1.0 - l1 - l2];
                        let v = l[0] * u[0] + l[1] * u[1] + l[2] * u[2];
                        let q = p.pressure(v) * area * h * h;
                        for k in 0..3 {
                            m[k] += q * l[k];
                        }
                    }
                }
            }
            let scale = m.iter().map(|x| x.abs()).sum::<f64>();
            for k in 0..3 {
                assert!(
                    (closed.moments[k] - m[k]).abs() < 1e-4 * scale,
                    "u {u:?} node {k}: {:e} vs {:e}",
                    closed.moments[k],
                    m[k]
                );
            }
        }
    }
}
