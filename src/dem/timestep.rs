//! Critical time step of the explicit scheme.
//!
//! For each free body, the stiffness of all its sub-contact springs (open or closed; normal
//! Kn·A/3 and two shear Ks·A/3 per node) is assembled into the body's 6 × 6 stiffness
//! `K = Σ k g gᵀ` with the generalized direction `g = (d, r × d)` of a spring of direction
//! `d` at arm `r`, and its largest generalized eigenvalue against the mass matrix
//! `diag(m, m, m, I)` gives the body's highest frequency with its neighbours held. Motion of
//! the neighbours at most doubles `ω²` (each spring joins two bodies), so
//! `ω_max² ≤ 2 max_body λ_max(M^{-1/2} K M^{-1/2})`, and the step is
//! `Δt = safety × 2 / ω_max` (central differences are stable for `Δt < 2/ω_max`).
//! The default safety factor 0.8 (of a bound that already doubles the single-body ω²)
//! leaves room for the stiffening of contacts between detections.

use super::engine::Contact;
use super::state::Body;
use crate::Vec3;
use nalgebra::{Matrix3, Matrix6, Vector6};

fn add_spring(k6: &mut Matrix6<f64>, k: f64, d: &Vec3, r: &Vec3) {
    let m = r.cross(d);
    let g = Vector6::new(d.x, d.y, d.z, m.x, m.y, m.z);
    *k6 += g * g.transpose() * k;
}

fn tangents(n: &Vec3) -> (Vec3, Vec3) {
    crate::geometry::polygon::plane_basis(n)
}

/// `I^{-1/2}` of a symmetric positive-definite inertia tensor.
pub fn inv_sqrt(i: &Matrix3<f64>) -> Matrix3<f64> {
    let e = i.symmetric_eigen();
    let d = Matrix3::from_diagonal(&e.eigenvalues.map(|v| if v > 0.0 { 1.0 / v.sqrt() } else { 0.0 }));
    e.eigenvectors * d * e.eigenvectors.transpose()
}

/// The largest eigenvalue `λ = ω²` (rad²/s²) of each body's 6 × 6 stiffness against its true
/// mass matrix, with its neighbours held; 0 for fixed bodies and bodies without contacts.
pub fn body_eigenvalues(bodies: &[Body], contacts: &[Contact]) -> Vec<f64> {
    let n = bodies.len();
    let mut k6 = vec![Matrix6::<f64>::zeros(); n];
    let mut touched = vec![false; n];
    for c in contacts {
        let (kn, ks) = (c.joint.kn, c.joint.ks);
        for s in &c.subs {
            let a3 = s.area / 3.0;
            for &i in &s.nodes {
                let nd = &c.nodes[i as usize];
                let mut sides: [(Option<usize>, Vec3, Vec3); 2] = [(None, Vec3::zeros(), Vec3::zeros()); 2];
                if let Some(a) = c.a {
                    sides[0] = (Some(a), nd.on_a, c.normal_a);
                }
                sides[1] = (Some(c.b), nd.on_b, c.normal_b);
                for (body, r, nrm) in sides {
                    let Some(b) = body else { continue };
                    let (t1, t2) = tangents(&nrm);
                    add_spring(&mut k6[b], kn * a3, &nrm, &r);
                    add_spring(&mut k6[b], ks * a3, &t1, &r);
                    add_spring(&mut k6[b], ks * a3, &t2, &r);
                    touched[b] = true;
                }
            }
        }
    }
    let mut out = vec![0.0; n];
    for (i, b) in bodies.iter().enumerate() {
        if b.fixed || !touched[i] {
            continue;
        }
        let mut s = Matrix6::<f64>::zeros();
        let ms = 1.0 / b.mass.sqrt();
        for k in 0..3 {
            s[(k, k)] = ms;
        }
        s.fixed_view_mut::<3, 3>(3, 3).copy_from(&inv_sqrt(&b.inertia));
        let a = s * k6[i] * s;
        out[i] = a.symmetric_eigenvalues().iter().cloned().fold(0.0, f64::max);
    }
    out
}

/// The stable time step, s, for the eigenvalue `λ` of the stiffest (scaled) body:
/// `safety × 2 / √(2λ)`; `None` if `λ` is 0.
pub fn step_for(lambda: f64, safety: f64) -> Option<f64> {
    (lambda > 0.0).then(|| safety * 2.0 / (2.0 * lambda).sqrt())
}

/// Density scaling for static solutions (3DEC's density scaling; Itasca 3DEC manual,
/// "static analysis"; Underwood's dynamic relaxation): every body in contact gets its
/// inertial mass and inertia multiplied by `s = λ/λ_target` so that all of them have the same
/// critical step, the one of the target `λ_target` = the median of the bodies' eigenvalues.
/// Stiff bodies (small wedges, slivers) get `s > 1` and no longer limit the step; soft ones
/// (large stones on few contacts) get `s < 1` and no longer lag behind: the scaled system is
/// the Jacobi-preconditioned one, whose slowest mode converges in the fewest steps. Bodies
/// without contacts keep `s = 1`. Returns the target and the factors. Equilibrium states do
/// not depend on inertia; only the path to them does.
pub fn density_scaling(lambdas: &[f64]) -> (f64, Vec<f64>) {
    let mut v: Vec<f64> = lambdas.iter().copied().filter(|l| *l > 0.0).collect();
    if v.is_empty() {
        return (0.0, vec![1.0; lambdas.len()]);
    }
    v.sort_by(f64::total_cmp);
    let target = v[(v.len() - 1) / 2];
    (target, lambdas.iter().map(|&l| if l > 0.0 { l / target } else { 1.0 }).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_spring_frequency_is_recovered() {
        // A mass on one normal spring through its centroid: λ = k/m exactly.
        let mut k6 = Matrix6::zeros();
        add_spring(&mut k6, 100.0, &Vec3::z(), &Vec3::zeros());
        let m: f64 = 4.0;
        let s = Matrix6::from_diagonal(&Vector6::new(1.0 / m.sqrt(), 1.0 / m.sqrt(), 1.0 / m.sqrt(), 1.0, 1.0, 1.0));
        let l = (s * k6 * s).symmetric_eigenvalues().iter().cloned().fold(0.0, f64::max);
        assert!((l - 25.0).abs() < 1e-12);
        let i = Matrix3::from_diagonal(&Vec3::new(4.0, 9.0, 16.0));
        let r = inv_sqrt(&i);
        assert!((r[(1, 1)] - 1.0 / 3.0).abs() < 1e-14);
    }
}
