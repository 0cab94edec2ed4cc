//! The joint law of one sub-contact: a pure function of the joint parameters, the
//! sub-contact's own history and this step's kinematics (LAMMPS granular kernel style).
//!
//! # Coulomb joint (3DEC "Coulomb slip", Itasca 3DEC manual; Cundall 1988)
//!
//! Per sub-contact of area `A` (m²), with normal stiffness `Kn` and shear stiffness `Ks`
//! (Pa/m: force per unit area per unit displacement):
//!
//! * normal force (compression positive): `Fn = Kn · A · uₙ` with the overlap `uₙ = −gap`;
//!   no tension (`Fn = 0` for an open joint) unless a tensile strength `T` (Pa) is given and
//!   intact, in which case `Fn ≥ −T A`; past it the joint breaks;
//! * shear force, incremental and rotated with the contact plane:
//!   `Fs ← rot(Fs) − Ks · A · Δuₛ`;
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
//! Other closure laws are added as variants of [`NormalClosure`] with their own kernel;
//! the engine calls only [`evaluate`].

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
    /// Normal gap, m (positive open, negative overlap).
    pub gap: f64,
    /// Tangential displacement increment of B relative to A, m, world frame.
    pub du_shear: Vec3,
    /// Tributary area, m².
    pub area: f64,
}

/// Evaluates the joint law: updates `state` and returns the force on B (N, world frame).
#[inline]
pub fn evaluate(p: &JointParams, state: &mut SubContactState, k: &Kinematics) -> Vec3 {
    match p.closure {
        NormalClosure::Linear => coulomb_linear(p, state, k),
    }
}

#[inline]
fn coulomb_linear(p: &JointParams, s: &mut SubContactState, k: &Kinematics) -> Vec3 {
    let n = k.normal;
    // Normal force.
    let fnorm = -p.kn * k.area * k.gap;
    if fnorm < 0.0 {
        if s.bonded && p.tensile_strength > 0.0 && -fnorm <= p.tensile_strength * k.area {
            // Tension carried by an intact joint.
        } else {
            s.bonded = false;
            s.shear = Vec3::zeros();
            s.normal = 0.0;
            s.slipping = false;
            return Vec3::zeros();
        }
    }
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
                    return Vec3::zeros();
                }
            }
            let mag = mag2.sqrt();
            fs *= if mag > 0.0 { limit / mag } else { 0.0 };
            s.slipping = true;
        }
    }
    s.shear = fs;
    s.normal = fnorm;
    n * fnorm + fs
}

/// Elastic energy stored in a sub-contact, J: `Fn²/(2 Kn A) + |Fs|²/(2 Ks A)`.
pub fn stored_energy(p: &JointParams, s: &SubContactState, area: f64) -> f64 {
    if area <= 0.0 {
        return 0.0;
    }
    s.normal * s.normal / (2.0 * p.kn * area) + s.shear.norm_squared() / (2.0 * p.ks * area)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One contract every closure law must meet (statrs `check_continuous_distribution`
    /// style): no force when open and unbonded, compression grows with overlap, shear bounded
    /// by the Coulomb limit, force along n and in the plane only.
    fn check_contact_law(p: JointParams) {
        let n = Vec3::new(0.0, 0.0, 1.0);
        let area = 0.01;
        let mut s = SubContactState::new(false);
        let f = evaluate(&p, &mut s, &Kinematics { normal: n, gap: 1e-4, du_shear: Vec3::x() * 1e-4, area });
        assert_eq!(f, Vec3::zeros());
        let mut last = 0.0;
        for i in 1..10 {
            let mut s = SubContactState::new(false);
            let f = evaluate(&p, &mut s, &Kinematics { normal: n, gap: -1e-5 * i as f64, du_shear: Vec3::zeros(), area });
            assert!(f.z > last);
            last = f.z;
        }
        let mut s = SubContactState::new(false);
        for _ in 0..100 {
            let f = evaluate(&p, &mut s, &Kinematics { normal: n, gap: -1e-4, du_shear: Vec3::x() * 1e-4, area });
            let fs = (f.x * f.x + f.y * f.y).sqrt();
            assert!(fs <= f.z * p.tan_phi * (1.0 + 1e-12) + 1e-12);
            assert!(f.x <= 0.0, "shear force opposes the motion of B");
        }
        assert!(s.slipping);
    }

    #[test]
    fn every_law_meets_the_contract() {
        check_contact_law(JointParams::coulomb(5e7, 2.5e7, 35f64.to_radians(), 0.0, 0.0));
        check_contact_law(JointParams::coulomb(1e9, 1e9, 20f64.to_radians(), 0.0, 0.0));
    }

    #[test]
    fn elastic_shear_matches_ks_a_du() {
        let p = JointParams::coulomb(5e7, 2.5e7, 35f64.to_radians(), 0.0, 0.0);
        let mut s = SubContactState::new(false);
        let f = evaluate(&p, &mut s, &Kinematics { normal: Vec3::z(), gap: -1e-3, du_shear: Vec3::y() * 1e-6, area: 0.02 });
        assert!((f.z - 5e7 * 0.02 * 1e-3).abs() < 1e-9);
        assert!((f.y + 2.5e7 * 0.02 * 1e-6).abs() < 1e-12);
    }

    #[test]
    fn cohesion_and_tension_are_lost_on_failure() {
        let p = JointParams::coulomb(1e8, 1e8, 30f64.to_radians(), 1e4, 1e4);
        let mut s = SubContactState::new(true);
        let area = 0.01;
        // Tension below strength: carried.
        let f = evaluate(&p, &mut s, &Kinematics { normal: Vec3::z(), gap: 5e-7, du_shear: Vec3::zeros(), area });
        assert!((f.z + 1e8 * area * 5e-7).abs() < 1e-9);
        assert!(s.bonded);
        // Beyond strength: broken, zero force, and stays broken.
        let f = evaluate(&p, &mut s, &Kinematics { normal: Vec3::z(), gap: 2e-4, du_shear: Vec3::zeros(), area });
        assert_eq!(f, Vec3::zeros());
        assert!(!s.bonded);
        let f = evaluate(&p, &mut s, &Kinematics { normal: Vec3::z(), gap: 5e-7, du_shear: Vec3::zeros(), area });
        assert_eq!(f, Vec3::zeros());
    }

    #[test]
    fn held_joint_never_slips() {
        let mut p = JointParams::coulomb(1e8, 1e8, 10f64.to_radians(), 0.0, 0.0);
        p.can_slip = false;
        let mut s = SubContactState::new(false);
        let f = evaluate(&p, &mut s, &Kinematics { normal: Vec3::z(), gap: -1e-6, du_shear: Vec3::x() * 1e-3, area: 1.0 });
        assert!((f.x + 1e8 * 1e-3).abs() < 1e-6);
        assert!(!s.slipping);
    }
}
