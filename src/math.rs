//! The vector and matrix types of the whole crate (nalgebra, f64): the ground floor every
//! layer imports them from (`use crate::math::Vec3`), so that no module points up to the
//! crate root.

/// 3-vector of f64 (nalgebra): positions (m), forces (N), moments (N·m) in the table frame
/// unless a doc says otherwise.
pub type Vec3 = nalgebra::Vector3<f64>;
/// 3×3 matrix of f64 (nalgebra): inertia tensors (kg·m²), rotation matrices, frames.
pub type Mat3 = nalgebra::Matrix3<f64>;
