//! The joint law of one sub-contact: a pure function of the joint parameters, the
//! sub-contact's own history and this step's kinematics (LAMMPS granular kernel style).
//!
//! # Coulomb joint (3DEC "Coulomb slip", Itasca 3DEC manual; Cundall 1988)
//!
//! A sub-contact is a triangle of area `A` (m²) of the contact polygon. With normal
//! stiffness `Kn` and shear stiffness `Ks` (Pa/m: stress per unit relative displacement):
//!
//! * normal pressure (compression positive) `q = Kn · uₙ` with the overlap `uₙ = −gap`; the
//!   gap is known at the triangle's three nodes and varies linearly over it. No tension
//!   (`q = 0` where the joint is open) unless a tensile strength `T` (Pa) is given and
//!   intact, in which case `q ≥ −T` at every node; past it the joint breaks;
//! * the normal force `Fn = ∫ q dA` and its point of application follow from the pressure
//!   field, integrated by the sub-contact [`Quadrature`]: `Exact` (default) clips the
//!   triangle at the zero-pressure line and integrates the linear pressure exactly, so that
//!   a joint opening across a sub-contact carries exactly the Winkler resultant whatever
//!   the sub-contact density; `Vertex` lumps A/3 at each node (3DEC's vertex sub-contacts),
//!   which converges to the same limit as the density grows;
//! * shear force, incremental and rotated with the contact plane:
//!   `Fs ← rot(Fs) − Ks · A · Δuₛ`, acting between the area centroid of the compressed part
//!   (no strength mobilised: the elastic traction Ks·uₛ is uniform there) and the point of
//!   `Fn` (at slip: the traction is then pressure-weighted), linearly in the mobilised
//!   fraction |Fs| / (c A + Fn tan φ). Applying the elastic shear at the pressure centroid
//!   couples the triangles of a face in torsion (a block pushed sideways through its
//!   centroid twisted about the vertical by 5 % of its displacement); applying the slipping
//!   shear at the area centroid lets a sliding block rotate about the vertical before α = φ;
//! * slip: `|Fs| ≤ c A + Fn tan φ`; past it `Fs` is scaled back onto the limit
//!   (elasto-plastic). When a joint fails in tension or shear, its tensile strength and
//!   cohesion drop to zero for good (3DEC's residual-strength convention).
//!
//! The normal force is computed from the total overlap rather than incrementally: for a
//! linear law this equals the incremental form of the paper's Eq. 2 and does not drift.
//!
//! Sign conventions: the contact normal `n` points from body A to body B; the forces
//! returned act on B (A receives the opposite); `Δuₛ` is the tangential displacement
//! increment of B relative to A over the step (m).
//!
//! Other closure laws are added as variants of [`NormalClosure`] with their own pressure
//! integral; the engine calls only [`evaluate`].

use crate::Vec3;

/// The normal closure law of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[non_exhaustive]
pub enum NormalClosure {
    /// Linear: `Fn = Kn A uₙ`.
    #[default]
    Linear,
}

/// Joint parameters (SI). Plain data: the kernel reads nothing else.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointParams {
    /// Normal stiffness Kn, Pa/m.
    pub kn: f64,
    /// Shear stiffness Ks, Pa/m.
    pub ks: f64,
    /// Friction angle φ, rad.
    pub phi: f64,
    /// tan φ (cached).
    pub tan_phi: f64,
    /// Cohesion c, Pa.
    pub cohesion: f64,
    /// Tensile strength T, Pa (0: no tension).
    pub tensile_strength: f64,
    /// Normal closure law.
    pub closure: NormalClosure,
    /// False for a joint held against slip (the base course's restraint): its shear spring
    /// stays elastic whatever the force.
    pub can_slip: bool,
}

impl JointParams {
    /// A Coulomb joint with linear closure (angles in rad, stresses in Pa, stiffness Pa/m).
    pub fn coulomb(kn: f64, ks: f64, phi: f64, cohesion: f64, tensile_strength: f64) -> Self {
        JointParams {
            kn,
            ks,
            phi,
            tan_phi: phi.tan(),
            cohesion,
            tensile_strength,
            closure: NormalClosure::Linear,
            can_slip: true,
        }
    }

    /// The joint between two different materials: series stiffness of two half-joints
    /// (`2 k₁ k₂ / (k₁ + k₂)`), the smaller friction angle, cohesion and tensile strength.
    pub fn combine(&self, other: &JointParams) -> JointParams {
        let series = |a: f64, b: f64| 2.0 * a * b / (a + b);
        let phi = self.phi.min(other.phi);
        JointParams {
            kn: series(self.kn, other.kn),
            ks: series(self.ks, other.ks),
            phi,
            tan_phi: phi.tan(),
            cohesion: self.cohesion.min(other.cohesion),
            tensile_strength: self.tensile_strength.min(other.tensile_strength),
            closure: self.closure,
            can_slip: self.can_slip && other.can_slip,
        }
    }
}

/// How the pressure is integrated over a sub-contact triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quadrature {
    /// Exact integral of the linear pressure over the compressed part of the triangle.
    #[default]
    Exact,
    /// One third of the area at each node (3DEC vertex sub-contacts).
    Vertex,
}

/// History of one sub-contact, carried from step to step (and across re-detections).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubContactState {
    /// Shear force on B, N, world frame, in the contact plane.
    pub shear: Vec3,
    /// Normal force on B along n, N (compression positive), of the last evaluation.
    pub normal: f64,
    /// Tensile strength and cohesion still intact.
    pub bonded: bool,
    /// The shear force was on the slip limit at the last evaluation.
    pub slipping: bool,
}

impl SubContactState {
    /// A fresh sub-contact with no force; `bonded` if its joint starts intact.
    pub fn new(bonded: bool) -> Self {
        SubContactState { shear: Vec3::zeros(), normal: 0.0, bonded, slipping: false }
    }
}

/// Kinematics of one sub-contact in one step.
#[derive(Debug, Clone, Copy)]
pub struct Kinematics {
    /// Current unit normal, A → B, world frame.
    pub normal: Vec3,
    /// Normal gap at the three nodes, m (positive open, negative overlap).
    pub gaps: [f64; 3],
    /// Tangential displacement increment of B relative to A, m, world frame.
    pub du_shear: Vec3,
    /// Triangle area, m².
    pub area: f64,
}

/// The force of a sub-contact on B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubContactForce {
    /// Total force on B (normal plus shear), N, world frame.
    pub force: Vec3,
    /// Point of application of the normal force, barycentric coordinates of the triangle's
    /// nodes (sums to 1): the centroid of the pressure.
    pub at: [f64; 3],
    /// The shear part of `force`, N, world frame (in the contact plane).
    pub shear: Vec3,
    /// Point of application of the shear force, barycentric: from the area centroid of the
    /// compressed part when no strength is mobilised (the elastic shear traction Ks·uₛ is
    /// uniform under the translation a sub-contact sees) to the pressure centroid `at` at
    /// slip (the traction is then c + q tan φ, pressure-weighted), linearly in the mobilised
    /// fraction |Fs| / (c A + Fn tan φ): slip spreads from the least-pressed part as the
    /// shear grows.
    pub at_shear: [f64; 3],
}

/// No force.
pub const NO_FORCE: SubContactForce = SubContactForce {
    force: Vec3::new(0.0, 0.0, 0.0),
    at: [1.0 / 3.0; 3],
    shear: Vec3::new(0.0, 0.0, 0.0),
    at_shear: [1.0 / 3.0; 3],
};

/// ∫ q λᵢ dA over a triangle with linear q (nodal values `q`), area `area`:
/// `A/12 (qᵢ + Σq)` for each barycentric coordinate λᵢ.
#[inline(always)]
fn moments_full(q: [f64; 3], area: f64) -> [f64; 3] {
    let s = q[0] + q[1] + q[2];
    let a12 = area * (1.0 / 12.0);
    [a12 * (q[0] + s), a12 * (q[1] + s), a12 * (q[2] + s)]
}

/// ∫ max(q, 0) λᵢ dA over a triangle with linear q: the triangle is clipped at q = 0 and
/// the compressed part (a triangle or a quadrilateral) integrated exactly.
///
/// Dispatches on the sign pattern of `q` to `clipped_moments`, compiled once per pattern
/// so that the clipping's branches and index arithmetic fold away (the floating-point
/// operations, and so the results, are those of the generic algorithm).
#[inline]
pub fn compressed_moments(q: [f64; 3], area: f64) -> [f64; 3] {
    compressed_moments_centroid(q, area).0
}

/// [`compressed_moments`] and, from the same clipping, the area centroid of the compressed
/// part in barycentric coordinates (the triangle's centroid when all or none of it is
/// compressed).
#[inline(always)]
pub fn compressed_moments_centroid(q: [f64; 3], area: f64) -> ([f64; 3], [f64; 3]) {
    let mask = (q[0] > 0.0) as u8 | ((q[1] > 0.0) as u8) << 1 | ((q[2] > 0.0) as u8) << 2;
    match mask {
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

/// [`compressed_moments`] for a partly compressed triangle whose nodes with `q > 0` are the
/// set bits of `MASK` (1 to 6).
#[inline(always)]
fn clipped_moments<const MASK: u8>(q: [f64; 3], area: f64) -> ([f64; 3], [f64; 3]) {
    let positive = |i: usize| MASK & (1 << i) != 0;
    // Vertices of the clipped polygon in barycentric coordinates with their q.
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
    let mut m = [0.0; 3];
    let det = |a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]| {
        // Area ratio of the sub-triangle (a, b, c) in barycentric coordinates.
        let (u1, v1) = (b[1] - a[1], b[2] - a[2]);
        let (u2, v2) = (c[1] - a[1], c[2] - a[2]);
        (u1 * v2 - u2 * v1).abs()
    };
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

/// Evaluates the joint law on one sub-contact: updates `state`, returns the force on B.
#[inline(always)]
pub fn evaluate(p: &JointParams, quad: Quadrature, state: &mut SubContactState, k: &Kinematics) -> SubContactForce {
    match p.closure {
        NormalClosure::Linear => coulomb_linear(p, quad, state, k),
    }
}

#[inline(always)]
fn coulomb_linear(p: &JointParams, quad: Quadrature, s: &mut SubContactState, k: &Kinematics) -> SubContactForce {
    let n = k.normal;
    let q = [-p.kn * k.gaps[0], -p.kn * k.gaps[1], -p.kn * k.gaps[2]];
    // Tension carried only by an intact joint with a tensile strength, up to it everywhere.
    let tension = s.bonded && p.tensile_strength > 0.0;
    if tension && q.iter().any(|&v| v < -p.tensile_strength) {
        s.bonded = false;
    }
    let tension = s.bonded && p.tensile_strength > 0.0;
    // Normal-pressure moments per node, and the area centroid of the compressed part (where
    // the elastic shear acts).
    let (moments, area_centroid) = match (quad, tension) {
        (Quadrature::Exact, true) => (moments_full(q, k.area), [1.0 / 3.0; 3]),
        (Quadrature::Exact, false) => compressed_moments_centroid(q, k.area),
        (Quadrature::Vertex, true) => (q.map(|v| v * k.area / 3.0), [1.0 / 3.0; 3]),
        (Quadrature::Vertex, false) => {
            let c = q.iter().filter(|&&v| v > 0.0).count().max(1) as f64;
            (q.map(|v| v.max(0.0) * k.area / 3.0), q.map(|v| if v > 0.0 { 1.0 / c } else { 0.0 }))
        }
    };
    let fnorm = moments[0] + moments[1] + moments[2];
    if fnorm <= 0.0 && !tension {
        s.bonded = false;
        s.shear = Vec3::zeros();
        s.normal = 0.0;
        s.slipping = false;
        return NO_FORCE;
    }
    let at = if fnorm.abs() > 0.0 {
        let inv = 1.0 / fnorm;
        [moments[0] * inv, moments[1] * inv, moments[2] * inv]
    } else {
        [1.0 / 3.0; 3]
    };
    // Rotate the stored shear force into the current plane, keeping its magnitude.
    let old = s.shear;
    let old_mag2 = old.norm_squared();
    let mut fs = old - n * n.dot(&old);
    if old_mag2 > 0.0 {
        let new_mag2 = fs.norm_squared();
        if new_mag2 > 0.0 {
            fs *= (old_mag2 / new_mag2).sqrt();
        }
    }
    fs -= k.du_shear * (p.ks * k.area);
    s.slipping = false;
    // Mobilised fraction of the shear strength, in [0, 1] (0 for a joint that cannot slip).
    let mut mobilised = 0.0;
    if p.can_slip {
        let cohesion = if s.bonded { p.cohesion * k.area } else { 0.0 };
        let mut limit = cohesion + fnorm.max(0.0) * p.tan_phi;
        let mag2 = fs.norm_squared();
        if mag2 > limit * limit {
            if s.bonded {
                // Shear failure of an intact joint: residual strength only.
                s.bonded = false;
                limit = fnorm.max(0.0) * p.tan_phi;
                if fnorm < 0.0 {
                    s.shear = Vec3::zeros();
                    s.normal = 0.0;
                    return NO_FORCE;
                }
            }
            let mag = mag2.sqrt();
            fs *= if mag > 0.0 { limit / mag } else { 0.0 };
            s.slipping = true;
        }
        mobilised = if s.slipping || limit <= 0.0 { 1.0 } else { (mag2.sqrt() / limit).min(1.0) };
    }
    s.shear = fs;
    s.normal = fnorm;
    let w = mobilised;
    let at_shear = [
        (1.0 - w) * area_centroid[0] + w * at[0],
        (1.0 - w) * area_centroid[1] + w * at[1],
        (1.0 - w) * area_centroid[2] + w * at[2],
    ];
    SubContactForce { force: n * fnorm + fs, at, shear: fs, at_shear }
}

/// Elastic energy stored in the normal springs of a sub-contact, J:
/// `∫ q₊² / (2 Kn) dA` over the compressed part (exact for the linear law).
pub fn normal_energy(p: &JointParams, gaps: [f64; 3], area: f64) -> f64 {
    squared_compressed(gaps.map(|g| -p.kn * g), area) / (2.0 * p.kn)
}

/// ∫ q₊² dA over a triangle with linear q: the compressed part is sub-triangulated and
/// `∫ q² dA = A/12 (Σqᵢ² + (Σqᵢ)²)` applied to each piece.
fn squared_compressed(q: [f64; 3], area: f64) -> f64 {
    // Sub-triangulate the compressed part and integrate q² on each sub-triangle exactly.
    let full = |a: f64, b: f64, c: f64, ar: f64| ar / 12.0 * (a * a + b * b + c * c + (a + b + c).powi(2));
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
            // Whole minus the negative corner, on q₊ = q on the quad; integrate the quad as
            // two triangles: (i, j, Pj) and (i, Pj, Pi) where P are the cut points.
            // Areas in barycentric units.
            let pi = {
                let mut b = [0.0; 3];
                b[k] = 1.0 - ti;
                b[i] = ti;
                b
            };
            let pj = {
                let mut b = [0.0; 3];
                b[k] = 1.0 - tj;
                b[j] = tj;
                b
            };
            let ei = {
                let mut b = [0.0; 3];
                b[i] = 1.0;
                b
            };
            let ej = {
                let mut b = [0.0; 3];
                b[j] = 1.0;
                b
            };
            let det = |a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]| {
                let (u1, v1) = (b[1] - a[1], b[2] - a[2]);
                let (u2, v2) = (c[1] - a[1], c[2] - a[2]);
                (u1 * v2 - u2 * v1).abs()
            };
            full(q[i], q[j], 0.0, area * det(&ei, &ej, &pj)) + full(q[i], 0.0, 0.0, area * det(&ei, &pj, &pi))
        }
        _ => full(q[0], q[1], q[2], area),
    }
}

/// Elastic energy stored in the shear spring of a sub-contact, J: `|Fs|² / (2 Ks A)`.
pub fn shear_energy(p: &JointParams, s: &SubContactState, area: f64) -> f64 {
    if area <= 0.0 {
        return 0.0;
    }
    s.shear.norm_squared() / (2.0 * p.ks * area)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn force(p: &JointParams, s: &mut SubContactState, gap: f64, du: Vec3) -> Vec3 {
        evaluate(p, Quadrature::Exact, s, &Kinematics { normal: Vec3::z(), gaps: [gap; 3], du_shear: du, area: 0.01 })
            .force
    }

    /// One contract every closure law must meet (statrs `check_continuous_distribution`
    /// style): no force when open and unbonded, compression grows with overlap, shear bounded
    /// by the Coulomb limit, force along n and in the plane only.
    fn check_contact_law(p: JointParams) {
        let mut s = SubContactState::new(false);
        assert_eq!(force(&p, &mut s, 1e-4, Vec3::x() * 1e-4), Vec3::zeros());
        let mut last = 0.0;
        for i in 1..10 {
            let mut s = SubContactState::new(false);
            let f = force(&p, &mut s, -1e-5 * i as f64, Vec3::zeros());
            assert!(f.z > last);
            last = f.z;
        }
        let mut s = SubContactState::new(false);
        for _ in 0..100 {
            let f = force(&p, &mut s, -1e-4, Vec3::x() * 1e-4);
            let fs = (f.x * f.x + f.y * f.y).sqrt();
            assert!(fs <= f.z * p.tan_phi * (1.0 + 1e-12) + 1e-12);
            assert!(f.x <= 0.0, "shear force opposes the motion of B");
        }
        assert!(s.slipping);
    }

    /// The generic clipping algorithm (the version before the sign-pattern dispatch), kept
    /// as the bit-level reference of [`compressed_moments`].
    fn compressed_moments_reference(q: [f64; 3], area: f64) -> [f64; 3] {
        let pos = q.iter().filter(|&&v| v > 0.0).count();
        match pos {
            0 => [0.0; 3],
            3 => moments_full(q, area),
            _ => {
                let mut poly: [([f64; 3], f64); 4] = [([0.0; 3], 0.0); 4];
                let mut n = 0;
                for i in 0..3 {
                    let j = (i + 1) % 3;
                    let mut bi = [0.0; 3];
                    bi[i] = 1.0;
                    if q[i] > 0.0 {
                        poly[n] = (bi, q[i]);
                        n += 1;
                    }
                    if (q[i] > 0.0) != (q[j] > 0.0) {
                        let t = q[i] / (q[i] - q[j]);
                        let mut b = [0.0; 3];
                        b[i] = 1.0 - t;
                        b[j] = t;
                        poly[n] = (b, 0.0);
                        n += 1;
                    }
                }
                let mut m = [0.0; 3];
                let det = |a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]| {
                    let (u1, v1) = (b[1] - a[1], b[2] - a[2]);
                    let (u2, v2) = (c[1] - a[1], c[2] - a[2]);
                    (u1 * v2 - u2 * v1).abs()
                };
                for k in 1..n - 1 {
                    let (a, qa) = poly[0];
                    let (b, qb) = poly[k];
                    let (c, qc) = poly[k + 1];
                    let sub = area * det(&a, &b, &c);
                    let mm = moments_full([qa, qb, qc], sub);
                    for i in 0..3 {
                        m[i] += mm[0] * a[i] + mm[1] * b[i] + mm[2] * c[i];
                    }
                }
                m
            }
        }
    }

    proptest::proptest! {
        /// The sign-pattern dispatch gives bit for bit the generic algorithm's moments.
        #[test]
        fn clipped_moments_are_bit_identical_to_the_generic_algorithm(
            q in proptest::array::uniform3(-1e6f64..1e6),
            zero in 0usize..4,
            area in 1e-8f64..1.0,
        ) {
            let mut q = q;
            if zero < 3 {
                q[zero] = 0.0; // a node exactly on the zero-pressure line
            }
            let new = compressed_moments(q, area).map(f64::to_bits);
            let old = compressed_moments_reference(q, area).map(f64::to_bits);
            proptest::prop_assert_eq!(new, old);
        }
    }

    #[test]
    fn every_law_meets_the_contract() {
        check_contact_law(JointParams::coulomb(5e7, 2.5e7, 35f64.to_radians(), 0.0, 0.0));
        check_contact_law(JointParams::coulomb(1e9, 1e9, 20f64.to_radians(), 0.0, 0.0));
    }

    #[test]
    fn elastic_forces_match_kn_a_un_and_ks_a_du() {
        let p = JointParams::coulomb(5e7, 2.5e7, 35f64.to_radians(), 0.0, 0.0);
        let mut s = SubContactState::new(false);
        let f = evaluate(
            &p,
            Quadrature::Exact,
            &mut s,
            &Kinematics { normal: Vec3::z(), gaps: [-1e-3; 3], du_shear: Vec3::y() * 1e-6, area: 0.02 },
        );
        assert!((f.force.z - 5e7 * 0.02 * 1e-3).abs() < 1e-9);
        assert!((f.force.y + 2.5e7 * 0.02 * 1e-6).abs() < 1e-12);
    }

    #[test]
    fn clipped_pressure_integral_matches_the_wedge() {
        // Right triangle (0,0),(1,0),(0,1), area 1/2, q = 1 − 2x: compressed for x < 1/2.
        // ∫ q₊ dA = ∫₀^½ (1 − 2x)(1 − x) dx = 5/24.
        let q = [1.0, -1.0, 1.0];
        let m = compressed_moments(q, 0.5);
        let f: f64 = m.iter().sum();
        assert!((f - 5.0 / 24.0).abs() < 1e-14, "{f}");
        // x̄ = ∫ x q₊ / ∫ q₊ = (∫₀^½ x(1−2x)(1−x) dx)/(5/24) = (1/32)/(5/24)... computed:
        let xbar_num = 1.0 / 8.0 - 1.0 / 8.0 + 1.0 / 32.0; // ∫ x − 3x² + 2x³ over [0, ½]
        assert!((m[1] / f - xbar_num / (5.0 / 24.0)).abs() < 1e-12);
        // Energy: ∫ q₊² dA = ∫₀^½ (1−2x)²(1−x) dx = 7/48, stored energy half of it (Kn = 1).
        let p = JointParams::coulomb(1.0, 1.0, 0.5, 0.0, 0.0);
        let e = normal_energy(&p, q.map(|v| -v), 0.5);
        assert!((e - 0.5 * 7.0 / 48.0).abs() < 1e-14, "{e}");
        // Fully compressed: A/12 (Σq² + (Σq)²).
        let e = normal_energy(&p, [-1.0, -2.0, -3.0], 0.5);
        assert!((e - 0.5 * 0.5 / 12.0 * (14.0 + 36.0)).abs() < 1e-14);
    }

    #[test]
    fn cohesion_and_tension_are_lost_on_failure() {
        let p = JointParams::coulomb(1e8, 1e8, 30f64.to_radians(), 1e4, 1e4);
        let mut s = SubContactState::new(true);
        let k = |g: f64| Kinematics { normal: Vec3::z(), gaps: [g; 3], du_shear: Vec3::zeros(), area: 0.01 };
        // Tension below strength (q = −5e3 Pa > −T): carried.
        let f = evaluate(&p, Quadrature::Exact, &mut s, &k(5e-5)).force;
        assert!((f.z + 1e8 * 0.01 * 5e-5).abs() < 1e-9);
        assert!(s.bonded);
        // Beyond strength: broken, zero force, and stays broken.
        assert_eq!(evaluate(&p, Quadrature::Exact, &mut s, &k(2e-4)).force, Vec3::zeros());
        assert!(!s.bonded);
        assert_eq!(evaluate(&p, Quadrature::Exact, &mut s, &k(5e-5)).force, Vec3::zeros());
    }

    #[test]
    fn held_joint_never_slips() {
        let mut p = JointParams::coulomb(1e8, 1e8, 10f64.to_radians(), 0.0, 0.0);
        p.can_slip = false;
        let mut s = SubContactState::new(false);
        let f = evaluate(
            &p,
            Quadrature::Exact,
            &mut s,
            &Kinematics { normal: Vec3::z(), gaps: [-1e-6; 3], du_shear: Vec3::x() * 1e-3, area: 1.0 },
        )
        .force;
        assert!((f.x + 1e8 * 1e-3).abs() < 1e-6);
        assert!(!s.slipping);
    }

    /// The compressed part's area centroid against a fine sampling of the triangle.
    #[test]
    fn compressed_centroid_matches_sampling() {
        for q in [[1.0, 2.0, 3.0], [1.0, -1.0, -2.0], [2.0, 1.0, -3.0], [-1.0, 4.0, -0.5], [-1.0, -1.0, -1.0]] {
            let c = compressed_moments_centroid(q, 1.0).1;
            let (mut acc, mut w) = ([0.0; 3], 0.0);
            let n = 600;
            for i in 0..n {
                for j in 0..n - i {
                    // Centre of a small cell in barycentric coordinates.
                    let (l1, l2) = ((i as f64 + 1.0 / 3.0) / n as f64, (j as f64 + 1.0 / 3.0) / n as f64);
                    let l = [1.0 - l1 - l2, l1, l2];
                    if q[0] * l[0] + q[1] * l[1] + q[2] * l[2] > 0.0 {
                        for k in 0..3 {
                            acc[k] += l[k];
                        }
                        w += 1.0;
                    }
                }
            }
            let expect = if w > 0.0 { acc.map(|v| v / w) } else { [1.0 / 3.0; 3] };
            for k in 0..3 {
                assert!((c[k] - expect[k]).abs() < 3e-3, "q {q:?}: {c:?} vs {expect:?}");
            }
            assert!((c.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
    }
}
