//! Built-in pulses: the one-sine pulse (Zhang & Makris 2001, J. Eng. Mech. 127:473, their
//! type-A cycloidal pulse in acceleration) and the Ricker wavelet.

use super::Motion;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A base-acceleration pulse of amplitude `amplitude_g` (g) and period `period_s` (s),
/// along +y.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Pulse {
    /// `a_g(t) = A g sin(2π t / T)` for `0 ≤ t ≤ T`, zero after: one full sine cycle, the
    /// one-sine (type-A) pulse of Zhang & Makris (2001).
    OneSine {
        /// Amplitude A, g.
        amplitude_g: f64,
        /// Period T, s.
        period_s: f64,
    },
    /// The Ricker wavelet of period T (dominant frequency 1/T):
    /// `a_g(t) = A g (1 − 2 (π τ / T)²) exp(−(π τ / T)²)` with `τ = t − T`, for
    /// `0 ≤ t ≤ 2T` (its value at the ends is below 1e-3 A), zero after; peak A at t = T.
    Ricker {
        /// Amplitude A (the central peak), g.
        amplitude_g: f64,
        /// Period T, s.
        period_s: f64,
    },
}

impl Pulse {
    /// Its name (`one-sine`, `ricker`).
    pub fn name(&self) -> &'static str {
        match self {
            Pulse::OneSine { .. } => "one-sine",
            Pulse::Ricker { .. } => "ricker",
        }
    }

    /// A pulse by name, `None` for an unknown name.
    pub fn from_name(name: &str, amplitude_g: f64, period_s: f64) -> Option<Pulse> {
        match name {
            "one-sine" => Some(Pulse::OneSine { amplitude_g, period_s }),
            "ricker" => Some(Pulse::Ricker { amplitude_g, period_s }),
            _ => None,
        }
    }

    /// The amplitude, g.
    pub fn amplitude_g(&self) -> f64 {
        match *self {
            Pulse::OneSine { amplitude_g, .. } | Pulse::Ricker { amplitude_g, .. } => amplitude_g,
        }
    }

    /// The period, s.
    pub fn period_s(&self) -> f64 {
        match *self {
            Pulse::OneSine { period_s, .. } | Pulse::Ricker { period_s, .. } => period_s,
        }
    }

    /// The acceleration at time `t_s`, g (exact, not sampled).
    pub fn at(&self, t_s: f64) -> f64 {
        match *self {
            Pulse::OneSine { amplitude_g, period_s } => {
                if (0.0..=period_s).contains(&t_s) {
                    amplitude_g * (2.0 * PI * t_s / period_s).sin()
                } else {
                    0.0
                }
            }
            Pulse::Ricker { amplitude_g, period_s } => {
                if (0.0..=2.0 * period_s).contains(&t_s) {
                    let x = (PI * (t_s - period_s) / period_s).powi(2);
                    amplitude_g * (1.0 - 2.0 * x) * (-x).exp()
                } else {
                    0.0
                }
            }
        }
    }

    /// Checks the amplitude (finite) and the period (> 0), naming the flag.
    ///
    /// # Errors
    /// [`PulseError`]: the bad value with its parameter's name.
    pub fn validate(&self) -> Result<(), PulseError> {
        if !self.amplitude_g().is_finite() {
            return Err(PulseError::Amplitude(self.amplitude_g()));
        }
        if !(self.period_s().is_finite() && self.period_s() > 0.0) {
            return Err(PulseError::Period(self.period_s()));
        }
        Ok(())
    }

    /// The pulse sampled every `dt_s` seconds over `duration_s` (at least the pulse).
    pub fn sampled(&self, dt_s: f64, duration_s: f64) -> Motion {
        let span = match self {
            Pulse::OneSine { period_s, .. } => *period_s,
            Pulse::Ricker { period_s, .. } => 2.0 * period_s,
        };
        let n = (duration_s.max(span) / dt_s).ceil() as usize + 1;
        Motion {
            name: format!("{}_{}g_{}s", self.name(), self.amplitude_g(), self.period_s()),
            dt_s,
            horizontal_g: (0..n).map(|k| self.at(k as f64 * dt_s)).collect(),
            vertical_g: None,
        }
    }
}

/// A pulse that cannot be built, naming the parameter (`amplitude_g`, `period_s`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PulseError {
    /// The amplitude is not finite, g.
    #[error("amplitude_g must be finite, got {0}")]
    Amplitude(f64),
    /// The period is not finite and > 0, s.
    #[error("period_s must be > 0, got {0}")]
    Period(f64),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pulses_have_their_shapes() {
        let p = Pulse::OneSine { amplitude_g: 0.5, period_s: 0.4 };
        assert!((p.at(0.1) - 0.5).abs() < 1e-12);
        assert!((p.at(0.3) + 0.5).abs() < 1e-12);
        assert_eq!(p.at(0.41), 0.0);
        let r = Pulse::Ricker { amplitude_g: 0.3, period_s: 0.5 };
        assert!((r.at(0.5) - 0.3).abs() < 1e-15);
        assert!(r.at(0.0).abs() < 1e-3 * 0.3);
        // The Ricker wavelet's zero crossings at τ = ± T / (π √2).
        let tz = 0.5 / (PI * 2f64.sqrt());
        assert!(r.at(0.5 + tz).abs() < 1e-12);
        let m = p.sampled(0.001, 1.0);
        assert!((m.pga_g() - 0.5).abs() < 1e-4);
        assert!((m.duration_s() - 1.0).abs() < 1e-9);
        assert!(Pulse::from_name("triangle", 1.0, 1.0).is_none());
        assert!(Pulse::OneSine { amplitude_g: 0.1, period_s: 0.0 }
            .validate()
            .unwrap_err()
            .to_string()
            .contains("period_s must be > 0"));
    }
}
