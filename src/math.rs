//! The vector and matrix types of the whole crate (nalgebra, f64): the ground floor every
//! layer imports them from (`use crate::math::Vec3`), so that no module points up to the
//! crate root.

/// 3-vector of f64 (nalgebra): positions (m), forces (N), moments (N·m) in the table frame
/// unless a doc says otherwise.
pub type Vec3 = nalgebra::Vector3<f64>;
/// 3×3 matrix of f64 (nalgebra): inertia tensors (kg·m²), rotation matrices, frames.
pub type Mat3 = nalgebra::Matrix3<f64>;

/// `I^{-1/2}` of a symmetric positive-semidefinite 3 × 3 tensor (an inertia, kg·m²: the
/// result in kg^{-1/2}·m^{-1}), by its eigen-decomposition; a zero or negative eigenvalue
/// gives 0 on its axis.
pub fn inv_sqrt(i: &Mat3) -> Mat3 {
    let e = i.symmetric_eigen();
    let d = Mat3::from_diagonal(&e.eigenvalues.map(|v| if v > 0.0 { 1.0 / v.sqrt() } else { 0.0 }));
    e.eigenvectors * d * e.eigenvectors.transpose()
}
