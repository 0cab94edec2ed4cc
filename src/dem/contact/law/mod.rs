//! The joint law of one sub-contact, as three sub-models in the manner of LAMMPS' GRANULAR
//! package (`gran_sub_mod_normal.h`, `gran_sub_mod_tangential.h`): each a pure kernel over
//! a plain parameter struct and the sub-contact's own history.
//!
//! * [`normal`]: the normal closure law and its integral over the sub-contact
//!   (the laws of [`crate::closure`]);
//! * [`tension`]: the tension cut-off ([`TensionCutoff`]);
//! * [`slip`]: the incremental shear spring with the Coulomb slip limit.
//!
//! [`evaluate`] composes them; the engine calls nothing else. A new normal closure law is
//! one file in [`crate::closure`] and one variant of [`Closure`]; [`contract`] holds the
//! checks every law must pass.
//!
//! # Coulomb joint (3DEC "Coulomb slip", Itasca 3DEC manual; Cundall 1988)
//!
//! A sub-contact is a triangle of area `A` (m²) of the contact polygon, with the normal gap
//! known at its three nodes and linear over it:
//!
//! * the normal force `Fn = ∫ q dA` (N) and its point of application follow from the
//!   pressure field `q(u)` of the closure law, `u = −gap`, integrated over the compressed
//!   part by the sub-contact [`Quadrature`]: `Exact` (default) clips the triangle at the
//!   zero-pressure line, so that a joint opening across a sub-contact carries the Winkler
//!   resultant whatever the sub-contact density; `Vertex` lumps A/3 at each node (3DEC's
//!   vertex sub-contacts);
//! * the shear force acts between the area centroid of the compressed part (no strength
//!   mobilised: the elastic traction Ks·uₛ is uniform there) and the point of `Fn` (at
//!   slip: the traction is then pressure-weighted), linearly in the mobilised fraction
//!   |Fs| / (c A + Fn tan φ). Applying the elastic shear at the pressure centroid would
//!   couple the triangles of a face in torsion; applying the slipping shear at the area
//!   centroid would let a sliding block rotate about the vertical before α = φ;
//! * when a joint fails in tension or shear, its tensile strength and cohesion drop to
//!   zero for good.
//!
//! The normal force is computed from the total closure rather than incrementally: for a
//! linear law this equals the incremental form of the paper's Eq. 2 (Santa-Cruz et al.
//! 2021) and does not drift.
//!
//! Sign conventions: the contact normal `n` points from body A to body B; the forces
//! returned act on B (A receives the opposite); `Δuₛ` is the tangential displacement
//! increment of B relative to A over the step (m).

pub mod contract;
pub mod normal;
pub mod slip;
pub mod tension;

pub use normal::{compressed_moments, compressed_moments_centroid, NormalParams, Quadrature};
pub use slip::SlipParams;
pub use tension::TensionCutoff;

use crate::closure::Closure;
#[cfg(test)]
use crate::closure::{Hyperbolic, Seating};
use crate::math::Vec3;

/// Joint parameters (SI). Plain data: the kernels read nothing else.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointParams {
    /// Normal stiffness Kn (initial stiffness Kni for a hyperbolic closure), Pa/m.
    pub kn: f64,
    /// Shear stiffness Ks, Pa/m.
    pub ks: f64,
    /// Friction angle φ, rad.
    pub phi: f64,
    /// tan φ (cached).
    pub tan_phi: f64,
    /// Cohesion c while intact, Pa.
    pub cohesion: f64,
    /// Tension cut-off.
    pub tension: TensionCutoff,
    /// Normal closure law.
    pub closure: Closure,
    /// False for a joint held against slip (the base course's restraint): its shear spring
    /// stays elastic whatever the force.
    pub can_slip: bool,
}

impl JointParams {
    /// A Coulomb joint with linear closure (angles in rad, stresses in Pa, stiffness Pa/m);
    /// a tensile strength of 0 Pa means no tension ([`TensionCutoff::from_strength`]).
    pub fn coulomb(kn: f64, ks: f64, phi: f64, cohesion: f64, tensile_strength: f64) -> Self {
        JointParams {
            kn,
            ks,
            phi,
            tan_phi: phi.tan(),
            cohesion,
            tension: TensionCutoff::from_strength(tensile_strength),
            closure: Closure::Linear,
            can_slip: true,
        }
    }

    /// The same joint with another normal closure law.
    pub fn with_closure(self, closure: Closure) -> Self {
        JointParams { closure, ..self }
    }

    /// The normal sub-model's parameters.
    #[inline(always)]
    pub fn normal(&self) -> NormalParams {
        NormalParams { kn: self.kn, closure: self.closure }
    }

    /// The shear/slip sub-model's parameters.
    #[inline(always)]
    pub fn slip(&self) -> SlipParams {
        SlipParams { ks: self.ks, tan_phi: self.tan_phi, cohesion: self.cohesion, can_slip: self.can_slip }
    }

    /// Largest normal tangent stiffness of the law, Pa/m (for the critical time step).
    pub fn kn_bound(&self) -> f64 {
        self.normal().stiffness_bound()
    }

    /// Whether a sub-contact of this joint starts intact (bonded): it has a cohesion or a
    /// tensile strength to lose.
    pub fn has_strength(&self) -> bool {
        self.cohesion > 0.0 || self.tension != TensionCutoff::NoTension
    }

    /// The joint between two different materials: series stiffness of two half-joints
    /// (`2 k₁ k₂ / (k₁ + k₂)`), the smaller friction angle, cohesion and tensile strength;
    /// the closure law of `self` (with the mean maximum closure when both are hyperbolic).
    pub fn combine(&self, other: &JointParams) -> JointParams {
        let series = |a: f64, b: f64| 2.0 * a * b / (a + b);
        let phi = self.phi.min(other.phi);
        let closure = self.closure.combine(&other.closure);
        JointParams {
            kn: series(self.kn, other.kn),
            ks: series(self.ks, other.ks),
            phi,
            tan_phi: phi.tan(),
            cohesion: self.cohesion.min(other.cohesion),
            tension: TensionCutoff::from_strength(self.tension.strength().min(other.tension.strength())),
            closure,
            can_slip: self.can_slip && other.can_slip,
        }
    }
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
    /// The factor the Coulomb return scaled the trial shear force by at the last
    /// evaluation, `limit / |Fs_trial|` in (0, 1] while slipping, 1 otherwise (–). Not
    /// history: the consistent tangent of the slip limit reads it
    /// (`crate::dem::drivers::newton`).
    pub return_scale: f64,
}

impl SubContactState {
    /// A fresh sub-contact with no force; `bonded` if its joint starts intact.
    pub fn new(bonded: bool) -> Self {
        SubContactState { shear: Vec3::zeros(), normal: 0.0, bonded, slipping: false, return_scale: 1.0 }
    }

    fn clear(&mut self) {
        self.shear = Vec3::zeros();
        self.normal = 0.0;
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
    /// compressed part when no strength is mobilised to the pressure centroid `at` at slip,
    /// linearly in the mobilised fraction |Fs| / (c A + Fn tan φ).
    pub at_shear: [f64; 3],
}

/// No force.
pub const NO_FORCE: SubContactForce = SubContactForce {
    force: Vec3::new(0.0, 0.0, 0.0),
    at: [1.0 / 3.0; 3],
    shear: Vec3::new(0.0, 0.0, 0.0),
    at_shear: [1.0 / 3.0; 3],
};

/// Evaluates the joint law on one sub-contact: tension cut-off, normal closure, then shear
/// and slip. Updates `state` and returns the force on B.
#[inline(always)]
pub fn evaluate(p: &JointParams, quad: Quadrature, s: &mut SubContactState, k: &Kinematics) -> SubContactForce {
    let np = p.normal();
    let u = [-k.gaps[0], -k.gaps[1], -k.gaps[2]];
    let tension = tension::carries_tension(p.tension, &mut s.bonded, || u.map(|v| np.pressure(v)));
    let nr = normal::integrate(&np, quad, u, k.area, tension);
    let fnorm = nr.moments[0] + nr.moments[1] + nr.moments[2];
    if fnorm <= 0.0 && !tension {
        s.bonded = false;
        s.clear();
        s.slipping = false;
        s.return_scale = 1.0;
        return NO_FORCE;
    }
    let at = if fnorm.abs() > 0.0 {
        let inv = 1.0 / fnorm;
        [nr.moments[0] * inv, nr.moments[1] * inv, nr.moments[2] * inv]
    } else {
        [1.0 / 3.0; 3]
    };
    let (fs, w) = match slip::shear(&p.slip(), s, k.normal, k.du_shear, k.area, fnorm) {
        slip::Shear::Force(fs, w) => (fs, w),
        slip::Shear::Lost => {
            s.clear();
            return NO_FORCE;
        }
    };
    s.shear = fs;
    s.normal = fnorm;
    let c = nr.area_centroid;
    let at_shear = [(1.0 - w) * c[0] + w * at[0], (1.0 - w) * c[1] + w * at[1], (1.0 - w) * c[2] + w * at[2]];
    SubContactForce { force: k.normal * fnorm + fs, at, shear: fs, at_shear }
}

/// Elastic energy stored in the normal closure of a sub-contact with nodal `gaps` (m) and
/// area `area` (m²), J.
pub fn normal_energy(p: &JointParams, gaps: [f64; 3], area: f64) -> f64 {
    normal::energy(&p.normal(), gaps.map(|g| -g), area)
}

/// Elastic energy stored in the shear spring of a sub-contact, J: `|Fs|² / (2 Ks A)`.
pub fn shear_energy(p: &JointParams, s: &SubContactState, area: f64) -> f64 {
    slip::energy(&p.slip(), s, area)
}

#[cfg(test)]
mod tests {
    use super::normal::moments_full;
    use super::*;

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
        for p in contract::representative_laws() {
            contract::check_contact_law(&p, 1e-4);
        }
        contract::check_contact_law(&JointParams::coulomb(1e9, 1e9, 20f64.to_radians(), 0.0, 0.0), 1e-5);
        let soft = JointParams::coulomb(1e7, 5e6, 30f64.to_radians(), 0.0, 0.0)
            .with_closure(Closure::Hyperbolic(Hyperbolic { max_closure_m: 2e-3 }));
        contract::check_contact_law(&soft, 5e-4);
    }

    /// Seating: `q = Kn u²/(2 g₀)` while the gaps close, `Kn (u − g₀/2)` after; the force of
    /// a uniform closure and the energy against these closed forms.
    #[test]
    fn seating_closure_is_quadratic_then_linear_with_the_offset() {
        let p = NormalParams { kn: 4e7, closure: Closure::Seating(Seating { max_gap_m: 1e-3 }) };
        assert!((p.pressure(5e-4) - 4e7 * 25e-8 / 2e-3).abs() < 1e-9);
        assert!((p.pressure(3e-3) - 4e7 * 2.5e-3).abs() < 1e-6);
        // A ramp from 0 to 2 g₀ across a unit square: ∫ q dA = (W(2g₀) − W(0)) / (2g₀).
        let j = JointParams::coulomb(4e7, 2e7, 0.6, 0.0, 0.0).with_closure(p.closure);
        let tri = [[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]];
        let f: f64 = tri
            .iter()
            .map(|t| {
                let mut s = SubContactState::new(false);
                let gaps = t.map(|v| -2e-3 * v[0]);
                let k = Kinematics { normal: Vec3::z(), gaps, du_shear: Vec3::zeros(), area: 0.5 };
                evaluate(&j, Quadrature::Exact, &mut s, &k).force.z
            })
            .sum();
        let expect = p.energy_density(2e-3) / 2e-3;
        assert!((f - expect).abs() < 1e-9 * expect, "{f} vs {expect}");
    }

    /// Bandis et al. (1983): σ = Kni u / (1 − u/Vm); at u = Vm/2 the pressure is Kni Vm and
    /// the secant stiffness twice the initial one.
    #[test]
    fn hyperbolic_closure_doubles_the_secant_stiffness_at_half_the_maximum_closure() {
        let p = NormalParams { kn: 1e7, closure: Closure::Hyperbolic(Hyperbolic { max_closure_m: 1e-3 }) };
        assert!((p.pressure(5e-4) - 1e7 * 1e-3).abs() < 1e-6);
        assert!((p.pressure(1e-9) / 1e-9 - 1e7).abs() < 1e-5 * 1e7);
        // Past 0.8 Vm: tangent continuation with 25 Kni.
        let qc = 1e7 * 8e-4 / 0.2;
        assert!((p.pressure(9e-4) - (qc + 25.0 * 1e7 * 1e-4)).abs() < 1e-6);
    }

    /// A closure varying linearly across a rectangle (two sub-contact triangles): the force
    /// and moment against the closed-form integrals of the hyperbolic law,
    /// `∫ Kni u/(1 − u/Vm) du = Kni Vm (−u − Vm ln(1 − u/Vm))`.
    #[test]
    fn hyperbolic_closure_integrates_a_closure_ramp_exactly() {
        let (kni, vm) = (2e7, 1e-3);
        let p = JointParams::coulomb(kni, kni / 2.0, 0.6, 0.0, 0.0)
            .with_closure(Closure::Hyperbolic(Hyperbolic { max_closure_m: vm }));
        // Unit square, closure u(x) = u0 + (u1 − u0) x over x ∈ [0, 1], partly open.
        for (u0, u1) in [(1e-4, 7e-4), (-2e-4, 6e-4), (3e-4, 3.000001e-4)] {
            let u = |x: f64| u0 + (u1 - u0) * x;
            // Triangles (0,0),(1,0),(1,1) and (0,0),(1,1),(0,1).
            let tri = [[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]];
            let (mut f, mut mx) = (0.0, 0.0);
            for t in tri {
                let mut s = SubContactState::new(false);
                let gaps = t.map(|v| -u(v[0]));
                let out = evaluate(
                    &p,
                    Quadrature::Exact,
                    &mut s,
                    &Kinematics { normal: Vec3::z(), gaps, du_shear: Vec3::zeros(), area: 0.5 },
                );
                f += out.force.z;
                mx += out.force.z * (0..3).map(|i| out.at[i] * t[i][0]).sum::<f64>();
            }
            // Closed forms over the compressed x-range.
            let w = |v: f64| kni * vm * (-v - vm * (1.0 - v / vm).ln());
            let (x0, slope) = (if u0 < 0.0 { -u0 / (u1 - u0) } else { 0.0 }, u1 - u0);
            let expect_f = if slope.abs() < 1e-9 {
                p.normal().pressure(0.5 * (u0 + u1))
            } else {
                (w(u1) - w(u0.max(0.0))) / slope
            };
            // ∫ x q dx by a fine midpoint sum (smooth integrand).
            let n = 200_000;
            let expect_m: f64 = (0..n)
                .map(|i| {
                    let x = x0 + (1.0 - x0) * (i as f64 + 0.5) / n as f64;
                    x * p.normal().pressure(u(x)) * (1.0 - x0) / n as f64
                })
                .sum();
            assert!((f - expect_f).abs() < 1e-7 * expect_f, "({u0}, {u1}): {f} vs {expect_f}");
            assert!((mx - expect_m).abs() < 1e-6 * expect_m, "({u0}, {u1}): {mx} vs {expect_m}");
        }
    }

    /// One evaluation of a fresh, unbonded sub-contact on a horizontal joint: every node at
    /// gap `gap` (m, negative in contact), the shear increment `du_shear` (m), area `area`
    /// (m²). Returns the forces and the state after.
    fn flat_contact(p: &JointParams, gap: f64, du_shear: Vec3, area: f64) -> (SubContactForce, SubContactState) {
        let mut s = SubContactState::new(false);
        let f =
            evaluate(p, Quadrature::Exact, &mut s, &Kinematics { normal: Vec3::z(), gaps: [gap; 3], du_shear, area });
        (f, s)
    }

    #[test]
    fn elastic_forces_match_kn_a_un_and_ks_a_du() {
        let p = JointParams::coulomb(5e7, 2.5e7, 35f64.to_radians(), 0.0, 0.0);
        let (f, _) = flat_contact(&p, -1e-3, Vec3::y() * 1e-6, 0.02);
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
        let (f, s) = flat_contact(&p, -1e-6, Vec3::x() * 1e-3, 1.0);
        let f = f.force;
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
