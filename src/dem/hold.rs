//! The vocabulary of what holds a body's degrees of freedom: [`Hold`] and
//! [`DofConstraint`] (the module [`super::constraint`] says how the engine applies them).

use crate::math::Vec3;
use nalgebra::UnitQuaternion;

/// What holds one body ([`super::constraint`]'s doc): the one vocabulary the penalty DEM, the
/// non-smooth solver and limit analysis read for a body's degrees of freedom.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Hold {
    /// Every degree of freedom free (a block of the wall).
    #[default]
    Free,
    /// Every degree of freedom held at the reference pose: the body never moves (the
    /// tilting table's base, a block a layout marks `fixed`).
    Fixed,
    /// Some degrees of freedom held, a translation possibly imposed (a loading beam that a
    /// protocol drives).
    Dof(DofConstraint),
}

impl Hold {
    /// Every degree of freedom held ([`Hold::Fixed`]).
    #[inline]
    pub fn is_fixed(&self) -> bool {
        matches!(self, Hold::Fixed)
    }

    /// The per-degree-of-freedom constraint, if that is what holds the body.
    #[inline]
    pub fn dof(&self) -> Option<&DofConstraint> {
        match self {
            Hold::Dof(c) => Some(c),
            Hold::Free | Hold::Fixed => None,
        }
    }

    /// The per-degree-of-freedom constraint, to move its targets
    /// ([`DofConstraint::set_target`]).
    #[inline]
    pub fn dof_mut(&mut self) -> Option<&mut DofConstraint> {
        match self {
            Hold::Dof(c) => Some(c),
            Hold::Free | Hold::Fixed => None,
        }
    }
}

/// The held degrees of freedom of one body ([`super::constraint`]'s doc). Table frame throughout.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DofConstraint {
    /// The anchor: the body-frame point (m, from the centroid) at which held translations
    /// act.
    pub anchor: Vec3,
    /// Per table axis (x, y, z): the coordinate (m) at which the anchor is held, `None`
    /// where the translation is free.
    pub translation: [Option<f64>; 3],
    /// Per table axis (x, y, z): whether the rotation about it is held.
    pub rotation: [bool; 3],
    /// A moment the rig applies to the body about a free rotation, linear in the body's
    /// motion from a reference pose ([`RigMoment`]); `None`: none.
    pub moment: Option<RigMoment>,
}

/// A moment a test rig applies to a held body about one table axis, linear in the body's
/// motion since a reference pose (table frame, N·m, right-handed about the axis):
///
/// ```text
/// M = m0 + k_u (x_along − x_along,ref) + k_θ θ_axis
/// ```
///
/// `x_along` the centroid's coordinate along table axis `along` (m), `θ_axis` the
/// component about `axis` of the rotation since the reference (rad, the rotation vector of
/// `rot · rot_ref⁻¹`). The in-plane rig's vertical load applied off the beam's centroid is
/// `m0 = e0 P` (eccentricity e0 along x, applied force P downwards) and, when the load's
/// point lags the beam by a share κ of its displacement, `k_u = −κ P`; a partial
/// rotational restraint of the beam is `k_θ = −K_θ` (`loading::inplane`, the module doc).
/// The penalty DEM adds it in its load stage ([`DofConstraint::react`]); a driver of
/// another engine applies [`RigMoment::moment_nm`] as the body's external torque.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigMoment {
    /// The table axis the moment acts about (0 x, 1 y, 2 z).
    pub axis: usize,
    /// The table axis of the displacement the moment follows (0 x, 1 y, 2 z).
    pub along: usize,
    /// `m0`, N·m: the moment at the reference pose.
    pub at_reference_nm: f64,
    /// `k_u`, N·m/m: per metre of the centroid's displacement along `along`.
    pub per_displacement_n: f64,
    /// `k_θ`, N·m/rad: per radian of rotation about `axis` (a spring that resists: < 0).
    pub per_rotation_nm: f64,
    /// The centroid at the reference pose, m.
    pub reference_pos: Vec3,
    /// The orientation at the reference pose.
    pub reference_rot: UnitQuaternion<f64>,
}

impl RigMoment {
    /// The moment on a body at the pose `pos` (its centroid, m), `rot`, N·m about
    /// [`RigMoment::axis`].
    #[inline]
    pub fn moment_nm(&self, pos: &Vec3, rot: &UnitQuaternion<f64>) -> f64 {
        let du = pos[self.along] - self.reference_pos[self.along];
        let theta = if self.per_rotation_nm == 0.0 {
            0.0
        } else {
            (rot * self.reference_rot.inverse()).scaled_axis()[self.axis]
        };
        self.at_reference_nm + self.per_displacement_n * du + self.per_rotation_nm * theta
    }
}

impl DofConstraint {
    /// No degree of freedom held, anchor at the centroid.
    pub fn free() -> DofConstraint {
        DofConstraint { anchor: Vec3::zeros(), translation: [None; 3], rotation: [false; 3], moment: None }
    }

    /// Holds the rotation about table axis `axis` (0 x, 1 y, 2 z).
    ///
    /// # Panics
    /// If `axis > 2`.
    pub fn hold_rotation(mut self, axis: usize) -> DofConstraint {
        self.rotation[axis] = true;
        self
    }

    /// Moves the target of a held translation (an imposed displacement), m. A free axis
    /// stays free.
    pub fn set_target(&mut self, axis: usize, value: f64) {
        if self.translation[axis].is_some() {
            self.translation[axis] = Some(value);
        }
    }

    /// Zeroes the held components of a velocity `v` and an angular velocity `w`.
    #[inline]
    pub fn hold_velocities(&self, v: &mut Vec3, w: &mut Vec3) {
        for i in 0..3 {
            if self.translation[i].is_some() {
                v[i] = 0.0;
            }
            if self.rotation[i] {
                w[i] = 0.0;
            }
        }
    }
}
