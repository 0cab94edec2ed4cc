//! Shear and slip sub-model: the incremental elastic shear spring with a Coulomb limit.
//!
//! `Fs ← rot(Fs) − Ks A Δuₛ` (N; Ks in Pa/m, A in m², Δuₛ in m), the stored force first
//! rotated into the current contact plane with its magnitude kept (Cundall & Strack 1979;
//! 3DEC's Coulomb slip joint, Itasca 3DEC manual). Slip: `|Fs| ≤ c A + Fn tan φ`; past it
//! `Fs` is scaled back onto the limit (elasto-plastic). A shear failure of an intact joint
//! leaves residual strength only (`c = 0`), for good.

use super::SubContactState;
use crate::math::Vec3;

/// Parameters of the shear/slip sub-model (plain data).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipParams {
    /// Shear stiffness Ks, Pa/m.
    pub ks: f64,
    /// tan φ of the friction angle φ.
    pub tan_phi: f64,
    /// Cohesion c while the joint is intact, Pa.
    pub cohesion: f64,
    /// False for a joint held against slip (the base course's restraint): its shear spring
    /// stays elastic whatever the force.
    pub can_slip: bool,
}

/// What the shear kernel returns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shear {
    /// The shear force on B (N, world frame, in the contact plane) and the mobilised
    /// fraction of the strength `|Fs| / (c A + Fn tan φ)` in [0, 1] (0 for a held joint).
    Force(Vec3, f64),
    /// An intact joint in tension failed in shear: the sub-contact carries nothing.
    Lost,
}

/// The shear kernel: updates the stored shear force, `slipping` and `bonded` in `s` from
/// the unit normal `n` (A → B), the shear displacement increment `du` of B relative to A
/// (m), the area (m²) and the normal force `fnorm` (N, compression positive).
#[inline(always)]
pub fn shear(p: &SlipParams, s: &mut SubContactState, n: Vec3, du: Vec3, area: f64, fnorm: f64) -> Shear {
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
    fs -= du * (p.ks * area);
    s.slipping = false;
    s.return_scale = 1.0;
    let mut mobilised = 0.0;
    if p.can_slip {
        let cohesion = if s.bonded { p.cohesion * area } else { 0.0 };
        let mut limit = cohesion + fnorm.max(0.0) * p.tan_phi;
        let mag2 = fs.norm_squared();
        if mag2 > limit * limit {
            if s.bonded {
                // Shear failure of an intact joint: residual strength only.
                s.bonded = false;
                limit = fnorm.max(0.0) * p.tan_phi;
                if fnorm < 0.0 {
                    return Shear::Lost;
                }
            }
            let mag = mag2.sqrt();
            let scale = if mag > 0.0 { limit / mag } else { 0.0 };
            fs *= scale;
            s.slipping = true;
            s.return_scale = scale;
        }
        mobilised = if s.slipping || limit <= 0.0 { 1.0 } else { (mag2.sqrt() / limit).min(1.0) };
    }
    Shear::Force(fs, mobilised)
}

/// Elastic energy stored in the shear spring of a sub-contact, J: `|Fs|² / (2 Ks A)`.
pub fn energy(p: &SlipParams, s: &SubContactState, area: f64) -> f64 {
    if area <= 0.0 {
        return 0.0;
    }
    s.shear.norm_squared() / (2.0 * p.ks * area)
}
