//! The table rolled by hand: how it is rolled ([`HandTilt`], run by
//! `loading::tilt_hand`) and the overshoot of its stops as the quasi-static tilting tests
//! load it ([`effective_tilt_deg`], the effect `table_kick`).

use crate::range::OutOfRange;
use crate::units::deg_to_rad;
use serde::{Deserialize, Serialize};

/// The increment between the stops of the paper's table, degrees (Santa-Cruz et al. 2021,
/// §2.2: "in increments of 5°").
pub const PAPER_INCREMENT_DEG: f64 = 5.0;

/// How the table is rolled by hand (the motion and the frame: `loading::tilt_hand`). Defaults: the paper's increment
/// of 5° (Santa-Cruz et al. 2021, §2.2); the rest are estimates of a table rolled by a
/// lever and pulley (the paper gives no rate): 2.5°/s, a start and a stop of 0.1 s, a
/// reading of 1 s, the axis 0.34 m below the surface (a semicircle of the platform's half
/// width, 0.3 m, under a 40 mm platform, §2.1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HandTilt {
    /// Increment between stops, degrees (> 0).
    pub increment_deg: f64,
    /// Angular speed between the ramps, degrees per second (> 0).
    pub rate_deg_per_s: f64,
    /// Duration of the start and of the stop, s (> 0, at most `increment_deg /
    /// rate_deg_per_s`: the start and the stop fit in the roll).
    pub ramp_s: f64,
    /// The table held still at each stop for the reading, s (≥ 0).
    pub hold_s: f64,
    /// Depth of the table's axis of rotation below its surface, m (≥ 0).
    pub axis_depth_m: f64,
}

impl Default for HandTilt {
    fn default() -> Self {
        HandTilt {
            increment_deg: PAPER_INCREMENT_DEG,
            rate_deg_per_s: 2.5,
            ramp_s: 0.1,
            hold_s: 1.0,
            axis_depth_m: 0.34,
        }
    }
}

/// The smallest increment of a table rolled by hand, degrees.
pub const MIN_INCREMENT_DEG: f64 = 0.01;

/// The largest number of time steps a run may take (the increments to `max_angle_deg`
/// with their holds, at the solver's step): beyond it the run is refused before it starts.
pub const MAX_STEPS: f64 = 2e7;

impl HandTilt {
    /// Checks every field.
    ///
    /// # Errors
    /// [`OutOfRange`] naming the field (`increment_deg`, `rate_deg_per_s`, `ramp_s`,
    /// `hold_s`, `axis_depth_m`) whose value is not finite or out of its range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        let check = |key: &str, v: f64, ok: bool, range: &'static str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(OutOfRange::new(key, v, range))
            }
        };
        check(
            "increment_deg",
            self.increment_deg,
            (MIN_INCREMENT_DEG..=45.0).contains(&self.increment_deg),
            "in [0.01, 45] (a table rolled by hand moves by whole degrees; below 0.01° no start or stop fits the roll)",
        )?;
        check(
            "rate_deg_per_s",
            self.rate_deg_per_s,
            self.rate_deg_per_s > 0.0 && self.rate_deg_per_s <= 90.0,
            "in (0, 90]",
        )?;
        check("hold_s", self.hold_s, (0.0..=600.0).contains(&self.hold_s), "in [0, 600]")?;
        check("axis_depth_m", self.axis_depth_m, (0.0..=100.0).contains(&self.axis_depth_m), "in [0, 100]")?;
        check(
            "ramp_s",
            self.ramp_s,
            self.ramp_s > 0.0 && self.ramp_s <= self.increment_deg / self.rate_deg_per_s,
            "in (0, increment_deg / rate_deg_per_s]: the start and the stop within the roll",
        )
    }

    /// Checks the motion against the solver's time step `dt_s` (s) and the largest tilt
    /// `max_angle_deg` (degrees): a start or a stop of at least 5 steps, and a run of at
    /// most [`MAX_STEPS`] steps (`⌈max_angle_deg / increment_deg⌉ × (roll_s + hold_s) /
    /// dt_s`). The fields must be valid ([`Self::validate`]).
    ///
    /// # Errors
    /// [`OutOfRange`] naming `ramp_s` (shorter than 5 steps), or `hold_s` or
    /// `rate_deg_per_s`, whichever makes the run long, with the bound.
    pub fn check_run(&self, dt_s: f64, max_angle_deg: f64) -> Result<(), OutOfRange> {
        if self.ramp_s < 5.0 * dt_s {
            return Err(OutOfRange::new(
                "ramp_s",
                self.ramp_s,
                "at least 5 time steps of the solver (5 dt_s): a shorter start or stop is not resolved",
            ));
        }
        let increments_needed = (max_angle_deg / self.increment_deg).ceil().max(1.0);
        let steps_needed = increments_needed * (self.roll_s() + self.hold_s) / dt_s;
        if steps_needed > MAX_STEPS {
            // Named by what makes the run long: the holds or the rolls.
            let (key, value) = if self.hold_s >= self.roll_s() {
                ("hold_s", self.hold_s)
            } else {
                ("rate_deg_per_s", self.rate_deg_per_s)
            };
            return Err(OutOfRange::new(
                key,
                value,
                "such that the run takes at most 2e7 time steps (increments to max_angle_deg × (increment_deg / rate_deg_per_s + ramp_s + hold_s) / dt_s)",
            ));
        }
        Ok(())
    }

    /// Duration of one increment's roll (start, constant speed, stop), s: `Δ / ω +
    /// ramp_s` (the trapezoid of speeds covers the increment).
    pub fn roll_s(&self) -> f64 {
        self.increment_deg / self.rate_deg_per_s + self.ramp_s
    }

    /// The table's angle (rad), angular speed (rad/s) and angular acceleration (rad/s²)
    /// at time `t` (s) into an increment that starts at `start_deg`.
    pub fn motion(&self, start_deg: f64, t: f64) -> (f64, f64, f64) {
        let w = deg_to_rad(self.rate_deg_per_s);
        let a = w / self.ramp_s;
        let (roll, tau) = (self.roll_s(), self.ramp_s);
        let a0 = deg_to_rad(start_deg);
        let delta = deg_to_rad(self.increment_deg);
        if t <= 0.0 {
            (a0, 0.0, 0.0)
        } else if t < tau {
            (a0 + 0.5 * a * t * t, a * t, a)
        } else if t < roll - tau {
            (a0 + 0.5 * w * tau + w * (t - tau), w, 0.0)
        } else if t < roll {
            let s = roll - t;
            (a0 + delta - 0.5 * a * s * s, a * s, -a)
        } else {
            (a0 + delta, 0.0, 0.0)
        }
    }

    /// The peak acceleration of a start or a stop at the top of a wall `height_m` high
    /// (m), in units of `gravity` (m/s²): `α̈ (d + H) / g`, `d` the axis depth.
    pub fn peak_top_acceleration_g(&self, height_m: f64, gravity: f64) -> f64 {
        self.peak_angular_acceleration() * (self.axis_depth_m + height_m) / gravity
    }

    /// A warning when the starts and stops push the top of a wall `height_m` high (m)
    /// harder than [`crate::ground::PLAUSIBLE_PGA_G`] (the shaking table's plausibility
    /// bound): a table rolled by hand does not do that; `None` otherwise. `keys` names the
    /// settings (e.g. `--hand-rate-deg-s, --hand-ramp-s, --table-axis-depth-m`).
    pub fn plausibility_warning(&self, height_m: f64, gravity: f64, keys: &str) -> Option<String> {
        let a = self.peak_top_acceleration_g(height_m, gravity);
        (a > crate::ground::PLAUSIBLE_PGA_G).then(|| {
            format!(
                "the starts and stops push the top of the wall with {a:.3e} g (α̈ = {:.3e} rad/s² at {:.3} m above \
                 the axis), implausible for a table rolled by hand (above {} g): check {keys}",
                self.peak_angular_acceleration(),
                self.axis_depth_m + height_m,
                crate::ground::PLAUSIBLE_PGA_G
            )
        })
    }

    /// The motion of one increment of `step_deg` degrees (0 < `step_deg` ≤ `increment_deg`;
    /// the last increment, which stops at the largest tilt, may be shorter): the same start
    /// and stop (`ramp_s`), and the speed lowered to `step_deg / ramp_s` where the full speed
    /// would not leave room for them (`step_deg / rate_deg_per_s < ramp_s`). The peak angular
    /// acceleration is then never above a full increment's, and the start and the stop keep
    /// the steps [`Self::check_run`] asked for; a step that fits at full speed is rolled
    /// exactly as a full increment.
    pub fn increment_of(&self, step_deg: f64) -> HandTilt {
        HandTilt { increment_deg: step_deg, rate_deg_per_s: self.rate_deg_per_s.min(step_deg / self.ramp_s), ..*self }
    }

    /// The peak angular acceleration of a start or a stop, rad/s² (`ω / ramp_s`).
    pub fn peak_angular_acceleration(&self) -> f64 {
        deg_to_rad(self.rate_deg_per_s) / self.ramp_s
    }
}

/// The tilt (degrees) at which the quasi-static tests load a wall when the table's angle is
/// `alpha_deg` and each stop of a table rolled by hand in the paper's 5° increments kicks
/// the wall as much as an extra inclination `overshoot_deg` would (`Layout::table_overshoot_deg`,
/// set by the effect `table_kick`): `max(α, s + Δ)`, s the last stop at or below α
/// (`s = 5° ⌊α / 5°⌋`, from the first stop on; a wall on a level table is not kicked).
/// Exactly `alpha_deg` when the overshoot is 0.
///
/// The quasi-static equivalent of the kicks of
/// [`run_tilt_by_hand`](crate::loading::tilt_hand::run_tilt_by_hand): the wall is loaded to
/// `s + Δ` at every stop s and the roll adds nothing until the table passes `s + Δ`, so a
/// wall collapses at a stop when the stop lies within Δ of its static limit, and at its
/// static limit otherwise, as in the dynamic run; the readings at a stop are those of the
/// wall loaded to `s + Δ` (the elastic part of a transient kick is recovered in the
/// dynamic run: an upper bound). A stop of peak angular deceleration `α̈` pushes a block at
/// height z above the table's axis downhill by `α̈ (z + d)`; in the dynamic run the
/// stops' effective overshoot is about 20–40 % of `atan(α̈ (z̄ + d) / g)` at the centroid
/// height z̄ (docs/discrepancy.md, "The table rolled by hand").
pub fn effective_tilt_deg(alpha_deg: f64, overshoot_deg: f64) -> f64 {
    if overshoot_deg == 0.0 {
        return alpha_deg;
    }
    let increment = PAPER_INCREMENT_DEG;
    let stop = (alpha_deg / increment).floor() * increment;
    if stop < increment {
        return alpha_deg;
    }
    alpha_deg.max(stop + overshoot_deg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_overshoot_loads_each_stop_to_the_stop_plus_the_overshoot() {
        assert_eq!(effective_tilt_deg(12.3, 0.0), 12.3);
        assert_eq!(effective_tilt_deg(4.9, 2.0), 4.9);
        assert_eq!(effective_tilt_deg(5.0, 2.0), 7.0);
        assert_eq!(effective_tilt_deg(6.5, 2.0), 7.0);
        assert_eq!(effective_tilt_deg(7.5, 2.0), 7.5);
        assert_eq!(effective_tilt_deg(10.0, 2.0), 12.0);
        // Non-decreasing in α (the bisections rely on it).
        let mut last = 0.0;
        for k in 0..4000 {
            let a = effective_tilt_deg(k as f64 * 0.01, 3.0);
            assert!(a >= last);
            last = a;
        }
    }

    #[test]
    fn the_motion_covers_the_increment_and_is_continuous() {
        let h = HandTilt::default();
        let (a_end, w_end, _) = h.motion(5.0, h.roll_s());
        assert!((crate::units::rad_to_deg(a_end) - 10.0).abs() < 1e-12);
        assert_eq!(w_end, 0.0);
        for &t in &[h.ramp_s, h.roll_s() - h.ramp_s] {
            let (a1, w1, _) = h.motion(0.0, t - 1e-9);
            let (a2, w2, _) = h.motion(0.0, t + 1e-9);
            assert!((a1 - a2).abs() < 1e-9 && (w1 - w2).abs() < 1e-6);
        }
        // The speed integrates to the angle (trapezoid over a fine grid).
        let n = 100_000;
        let dt = h.roll_s() / n as f64;
        let s: f64 = (0..n).map(|i| h.motion(0.0, (i as f64 + 0.5) * dt).1 * dt).sum();
        assert!((s - deg_to_rad(5.0)).abs() < 1e-9);
    }

    /// A short last increment (30.01° in 5° increments: 0.01°) is rolled slower with the
    /// same start and stop: it covers its step exactly (the speed integrates to it, as the
    /// trapezoid's area `ω (Δ/ω)`), its peak angular acceleration is at most a full
    /// increment's, and a step that fits at full speed is rolled as a full increment.
    #[test]
    fn a_short_last_increment_is_rolled_slower_not_harder() {
        let h = HandTilt::default();
        for step in [0.01, 0.1, 0.25, 1.0, 4.99, 5.0] {
            let last = h.increment_of(step);
            assert_eq!(last.ramp_s, h.ramp_s);
            assert!(last.validate().is_ok(), "step {step}: {:?}", last.validate());
            assert!(last.peak_angular_acceleration() <= h.peak_angular_acceleration() * (1.0 + 1e-12));
            let (a_end, w_end, _) = last.motion(30.0, last.roll_s());
            assert!((crate::units::rad_to_deg(a_end) - (30.0 + step)).abs() < 1e-9, "step {step}");
            assert_eq!(w_end, 0.0);
            let n = 20_000;
            let dt = last.roll_s() / n as f64;
            let s: f64 = (0..n).map(|i| last.motion(0.0, (i as f64 + 0.5) * dt).1 * dt).sum();
            assert!((s - deg_to_rad(step)).abs() < 1e-9 * deg_to_rad(step).max(1.0), "step {step}: {s}");
            if step / h.rate_deg_per_s >= h.ramp_s {
                assert_eq!(last.rate_deg_per_s, h.rate_deg_per_s);
            }
        }
    }

    #[test]
    fn bad_fields_are_refused_by_name() {
        let bad = [
            HandTilt { increment_deg: 0.0, ..HandTilt::default() },
            HandTilt { rate_deg_per_s: f64::NAN, ..HandTilt::default() },
            HandTilt { ramp_s: 2.5, ..HandTilt::default() },
            HandTilt { hold_s: -1.0, ..HandTilt::default() },
            HandTilt { axis_depth_m: f64::INFINITY, ..HandTilt::default() },
        ];
        let keys = ["increment_deg", "rate_deg_per_s", "ramp_s", "hold_s", "axis_depth_m"];
        for (h, key) in bad.iter().zip(keys) {
            let e = h.validate().unwrap_err().to_string();
            assert!(e.contains(key), "{e}");
        }
        assert!(HandTilt::default().validate().is_ok());
    }
}
