//! The local 3D Coulomb problem of one contact point.
//!
//! Given the point's Delassus block W (3 × 3, symmetric positive definite, s/kg) and the
//! velocity the point would have without its own impulse, `q` (local frame (n, t₁, t₂),
//! m/s, Signorini's term b already added to qₙ), find the impulse r with `u = W r + q`:
//!
//! ```text
//! uₙ ≥ 0, rₙ ≥ 0, uₙ rₙ = 0;   ‖r_t‖ ≤ μ rₙ;   u_t ≠ 0 ⇒ r_t = −μ rₙ u_t / ‖u_t‖
//! ```
//!
//! (Signorini–Coulomb in velocity form; Jean 1999, §4; Acary & Brogliato 2008, §12.3).
//! Solved by cases, exactly:
//!
//! 1. **separation**: `qₙ ≥ 0` — r = 0 is a solution;
//! 2. **stick**: `r = −W⁻¹ q` (u = 0) if it lies in the Coulomb cone;
//! 3. **slip**: `uₙ = 0`, `‖r_t‖ = μ rₙ`, `u_t = −ν r_t` with ν ≥ 0 (slip opposite to the
//!    friction). Eliminating rₙ by `uₙ = 0` leaves `r_t = −(Ŵ + ν I)⁻¹ q̂` (Ŵ the Schur
//!    complement of Wₙₙ, q̂ the reduced free velocity), and ν is the root of the scalar
//!    equation `‖r_t(ν)‖ = μ rₙ(ν)`, found by Newton's method safeguarded on a bracket (as
//!    the trust-region secular equation of Moré & Sorensen 1983).
//!
//! Should the slip iteration not settle (a strongly coupled W), De Saxcé's fixed point on
//! the bipotential, `r ← proj_K(r − ρ (u + μ ‖u_t‖ n))` with `ρ = 1/tr W` (De Saxcé &
//! Feng 1998), finishes the job from the slip iterate.

use crate::math::{Mat3, Vec3};

/// Relative tolerance of the local iterations.
const LOCAL_TOL: f64 = 1e-13;

/// The impulse solving the local problem (see the module doc).
#[inline]
pub fn solve(w: &Mat3, w_inv: &Mat3, q: &Vec3, mu: f64) -> Vec3 {
    solve_from(w, w_inv, q, mu, &mut 0.0)
}

/// As [`solve`], with `nu` the slip multiplier ν to start the slip case's Newton iteration
/// from (≥ 0, s/kg; 0: from the stick solution), set to the root found when the point
/// slips. The answer is the same root to the local tolerance from any start: the
/// multiplier of the same point at the previous sweep only saves Newton iterations.
#[inline]
pub fn solve_from(w: &Mat3, w_inv: &Mat3, q: &Vec3, mu: f64, nu: &mut f64) -> Vec3 {
    if q.x >= 0.0 {
        return Vec3::zeros();
    }
    let stick = -(w_inv * q);
    if stick.x > 0.0 && stick.y * stick.y + stick.z * stick.z <= mu * mu * stick.x * stick.x {
        return stick;
    }
    slip(w, q, mu, nu).unwrap_or_else(|| de_saxce(w, q, mu, stick))
}

/// The slip case; `None` if W is not positive definite or no root is found.
///
/// With `uₙ = 0`, `rₙ = r̂ₙ − c · r_t` (`r̂ₙ = −qₙ/Wₙₙ`, `c = W_nt/Wₙₙ`), and the tangential
/// velocity is `u_t = Ŵ r_t + q̂` with the Schur complement `Ŵ = W_tt − W_tn W_nt/Wₙₙ`
/// and `q̂ = q_t − W_tn qₙ/Wₙₙ`. Slip opposite to the friction, `u_t = −ν r_t` (ν ≥ 0),
/// gives `r_t(ν) = −(Ŵ + ν I)⁻¹ q̂`, and ν is the root of
/// `F(ν) = ‖r_t(ν)‖ − μ rₙ(ν)`: `F(0) > 0` (the stick impulse is outside the cone) and
/// `F(∞) = −μ r̂ₙ < 0`. Newton from `start` (0 if not positive), safeguarded on a bracket
/// `[lo, hi]` with `F(lo) > 0 ≥ F(hi)`: the upper end is found by doubling when Newton
/// does not give one; bisection when a Newton step leaves the bracket.
fn slip(w: &Mat3, q: &Vec3, mu: f64, start: &mut f64) -> Option<Vec3> {
    let wnn = w[(0, 0)];
    if wnn.is_nan() || wnn <= 0.0 {
        return None;
    }
    let rn_hat = -q.x / wnn;
    let c = [w[(0, 1)] / wnn, w[(0, 2)] / wnn];
    let (p, r, s) = (
        w[(1, 1)] - w[(1, 0)] * c[0],
        0.5 * (w[(1, 2)] - w[(1, 0)] * c[1] + w[(2, 1)] - w[(2, 0)] * c[0]),
        w[(2, 2)] - w[(2, 0)] * c[1],
    );
    let qh = [q.y + w[(1, 0)] * rn_hat, q.z + w[(2, 0)] * rn_hat];
    // Ŵ positive definite (a 2 × 2 Schur complement of an SPD matrix, unless rounding).
    if !(p > 0.0 && p * s - r * r > 0.0) {
        return None;
    }
    // F and F' at ν: x = r_t(ν) = −(Ŵ + ν I)⁻¹ q̂, dx/dν = −(Ŵ + ν I)⁻¹ x.
    let eval = |nu: f64| {
        let (a, d) = (p + nu, s + nu);
        let inv_det = 1.0 / (a * d - r * r);
        let solve = |b: [f64; 2]| [(d * b[0] - r * b[1]) * inv_det, (a * b[1] - r * b[0]) * inv_det];
        let x = solve([-qh[0], -qh[1]]);
        let dx = solve([-x[0], -x[1]]);
        let norm = (x[0] * x[0] + x[1] * x[1]).sqrt();
        let rn = rn_hat - (c[0] * x[0] + c[1] * x[1]);
        let f = norm - mu * rn;
        let dnorm = if norm > 0.0 { (x[0] * dx[0] + x[1] * dx[1]) / norm } else { 0.0 };
        let df = dnorm + mu * (c[0] * dx[0] + c[1] * dx[1]);
        (f, df, x, rn)
    };
    let l1 = (p.max(s) + r.abs()).max(1e-300);
    let scale = rn_hat * mu.max(1e-3);
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    let mut nu = if *start > 0.0 && start.is_finite() { *start } else { 0.0 };
    let mut at = eval(nu);
    for _ in 0..400 {
        let (f, df, ..) = at;
        if f.abs() <= LOCAL_TOL * scale {
            break;
        }
        if f > 0.0 {
            lo = nu;
        } else {
            hi = nu;
        }
        let newton = nu - f / df;
        nu = if df != 0.0 && newton > lo && newton < hi {
            newton
        } else if hi.is_finite() {
            0.5 * (lo + hi)
        } else {
            (2.0 * lo).max(l1)
        };
        if hi.is_finite() && hi - lo <= LOCAL_TOL * hi {
            at = eval(nu);
            break;
        }
        at = eval(nu);
    }
    let (_, _, x, rn) = at;
    if !(rn > 0.0) || !x[0].is_finite() || !x[1].is_finite() {
        return None;
    }
    *start = nu;
    Some(Vec3::new(rn, x[0], x[1]))
}

/// Projection onto the Coulomb cone `‖r_t‖ ≤ μ rₙ`.
#[inline]
pub fn project(r: &Vec3, mu: f64) -> Vec3 {
    let t = (r.y * r.y + r.z * r.z).sqrt();
    if t <= mu * r.x {
        *r
    } else if mu * t <= -r.x {
        Vec3::zeros()
    } else {
        let rn = (r.x + mu * t) / (1.0 + mu * mu);
        Vec3::new(rn, mu * rn * r.y / t, mu * rn * r.z / t)
    }
}

/// De Saxcé's projection iteration from `r`.
fn de_saxce(w: &Mat3, q: &Vec3, mu: f64, start: Vec3) -> Vec3 {
    let rho = 1.0 / w.trace();
    let mut r = project(&start, mu);
    for _ in 0..2_000 {
        let u = w * r + q;
        let ut = (u.y * u.y + u.z * u.z).sqrt();
        let next = project(&(r - rho * Vec3::new(u.x + mu * ut, u.y, u.z)), mu);
        let change = (next - r).norm();
        r = next;
        if change <= LOCAL_TOL * r.norm() {
            break;
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The residual of the Signorini–Coulomb conditions at (r, u), relative.
    fn residual(r: &Vec3, u: &Vec3, q: &Vec3, mu: f64) -> f64 {
        let scale = r.norm().max(1e-300);
        let uscale = q.norm().max(1e-300);
        let cone = (r.y.hypot(r.z) - mu * r.x).max(0.0) / scale;
        let sign = (-r.x).max(0.0) / scale + (-u.x).max(0.0) / uscale;
        let comp = (r.x * u.x).abs() / (scale * uscale);
        let ut = u.y.hypot(u.z);
        let slip = if ut > 1e-12 * uscale {
            let want = Vec3::new(r.x, -mu * r.x * u.y / ut, -mu * r.x * u.z / ut);
            (want - r).norm() / scale
        } else {
            0.0
        };
        cone + sign + comp + slip
    }

    /// A deterministic pseudo-random number in [-1, 1).
    fn lcg(s: &mut u64) -> f64 {
        *s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// Over random SPD blocks, free velocities and friction coefficients, the solution
    /// satisfies the Signorini–Coulomb conditions to rounding, in each case met.
    #[test]
    fn the_local_solution_satisfies_signorini_and_coulomb() {
        let mut s = 7u64;
        let mut cases = [0usize; 3];
        for _ in 0..5000 {
            let a = Mat3::from_fn(|_, _| lcg(&mut s));
            let w = a * a.transpose() + Mat3::identity() * (0.05 + lcg(&mut s).abs());
            let q = Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s));
            let mu = 0.05 + 1.5 * lcg(&mut s).abs();
            let r = solve(&w, &w.try_inverse().unwrap(), &q, mu);
            let u = w * r + q;
            let res = residual(&r, &u, &q, mu);
            assert!(res < 1e-9, "w {w} q {q} mu {mu}: r {r} u {u} residual {res}");
            let k = if r.x == 0.0 {
                0
            } else if u.norm() < 1e-12 * q.norm() {
                1
            } else {
                2
            };
            cases[k] += 1;
        }
        assert!(cases.iter().all(|&c| c > 200), "{cases:?}");
    }

    /// The slip solve started from any multiplier finds the root it finds from the stick
    /// solution, to the local tolerance, and reports that multiplier.
    #[test]
    fn the_slip_root_does_not_depend_on_the_start() {
        let mut s = 11u64;
        let mut slips = 0;
        for _ in 0..5000 {
            let a = Mat3::from_fn(|_, _| lcg(&mut s));
            let w = a * a.transpose() + Mat3::identity() * (0.05 + lcg(&mut s).abs());
            let w_inv = w.try_inverse().unwrap();
            let q = Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s));
            let mu = 0.05 + 1.5 * lcg(&mut s).abs();
            let mut nu0 = 0.0;
            let r0 = solve_from(&w, &w_inv, &q, mu, &mut nu0);
            if nu0 == 0.0 {
                continue;
            }
            slips += 1;
            for start in [1e-3 * nu0, 0.5 * nu0, nu0, 2.0 * nu0, 1e3 * nu0] {
                let mut nu = start;
                let r = solve_from(&w, &w_inv, &q, mu, &mut nu);
                assert!((r - r0).norm() <= 1e-9 * r0.norm(), "start {start}: {r} against {r0}");
                assert!((nu - nu0).abs() <= 1e-6 * nu0, "start {start}: nu {nu} against {nu0}");
            }
        }
        assert!(slips > 500, "{slips}");
    }

    /// A block pushed along the table harder than μ times its weight slides with
    /// r_t = −μ rₙ along the push (isotropic W).
    #[test]
    fn an_isotropic_point_slips_at_mu_times_the_normal_impulse() {
        let w = Mat3::identity() * 2.0;
        let q = Vec3::new(-1.0, 3.0, 0.0);
        let r = solve(&w, &w.try_inverse().unwrap(), &q, 0.5);
        assert!((r - Vec3::new(0.5, -0.25, 0.0)).norm() < 1e-14, "{r}");
    }
}
