//! The in-plane test's parameters ([`InPlaneParams`]): the history, the beam's rotation,
//! their validation, the cyclic amplitudes and the imposed path, and the bounds they are
//! checked against.

use crate::range::{check_ranges, OutOfRange};
use serde::{Deserialize, Serialize};

/// The most static solves a history may take (some 100 s of CPU on the granite wall).
pub const MAX_INCREMENTS: usize = 100_000;

/// The most static solves of a quarter cycle ([`InPlaneParams::quarter_increments`]).
pub const MAX_QUARTER_INCREMENTS: u32 = 1000;

/// The highest shear span and measuring point accepted, as a multiple of the wall's
/// height \[10\]: both are on the loading beam, on top of the wall, and a test's shear span
/// is a few times the wall's height at most (the tests of the Stone Masonry Database: 0.5
/// to 1.5 times); past ten times it is a probable unit mistake (millimetres for metres),
/// which would otherwise run as a path of drift × H0 refused only by its length.
pub const MAX_HEIGHT_RATIO: f64 = 10.0;

/// The most cycles per amplitude ([`InPlaneParams::cycles`]).
pub const MAX_CYCLES: u32 = 100;

/// The loading history.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum History {
    /// Monotonic, towards +x, to [`InPlaneParams::drift_pct`].
    #[default]
    Monotonic,
    /// Cycles of growing amplitude ([`InPlaneParams::amplitudes_pct`], each
    /// [`InPlaneParams::cycles`] times: 0 → +a → −a → 0).
    Cyclic,
}

impl History {
    /// Its name in study files and reports (`monotonic`, `cyclic`).
    pub fn name(self) -> &'static str {
        match self {
            History::Monotonic => "monotonic",
            History::Cyclic => "cyclic",
        }
    }

    /// The history a measured specimen's `loading` column names (`Monotonic`, `Cyclic`,
    /// in any case, as the Stone Masonry Database writes them); `None` where it names
    /// neither.
    pub fn of_loading(loading: &str) -> Option<History> {
        let l = loading.to_ascii_lowercase();
        if l.contains("monotonic") {
            Some(History::Monotonic)
        } else if l.contains("cyclic") {
            Some(History::Cyclic)
        } else {
            None
        }
    }
}

/// The loading beam's rotation in the wall's plane.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BeamRotation {
    /// Free: the horizontal force acts at the shear span `H0` (cantilever; the tests').
    #[default]
    Free,
    /// Held: double-fixed (double curvature); no shear span.
    Fixed,
}

/// What holds the wall's blocks out of the wall's plane in the penalty DEM's in-plane test.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OutOfPlane {
    /// Each block's out-of-plane degrees of freedom held (its translation across the wall,
    /// y, and its rotations about x and z): the plane model of the test, the wall a plane
    /// body loaded in its plane, as the interface models of these tests are 2D (Lourenço,
    /// Oliveira, Roca & Orduña 2005, J. Struct. Eng. 131(11):1665, on Vasconcelos's granite
    /// walls). In a 3D penalty DEM a block that the loading beam or a crack leaves lightly
    /// held has no stiffness against a twist about the vertical or a walk across the wall:
    /// friction resists the motion, not the position reached, so each relaxation's small
    /// out-of-plane imbalance adds to the last; on the granite wall the top course's end
    /// half-stones twisted 4–6° and walked 18 mm across a 200 mm wall over a monotonic run
    /// to 3.25 %, and the wall read `mixed` where the specimens rocked.
    #[default]
    Held,
    /// Every degree of freedom of the blocks free (a 3D run: a wall of more than one leaf,
    /// through stones, a thickness that varies along the wall).
    Free,
}

impl OutOfPlane {
    /// Its name in study files and on the command line (`held`, `free`).
    pub fn name(self) -> &'static str {
        match self {
            OutOfPlane::Held => "held",
            OutOfPlane::Free => "free",
        }
    }
}

/// The in-plane test's parameters (`[in_plane]` in a study). Defaults in brackets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InPlaneParams {
    /// Vertical stress applied through the beam, MPa, > 0 (the wall's self-weight comes on
    /// top) \[0.5\].
    pub sigma0_mpa: f64,
    /// Shear span `H0`: the height above the base at which the horizontal force acts, m,
    /// at least the wall's height and at most [`MAX_HEIGHT_RATIO`] times it; with a free
    /// beam rotation it is required, with a held one it is not read \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear_span_m: Option<f64>,
    /// The largest drift, %, in (0, 50] \[3\]; the penalty DEM follows at most
    /// [`super::max_drift_pct`] of its face-angle tolerance (8.8 % at the default).
    pub drift_pct: f64,
    /// The history \[monotonic\].
    pub history: History,
    /// The cyclic history's amplitudes, drift %, strictly growing and each at most
    /// `drift_pct`; unset: 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1, 1.5, 2, 2.5, 3, 4, 5 … %
    /// up to `drift_pct` ([`InPlaneParams::amplitudes`]) \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitudes_pct: Option<Vec<f64>>,
    /// Cycles per amplitude, ≥ 1 \[2\].
    pub cycles: u32,
    /// The height above the base of the point where the horizontal displacement is read
    /// (the database's `HLVDT_mm`), m, on the loading beam: at least the wall's height;
    /// the drift is that displacement over this height. Unset: the actuator's height, the
    /// shear span `H0` with the beam's rotation free (the database's reading where a test
    /// reports none), the wall's height with it held \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measuring_height_m: Option<f64>,
    /// The beam's rotation \[free\].
    pub beam_rotation: BeamRotation,
    /// What holds the blocks out of the wall's plane in the penalty DEM ([`OutOfPlane`];
    /// nscd and limit analysis do not read it: their walls are 3D) \[held\].
    pub out_of_plane: OutOfPlane,
    /// The displacement increment of one static solve, mm, > 0 \[0.25\]; the first 2.5 mm
    /// of a monotonic run take a fifth of it ([`InPlaneParams::path`]).
    pub step_mm: f64,
    /// A cyclic history replayed point by point, drift % (signed; the points the actuator
    /// turned at, in the order it reached them, as a specimen's measured curve gives them:
    /// [`crate::loading::inplane_loops::turning_points`]): 0 → r₁ → r₂ → … → rₙ, each
    /// leg in increments of `step_mm` or a `quarter_increments`-th of the larger of its
    /// two ends' drifts, whichever is smaller (the ladder's increments on a ladder's
    /// points). It is given with a cyclic history only, never with `amplitudes_pct`;
    /// `cycles` is not read with it; every |rᵢ| is at most
    /// `drift_pct` and no two consecutive points are equal \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reversals_pct: Option<Vec<f64>>,
    /// The fewest static solves of a quarter cycle (0 → a, a → 0, …) of a cyclic history,
    /// ≥ 2 \[8\]: a quarter cycle takes increments of `step_mm` or a `quarter_increments`-th
    /// of its amplitude, whichever is smaller (the first increments of a run and of each
    /// reversal are finer still, see the driver).
    pub quarter_increments: u32,
    /// A monotonic history's −x direction read too, as the mirror image of the +x push
    /// (the model's ± asymmetry, [`InPlaneResult::mirror`](super::InPlaneResult::mirror)): where the rig's
    /// eccentricity moves the wall, a second run with it mirrored. Not a key of
    /// `[in_plane]`: set by the discrepancy analysis's forward runs \[false\].
    #[serde(skip)]
    pub mirror_reading: bool,
}

impl Default for InPlaneParams {
    fn default() -> Self {
        InPlaneParams {
            sigma0_mpa: 0.5,
            shear_span_m: None,
            drift_pct: 3.0,
            history: History::Monotonic,
            amplitudes_pct: None,
            cycles: 2,
            measuring_height_m: None,
            beam_rotation: BeamRotation::Free,
            out_of_plane: OutOfPlane::Held,
            step_mm: 0.25,
            quarter_increments: 8,
            reversals_pct: None,
            mirror_reading: false,
        }
    }
}

/// The default ladder of cyclic amplitudes, drift %.
const LADDER_PCT: [f64; 11] = [0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0];

impl InPlaneParams {
    /// Checks the ranges that need no layout.
    ///
    /// # Errors
    /// The first key out of its range, named.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        check_ranges(&[
            (
                "sigma0_mpa",
                self.sigma0_mpa,
                self.sigma0_mpa > 0.0 && self.sigma0_mpa <= 1e3,
                "in (0, 1000] (the vertical stress applied, MPa; above any stone's compressive strength past that)",
            ),
            ("drift_pct", self.drift_pct, self.drift_pct > 0.0 && self.drift_pct <= 50.0, "in (0, 50]"),
            ("step_mm", self.step_mm, self.step_mm > 0.0, "> 0"),
            ("cycles", f64::from(self.cycles), self.cycles >= 1, ">= 1"),
            (
                "quarter_increments",
                f64::from(self.quarter_increments),
                (2..=MAX_QUARTER_INCREMENTS).contains(&self.quarter_increments),
                "in [2, 1000] (static solves per quarter cycle; the default is 8)",
            ),
            ("cycles", f64::from(self.cycles), self.cycles <= MAX_CYCLES, "at most 100 per amplitude"),
        ])?;
        if let (BeamRotation::Free, Some(h0)) = (self.beam_rotation, self.shear_span_m) {
            check_ranges(&[("shear_span_m", h0, h0 > 0.0, "> 0")])?;
        }
        if let Some(hm) = self.measuring_height_m {
            check_ranges(&[("measuring_height_m", hm, hm > 0.0 && hm.is_finite(), "> 0 (m above the base)")])?;
        }
        if self.beam_rotation == BeamRotation::Free && self.shear_span_m.is_none() {
            return Err(OutOfRange::without_value(
                "shear_span_m",
                "given: a free beam rotation needs the height of the horizontal force (H0, m)",
            ));
        }
        if let Some(r) = &self.reversals_pct {
            if self.history != History::Cyclic {
                return Err(OutOfRange::without_value("reversals_pct", "given with history = \"cyclic\" only"));
            }
            if self.amplitudes_pct.is_some() {
                return Err(OutOfRange::without_value(
                    "amplitudes_pct",
                    "not given with reversals_pct (the replayed points are the history)",
                ));
            }
            if r.is_empty() {
                return Err(OutOfRange::without_value("reversals_pct", "not empty"));
            }
            for (i, &v) in r.iter().enumerate() {
                check_ranges(&[(
                    "reversals_pct",
                    v,
                    v.is_finite() && v.abs() <= self.drift_pct,
                    "each within ±drift_pct (drift %, signed)",
                )])?;
                let before = if i == 0 { 0.0 } else { r[i - 1] };
                if v == before {
                    return Err(OutOfRange::new(
                        "reversals_pct",
                        v,
                        "no point equal to the one before it (the first: not 0, where the history starts)",
                    ));
                }
            }
        }
        if let Some(a) = &self.amplitudes_pct {
            if a.is_empty() {
                return Err(OutOfRange::without_value("amplitudes_pct", "not empty"));
            }
            for (i, &v) in a.iter().enumerate() {
                check_ranges(&[("amplitudes_pct", v, v > 0.0 && v <= self.drift_pct, "in (0, drift_pct]")])?;
                if i > 0 && v <= a[i - 1] {
                    return Err(OutOfRange::new(
                        "amplitudes_pct",
                        v,
                        "strictly growing: a cyclic history whose amplitude does not grow",
                    ));
                }
            }
        }
        Ok(())
    }

    /// A key given that no run of these parameters reads, with the reason; `any_cyclic`:
    /// whether any run is cyclic (a study's `[in_plane]` table is shared by its groups,
    /// each with its own history). The cyclic history's keys (`amplitudes_pct`, and
    /// `cycles`, `quarter_increments` away from their defaults) when no run is cyclic; the
    /// shear span with the beam's rotation held. A study refuses it by name, as the
    /// command line refuses the flags, rather than run without it.
    pub fn unread_key(&self, any_cyclic: bool) -> Option<(&'static str, &'static str)> {
        let d = InPlaneParams::default();
        let cyclic_only = "is read only by a cyclic history, and every run here is monotonic";
        if !any_cyclic {
            if self.amplitudes_pct.is_some() {
                return Some(("amplitudes_pct", cyclic_only));
            }
            if self.cycles != d.cycles {
                return Some(("cycles", cyclic_only));
            }
            if self.quarter_increments != d.quarter_increments {
                return Some(("quarter_increments", cyclic_only));
            }
        }
        if self.beam_rotation == BeamRotation::Fixed && self.shear_span_m.is_some() {
            return Some((
                "shear_span_m",
                "is not read with beam_rotation = \"fixed\" (the beam held level has no shear span)",
            ));
        }
        None
    }

    /// Checks that the path of a wall of height `height_m` (the lever of
    /// [`InPlaneParams::path`]) is at most [`MAX_INCREMENTS`] static solves.
    ///
    /// # Errors
    /// Naming `step_mm` (monotonic), `reversals_pct` (their count) or `cycles` (cyclic).
    pub fn check_path(&self, height_m: f64) -> Result<(), OutOfRange> {
        // The count of the path's solves, leg by leg, as `path` makes them (no path built:
        // a history past the bound would take its memory).
        let mut count = 0.0;
        self.legs(height_m, &mut |from, to, inc| count += ((to - from).abs() / inc).ceil().max(1.0));
        if count <= MAX_INCREMENTS as f64 {
            return Ok(());
        }
        Err(match (self.history, &self.reversals_pct) {
            (History::Monotonic, _) => OutOfRange::new(
                "step_mm",
                self.step_mm,
                "large enough that the history is at most 100000 static solves (with drift_pct)",
            ),
            (History::Cyclic, Some(r)) => OutOfRange::new(
                "reversals_pct",
                r.len() as f64,
                "a history of at most 100000 static solves: every leg takes at least quarter_increments solves \
                 and at most one per step_mm (fewer reversals, or fewer quarter_increments)",
            ),
            (History::Cyclic, None) => OutOfRange::new(
                "cycles",
                f64::from(self.cycles),
                "few enough, with amplitudes_pct, for a history of at most 100000 static solves: every quarter \
                 cycle takes at least quarter_increments solves and at most one per step_mm",
            ),
        })
    }

    /// The cyclic amplitudes, drift %: the given ones, or the default ladder up to
    /// `drift_pct` (ending at `drift_pct`).
    pub fn amplitudes(&self) -> Vec<f64> {
        if let Some(a) = &self.amplitudes_pct {
            return a.clone();
        }
        let mut a: Vec<f64> = LADDER_PCT.iter().copied().filter(|&v| v < self.drift_pct - 1e-9).collect();
        let mut next = 4.0;
        while a.last().is_some_and(|&l| l >= 3.0) && next < self.drift_pct - 1e-9 {
            a.push(next);
            next += 1.0;
        }
        a.push(self.drift_pct);
        a
    }

    /// The imposed displacements of the beam's anchor, m from the start, one per static
    /// solve, the drifts acting over the lever `height_m` (the driver gives the shear span
    /// with the beam's rotation free, the wall's height with it held): monotonic, increments of a fifth of
    /// `step_mm` up to 10 steps, then `step_mm`; cyclic, each quarter cycle in increments
    /// of `step_mm` or a `quarter_increments`-th of the amplitude, whichever is smaller.
    pub fn path(&self, height_m: f64) -> Vec<f64> {
        let mut path = Vec::new();
        self.legs(height_m, &mut |from, to, inc| {
            let n = ((to - from).abs() / inc).ceil().max(1.0) as usize;
            for k in 1..=n {
                path.push(from + (to - from) * k as f64 / n as f64);
            }
        });
        path
    }

    /// Whether the history pushes the wall the negative way: a cyclic history of the ladder,
    /// or one whose replayed reversals ([`InPlaneParams::reversals_pct`]) turn at a negative
    /// drift. A history that never does has no negative direction to read (its unloading
    /// back to zero overshoots by the joints' elastic recovery alone).
    pub fn pushes_negative(&self) -> bool {
        self.history == History::Cyclic && self.reversals_pct.as_deref().is_none_or(|r| r.iter().any(|&x| x < 0.0))
    }

    /// The legs of [`InPlaneParams::path`]: for each, where it starts and ends (m) and the
    /// largest increment along it (m), in order.
    fn legs(&self, height_m: f64, leg: &mut dyn FnMut(f64, f64, f64)) {
        let step = self.step_mm * 1e-3;
        let mut at = 0.0;
        let mut go = |to: f64, inc: f64| {
            leg(at, to, inc);
            at = to;
        };
        match self.history {
            History::Monotonic => {
                let target = self.drift_pct / 100.0 * height_m;
                let fine = (10.0 * step).min(target);
                go(fine, step / 5.0);
                if target > fine {
                    go(target, step);
                }
            }
            History::Cyclic if self.reversals_pct.is_some() => {
                let mut from = 0.0f64;
                for &r in self.reversals_pct.as_deref().unwrap_or_default() {
                    let to = r / 100.0 * height_m;
                    let inc = step.min(to.abs().max(from.abs()) / f64::from(self.quarter_increments));
                    go(to, inc);
                    from = to;
                }
            }
            History::Cyclic => {
                for a in self.amplitudes() {
                    let amp = a / 100.0 * height_m;
                    let inc = step.min(amp / f64::from(self.quarter_increments));
                    for _ in 0..self.cycles {
                        go(amp, inc);
                        go(-amp, inc);
                        go(0.0, inc);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound counts the solves the path makes: every leg at least `quarter_increments`
    /// of them however large `step_mm` (a history of 10,000 cycles at a 100 mm step made
    /// 140,000 solves where the step alone counted 70), and it names the reversals, not the
    /// step, when they are the cause.
    #[test]
    fn the_path_bound_counts_the_solves_the_path_makes() {
        let reversals = |n: usize| Some((0..n).map(|i| if i % 2 == 0 { 0.2 } else { -0.2 }).collect::<Vec<f64>>());
        let p = InPlaneParams {
            history: History::Cyclic,
            reversals_pct: reversals(200),
            quarter_increments: 2,
            step_mm: 100.0,
            ..InPlaneParams::default()
        };
        let mut count = 0.0;
        p.legs(1.325, &mut |from, to, inc| count += ((to - from).abs() / inc).ceil().max(1.0));
        assert_eq!(count as usize, p.path(1.325).len());
        assert!(p.check_path(1.325).is_ok());
        let long = InPlaneParams { reversals_pct: reversals(60_000), ..p };
        let e = long.check_path(1.325).unwrap_err();
        assert_eq!((e.key.as_str(), e.value), ("reversals_pct", 60_000.0));
        let mono = InPlaneParams { step_mm: 1e-6, drift_pct: 3.0, ..InPlaneParams::default() };
        assert_eq!(mono.check_path(1.325).unwrap_err().key, "step_mm");
    }
}
