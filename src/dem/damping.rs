//! Normal contact damping for true dynamics with the penalty DEM: a viscous dashpot in
//! parallel with every contact's normal springs, its coefficient set by a coefficient of
//! restitution `e` (the linear spring–dashpot contact of Cundall & Strack 1979 and Tsuji,
//! Tanaka & Ishida 1992, Powder Technol. 71:239; the "contact damping" of 3DEC's dynamic
//! analysis, Itasca 3DEC manual).
//!
//! A mass `m` on a spring `k` and a dashpot `c` that meets an obstacle at speed `v` leaves it,
//! when the overlap returns to zero, at `e v` with
//!
//! ```text
//! ζ = −ln e / √(π² + ln² e),      c = 2 ζ √(k m)          (ζ = 1 at e = 0, 0 at e = 1)
//! ```
//!
//! For a contact between two blocks `m` is the pair's effective mass `m_a m_b / (m_a + m_b)`
//! (the free block's mass against the table or a fixed block) and `k = Kn A`, with `A` the
//! area of the contact polygon: the dashpot is spread over the polygon as a pressure
//! `c_p = c / A = 2 ζ √(Kn m / A)` (N·s/m³), acting on the nodes in overlap
//! (`contact::forces::contact_dashpot`). A flat block dropped on its face rebounds at `e`
//! times its impact speed; a rocking block's impact on an edge, which closes a part of
//! the polygon first, dissipates differently from Housner's rigid impact (see
//! docs/shake.md for what is checked).
//!
//! Unlike local damping (`dem::integrator`), which removes energy in proportion to the
//! out-of-balance force and is a relaxation device for static solutions, the dashpot only
//! acts across closing and opening contacts: a block in free flight or rocking on an edge
//! is not damped.
//!
//! Time step: the central-difference scheme with the damping force of the lagged velocity
//! is stable for a mode of frequency ω and damping rate d (`ü + d u̇ + ω² u = 0`) when
//! `ω² Δt² + 2 d Δt ≤ 4`, i.e. `ω Δt ≤ 2 (√(1 + ζ²) − ζ)` with `ζ = d / 2ω` (Belytschko &
//! Hughes 1983, §2.5). With `ω_max` the assembly's highest frequency and `d_max` the
//! largest eigenvalue of `M⁻¹ C` (the dashpots assembled as the normal springs of the
//! stiffness estimate, `dem::workspace`), both upper bounds, the step
//! `2/ω_max · (√(1 + ζ²) − ζ)`, `ζ = d_max / 2ω_max`, is stable for every mode:
//! [`ContactDamping::step_factor`].

use crate::range::{check_ranges, OutOfRange};

/// Normal contact damping set by a coefficient of restitution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactDamping {
    restitution: f64,
    zeta: f64,
}

impl ContactDamping {
    /// The damping of restitution coefficient `e` (dimensionless, in [0, 1]; 0: a critically
    /// damped, plastic impact; 1: no damping).
    ///
    /// # Errors
    /// `restitution` out of [0, 1] or not finite (key `restitution`).
    pub fn from_restitution(e: f64) -> Result<ContactDamping, OutOfRange> {
        check_ranges(&[("restitution", e, (0.0..=1.0).contains(&e), "in [0, 1]")])?;
        Ok(ContactDamping { restitution: e, zeta: damping_ratio(e) })
    }

    /// The coefficient of restitution, –.
    pub fn restitution(&self) -> f64 {
        self.restitution
    }

    /// The damping ratio ζ of a contact as a single degree of freedom, –.
    pub fn zeta(&self) -> f64 {
        self.zeta
    }

    /// The dashpot pressure `c_p = 2 ζ √(Kn m / A)` of a contact of normal stiffness `kn`
    /// (Pa/m), polygon area `area` (m², > 0) and effective mass `m` (kg), N·s/m³.
    pub fn dashpot_pressure(&self, kn: f64, area: f64, m: f64) -> f64 {
        2.0 * self.zeta * (kn * m / area).sqrt()
    }

    /// The factor `√(1 + z²) − z` (in (0, 1]) on the undamped critical step `2/ω_max`, with
    /// `z = d_max / (2 ω_max)`: `omega_max` the assembly's highest frequency (rad/s) and
    /// `d_max` the largest damping rate of its dashpots, `λ_max(M⁻¹ C)` (1/s). 1 without
    /// damping.
    pub fn step_factor(&self, omega_max: f64, d_max: f64) -> f64 {
        if self.zeta == 0.0 || !(omega_max > 0.0) || !(d_max > 0.0) {
            return 1.0;
        }
        let z = d_max / (2.0 * omega_max);
        (1.0 + z * z).sqrt() - z
    }
}

/// The damping ratio ζ of the linear spring–dashpot contact whose coefficient of restitution
/// is `e` (in [0, 1]): `ζ = −ln e / √(π² + ln² e)`, 1 at `e = 0` (Tsuji et al. 1992).
pub fn damping_ratio(e: f64) -> f64 {
    if e <= 0.0 {
        return 1.0;
    }
    let l = e.ln();
    -l / (std::f64::consts::PI * std::f64::consts::PI + l * l).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The damped oscillator `m ü + c u̇ + k u = 0` from `u = 0`, `u̇ = −v` (an impact),
    /// integrated here by RK4 until `u` returns to 0: the exit speed over `v` is `e`.
    #[test]
    fn the_dashpot_of_e_returns_e_times_the_impact_speed() {
        for e in [0.1, 0.3, 0.5, 0.8, 0.95] {
            let d = ContactDamping::from_restitution(e).unwrap();
            let (m, k): (f64, f64) = (2.0, 1e6);
            let c = 2.0 * d.zeta() * (k * m).sqrt();
            let acc = |u: f64, v: f64| (-k * u - c * v) / m;
            let dt = 1e-7;
            let (mut u, mut v) = (0.0_f64, -1.0_f64);
            loop {
                let (k1u, k1v) = (v, acc(u, v));
                let (k2u, k2v) = (v + 0.5 * dt * k1v, acc(u + 0.5 * dt * k1u, v + 0.5 * dt * k1v));
                let (k3u, k3v) = (v + 0.5 * dt * k2v, acc(u + 0.5 * dt * k2u, v + 0.5 * dt * k2v));
                let (k4u, k4v) = (v + dt * k3v, acc(u + dt * k3u, v + dt * k3v));
                let nu = u + dt / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
                let nv = v + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
                if nu > 0.0 && u < 0.0 {
                    // Linear interpolation of v at the crossing.
                    let s = -u / (nu - u);
                    let exit = v + s * (nv - v);
                    assert!((exit - e).abs() < 1e-4, "e {e}: exit speed {exit}");
                    break;
                }
                u = nu;
                v = nv;
            }
        }
        assert_eq!(damping_ratio(0.0), 1.0);
        assert_eq!(damping_ratio(1.0), 0.0);
        assert!(ContactDamping::from_restitution(1.5).is_err());
        assert!(ContactDamping::from_restitution(f64::NAN).is_err());
    }
}
