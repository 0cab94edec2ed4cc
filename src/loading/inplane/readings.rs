//! The readings of a force–displacement curve ([`CurvePoint`]): per direction
//! ([`direction`], [`DirectionResult`]) the database's definitions and the robust readings of
//! the envelope ([`envelope_readings`]).

use serde::{Deserialize, Serialize};

/// The drop of the force past the peak that defines the ultimate drift (Vanin et al. 2017):
/// 20 %.
pub const ULTIMATE_DROP: f64 = 0.2;

/// The share of the peak force at which the initial (secant) stiffness is read (Vanin et
/// al. 2017): 15 %.
pub const STIFFNESS_SHARE: f64 = 0.15;

/// One point of the force–displacement curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CurvePoint {
    /// The beam's horizontal displacement at the measuring point, mm (+x positive; the
    /// database's `top_displacement`, read at [`Rig::measure_z_m`](super::Rig::measure_z_m)).
    pub top_mm: f64,
    /// Drift, %: `top_mm` over the measuring point's height ([`Rig::measure_z_m`](super::Rig::measure_z_m): the
    /// shear span by default, as the database's files give it).
    pub drift_pct: f64,
    /// The actuator's horizontal force, kN (positive towards +x).
    pub force_kn: f64,
    /// Whether the static solve reached equilibrium (the unbalanced-force ratio below the
    /// tolerance, every block in balance) within its step budget, on the loading path (no
    /// block thrown from the wall: [`InPlaneResult::unconverged`](super::InPlaneResult::unconverged)).
    pub converged: bool,
}

/// What one direction of loading gave (the database's definitions).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DirectionResult {
    /// The peak force, kN (its magnitude).
    pub peak_force_kn: f64,
    /// The drift at the peak, % (its magnitude).
    pub drift_at_peak_pct: f64,
    /// The ultimate drift, % (magnitude): where the envelope's force first falls below
    /// 80 % of the peak past it, or the largest drift run.
    pub ultimate_drift_pct: f64,
    /// Whether the ultimate drift is the 20 % drop (true) or the largest drift run.
    pub dropped: bool,
    /// The initial stiffness, secant at 15 % of the peak, kN/mm. NaN by non-smooth contact
    /// dynamics, whose rigid contacts give the wall none (the secant of its first points
    /// would be the actuator's step).
    pub initial_stiffness_kn_per_mm: f64,
    /// The envelope's force at the drifts [`READING_DRIFTS_PCT`], kN (magnitude; NaN past
    /// the largest drift run): a reading of the whole envelope that does not hang on one
    /// point as the peak does.
    #[serde(default = "nan_readings")]
    pub force_at_drift_kn: [f64; READING_DRIFTS_PCT.len()],
    /// The drift where the envelope first reaches 80 % of the peak force, % (linear
    /// between the envelope's points).
    #[serde(default = "nan")]
    pub drift_at_80_pct: f64,
    /// The drift where the envelope first reaches 95 % of the peak force, %.
    #[serde(default = "nan")]
    pub drift_at_95_pct: f64,
    /// The plateau's slope, kN per % of drift: the least-squares slope of the envelope's
    /// force against its drift from `drift_at_95_pct` to the largest drift run (negative:
    /// the force falls past the peak; NaN with fewer than three points there).
    #[serde(default = "nan")]
    pub plateau_slope_kn_per_pct: f64,
}

/// The drifts at which [`DirectionResult::force_at_drift_kn`] reads the envelope, %.
pub const READING_DRIFTS_PCT: [f64; 4] = [0.25, 0.5, 1.0, 2.0];

/// NaN readings, for serde's defaults.
fn nan_readings() -> [f64; READING_DRIFTS_PCT.len()] {
    [f64::NAN; READING_DRIFTS_PCT.len()]
}

/// The robust readings of an envelope `env` (drift %, force kN; magnitudes, growing drift,
/// starting at the origin) whose peak `fp` (kN) is at index `ip`: the force at
/// [`READING_DRIFTS_PCT`], the drifts at 80 % and 95 % of the peak, the plateau's slope
/// (see [`DirectionResult`]). The measured envelopes are read by the same function.
pub fn envelope_readings(env: &[(f64, f64)], ip: usize, fp: f64) -> ([f64; READING_DRIFTS_PCT.len()], f64, f64, f64) {
    let reach = env.last().map_or(0.0, |p| p.0);
    let at = |d: f64| -> f64 {
        if d > reach + 1e-12 {
            return f64::NAN;
        }
        for w in env.windows(2) {
            let ((d0, f0), (d1, f1)) = (w[0], w[1]);
            if d <= d1 {
                return if d1 > d0 { f0 + (f1 - f0) * (d - d0) / (d1 - d0) } else { f1 };
            }
        }
        env.last().map_or(f64::NAN, |p| p.1)
    };
    let first_reach = |share: f64| -> f64 {
        let f = share * fp;
        for w in env[..=ip].windows(2) {
            let ((d0, f0), (d1, f1)) = (w[0], w[1]);
            if f1 >= f {
                return if f1 > f0 { d0 + (d1 - d0) * ((f - f0) / (f1 - f0)).clamp(0.0, 1.0) } else { d1 };
            }
        }
        f64::NAN
    };
    let forces = READING_DRIFTS_PCT.map(at);
    let (d80, d95) = (first_reach(0.8), first_reach(0.95));
    let tail: Vec<(f64, f64)> = env.iter().copied().filter(|p| p.0 >= d95).collect();
    let slope = if tail.len() >= 3 {
        let n = tail.len() as f64;
        let (mx, my) = (tail.iter().map(|p| p.0).sum::<f64>() / n, tail.iter().map(|p| p.1).sum::<f64>() / n);
        let sxx: f64 = tail.iter().map(|p| (p.0 - mx).powi(2)).sum();
        let sxy: f64 = tail.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        if sxx > 0.0 {
            sxy / sxx
        } else {
            f64::NAN
        }
    } else {
        f64::NAN
    };
    (forces, d80, d95, slope)
}

/// The per-direction outputs of a curve (see the module doc); `sign` +1 or −1.
pub fn direction(curve: &[CurvePoint], sign: f64) -> Option<DirectionResult> {
    // The envelope: the points at a new largest drift of the direction.
    let mut env: Vec<(f64, f64)> = vec![(0.0, 0.0)];
    let mut reach = 0.0;
    for p in curve {
        let (d, f) = (sign * p.top_mm, sign * p.force_kn);
        if d > reach + 1e-12 {
            reach = d;
            env.push((d, f));
        }
    }
    if env.len() < 2 {
        return None;
    }
    let (ip, &(dp, fp)) = env.iter().enumerate().max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))?;
    if !(fp > 0.0) {
        return None;
    }
    let (mut du, mut dropped) = (reach, false);
    if let Some(&(d, _)) = env[ip..].iter().find(|&&(_, f)| f < (1.0 - ULTIMATE_DROP) * fp) {
        du = d;
        dropped = true;
    }
    let f15 = STIFFNESS_SHARE * fp;
    let mut k = f64::NAN;
    for w in env.windows(2) {
        let ((d0, f0), (d1, f1)) = (w[0], w[1]);
        if f1 >= f15 {
            let d = if f1 > f0 { d0 + (d1 - d0) * (f15 - f0) / (f1 - f0) } else { d1 };
            k = f15 / d;
            break;
        }
    }
    let h = curve.iter().find(|p| p.top_mm != 0.0).map_or(f64::NAN, |p| p.drift_pct / p.top_mm);
    let env_pct: Vec<(f64, f64)> = env.iter().map(|&(d, f)| (d * h, f)).collect();
    let (force_at_drift_kn, drift_at_80_pct, drift_at_95_pct, plateau_slope_kn_per_pct) =
        envelope_readings(&env_pct, ip, fp);
    Some(DirectionResult {
        peak_force_kn: fp,
        drift_at_peak_pct: dp * h,
        ultimate_drift_pct: du * h,
        dropped,
        initial_stiffness_kn_per_mm: k,
        force_at_drift_kn,
        drift_at_80_pct,
        drift_at_95_pct,
        plateau_slope_kn_per_pct,
    })
}

/// NaN, for serde's defaults.
pub(super) fn nan() -> f64 {
    f64::NAN
}
