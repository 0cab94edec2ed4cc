//! The vocabulary of what holds a body's degrees of freedom: [`Hold`] and
//! [`DofConstraint`] (the module [`super::constraint`] says how the engine applies them).

use crate::math::Vec3;

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
}

impl DofConstraint {
    /// No degree of freedom held, anchor at the centroid.
    pub fn free() -> DofConstraint {
        DofConstraint { anchor: Vec3::zeros(), translation: [None; 3], rotation: [false; 3] }
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
