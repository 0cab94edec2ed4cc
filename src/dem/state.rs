//! Rigid bodies: mass properties, pose and velocities.

use super::hold::Hold;
use crate::geometry::ConvexBlock;
use crate::math::{Mat3, Vec3};
use nalgebra::UnitQuaternion;

/// A 6 × 6 inertial mass matrix `M = Q diag(λ) Qᵀ` (dofs: translation in m, then rotation
/// in rad; table frame), kept as its eigenvectors `q` (columns, orthonormal) and the
/// reciprocals of its eigenvalues `inv_lambda` (1/kg and 1/(kg·m²) mixed along `q`).
#[derive(Debug, Clone, PartialEq)]
pub struct BlockMass {
    /// Eigenvectors of M, columns.
    pub q: nalgebra::Matrix6<f64>,
    /// 1/λ for each eigenvalue λ > 0 of M.
    pub inv_lambda: nalgebra::Vector6<f64>,
}

/// One rigid block.
///
/// Pose: `x_world = pos + rot · x_body` (body frame: origin at the centroid, axes parallel
/// to the table frame in the reference configuration). Velocities are at the half step of
/// the central-difference scheme.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Id from the layout.
    pub id: String,
    /// Geometry in the body frame, m.
    pub shape: ConvexBlock,
    /// Mass, kg.
    pub mass: f64,
    /// Inertia tensor about the centroid in the body frame, kg·m².
    pub inertia: Mat3,
    /// Inverse of `inertia`.
    pub inv_inertia: Mat3,
    /// `inertia^{-1/2}` (body frame, kg^{-1/2}·m^{-1}), kept for the time step's mass roots
    /// ([`crate::math::inv_sqrt`] of `inertia`, computed once).
    pub inv_sqrt_inertia: Mat3,
    /// Smallest principal moment of inertia, kg·m².
    pub min_inertia: f64,
    /// Distance from the centroid to the farthest vertex, m.
    pub radius: f64,
    /// What holds the body ([`Hold`]): free, fixed (never moves) or constrained per degree
    /// of freedom. Built [`Hold::Fixed`] for a block the layout marks `fixed`, else
    /// [`Hold::Free`]; a protocol sets a [`Hold::Dof`].
    pub hold: Hold,
    /// Index of the block's material in the layout.
    pub material: usize,
    /// 1/s for the density scaling factor s > 0 of the inertial mass and inertia (1: none).
    pub inertia_scale_inv: f64,
    /// Block density scaling (`DensityScaling::Block`): the body's 6 × 6 inertial mass
    /// matrix in the table frame, replacing `s m` and `s I` while set.
    pub block_mass: Option<BlockMass>,
    /// Centroid position, table frame, m.
    pub pos: Vec3,
    /// Orientation (body → table frame).
    pub rot: UnitQuaternion<f64>,
    /// `rot` as a matrix, refreshed after every rotation update.
    pub rot_mat: Mat3,
    /// Velocity of the centroid, m/s.
    pub vel: Vec3,
    /// Angular velocity, rad/s, table frame.
    pub angvel: Vec3,
    /// Centroid in the reference configuration, m.
    pub pos0: Vec3,
}

/// The bodies of every block of a checked layout, in layout order, at rest in their
/// reference configuration (the model state's and the non-smooth solver's bodies).
pub fn bodies_of(layout: &crate::layout::Layout) -> Vec<Body> {
    layout
        .blocks
        .iter()
        .map(|b| {
            let mp = b.mass_properties(layout.materials[b.material].density);
            Body::with_mass(b.id.clone(), &b.shape, mp, b.material, b.fixed)
        })
        .collect()
}

impl Body {
    /// Never moves: every degree of freedom held ([`Hold::Fixed`]).
    #[inline]
    pub fn fixed(&self) -> bool {
        self.hold.is_fixed()
    }

    /// A body at rest in its reference configuration from a block given in the table frame,
    /// homogeneous of `density` (kg/m³): its mass properties are its shape's.
    pub fn new(id: String, shape_world: &ConvexBlock, density: f64, material: usize, fixed: bool) -> Body {
        Body::with_mass(id, shape_world, shape_world.mass_properties(density), material, fixed)
    }

    /// A body at rest in its reference configuration from a block given in the table frame
    /// (its contact geometry) with the mass properties `mp` (table frame: mass kg, centroid
    /// m, inertia kg·m² about the centroid; [`crate::layout::Block::mass_properties`], which
    /// may be a scanned stone's own rather than its hull's). The body frame's origin is
    /// `mp.centroid`.
    pub fn with_mass(
        id: String,
        shape_world: &ConvexBlock,
        mp: crate::geometry::MassProperties,
        material: usize,
        fixed: bool,
    ) -> Body {
        let c = mp.centroid;
        let shape = shape_world.transformed(|v| v - c, &Mat3::identity());
        let radius = shape.vertices.iter().map(|v| v.norm()).fold(0.0, f64::max);
        let inv_inertia = mp.inertia.try_inverse().unwrap_or_else(Mat3::zeros);
        let min_inertia = mp.inertia.symmetric_eigenvalues().iter().cloned().fold(f64::INFINITY, f64::min);
        Body {
            id,
            shape,
            mass: mp.mass,
            inertia: mp.inertia,
            inv_inertia,
            inv_sqrt_inertia: crate::math::inv_sqrt(&mp.inertia),
            min_inertia,
            radius,
            hold: if fixed { Hold::Fixed } else { Hold::Free },
            material,
            inertia_scale_inv: 1.0,
            block_mass: None,
            pos: c,
            rot: UnitQuaternion::identity(),
            rot_mat: Mat3::identity(),
            vel: Vec3::zeros(),
            angvel: Vec3::zeros(),
            pos0: c,
        }
    }

    /// Turns the body by the rotation vector `phi` (rad, table frame: `q ← exp(φ) q`, see
    /// [`rotation_increment`]) and refreshes `rot_mat`.
    #[inline(always)]
    pub fn rotate(&mut self, phi: Vec3) {
        self.rot = rotation_increment(phi) * self.rot;
        self.rot.renormalize_fast();
        self.rot_mat = *self.rot.to_rotation_matrix().matrix();
    }

    /// A body-frame point in the table frame.
    #[inline]
    pub fn to_world(&self, p: &Vec3) -> Vec3 {
        self.pos + self.rot_mat * p
    }

    /// A table-frame point in the body frame.
    #[inline]
    pub fn to_body(&self, x: &Vec3) -> Vec3 {
        self.rot_mat.transpose() * (x - self.pos)
    }

    /// The block's geometry at its current pose, table frame.
    pub fn world_shape(&self) -> ConvexBlock {
        let r = self.rot_mat;
        let p = self.pos;
        self.shape.transformed(|v| p + r * v, &r)
    }

    /// Kinetic energy, J.
    pub fn kinetic_energy(&self) -> f64 {
        let iw = self.rot_mat * self.inertia * self.rot_mat.transpose();
        0.5 * self.mass * self.vel.norm_squared() + 0.5 * self.angvel.dot(&(iw * self.angvel))
    }
}

/// The unit quaternion of the rotation vector `phi` (rad): `(cos(θ/2), sin(θ/2) φ/θ)` with
/// `θ = |φ|`. The rotation of one step is tiny (θ ~ 1e-6), so below θ = 1e-3 the two
/// factors come from their Taylor series in θ², to four terms: the first omitted terms are
/// θ⁸/10321920 and θ⁸/185794560 relative, below 1e-30, far under the rounding of the result
/// (this also avoids a square root and a call to `sincos` per body and step). Larger
/// rotations use `UnitQuaternion::from_scaled_axis`.
#[inline]
pub fn rotation_increment(phi: Vec3) -> UnitQuaternion<f64> {
    let t2 = phi.norm_squared();
    if t2 < 1e-6 {
        // cos(θ/2) = 1 − θ²/8 + θ⁴/384 − θ⁶/46080; sin(θ/2)/θ = 1/2 − θ²/48 + θ⁴/3840 − θ⁶/645120.
        let c = 1.0 - t2 * (1.0 / 8.0 - t2 * (1.0 / 384.0 - t2 * (1.0 / 46080.0)));
        let s = 0.5 - t2 * (1.0 / 48.0 - t2 * (1.0 / 3840.0 - t2 * (1.0 / 645120.0)));
        UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(c, s * phi.x, s * phi.y, s * phi.z))
    } else {
        UnitQuaternion::from_scaled_axis(phi)
    }
}
