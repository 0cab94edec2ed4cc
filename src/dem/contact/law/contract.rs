//! The contract every joint law must meet, public so that the tests of the crate and of its
//! users run it over every law (in the manner of statrs' `check_continuous_distribution`).
//!
//! [`check_contact_law`] panics with a message naming the violated property:
//! * an open, unbonded sub-contact carries nothing;
//! * a uniform closure `u` over a sub-contact of area `A` gives `Fn = q(u) A` along `n`,
//!   applied at the centroid;
//! * the normal force never falls as the closure grows, with a tangent stiffness never above the
//!   law's [`super::JointParams::kn_bound`] (the time step depends on it), nor, within a
//!   tangent window ([`crate::closure::ClosureLaw::tangent_window`]), above the window's
//!   bound, which never exceeds the law's;
//! * the stored normal energy is the work of the normal force (`dE/du = Fn`);
//! * the shear force opposes the motion, never exceeds `c A + Fn tan φ`, and reaches slip.

use super::{evaluate, normal_energy, JointParams, Kinematics, Quadrature, SubContactState};
use crate::closure::{Closure, Crushing, Hyperbolic, Seating};
use crate::math::Vec3;

const AREA: f64 = 0.01;

fn uniform(p: &JointParams, quad: Quadrature, s: &mut SubContactState, u: f64, du: Vec3) -> super::SubContactForce {
    evaluate(p, quad, s, &Kinematics { normal: Vec3::z(), gaps: [-u; 3], du_shear: du, area: AREA })
}

/// One joint per normal closure law, with the paper's shale joint stiffness (Kn 5e7 Pa/m,
/// Ks = Kn/2, φ 35°): the laws the contract is run over. Adding a [`Closure`] variant
/// fails to compile here until it is listed.
pub fn representative_laws() -> Vec<JointParams> {
    let base = JointParams::coulomb(5e7, 2.5e7, 35f64.to_radians(), 0.0, 0.0);
    let laws = [
        Closure::Linear,
        Closure::Hyperbolic(Hyperbolic { max_closure_m: 1e-3 }),
        Closure::Seating(Seating { max_gap_m: 2e-4 }),
        // Its kink (fc / Kn = 0.22 mm) between the contract's sample closures, where the
        // energy's central difference is exact.
        Closure::Crushing(Crushing { strength_pa: 1.1e4 }),
    ];
    for l in laws {
        match l {
            Closure::Linear | Closure::Hyperbolic(_) | Closure::Seating(_) | Closure::Crushing(_) => {}
        }
    }
    laws.iter().map(|&c| base.with_closure(c)).collect()
}

/// A tangent window taken at the closure `u0` (m) bounds the law's tangent from any
/// closure up to `u0` to the window's cap (sampled, with the cap far out read as the
/// contract's range `[u0, 20 scale]`), and its bound is never above the law's.
fn check_windows_cover(p: &JointParams, u0: f64, scale: f64) {
    let np = p.normal();
    let Some((cap, k)) = p.closure.tangent_window(p.kn, u0) else {
        return;
    };
    assert!(cap > u0.max(0.0), "{p:?}: the window at {u0:e} m ends at {cap:e} m, not past it");
    assert!(k <= p.kn_bound() * (1.0 + 1e-12), "{p:?}: the window's bound {k:e} above the law's");
    let hi = cap.min(u0.max(0.0) + 20.0 * scale);
    for j in 0..=50 {
        let u = u0.min(0.0) + (hi - u0.min(0.0)) * j as f64 / 50.0;
        assert!(
            np.tangent(u) <= k * (1.0 + 1e-9),
            "{p:?}: the window taken at {u0:e} m bounds the tangent by {k:e} Pa/m, but it is {:e} at {u:e} m",
            np.tangent(u)
        );
    }
}

/// Checks the contract on `p` with both quadratures; panics naming the property violated.
/// `scale` is a closure (m) of the order the law is meant for (e.g. 1e-4).
pub fn check_contact_law(p: &JointParams, scale: f64) {
    for quad in [Quadrature::Exact, Quadrature::Vertex] {
        let mut s = SubContactState::new(false);
        let f = uniform(p, quad, &mut s, -scale, Vec3::x() * scale).force;
        assert_eq!(f, Vec3::zeros(), "{p:?}: an open, unbonded sub-contact carries a force");

        let np = p.normal();
        let mut last = 0.0;
        for i in 1..=20 {
            let u = scale * i as f64 / 4.0;
            let mut s = SubContactState::new(false);
            let out = uniform(p, quad, &mut s, u, Vec3::zeros());
            let expect = np.pressure(u) * AREA;
            assert!(
                (out.force.z - expect).abs() <= 1e-9 * expect.abs(),
                "{p:?} {quad:?}: uniform closure {u:e} m gives Fn {} N, not q(u) A = {expect} N",
                out.force.z
            );
            assert!(out.force.z >= last, "{p:?}: the normal force falls as the closure grows at {u:e} m");
            assert!(out.at.iter().all(|&b| (b - 1.0 / 3.0).abs() < 1e-9), "{p:?}: uniform pressure off-centre");
            last = out.force.z;
            // Tangent stiffness against the bound, and the energy against the work.
            let h = scale * 1e-4;
            let q1 = np.pressure(u + h);
            let q0 = np.pressure(u - h);
            let tangent = (q1 - q0) / (2.0 * h);
            assert!(tangent <= p.kn_bound() * (1.0 + 1e-6), "{p:?}: tangent {tangent:e} above the bound at {u:e} m");
            check_windows_cover(p, u, scale);
            if quad == Quadrature::Exact {
                let e1 = normal_energy(p, [-(u + h); 3], AREA);
                let e0 = normal_energy(p, [-(u - h); 3], AREA);
                let work = (e1 - e0) / (2.0 * h);
                assert!(
                    (work - expect).abs() <= 1e-5 * expect,
                    "{p:?}: dE/du = {work} N is not the normal force {expect} N at {u:e} m"
                );
            }
        }

        let mut s = SubContactState::new(false);
        for _ in 0..100 {
            let f = uniform(p, quad, &mut s, scale, Vec3::x() * scale).force;
            let fs = (f.x * f.x + f.y * f.y).sqrt();
            assert!(fs <= f.z * p.tan_phi * (1.0 + 1e-12) + 1e-12, "{p:?}: shear above the Coulomb limit");
            assert!(f.x <= 0.0, "{p:?}: the shear force does not oppose the motion of B");
        }
        assert!(!p.can_slip || s.slipping, "{p:?}: the joint never reaches slip");
    }
}
