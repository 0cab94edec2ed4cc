//! Ground motions for the shaking protocol: the base acceleration a table is driven by.
//!
//! A [`Motion`] is a uniformly sampled acceleration history along the out-of-plane axis +y
//! of the table frame (optionally a vertical component along +z), in units of g, sample `k`
//! at time `k · dt`. It comes from a record file ([`read_record`]: PEER NGA `.AT2`, or a
//! two-column CSV/TSV whose header states the unit), from a built-in pulse ([`Pulse`]:
//! the one-sine pulse of Zhang & Makris 2001, the Ricker wavelet), or from the seeded
//! stochastic model of [`stochastic`] (Kanai–Tajimi filtered white noise under a
//! Saragoni–Hart envelope). A solver reads it at its own step by linear interpolation
//! ([`Motion::horizontal_at`]), zero outside the record: resampling to the solver's step.
//!
//! Intensity: the peak ground acceleration [`Motion::pga_g`]; incremental dynamic analysis
//! scales a motion to a PGA level with [`Motion::scaled_to_pga`].

mod pulse;
mod read;
pub mod stochastic;

pub use pulse::{Pulse, PulseError};
pub use read::{read_record, read_record_with, ColumnMap, RecordError};
pub use stochastic::StochasticMotion;

use serde::{Deserialize, Serialize};

/// Standard gravity, m/s² (the unit g of records).
pub const G: f64 = 9.80665;

/// Most samples a motion may hold per component \[20 000 000\]: 160 MB of `f64`, an hour
/// of record at 5 kHz. A record file, its resampling, a pulse or a generated motion that
/// would need more is refused before anything is allocated.
pub const MAX_MOTION_SAMPLES: f64 = 2e7;

/// Fewest samples (at the step a pulse is sampled at, the solver's) a pulse's period may
/// span \[10\]: fewer and the pulse is not resolved (a one-sine of two steps samples to
/// zeros).
pub const MIN_SAMPLES_PER_PERIOD: f64 = 10.0;

/// Longest motion, s \[3600\]: an hour (the longest strong-motion records last minutes).
pub const MAX_MOTION_DURATION_S: f64 = 3600.0;

/// Above this PGA, g \[5\], a motion is implausible as a ground motion (the largest
/// recorded horizontal PGAs are about 3 to 4 g): it is run, with a warning line.
pub const PLAUSIBLE_PGA_G: f64 = 5.0;

/// Coarsest sampling interval of a motion run without a warning, s \[0.05\]: 20 samples
/// per second keep content up to 10 Hz, the range of a wall's rocking and of strong motion.
pub const COARSE_RECORD_DT_S: f64 = 0.05;

/// What `n` samples of `f64` would take, in words (`"8.0 TB"`), for the refusals of sizes.
pub fn bytes_in_words(n: f64) -> String {
    let b = n * 8.0;
    let (v, unit) = [(1e12, "TB"), (1e9, "GB"), (1e6, "MB"), (1e3, "kB")]
        .into_iter()
        .find(|(s, _)| b >= *s)
        .map_or((b, "B"), |(s, u)| (b / s, u));
    format!("{v:.1} {unit}")
}

/// Checks that a motion of `samples` samples per component spanning `duration_s` seconds
/// is within [`MAX_MOTION_SAMPLES`] and [`MAX_MOTION_DURATION_S`], before it is built.
///
/// # Errors
/// The refusal in words, with what the motion would cost (samples, memory, duration).
pub fn check_motion_size(samples: f64, duration_s: f64) -> Result<(), String> {
    if !(duration_s <= MAX_MOTION_DURATION_S) {
        return Err(format!(
            "the motion would last {duration_s:.3e} s; the limit is {MAX_MOTION_DURATION_S} s (an hour)"
        ));
    }
    if !(samples <= MAX_MOTION_SAMPLES) {
        return Err(format!(
            "the motion would hold {samples:.3e} samples ({} per component); the limit is {MAX_MOTION_SAMPLES:.0e} samples",
            bytes_in_words(samples)
        ));
    }
    Ok(())
}

/// A ground acceleration history, uniformly sampled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    /// Name (the record file's stem, the pulse or the generated motion).
    pub name: String,
    /// Sampling interval, s (> 0).
    pub dt_s: f64,
    /// Horizontal acceleration along +y (out of plane, towards the side the wall falls
    /// to), g; sample `k` at `k · dt_s`.
    pub horizontal_g: Vec<f64>,
    /// Vertical acceleration along +z (up), g, sampled as `horizontal_g`; `None`: none.
    pub vertical_g: Option<Vec<f64>>,
}

impl Motion {
    /// Duration of the record, s: `(n − 1) dt`.
    pub fn duration_s(&self) -> f64 {
        self.horizontal_g.len().saturating_sub(1) as f64 * self.dt_s
    }

    /// Peak ground acceleration of the horizontal component, g (≥ 0).
    pub fn pga_g(&self) -> f64 {
        self.horizontal_g.iter().fold(0.0_f64, |m, a| m.max(a.abs()))
    }

    /// The horizontal acceleration at time `t_s`, g: linear interpolation between samples,
    /// 0 before the start and after the end.
    pub fn horizontal_at(&self, t_s: f64) -> f64 {
        interpolate(&self.horizontal_g, self.dt_s, t_s)
    }

    /// The vertical acceleration at time `t_s`, g (0 without a vertical component).
    pub fn vertical_at(&self, t_s: f64) -> f64 {
        self.vertical_g.as_deref().map_or(0.0, |v| interpolate(v, self.dt_s, t_s))
    }

    /// The mean horizontal acceleration over `[t0_s, t1_s]`, g: the integral of the
    /// linear interpolation between samples (0 before the start and after the end) over the
    /// interval, divided by its length; the value at `t0_s` for an empty interval. A solver
    /// step longer than the sampling interval given this mean receives the record's
    /// impulse over the step exactly, however short its peaks.
    pub fn horizontal_mean(&self, t0_s: f64, t1_s: f64) -> f64 {
        mean(&self.horizontal_g, self.dt_s, t0_s, t1_s)
    }

    /// The mean vertical acceleration over `[t0_s, t1_s]`, g, as
    /// [`Motion::horizontal_mean`] (0 without a vertical component).
    pub fn vertical_mean(&self, t0_s: f64, t1_s: f64) -> f64 {
        self.vertical_g.as_deref().map_or(0.0, |v| mean(v, self.dt_s, t0_s, t1_s))
    }

    /// Both components multiplied by `factor`.
    pub fn scaled(&self, factor: f64) -> Motion {
        Motion {
            name: self.name.clone(),
            dt_s: self.dt_s,
            horizontal_g: self.horizontal_g.iter().map(|a| a * factor).collect(),
            vertical_g: self.vertical_g.as_ref().map(|v| v.iter().map(|a| a * factor).collect()),
        }
    }

    /// Scaled (both components by one factor) so that the horizontal PGA is `pga_g`; a
    /// motion of zero PGA is returned unchanged.
    pub fn scaled_to_pga(&self, pga_g: f64) -> Motion {
        let p = self.pga_g();
        if p > 0.0 {
            self.scaled(pga_g / p)
        } else {
            self.clone()
        }
    }

    /// The first `duration_s` seconds (the whole record if shorter).
    pub fn truncated(&self, duration_s: f64) -> Motion {
        let n = ((duration_s / self.dt_s).floor() as usize + 1).min(self.horizontal_g.len());
        Motion {
            name: self.name.clone(),
            dt_s: self.dt_s,
            horizontal_g: self.horizontal_g[..n].to_vec(),
            vertical_g: self.vertical_g.as_ref().map(|v| v[..n.min(v.len())].to_vec()),
        }
    }

    /// Baseline correction: the least-squares straight line of the velocity (trapezoidal
    /// integral of the acceleration) removed from each component, which takes a constant
    /// offset of the acceleration out and ends the record at (nearly) zero velocity
    /// (Boore 2001's simplest correction; a record with a drift of its zero line would
    /// otherwise carry the table away).
    pub fn baseline_corrected(&self) -> Motion {
        Motion {
            name: self.name.clone(),
            dt_s: self.dt_s,
            horizontal_g: baseline(&self.horizontal_g, self.dt_s),
            vertical_g: self.vertical_g.as_ref().map(|v| baseline(v, self.dt_s)),
        }
    }

    /// Peak ground velocity of the horizontal component, m/s (trapezoidal integral).
    pub fn pgv_m_s(&self) -> f64 {
        let mut v = 0.0_f64;
        let mut peak = 0.0_f64;
        for w in self.horizontal_g.windows(2) {
            v += 0.5 * (w[0] + w[1]) * G * self.dt_s;
            peak = peak.max(v.abs());
        }
        peak
    }
}

fn interpolate(a: &[f64], dt: f64, t: f64) -> f64 {
    if a.is_empty() || !(t >= 0.0) {
        return 0.0;
    }
    let x = t / dt;
    let k = x.floor() as usize;
    if k + 1 >= a.len() {
        return if k + 1 == a.len() && x == k as f64 { a[k] } else { 0.0 };
    }
    let f = x - k as f64;
    a[k] * (1.0 - f) + a[k + 1] * f
}

/// The mean of the linear interpolation of `a` (samples every `dt`, 0 outside them) over
/// `[t0, t1]`: the trapezoid rule on each sampling interval's part inside, exact for the
/// piecewise-linear interpolant; `interpolate(a, dt, t0)` when `t1 ≤ t0`.
fn mean(a: &[f64], dt: f64, t0: f64, t1: f64) -> f64 {
    if !(t1 > t0) {
        return interpolate(a, dt, t0);
    }
    let end = a.len().saturating_sub(1) as f64 * dt;
    let (lo, hi) = (t0.max(0.0), t1.min(end));
    if !(hi > lo) {
        return 0.0;
    }
    let mut k = (lo / dt).floor() as usize;
    let mut sum = 0.0;
    while k + 1 < a.len() && (k as f64) * dt < hi {
        let (s0, s1) = ((k as f64 * dt).max(lo), ((k + 1) as f64 * dt).min(hi));
        if s1 > s0 {
            let at = |s: f64| {
                let f = (s / dt - k as f64).clamp(0.0, 1.0);
                a[k] * (1.0 - f) + a[k + 1] * f
            };
            sum += 0.5 * (at(s0) + at(s1)) * (s1 - s0);
        }
        k += 1;
    }
    sum / (t1 - t0)
}

/// `a` minus the slope of the least-squares line through its velocity: the velocity's
/// linear trend `c0 + c1 t` comes from a constant acceleration offset `c1` (and an initial
/// velocity `c0`, which a base at rest does not have); removing `c1` is the correction.
fn baseline(a: &[f64], dt: f64) -> Vec<f64> {
    let n = a.len();
    if n < 3 {
        return a.to_vec();
    }
    let mut v = vec![0.0; n];
    for k in 1..n {
        v[k] = v[k - 1] + 0.5 * (a[k - 1] + a[k]) * dt;
    }
    let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
    let (tm, vm) = (t.iter().sum::<f64>() / n as f64, v.iter().sum::<f64>() / n as f64);
    let (mut stv, mut stt) = (0.0, 0.0);
    for k in 0..n {
        stv += (t[k] - tm) * (v[k] - vm);
        stt += (t[k] - tm) * (t[k] - tm);
    }
    let slope = stv / stt;
    a.iter().map(|x| x - slope).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> Motion {
        Motion { name: "ramp".into(), dt_s: 0.01, horizontal_g: vec![0.0, 0.1, -0.3, 0.2], vertical_g: None }
    }

    #[test]
    fn interpolation_scaling_and_peaks() {
        let m = ramp();
        assert!((m.duration_s() - 0.03).abs() < 1e-15);
        assert_eq!(m.pga_g(), 0.3);
        assert!((m.horizontal_at(0.005) - 0.05).abs() < 1e-12);
        assert!((m.horizontal_at(0.025) - (-0.05)).abs() < 1e-12);
        assert_eq!(m.horizontal_at(-0.001), 0.0);
        assert_eq!(m.horizontal_at(0.5), 0.0);
        assert_eq!(m.vertical_at(0.01), 0.0);
        let s = m.scaled_to_pga(0.6);
        assert!((s.pga_g() - 0.6).abs() < 1e-15);
        assert_eq!(m.truncated(0.015).horizontal_g.len(), 2);
    }

    /// The mean over an interval conserves the record's impulse: over steps of any length,
    /// aligned with the samples or not, the means times the steps sum to the integral of
    /// the linear interpolation, `dt (Σ a − (a₀ + a_last) / 2)` (the trapezoid rule); one
    /// sample of 5 g in a record of 5 ms gives 0.025 g·s, whether the step is 1 ms or
    /// 50 ms. Within one sampling interval the mean is the interpolation's at the midpoint.
    #[test]
    fn the_mean_over_a_step_conserves_the_record_s_impulse() {
        let spike = Motion { name: "spike".into(), dt_s: 0.005, horizontal_g: vec![0.0, 5.0, 0.0], vertical_g: None };
        for h in [0.001f64, 0.003, 0.005, 0.0071, 0.05] {
            let impulse: f64 =
                (0..(0.2 / h) as usize).map(|k| spike.horizontal_mean(k as f64 * h, (k + 1) as f64 * h) * h).sum();
            assert!((impulse - 0.025).abs() < 1e-12, "step {h}: impulse {impulse} g·s against 0.025");
        }
        let m = ramp();
        let exact = m.dt_s * (0.0 + 0.1 - 0.3 + 0.2 - (0.0 + 0.2) / 2.0);
        for h in [0.004f64, 0.01, 0.013, 1.0] {
            let impulse: f64 =
                (0..(0.1 / h).ceil() as usize).map(|k| m.horizontal_mean(k as f64 * h, (k + 1) as f64 * h) * h).sum();
            assert!((impulse - exact).abs() < 1e-14, "step {h}: {impulse} against {exact}");
        }
        assert!((m.horizontal_mean(0.012, 0.018) - m.horizontal_at(0.015)).abs() < 1e-14);
        assert_eq!(m.horizontal_mean(0.02, 0.02), m.horizontal_at(0.02));
        assert_eq!(m.horizontal_mean(0.5, 0.6), 0.0);
    }

    /// A constant offset of the acceleration (a record whose zero line drifted) is what
    /// the baseline correction removes: a sine plus an offset comes back as the sine.
    #[test]
    fn baseline_correction_removes_a_constant_offset() {
        let dt = 0.005;
        let sine: Vec<f64> = (0..=2000).map(|k| (2.0 * std::f64::consts::PI * k as f64 * dt).sin() * 0.2).collect();
        let shifted = Motion {
            name: "s".into(),
            dt_s: dt,
            horizontal_g: sine.iter().map(|a| a + 0.01).collect(),
            vertical_g: None,
        };
        let c = shifted.baseline_corrected();
        let err = c.horizontal_g.iter().zip(&sine).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(err < 2e-4, "{err}");
    }
}
