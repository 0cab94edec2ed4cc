//! The in-plane shear–compression test of a wall (the masonry laboratory's most common wall
//! test; Vasconcelos & Lourenço 2009, J. Struct. Eng. 135(10):1269; Vanin et al. 2017, Bull.
//! Earthquake Eng. 15:5435 for the database's definitions of its outputs).
//!
//! # The rig
//!
//! The wall stands on the table (the fixed foundation; its base course's joint is the table
//! joint of the layout, with the bed joints' law). A rigid **loading beam** is laid on the
//! top course ([`Rig::build`]): a block `loading_beam` over the wall's whole length and
//! thickness, of the top course's material (so the beam–wall joint has the bed joints' law),
//! as deep as twice the distance from the wall's top to the shear span (at most a quarter of
//! the wall's height, at least a twentieth). Its degrees of freedom
//! ([`crate::dem::constraint`]):
//!
//! * **vertical**: free, under a constant force `N = σ0 · L · t` (the applied stress times the
//!   wall's plan area), the beam's own weight included in it; the wall's self-weight comes on
//!   top, so the axial force at the base is `N_total = N + W_wall`;
//! * **horizontal (x)**: held at the actuator's point, the *shear span* `H0` above the base
//!   (the anchor), and moved by the imposed displacement, quasi-statically: one static solve
//!   (dynamic relaxation to the penalty tolerance) per increment. The actuator's force `V`
//!   is the reaction of that hold;
//! * **rotation in the plane (about y)**: free (cantilever: the horizontal force acts at
//!   `H0`, where the moment is zero, the tests' case) or held (double-fixed, no shear span);
//! * **out of plane** (y, and the rotations about x and z): held by the rig's guides.
//!
//! # The history
//!
//! Monotonic to a drift ([`InPlaneParams::drift_pct`]), or cycles of growing amplitude
//! ([`History::Cyclic`]: each amplitude [`InPlaneParams::cycles`] times, 0 → +a → −a → 0).
//! The displacement is read on the beam at the *measuring point*
//! ([`InPlaneParams::measuring_height_m`]; unset, the actuator's height: the shear span `H0`
//! with the beam's rotation free, the wall's top with it held), and the drift is that
//! displacement over the measuring point's height. This is the Stone Masonry Database's
//! reading (Vanin et al. 2017): where a test reports no measuring height (`HLVDT_mm`
//! empty), the displacement is taken at the actuator's height, and every curve and
//! envelope file gives `drift_% = displacement_mm / H0 × 100`. The initial stiffness
//! (kN/mm) is read on the same displacement.
//!
//! # The outputs (the database's definitions, Vanin et al. 2017)
//!
//! The curve (top displacement mm, drift %, force kN). Per direction: the peak force and the
//! drift where it was reached; the ultimate drift, where the force on the envelope (the
//! points at a new largest drift of the direction) first falls below 80 % of the peak past
//! it, or the largest drift run; the initial stiffness, the secant at 15 % of the peak
//! (kN/mm). The mechanism ([`InPlaneMechanism`], read from the blocks' motion): rocking
//! about a toe, sliding of a bed joint, a stepped diagonal (shear) crack, or mixed.
//!
//! # Closed forms
//!
//! A monolithic wall rocking about its toe carries `V = N_total · L / (2 H0)`; a wall whose
//! joints slide before it rocks carries `V = μ N_total` (μ of the sliding joint); a one-block
//! wall on a linear joint of normal and shear stiffness Kn, Ks has the elastic stiffness
//! [`one_block_stiffness`] (`drystone verify`, `tests/suite/inplane.rs`).

use super::settle::{settle, SettleError};
use crate::dem::contact::types::Contact;
use crate::dem::motion::poses;
use crate::dem::{solve_static, Cascade, DemError, DofConstraint, End, Hold, Simulation, SolverParams, StaticSolve};
use crate::geometry::ConvexBlock;
use crate::layout::{Block, Layout, VerticalLoadRig};
use crate::math::Vec3;
use crate::range::{check_ranges, OutOfRange};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The id of the loading beam's block in the rig's layout.
pub const BEAM_ID: &str = "loading_beam";

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

/// The drop of the force past the peak that defines the ultimate drift (Vanin et al. 2017):
/// 20 %.
pub const ULTIMATE_DROP: f64 = 0.2;

/// The share of the peak force at which the initial (secant) stiffness is read (Vanin et
/// al. 2017): 15 %.
pub const STIFFNESS_SHARE: f64 = 0.15;

/// How far below the wall's top a block's top may lie and still carry the beam, as a share
/// of the wall's height \[0.002\] (2.4 mm on a 1.2 m wall: sawn stone's tolerance).
pub const LEVEL_TOLERANCE_FRACTION: f64 = 0.002;

/// The share of the wall's length the blocks carrying the beam must cover \[0.8\].
pub const BEARING_SHARE: f64 = 0.8;

/// A joint takes part in the mechanism when its largest relative motion is at least this
/// share of the beam's \[0.05\].
pub const ACTIVE_JOINT_SHARE: f64 = 0.05;

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
    /// The largest drift, %, in (0, 50] \[3\].
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
    /// (the model's ± asymmetry, [`InPlaneResult::mirror`]): where the rig's
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
            return Err(OutOfRange::new(
                "shear_span_m",
                f64::NAN,
                "given: a free beam rotation needs the height of the horizontal force (H0, m)",
            ));
        }
        if let Some(r) = &self.reversals_pct {
            if self.history != History::Cyclic {
                return Err(OutOfRange::new("reversals_pct", f64::NAN, "given with history = \"cyclic\" only"));
            }
            if self.amplitudes_pct.is_some() {
                return Err(OutOfRange::new(
                    "amplitudes_pct",
                    f64::NAN,
                    "not given with reversals_pct (the replayed points are the history)",
                ));
            }
            if r.is_empty() {
                return Err(OutOfRange::new("reversals_pct", f64::NAN, "not empty"));
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
                return Err(OutOfRange::new("amplitudes_pct", f64::NAN, "not empty"));
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
    /// Naming `step_mm` with the count.
    pub fn check_path(&self, height_m: f64) -> Result<(), OutOfRange> {
        let travel: f64 = match self.history {
            History::Monotonic => self.drift_pct / 100.0 * height_m,
            History::Cyclic => match &self.reversals_pct {
                Some(r) => {
                    let legs: f64 = r.iter().scan(0.0, |at, &v| Some((v - std::mem::replace(at, v)).abs())).sum();
                    legs / 100.0 * height_m
                }
                None => 4.0 * f64::from(self.cycles) * self.amplitudes().iter().sum::<f64>() / 100.0 * height_m,
            },
        };
        if travel / (self.step_mm * 1e-3) > MAX_INCREMENTS as f64 {
            return Err(OutOfRange::new(
                "step_mm",
                self.step_mm,
                "large enough that the history is at most 100000 static solves (with drift_pct, amplitudes_pct and cycles)",
            ));
        }
        Ok(())
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
        let step = self.step_mm * 1e-3;
        let mut path = Vec::new();
        let mut at = 0.0;
        let mut go = |path: &mut Vec<f64>, to: f64, inc: f64| {
            let n = ((to - at).abs() / inc).ceil().max(1.0) as usize;
            let from = at;
            for k in 1..=n {
                path.push(from + (to - from) * k as f64 / n as f64);
            }
            at = to;
        };
        match self.history {
            History::Monotonic => {
                let target = self.drift_pct / 100.0 * height_m;
                let fine = (10.0 * step).min(target);
                go(&mut path, fine, step / 5.0);
                if target > fine {
                    go(&mut path, target, step);
                }
            }
            History::Cyclic if self.reversals_pct.is_some() => {
                let mut from = 0.0f64;
                for &r in self.reversals_pct.as_deref().unwrap_or_default() {
                    let to = r / 100.0 * height_m;
                    let inc = step.min(to.abs().max(from.abs()) / f64::from(self.quarter_increments));
                    go(&mut path, to, inc);
                    from = to;
                }
            }
            History::Cyclic => {
                for a in self.amplitudes() {
                    let amp = a / 100.0 * height_m;
                    let inc = step.min(amp / f64::from(self.quarter_increments));
                    for _ in 0..self.cycles {
                        go(&mut path, amp, inc);
                        go(&mut path, -amp, inc);
                        go(&mut path, 0.0, inc);
                    }
                }
            }
        }
        path
    }
}

/// Errors of the in-plane test.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum InPlaneError {
    /// A parameter out of its range.
    #[error("in_plane.{0}")]
    Parameter(OutOfRange),
    /// A solver setting out of its range.
    #[error("solver: {0}")]
    Solver(OutOfRange),
    /// The measuring point is below the wall's top.
    #[error(
        "in_plane.measuring_height_m = {measuring_height_m} m is below the wall's height {height_m} m: the displacement is read on the loading beam, on top of the wall"
    )]
    MeasuringPoint {
        /// The measuring point's height, m.
        measuring_height_m: f64,
        /// The wall's height, m.
        height_m: f64,
    },
    /// The shear span is below the wall's top.
    #[error(
        "in_plane.shear_span_m = {shear_span_m} m is below the wall's height {height_m} m: the horizontal force acts on the beam, on top of the wall"
    )]
    ShearSpan {
        /// The shear span given, m.
        shear_span_m: f64,
        /// The wall's height, m.
        height_m: f64,
    },
    /// The shear span or the measuring point is implausibly far above the wall.
    #[error(
        "in_plane.{key} = {value_m} m is more than {ratio} times the wall's height {height_m} m: a probable unit mistake (millimetres for metres?); it is a height on the loading beam, above the wall's top"
    )]
    TooHigh {
        /// The key (`shear_span_m`, `measuring_height_m`).
        key: &'static str,
        /// The value given, m.
        value_m: f64,
        /// The wall's height, m.
        height_m: f64,
        /// [`MAX_HEIGHT_RATIO`].
        ratio: f64,
    },
    /// The top course is not level enough to carry the beam.
    #[error(
        "the top course is not level enough to carry the loading beam: block {block} tops at {top_m:.4} m, {below_mm:.1} mm below the wall's top {height_m:.4} m, and the blocks within {tolerance_mm:.1} mm of the top cover {covered_pct:.0} % of the wall's length (at least {need_pct:.0} % needed)"
    )]
    NotLevel {
        /// The highest block below the level band.
        block: String,
        /// Its top, m.
        top_m: f64,
        /// How far below the top, mm.
        below_mm: f64,
        /// The wall's height, m.
        height_m: f64,
        /// The level tolerance, mm.
        tolerance_mm: f64,
        /// The share of the length covered by level blocks, %.
        covered_pct: f64,
        /// The share needed, %.
        need_pct: f64,
    },
    /// The layout does not stand under gravity alone.
    #[error(transparent)]
    DoesNotStand(SettleError),
    /// The wall does not stand under the vertical force.
    #[error(
        "the wall does not stand under the vertical force of {force_kn:.1} kN: block {block} moved {moved_mm:.2} mm (at most {allowed_mm:.2} mm, what its joints' closure explains){}", if *.equilibrium { "" } else { ", and no equilibrium was reached" }
    )]
    UnderVerticalForce {
        /// The block that moved most.
        block: String,
        /// How far, mm.
        moved_mm: f64,
        /// The tolerance, mm.
        allowed_mm: f64,
        /// The vertical force, kN.
        force_kn: f64,
        /// Whether the relaxation reached equilibrium.
        equilibrium: bool,
    },
    /// The engine blew up.
    #[error(transparent)]
    Dem(#[from] DemError),
    /// The non-smooth solver refused the layout or blew up.
    #[error(transparent)]
    Nscd(#[from] crate::nscd::NscdError),
    /// The layout's geometry is degenerate for the beam.
    #[error("the loading beam cannot be built on this layout: {0}")]
    Beam(String),
    /// A cyclic history by the penalty DEM on joints too stiff in shear for it
    /// ([`MIN_CYCLIC_SLIP_RANGE_M`]).
    #[error(
        "material {material}: its joints' elastic slip range tan φ σ0 / Ks = {range_um:.2} µm (φ {friction_deg:.1}°, Ks {ks_pa_per_m:.3e} Pa/m, σ0 {sigma0_mpa} MPa) is below the {min_um:.0} µm a cyclic history by the penalty DEM needs: the path's own errors within an increment exceed it, the joints slip against the load and their friction falls over the cycles. Run it monotonic, with --solver nscd (rigid joints, which reverse exactly), or with Ks at most {ks_max_pa_per_m:.3e} Pa/m"
    )]
    CyclicSlipRange {
        /// The material's index in the layout.
        material: usize,
        /// Its elastic slip range, µm.
        range_um: f64,
        /// Its friction angle, degrees.
        friction_deg: f64,
        /// Its shear stiffness, Pa/m.
        ks_pa_per_m: f64,
        /// The vertical stress, MPa.
        sigma0_mpa: f64,
        /// [`MIN_CYCLIC_SLIP_RANGE_M`], µm.
        min_um: f64,
        /// The largest Ks that gives the range at this φ and σ0, Pa/m.
        ks_max_pa_per_m: f64,
    },
    /// Joints that the vertical stress closes past the penalty DEM's small overlaps
    /// ([`MAX_CLOSURE_SHARE`]).
    #[error(
        "material {material}: the vertical stress σ0 {sigma0_mpa} MPa closes its joints by σ0 / Kn = {closure_mm:.3} mm (Kn {kn_pa_per_m:.3e} Pa/m), {share_pct:.1} % of the lowest block's height ({height_mm:.1} mm); the penalty DEM's contacts hold for overlaps up to {max_pct:.0} % of it, a σ0 of at most {sigma0_max_mpa:.3} MPa on these joints. Check the stress's unit (MPa) and Kn, or run --solver nscd or limit (rigid joints)"
    )]
    JointClosure {
        /// The material's index in the layout.
        material: usize,
        /// The vertical stress, MPa.
        sigma0_mpa: f64,
        /// The joints' closure `σ0 / Kn`, mm.
        closure_mm: f64,
        /// Its normal stiffness, Pa/m.
        kn_pa_per_m: f64,
        /// The closure over the lowest block's height, %.
        share_pct: f64,
        /// The lowest block's height, mm.
        height_mm: f64,
        /// [`MAX_CLOSURE_SHARE`], %.
        max_pct: f64,
        /// The largest σ0 the bound allows on these joints, MPa.
        sigma0_max_mpa: f64,
    },
    /// The method chosen does not run this form of the test (the protocol seam's
    /// refusal, or a setting the method cannot state), as text.
    #[error("{0}")]
    Unsupported(String),
}

/// The least elastic slip range `tan φ σ0 / Ks` of a joint that a cyclic history by the
/// penalty DEM accepts, m (20 µm). Below it the path's own errors within an increment (the
/// predictor's mismatch, the relaxation's swing, out of plane and in torsion) exceed the
/// slip a joint takes elastically, so joints slip in senses the load does not drive and
/// their friction falls over the cycles. Measured on one block under σ0 = 0.5 MPa on a base
/// of φ 10° (μN 18.7 kN), cycled to ±0.25 and ±0.5 % twice at the defaults, the least force
/// 0.2 mm past a reversal: Ks 4e9 Pa/m (22 µm) 16.5–18.7 kN, 1e10 (8.8 µm) 13.9 kN, 4e10
/// (2.2 µm) 4.1 kN, 4e11 (0.22 µm) −9.5 kN, against the motion for whole half-cycles.
/// The granite walls' joints (Ks 1e9 Pa/m) have about 300 µm at 0.5 MPa. A monotonic
/// history does not reverse and is not refused; nscd's rigid joints reverse exactly.
pub const MIN_CYCLIC_SLIP_RANGE_M: f64 = 20e-6;

/// Refuses a cyclic history by the penalty DEM on a layout whose joints' elastic slip
/// range at the applied vertical stress is below [`MIN_CYCLIC_SLIP_RANGE_M`], naming the
/// material of the least range (its index in the layout), the range, and the Ks that would
/// give it.
///
/// # Errors
/// [`InPlaneError::CyclicSlipRange`].
pub fn check_cyclic_slip_range(wall: &Layout, params: &InPlaneParams) -> Result<(), InPlaneError> {
    if params.history != History::Cyclic {
        return Ok(());
    }
    let sigma0 = params.sigma0_mpa * 1e6;
    let range = |m: &crate::layout::Material| m.friction.tan() * sigma0 / m.ks;
    let least = wall.materials.iter().enumerate().min_by(|a, b| range(a.1).total_cmp(&range(b.1)));
    match least {
        Some((k, m)) if range(m) < MIN_CYCLIC_SLIP_RANGE_M => Err(InPlaneError::CyclicSlipRange {
            material: k,
            range_um: range(m) * 1e6,
            friction_deg: m.friction.to_degrees(),
            ks_pa_per_m: m.ks,
            sigma0_mpa: params.sigma0_mpa,
            min_um: MIN_CYCLIC_SLIP_RANGE_M * 1e6,
            ks_max_pa_per_m: m.friction.tan() * sigma0 / MIN_CYCLIC_SLIP_RANGE_M,
        }),
        _ => Ok(()),
    }
}

/// The largest closure of a joint under the vertical stress that the penalty DEM accepts,
/// as a share of the lowest block's height \[0.01\]. The penalty method reads a contact's
/// force from the blocks' overlap on the geometry as laid, which holds while overlaps are
/// small beside the blocks (Cundall & Hart 1992, "Numerical modelling of discontinua",
/// Eng. Comput. 9:101; 3DEC's guidance on the choice of Kn): past about a percent of a
/// block's height the sub-contacts' faces turn and slide into each other and the forces
/// stop being the joint's law. A stress that closes linear joints (`q = Kn u`) further is
/// a unit mistake or a joint far softer than stone's; at σ0 = 1000 MPa the granite wall
/// (Kn 2e10 Pa/m, courses of about 0.15 m) would close each joint by 50 mm, and its run
/// blew up or gave a force of the wrong sign throughout; its bound is some 30 MPa. Joints with a nonlinear closure law are bounded by their law.
pub const MAX_CLOSURE_SHARE: f64 = 0.01;

/// Refuses a run by the penalty DEM whose vertical stress closes a material's linear joints
/// (`σ0 / Kn`) by more than [`MAX_CLOSURE_SHARE`] of the lowest block's height, naming the
/// material.
///
/// # Errors
/// [`InPlaneError::JointClosure`].
pub fn check_joint_closure(wall: &Layout, params: &InPlaneParams) -> Result<(), InPlaneError> {
    let height =
        wall.blocks.iter().filter(|b| !b.fixed).map(|b| b.shape.aabb().extent().z).fold(f64::INFINITY, f64::min);
    if !height.is_finite() {
        return Ok(());
    }
    let sigma0 = params.sigma0_mpa * 1e6;
    let worst = wall
        .materials
        .iter()
        .enumerate()
        .filter(|(_, m)| m.closure.is_linear())
        .min_by(|a, b| a.1.kn.total_cmp(&b.1.kn));
    match worst {
        Some((k, m)) if sigma0 / m.kn > MAX_CLOSURE_SHARE * height => Err(InPlaneError::JointClosure {
            material: k,
            sigma0_mpa: params.sigma0_mpa,
            closure_mm: sigma0 / m.kn * 1e3,
            kn_pa_per_m: m.kn,
            share_pct: 100.0 * sigma0 / m.kn / height,
            height_mm: height * 1e3,
            max_pct: 100.0 * MAX_CLOSURE_SHARE,
            sigma0_max_mpa: MAX_CLOSURE_SHARE * height * m.kn * 1e-6,
        }),
        _ => Ok(()),
    }
}

/// The rig: the wall's layout with the loading beam, and what the test needs of them.
#[derive(Debug, Clone)]
pub struct Rig {
    /// The layout with the beam as its last block.
    pub layout: Layout,
    /// The beam's block index.
    pub beam: usize,
    /// Wall length L (x extent), height H (z extent), thickness t (y extent), m.
    pub length_m: f64,
    /// See `length_m`.
    pub height_m: f64,
    /// See `length_m`.
    pub thickness_m: f64,
    /// The wall's lowest x, m (the toes are at `x_min` and `x_min + L`).
    pub x_min: f64,
    /// The applied vertical force `σ0 L t`, N.
    pub vertical_force_n: f64,
    /// The wall's self-weight (the beam excluded), N.
    pub wall_weight_n: f64,
    /// The beam's weight, N (part of `vertical_force_n`).
    pub beam_weight_n: f64,
    /// The height of the horizontal force (the anchor), m: `H0`, or the beam's centroid
    /// with a held rotation.
    pub anchor_z_m: f64,
    /// The beam's centroid height, m.
    pub beam_z_m: f64,
    /// The height of the measuring point, m ([`InPlaneParams::measuring_height_m`], or the
    /// actuator's height: `H0` with the beam's rotation free, the wall's height with it
    /// held). The drift is the displacement there over this height.
    pub measure_z_m: f64,
}

impl Rig {
    /// The axial force at the base, `N + W_wall`, N.
    pub fn n_total_n(&self) -> f64 {
        self.vertical_force_n + self.wall_weight_n
    }

    /// Builds the rig on `wall`: checks the shear span and the top course's level, and lays
    /// the beam (see the module doc).
    ///
    /// # Errors
    /// [`InPlaneError::Parameter`], [`InPlaneError::ShearSpan`], [`InPlaneError::NotLevel`]
    /// naming the block, [`InPlaneError::Beam`].
    pub fn build(wall: &Layout, params: &InPlaneParams) -> Result<Rig, InPlaneError> {
        params.validate().map_err(InPlaneError::Parameter)?;
        if wall.blocks.iter().any(|b| b.id == BEAM_ID) {
            return Err(InPlaneError::Beam(format!("the layout already has a block named {BEAM_ID}")));
        }
        let bounds = wall.bounds();
        let e = bounds.extent();
        let (length, thickness, height) = (e.x, e.y, e.z);
        if !(length > 0.0 && thickness > 0.0 && height > 0.0) {
            return Err(InPlaneError::Beam("the layout has no extent".into()));
        }
        let top = bounds.max.z;
        // The top course: the blocks within the level tolerance of the top carry the beam.
        let tol = LEVEL_TOLERANCE_FRACTION * height;
        let mut spans: Vec<(f64, f64)> = Vec::new();
        let mut highest_low: Option<(f64, &Block)> = None;
        let band = top - 0.5 * wall.blocks.iter().map(|b| b.shape.aabb().extent().z).fold(f64::INFINITY, f64::min);
        for b in &wall.blocks {
            let bb = b.shape.aabb();
            if bb.max.z >= top - tol {
                spans.push((bb.min.x, bb.max.x));
            } else if bb.max.z > band && highest_low.is_none_or(|(z, _)| bb.max.z > z) {
                highest_low = Some((bb.max.z, b));
            }
        }
        spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut covered = 0.0;
        let mut reach = f64::NEG_INFINITY;
        for (a, b) in spans {
            let a = a.max(reach);
            if b > a {
                covered += b - a;
            }
            reach = reach.max(b);
        }
        if covered < BEARING_SHARE * length {
            let (z, b) = highest_low.map_or((f64::NAN, "(none)".to_string()), |(z, b)| (z, b.id.clone()));
            return Err(InPlaneError::NotLevel {
                block: b,
                top_m: z,
                below_mm: (top - z) * 1e3,
                height_m: top,
                tolerance_mm: tol * 1e3,
                covered_pct: 100.0 * covered / length,
                need_pct: 100.0 * BEARING_SHARE,
            });
        }
        let (depth, anchor_z) = match params.beam_rotation {
            BeamRotation::Free => {
                let h0 = params.shear_span_m.expect("validated");
                if h0 < top - 1e-9 {
                    return Err(InPlaneError::ShearSpan { shear_span_m: h0, height_m: top });
                }
                if h0 > MAX_HEIGHT_RATIO * top {
                    return Err(InPlaneError::TooHigh {
                        key: "shear_span_m",
                        value_m: h0,
                        height_m: top,
                        ratio: MAX_HEIGHT_RATIO,
                    });
                }
                ((2.0 * (h0 - top)).clamp(0.05 * height, 0.25 * height), h0)
            }
            BeamRotation::Fixed => (0.1 * height, top + 0.05 * height),
        };
        let lever = match params.beam_rotation {
            BeamRotation::Free => anchor_z,
            BeamRotation::Fixed => top,
        };
        params.check_path(lever).map_err(InPlaneError::Parameter)?;
        let measure_z = params.measuring_height_m.unwrap_or(lever);
        if measure_z < top - 1e-9 {
            return Err(InPlaneError::MeasuringPoint { measuring_height_m: measure_z, height_m: top });
        }
        if measure_z > MAX_HEIGHT_RATIO * top {
            return Err(InPlaneError::TooHigh {
                key: "measuring_height_m",
                value_m: measure_z,
                height_m: top,
                ratio: MAX_HEIGHT_RATIO,
            });
        }
        let (x0, x1, y0, y1) = (bounds.min.x, bounds.max.x, bounds.min.y, bounds.max.y);
        let corners: Vec<Vec3> = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
            .iter()
            .flat_map(|&(x, y)| [Vec3::new(x, y, top), Vec3::new(x, y, top + depth)])
            .collect();
        let shape = ConvexBlock::from_vertices(&corners).map_err(|e| InPlaneError::Beam(e.to_string()))?;
        // The beam's material: that of the highest block (the top course's), so that the
        // beam–wall joint has the bed joints' law.
        let material = wall
            .blocks
            .iter()
            .max_by(|a, b| a.shape.aabb().max.z.total_cmp(&b.shape.aabb().max.z))
            .map_or(0, |b| b.material);
        let g = wall.gravity;
        let volume = |s: &ConvexBlock| s.volume();
        let wall_weight: f64 = wall
            .blocks
            .iter()
            .filter(|b| !b.fixed)
            .map(|b| wall.materials[b.material].density * volume(&b.shape))
            .sum::<f64>()
            * g;
        let beam_weight = wall.materials[material].density * volume(&shape) * g;
        let vertical_force_n = params.sigma0_mpa * 1e6 * length * thickness;
        if vertical_force_n < beam_weight {
            return Err(InPlaneError::Parameter(OutOfRange::new(
                "sigma0_mpa",
                params.sigma0_mpa,
                "at least the loading beam's own weight over the wall's plan area (the beam is part of the applied force)",
            )));
        }
        let mut layout = wall.clone();
        layout.blocks.push(Block {
            id: BEAM_ID.to_string(),
            material,
            shape,
            fixed: false,
            course: None,
            wedge: false,
        });
        let beam = layout.blocks.len() - 1;
        Ok(Rig {
            layout,
            beam,
            length_m: length,
            height_m: top,
            thickness_m: thickness,
            x_min: x0,
            vertical_force_n,
            wall_weight_n: wall_weight,
            beam_weight_n: beam_weight,
            anchor_z_m: anchor_z,
            beam_z_m: top + 0.5 * depth,
            measure_z_m: measure_z,
        })
    }

    /// The beam's constraint at its pose in `sim` (see the module doc): x held at the
    /// anchor, y and the rotations about x and z held, the rotation about y held if
    /// `rotation` is [`BeamRotation::Fixed`].
    pub fn constraint(&self, sim: &Simulation, rotation: BeamRotation) -> DofConstraint {
        self.constraint_of(&sim.state.bodies[self.beam], rotation)
    }

    /// The beam's constraint at the pose of its body `b` (any engine's; see
    /// [`Rig::constraint`]).
    pub fn constraint_of(&self, b: &crate::dem::state::Body, rotation: BeamRotation) -> DofConstraint {
        let anchor = Vec3::new(0.0, 0.0, self.anchor_z_m - b.pos.z);
        let c = DofConstraint { anchor, ..DofConstraint::free() }
            .hold_translation(b, 0)
            .hold_translation(b, 1)
            .hold_rotation(0)
            .hold_rotation(2);
        match rotation {
            BeamRotation::Free => c,
            BeamRotation::Fixed => c.hold_rotation(1),
        }
    }

    /// Adds to each point of `curve` what the rig's terms that the readings carry add to
    /// it (`Layout::vertical_load_rig`, [`add_rig_force`]); nothing for an ideal rig.
    pub fn add_vertical_load_rig(&self, curve: &mut [CurvePoint]) {
        add_rig_force(self.layout.vertical_load_rig, self.vertical_force_n, self.measure_z_m, curve);
    }

    /// The moment the rig's terms that move the wall apply to the beam about y, with the
    /// beam's pose `beam` as its reference (`Layout::vertical_load_rig`: `e0 P`, `−κ P u_c`
    /// and `−K_θ θ`, P the force the jacks apply, `N − W_beam`); `None` when the rig has no
    /// term that moves the wall.
    pub fn beam_moment(&self, beam: &crate::dem::state::Body) -> Option<crate::dem::RigMoment> {
        let r = &self.layout.vertical_load_rig;
        let p = self.vertical_force_n - self.beam_weight_n;
        r.moves_wall().then(|| crate::dem::RigMoment {
            axis: 1,
            along: 0,
            at_reference_nm: r.eccentricity_m * p,
            per_displacement_n: -r.fixed_share * p,
            per_rotation_nm: -r.rotational_stiffness_nm_per_rad,
            reference_pos: beam.pos,
            reference_rot: beam.rot,
        })
    }

    /// The rigid rocking capacity of the monolithic wall, N: `N_total L / (2 H0)` with the
    /// beam's rotation free; with it held (double curvature: the wall turns about its toe
    /// and bears on the level beam at its opposite top corner), `(N L + W L / 2) / H`.
    pub fn rocking_force_n(&self, rotation: BeamRotation) -> f64 {
        match rotation {
            BeamRotation::Free => self.n_total_n() * self.length_m / (2.0 * self.anchor_z_m),
            BeamRotation::Fixed => (self.vertical_force_n + 0.5 * self.wall_weight_n) * self.length_m / self.height_m,
        }
    }
}

/// Adds to each point of `curve` what the rig's terms that the readings carry
/// ([`VerticalLoadRig::reads_only`]) add to it under the applied vertical force `n` (N):
/// to the force, `n (u / L + μ_r sgn(u̇) + tan β)`, u the point's displacement, u̇'s sense
/// that of the increment that led to it (none at the first point); then to the displacement
/// the series compliance's `c V` (V the force so read) and to the drift its share over the
/// measuring point's height `measure_z_m` (m). Nothing for an ideal rig. The one place the
/// rig's readings enter a curve: [`Rig::add_vertical_load_rig`] in a run, [`read_curve`] on
/// a run's curve of the wall's own shear.
pub fn add_rig_force(r: VerticalLoadRig, n: f64, measure_z_m: f64, curve: &mut [CurvePoint]) {
    let Some(r) = r.reads_only() else {
        return;
    };
    let mut last = None;
    for p in curve.iter_mut() {
        // The sense of the increment that led to the point (0 at the first, or none).
        let sense = last.map_or(0.0, |u0: f64| {
            let du = p.top_mm - u0;
            if du == 0.0 {
                0.0
            } else {
                du.signum()
            }
        });
        last = Some(p.top_mm);
        p.force_kn += 1e-3 * r.actuator_force_n(n, 1e-3 * p.top_mm, sense);
        if r.series_compliance_m_per_n != 0.0 {
            let extra_m = r.series_compliance_m_per_n * p.force_kn * 1e3;
            p.top_mm += extra_m * 1e3;
            p.drift_pct += 100.0 * extra_m / measure_z_m;
        }
    }
}

/// The push towards −x of a monotonic run read both ways, as its mirror image
/// ([`InPlaneResult::mirror`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mirror {
    /// The curve of the wall's own shear pushed the other way, read as its mirror image
    /// (+x): a second monotonic run with the rig's eccentricity `e0` mirrored, made where the
    /// eccentricity is not 0 (a moment on the beam whose sense the push's does not follow).
    /// `None`: the run's own `wall_curve` is its mirror (the wall's layout taken as one of
    /// an ensemble that is its own mirror image).
    pub wall_curve: Option<Vec<CurvePoint>>,
}

/// The force read and the first direction's outputs (+x, [`direction`]) of a run's curve of
/// the wall's own shear (`wall_curve`, [`InPlaneResult::wall_curve`]) under the rig's
/// terms `rig` and the applied vertical force `vertical_force_n` (N), the displacement read
/// at the height `measure_z_m` (m): the same computation as the run's own
/// ([`Rig::add_vertical_load_rig`], then [`direction`]), so that a run with `rig` and a run
/// without it read here give the same numbers, bit for bit.
pub fn read_curve(
    wall_curve: &[CurvePoint],
    rig: VerticalLoadRig,
    vertical_force_n: f64,
    measure_z_m: f64,
) -> (Vec<CurvePoint>, Option<DirectionResult>) {
    let mut curve = wall_curve.to_vec();
    add_rig_force(rig, vertical_force_n, measure_z_m, &mut curve);
    let positive = direction(&curve, 1.0);
    (curve, positive)
}

/// The elastic stiffness (N/m) of a one-block wall of length `l`, thickness `t` and height
/// `h` (weight `w`, N) on a linear joint of normal and shear stiffness `kn`, `ks` (Pa/m),
/// under the loading beam (its centroid, where the horizontal force and the vertical force
/// `n` (N, the beam's weight included) act, at the shear span `h0`) on a joint of the same
/// law, the beam's rotation free; the displacement read on the beam at the height `hm`
/// (the measuring point, at least `h`: `h0` for the actuator's point).
///
/// Small displacements with the vertical loads staying vertical (first-order P–Δ). The
/// unknowns: the force V, the base joint's rotation θ and the beam joint's ψ (about their
/// centres; rotational stiffness `Kn I`, I = t L³ / 12), each joint's shear slip `V / (Ks A)`
/// (A = L t). For an imposed beam displacement `u = 2 V / (Ks A) + θ h + (θ + ψ)(h0 − h)`:
///
/// ```text
/// Kn I θ = V h0 + n u + w (V / (Ks A) + θ h / 2)                    (base joint)
/// Kn I ψ = V (h0 − h) + n (V / (Ks A) + (θ + ψ)(h0 − h))              (beam joint)
/// ```
///
/// and the stiffness is `V / (2 V / (Ks A) + θ h + (θ + ψ)(hm − h))` (at `hm = h0`, `V / u`).
/// Without vertical load, read at the wall's top, it is `1 / (2 / (Ks A) + h0 h / (Kn I))`.
/// The block is rigid (the DEM's blocks are) and the joints stay closed (while
/// `V h0 < N_total L / 6`).
#[allow(clippy::too_many_arguments)]
pub fn one_block_stiffness(l: f64, t: f64, h: f64, h0: f64, hm: f64, kn: f64, ks: f64, n: f64, w: f64) -> f64 {
    let (a, i) = (l * t, t * l.powi(3) / 12.0);
    let (kr, c) = (kn * i, 1.0 / (ks * a));
    let e = h0 - h;
    // Unknowns (V, θ, ψ) for u = 1: rows base joint, beam joint, kinematics.
    let m = nalgebra::Matrix3::new(
        -(h0 + w * c),
        kr - w * h / 2.0,
        0.0,
        -(e + n * c),
        -n * e,
        kr - n * e,
        2.0 * c,
        h + e,
        e,
    );
    let rhs = nalgebra::Vector3::new(n, 0.0, 1.0);
    match m.lu().solve(&rhs) {
        Some(x) => x[0] / (2.0 * x[0] * c + x[1] * h + (x[1] + x[2]) * (hm - h)),
        None => f64::NAN,
    }
}

/// One point of the force–displacement curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CurvePoint {
    /// The beam's horizontal displacement at the measuring point, mm (+x positive; the
    /// database's `top_displacement`, read at [`Rig::measure_z_m`]).
    pub top_mm: f64,
    /// Drift, %: `top_mm` over the measuring point's height ([`Rig::measure_z_m`]: the
    /// shear span by default, as the database's files give it).
    pub drift_pct: f64,
    /// The actuator's horizontal force, kN (positive towards +x).
    pub force_kn: f64,
    /// Whether the static solve reached equilibrium (the unbalanced-force ratio below the
    /// tolerance, every block in balance) within its step budget, on the loading path (no
    /// block thrown from the wall: [`InPlaneResult::unconverged`]).
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
    /// The initial stiffness, secant at 15 % of the peak, kN/mm.
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

/// The kind of an in-plane mechanism.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MechanismKind {
    /// The part that moves with the beam rotates about a toe (flexural; the database's
    /// failure type 1), above a horizontal or a stepped crack.
    Rocking,
    /// One bed joint slides (shear; type 0).
    Sliding,
    /// The part that moves with the beam translates along a stepped crack through bed and
    /// head joints at several courses (diagonal shear; type 0).
    Diagonal,
    /// Rotation and translation in comparable shares (type 0.5).
    Mixed,
    /// No joint moved past the threshold.
    None,
}

impl MechanismKind {
    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            MechanismKind::Rocking => "rocking",
            MechanismKind::Sliding => "sliding",
            MechanismKind::Diagonal => "diagonal",
            MechanismKind::Mixed => "mixed",
            MechanismKind::None => "none",
        }
    }

    /// The database's failure type: 1 flexural, 0.5 mixed, 0 shear (Vanin et al. 2017);
    /// `None` for no mechanism.
    pub fn failure_type(self) -> Option<f64> {
        match self {
            MechanismKind::Rocking => Some(1.0),
            MechanismKind::Mixed => Some(0.5),
            MechanismKind::Sliding | MechanismKind::Diagonal => Some(0.0),
            MechanismKind::None => None,
        }
    }
}

/// The mechanism read from the blocks' motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InPlaneMechanism {
    /// Its kind.
    pub kind: MechanismKind,
    /// The share of the beam's horizontal motion that the moving part's rotation (about y,
    /// the mean of its blocks') about the crack's foot explains, in [0, 1]: 1 for a rotation
    /// about a toe, 0 for a translation.
    pub rotation_share: f64,
    /// The share of the crack's relative motion that is opening (normal), in [0, 1].
    pub opening_share: f64,
    /// The crack's shape: `horizontal` (bed joints at one level), `stepped` (bed and head
    /// joints at several levels), or `none`.
    pub crack: String,
    /// The moving joints (`ID_A/ID_B`, `table/ID`), in contact order.
    pub joints: Vec<String>,
    /// The heights of the moving bed joints, m, lowest first.
    pub bed_levels_m: Vec<f64>,
    /// The blocks that move with the beam (rigidly joined to it by joints that do not
    /// move), the beam excluded.
    pub moving_blocks: Vec<String>,
}

/// A joint for the mechanism reading: its bodies, normal and points (table frame).
#[derive(Debug, Clone)]
pub struct MechanismJoint {
    /// Body A (`None`: the table).
    pub a: Option<usize>,
    /// Body B.
    pub b: usize,
    /// `ID_A/ID_B` or `table/ID`.
    pub name: String,
    /// Unit normal A → B.
    pub normal: Vec3,
    /// Points on the joint, m.
    pub points: Vec<Vec3>,
}

/// The joints of a simulation's current contacts, for [`read_mechanism`].
pub fn mechanism_joints(sim: &Simulation) -> Vec<MechanismJoint> {
    let st = &sim.state;
    st.contacts
        .iter()
        .map(|c: &Contact| MechanismJoint {
            a: c.a,
            b: c.b,
            name: st.joint_name(c),
            normal: st.contact_normal(c),
            points: c
                .nodes
                .iter()
                .map(|nd| {
                    let (pa, pb) = st.node_points(c, nd);
                    0.5 * (pa + pb)
                })
                .collect(),
        })
        .collect()
}

/// Reads the mechanism of a motion of the blocks: `motion(k, x)` is the displacement (or
/// virtual velocity) of body k's material point at `x` (table frame), `ids` the bodies' ids,
/// `beam` the beam's index and `scale` the beam's motion (the relative motions are compared
/// with it). A joint moves when its largest relative motion reaches [`ACTIVE_JOINT_SHARE`]
/// of `scale`; the joints that do not move join the blocks into rigid groups, and the
/// crack is the moving joints around the beam's group (bed joints: a normal within 45° of z;
/// head joints: within 45° of x). `rotation(k)` is body k's rotation about y and `anchor`
/// the actuator's point (table frame): the mechanism is rocking where the group's rotation
/// about the crack's foot explains at least two thirds of the beam's motion at the anchor
/// (a rotation about a toe, whatever the crack's steps), shear (sliding on one bed level
/// without head joints, diagonal otherwise) where it explains at most a third (a
/// translation along the crack), mixed between.
pub fn read_mechanism(
    joints: &[MechanismJoint],
    ids: &[String],
    beam: usize,
    anchor: Vec3,
    scale: f64,
    motion: impl Fn(usize, &Vec3) -> Vec3,
    rotation: impl Fn(usize) -> f64,
) -> InPlaneMechanism {
    let n = ids.len();
    // Union of the bodies joined by joints that do not move (index n: the table).
    let mut parent: Vec<usize> = (0..=n).collect();
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    // Per moving joint: its index, opening and sliding (sums over its points).
    let mut moving: Vec<(usize, f64, f64)> = Vec::new();
    for (i, j) in joints.iter().enumerate() {
        let mut largest = 0.0_f64;
        let (mut jo, mut js) = (0.0, 0.0);
        for x in &j.points {
            let ua = j.a.map_or(Vec3::zeros(), |a| motion(a, x));
            let d = motion(j.b, x) - ua;
            let dn = d.dot(&j.normal);
            jo += dn.abs();
            js += (d - j.normal * dn).norm();
            largest = largest.max(d.norm());
        }
        if scale > 0.0 && largest >= ACTIVE_JOINT_SHARE * scale {
            moving.push((i, jo, js));
        } else {
            let (ra, rb) = (root(&mut parent, j.a.unwrap_or(n)), root(&mut parent, j.b));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // The crack: the moving joints around the group that moves with the beam (joints
    // inside it, or between blocks left behind, are not its crack).
    let rb = root(&mut parent, beam);
    let (mut open, mut slide) = (0.0, 0.0);
    let mut active = Vec::new();
    let mut levels: Vec<f64> = Vec::new();
    let mut heads = 0usize;
    for &(i, jo, js) in &moving {
        let j = &joints[i];
        if (root(&mut parent, j.a.unwrap_or(n)) == rb) == (root(&mut parent, j.b) == rb) {
            continue;
        }
        open += jo;
        slide += js;
        active.push(j.name.clone());
        if j.normal.z.abs() >= std::f64::consts::FRAC_1_SQRT_2 {
            let z = j.points.iter().map(|p| p.z).sum::<f64>() / j.points.len().max(1) as f64;
            levels.push(z);
        } else if j.normal.x.abs() >= std::f64::consts::FRAC_1_SQRT_2 {
            heads += 1;
        }
    }
    levels.sort_by(f64::total_cmp);
    let mut distinct: Vec<f64> = Vec::new();
    for z in levels {
        if distinct.last().is_none_or(|&l| z - l > 0.01) {
            distinct.push(z);
        }
    }
    let moving_blocks = (0..n).filter(|&k| k != beam && root(&mut parent, k) == rb).map(|k| ids[k].clone()).collect();
    let share = if open + slide > 0.0 { open / (open + slide) } else { 0.0 };
    // How much of the beam's motion the moving part's rotation about the crack's foot
    // explains: 1 for a rotation about a toe, 0 for a translation.
    let group: Vec<usize> = (0..n).filter(|&k| root(&mut parent, k) == rb).collect();
    let theta = group.iter().map(|&k| rotation(k)).sum::<f64>() / group.len().max(1) as f64;
    let foot = distinct.first().copied().unwrap_or(0.0).min(anchor.z);
    let u = motion(beam, &anchor).x;
    let rotating = if u.abs() > 0.0 { (theta.abs() * (anchor.z - foot) / u.abs()).min(1.0) } else { 0.0 };
    let kind = if active.is_empty() {
        MechanismKind::None
    } else if rotating >= 2.0 / 3.0 {
        MechanismKind::Rocking
    } else if rotating <= 1.0 / 3.0 {
        if distinct.len() <= 1 && heads == 0 {
            MechanismKind::Sliding
        } else {
            MechanismKind::Diagonal
        }
    } else {
        MechanismKind::Mixed
    };
    let crack = if active.is_empty() {
        "none"
    } else if distinct.len() <= 1 && heads == 0 {
        "horizontal"
    } else {
        "stepped"
    };
    InPlaneMechanism {
        kind,
        rotation_share: rotating,
        opening_share: share,
        crack: crack.to_string(),
        joints: active,
        bed_levels_m: distinct,
        moving_blocks,
    }
}

/// The outcome of an in-plane test by the penalty DEM or by non-smooth contact dynamics
/// ([`super::inplane_nscd`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InPlaneResult {
    /// The force–displacement curve, one point per static solve (the first the state under
    /// the vertical force).
    pub curve: Vec<CurvePoint>,
    /// The positive direction (+x).
    pub positive: Option<DirectionResult>,
    /// The negative direction (cyclic histories).
    pub negative: Option<DirectionResult>,
    /// The mechanism at the largest positive drift.
    pub mechanism: InPlaneMechanism,
    /// The bodies' poses there (centroid m, rotation as a scaled axis rad), layout order
    /// with the beam last, for drawing.
    #[serde(skip)]
    pub poses_at_reading: Vec<(Vec3, Vec3)>,
    /// The applied vertical force `σ0 L t`, kN.
    pub vertical_force_kn: f64,
    /// The axial force at the base, self-weight included, kN.
    pub n_total_kn: f64,
    /// The rigid rocking capacity `N_total L / (2 H0)`, kN (a reference, not a result).
    pub rocking_force_kn: f64,
    /// Wall length, height, thickness, m.
    pub length_m: f64,
    /// See `length_m`.
    pub height_m: f64,
    /// See `length_m`.
    pub thickness_m: f64,
    /// The height of the horizontal force, m.
    pub shear_span_m: f64,
    /// The height of the measuring point, m: `top_mm` is read there and the drift is
    /// `top_mm` over it ([`Rig::measure_z_m`]; 0 when read from results written before it
    /// was recorded).
    #[serde(default)]
    pub measuring_height_m: f64,
    /// The wall's vertical modulus, MPa, as the laboratory reads it from the vertical
    /// loading phase (the database's `Epc`, Vanin et al. 2017): the secant of the loading
    /// branch, the vertical stress added by the actuator's force (`(N − W_beam) / (L t)`)
    /// over the wall's shortening (the beam's settlement under it, its centroid's, over the
    /// wall's height `H`). It holds every joint of the wall's height (base, beds, the beam's
    /// bed) and the blocks are rigid, so it is about `Kn H / n_joints` for linear joints.
    /// NaN where the method has no joint compliance (non-smooth contact dynamics: rigid
    /// contacts) or when read from results written before it was recorded.
    #[serde(default = "nan")]
    pub wall_vertical_modulus_mpa: f64,
    /// The largest excursion of any block from the rigid motion of its course over the
    /// history, mm ([`super::excursion`]: the distance of its centroid from where the
    /// nearer-moving of its course neighbours carries it): a wall that stays whole keeps it
    /// to the joints' own deformation and the crack's opening beside a block; a block shed
    /// from the wall reads its walk. NaN when read from results written before it was
    /// recorded.
    #[serde(default = "nan")]
    pub largest_block_excursion_mm: f64,
    /// The block of `largest_block_excursion_mm` (empty: none moved from its course).
    #[serde(default)]
    pub excursion_block: String,
    /// The push read both ways ([`InPlaneParams::mirror_reading`]; `None`: read one way).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mirror: Option<Box<Mirror>>,
    /// Static solves that ended at the step budget rather than in equilibrium, with a
    /// block out of balance, or with a block thrown from the wall (the penalty DEM's
    /// driver: a block that walked from every joint neighbour by more than the increment
    /// can move it, once more when solved again from the increment's start) (nscd: increments with a step whose contact problem did not meet its
    /// criterion).
    pub unconverged: usize,
    /// Increments solved again from their start, warming up from the smallest increment:
    /// those whose relaxation blew up from the predicted state, and those whose relaxation
    /// threw a block off the path (the penalty DEM's driver, see `unconverged`).
    pub retried: usize,
    /// Engine steps, settling included.
    pub steps: u64,
    /// Time step, s.
    pub dt_s: f64,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
    /// The curve of the wall's own shear: `curve` before the rig's vertical-load system
    /// added its force (the same as `curve` for an ideal vertical force). With
    /// `vertical_load_rig` it gives the force read under any other such system without a
    /// new run ([`read_curve`]: the beam's motion is imposed, so the system leaves the
    /// wall's motion as it is). Not written to the results (empty when read from them).
    #[serde(skip)]
    pub wall_curve: Vec<CurvePoint>,
    /// The rig's vertical-load system the run had (`Layout::vertical_load_rig`). Not
    /// written to the results (ideal when read from them).
    #[serde(skip)]
    pub vertical_load_rig: Box<VerticalLoadRig>,
    /// The applied vertical force `σ0 L t`, N, as the rig's system reads it (0 when read
    /// from the results).
    #[serde(skip)]
    pub vertical_force_n: f64,
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

/// The in-plane test of a wall by the penalty DEM: the driver of the protocol's penalty
/// way (`protocol::inplane`). `observe(drift_pct, converged, state)` sees the state under
/// the vertical force (drift 0) and every increment's.
///
/// # Errors
/// See [`InPlaneError`]: bad parameters, a top course not level, a wall that does not stand
/// under gravity or under the vertical force (naming the block), a blow-up.
pub fn run_in_plane_penalty(
    wall: &Layout,
    solver: SolverParams,
    params: &InPlaneParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<InPlaneResult, InPlaneError> {
    let t0 = Instant::now();
    check_cyclic_slip_range(wall, params)?;
    let rig = Rig::build(wall, params)?;
    check_joint_closure(wall, params)?;
    solver.validate_static().map_err(InPlaneError::Solver)?;
    let solver = SolverParams { density_scaling: solver.density_scaling.without_block(), ..solver };
    let mut sim = Simulation::new(&rig.layout, solver);
    let (tol, budget) = (solver.penalty.tolerance, solver.penalty.max_steps);
    let bi = rig.beam;
    sim.state.bodies[bi].hold = Hold::Dof(rig.constraint(&sim, params.beam_rotation));
    settle(&mut sim, &rig.layout, tol, budget).map_err(|e| match e {
        SettleError::Dem(e) => InPlaneError::Dem(e),
        other => InPlaneError::DoesNotStand(other),
    })?;
    // The vertical force, the beam's weight part of it.
    let start = poses(&sim);
    sim.state.external_force[bi] = Vec3::new(0.0, 0.0, -(rig.vertical_force_n - rig.beam_weight_n));
    // The rig's terms that move the wall: a moment on the beam from its pose now.
    let moment = rig.beam_moment(&sim.state.bodies[bi]);
    if let Some(c) = sim.state.bodies[bi].hold.dof_mut() {
        c.moment = moment;
    }
    // The static solves: the solver's stages over the protocol's own, dynamic relaxation.
    // The implicit iteration holds the beam's constrained degrees of freedom (`--solver
    // implicit`), but it leaves increments after a reversal unconverged (BENCHMARKS.md).
    let relax =
        StaticSolve::of(&solver.penalty, solver.kind.cascade(Cascade::RELAXATION).unwrap_or(Cascade::RELAXATION), None);
    let out = solve_static(&mut sim, &relax, &start, |_| None::<()>)?;
    // What the joints' closure under the vertical stress explains, twice, on top of the
    // settling's tolerance: a stack of H / h_min joints each closing σ0 / Kn.
    let h_min = rig.layout.blocks.iter().map(|b| b.shape.aabb().extent().z).fold(f64::INFINITY, f64::min);
    let kn_min = rig.layout.materials.iter().map(|m| m.kn).fold(f64::INFINITY, f64::min);
    let allowed = super::settle::settle_tolerance(&rig.layout)
        + 2.0 * (rig.height_m / h_min).ceil() * params.sigma0_mpa * 1e6 / kn_min;
    let worst = sim
        .state
        .bodies
        .iter()
        .zip(&start)
        .map(|(b, (x0, _))| (b.id.clone(), (b.pos - x0).norm()))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((block, moved)) = worst {
        if out.end != End::Equilibrium || moved > allowed {
            return Err(InPlaneError::UnderVerticalForce {
                block,
                moved_mm: moved * 1e3,
                allowed_mm: allowed * 1e3,
                force_kn: rig.vertical_force_n * 1e-3,
                equilibrium: out.end == End::Equilibrium,
            });
        }
    }
    observe(0.0, true, &sim);
    // The vertical modulus: the stress the actuator added over the wall's shortening.
    let settlement = start[bi].0.z - sim.state.bodies[bi].pos.z;
    let added_stress = (rig.vertical_force_n - rig.beam_weight_n) / (rig.length_m * rig.thickness_m);
    let vertical_modulus_mpa = added_stress * rig.height_m / settlement * 1e-6;
    let reference = poses(&sim);
    let neighbours = super::excursion::JointNeighbours::of(&rig.layout);
    let mut excursion = Excursion::default();
    let ref_joints = mechanism_joints(&sim);
    let beam_ref = sim.state.bodies[bi].clone();
    let top_local = beam_ref.to_body(&Vec3::new(beam_ref.pos.x, beam_ref.pos.y, rig.measure_z_m));
    let top_x0 = beam_ref.to_world(&top_local).x;
    let anchor_x0 = sim.state.bodies[bi].hold.dof().expect("set").anchor_world(&beam_ref).x;
    let force = |sim: &Simulation| -> f64 {
        let mut fx = 0.0;
        for c in &sim.state.contacts {
            if c.b == bi {
                fx += c.force.x;
            }
            if c.a == Some(bi) {
                fx -= c.force.x;
            }
        }
        -fx
    };
    let mut curve = vec![CurvePoint { top_mm: 0.0, drift_pct: 0.0, force_kn: force(&sim) * 1e-3, converged: true }];
    let mut unconverged = 0;
    let mut reading = (f64::NEG_INFINITY, reference.clone());
    // Where the half-cycle that led to the reading started (module doc, the mechanism).
    let mut half = HalfCycle::new(&reference);
    // The secant predictor: each increment starts from the last one's motion scaled to its
    // own (the first from a motion growing linearly with height), so that the joints are
    // not made to slip by the jump of the beam alone (a joint's shear law is incremental:
    // a jump of the beam's target alone would be one step's shear increment at its joints).
    let mut last: Option<(Vec<Vec3>, Vec<Vec3>, f64)> = None;
    // The bodies that walked alone in the last increment (moved from every joint
    // neighbour), each with the body that pressed on it hardest (`None`: the table): the
    // predictor carries such a body with that one instead of repeating its own motion. A
    // loose block (one the beam has lifted off) is in neutral equilibrium along its bed:
    // wherever the predictor puts it, the relaxation leaves it, so a slip repeated by the
    // predictor would walk it out of the wall an increment at a time.
    let mut carriers: Vec<Option<Option<usize>>> = vec![None; sim.state.bodies.len()];
    let mut u_prev = 0.0;
    // The first increment, and the first after a reversal, are a quarter of the smallest
    // slip displacement of the joints under the vertical stress (μ σ0 / Ks), so that a
    // predictor that is not yet the path's own does not make a joint slip; each converged
    // increment doubles the next, up to the path's.
    let first = 0.25
        * rig
            .layout
            .materials
            .iter()
            .map(|m| m.friction.tan().max(1e-3) * params.sigma0_mpa * 1e6 / m.ks)
            .fold(f64::INFINITY, f64::min);
    let mut allowed = first;
    let mut retried = 0usize;
    // Whether the increment being solved is one thrown off the path solved again from its
    // start (it is not solved a third time).
    let mut from_start = false;
    // The drift history is imposed at the actuator: a drift d moves it by d H0 (free
    // rotation: a rotation of the wall about its base reads the drift d at its top) or
    // d H (the beam held level).
    let lever = match params.beam_rotation {
        BeamRotation::Free => rig.anchor_z_m,
        BeamRotation::Fixed => rig.height_m,
    };
    let walk_bound = WalkBound::of(&rig, params.sigma0_mpa, lever);
    let radii: Vec<f64> = sim.state.bodies.iter().map(|b| b.radius).collect();
    for u in params.path(lever) {
        while (u - u_prev).abs() > 1e-15 {
            let du = (u - u_prev).clamp(-allowed, allowed);
            if last.as_ref().is_some_and(|l| l.2 * du < 0.0) {
                // A reversal: the last motion is no predictor of the unloading.
                last = None;
                allowed = first;
                continue;
            }
            u_prev = if (u - u_prev).abs() <= allowed { u } else { u_prev + du };
            allowed = (2.0 * allowed).min(params.step_mm * 1e-3);
            if let Some(c) = sim.state.bodies[bi].hold.dof_mut() {
                c.set_target(0, anchor_x0 + u_prev);
            }
            let start = poses(&sim);
            let (dpos, drot): (Vec<Vec3>, Vec<Vec3>) = match &last {
                Some((dp, dr, d0)) if *d0 != 0.0 => {
                    // No body is predicted to move more than the beam's increment (the
                    // last solve's relaxation left no creep to extrapolate).
                    let k = du / d0;
                    let cap = du.abs();
                    let clip = |v: Vec3, r: f64| if v.norm() * r > cap { v * (cap / (v.norm() * r)) } else { v };
                    let mut p: Vec<Vec3> = dp.iter().map(|v| clip(v * k, 1.0)).collect();
                    let mut r: Vec<Vec3> =
                        dr.iter().zip(&sim.state.bodies).map(|(v, b)| clip(v * k, b.radius)).collect();
                    carry_with(&mut p, &mut r, &carriers, &sim);
                    (p, r)
                }
                _ => sim
                    .state
                    .bodies
                    .iter()
                    .map(|b| (Vec3::new(du * (b.pos.z / rig.anchor_z_m).clamp(0.0, 1.0), 0.0, 0.0), Vec3::zeros()))
                    .unzip(),
            };
            let before = sim.clone();
            sim.predict(&dpos, &drot);
            let solved = match solve_static(&mut sim, &relax, &start, |_| None::<()>) {
                Ok(out) => Some(out),
                // A predicted jump the dynamics of the relaxation could not take: the
                // increment again from its start, warming up from the smallest one.
                Err(DemError::NonFinite { .. }) if last.is_some() || allowed > first => None,
                Err(e) => return Err(e.into()),
            };
            let now = poses(&sim);
            // A block that walked from every joint neighbour by more than the increment can
            // move it ([`WalkBound`]) has left the path: the relaxation threw it to an
            // equilibrium the loading would not reach (a loose block launched in one
            // relaxation, or a stiff wall and its beam swung off their supports by the
            // contact springs' energy). The increment again from its start, warming up from
            // the smallest one; where even that throws a block, the increment is not
            // converged, however well balanced the state it ended in.
            let off_path = solved.is_some() && neighbours.largest_walk(&start, &now, &radii).0 > walk_bound.at(du);
            let Some(out) = solved.filter(|_| !off_path || from_start) else {
                from_start |= off_path;
                sim = before;
                u_prev -= du;
                if let Some(c) = sim.state.bodies[bi].hold.dof_mut() {
                    c.set_target(0, anchor_x0 + u_prev);
                }
                last = None;
                allowed = first;
                retried += 1;
                continue;
            };
            from_start = false;
            excursion.read(&neighbours, &reference, &now, &rig.layout);
            let now_for_reading = now.clone();
            let alone = neighbours.walked_alone(&start, &now, (WALK_SHARE * du.abs()).max(WALK_FLOOR_M));
            carriers = alone
                .iter()
                .enumerate()
                .map(|(k, &a)| (a && k != bi).then(|| loose_carrier(&sim, k)).flatten())
                .collect();
            carriers.resize(sim.state.bodies.len(), None);
            last = Some((
                now.iter().zip(&start).map(|(a, b)| a.0 - b.0).collect(),
                now.iter().zip(&start).map(|(a, b)| (a.1 * b.1.inverse()).scaled_axis()).collect(),
                du,
            ));
            // Equilibrium of the wall as a whole (the unbalanced-force ratio is a mean over
            // the bodies) and of each block: a block whose own out-of-balance force is a
            // share of its weight is moving, whatever the mean says; and on the path: no
            // block thrown from the wall.
            let converged = out.end == End::Equilibrium && every_block_balanced(&sim, bi) && !off_path;
            unconverged += usize::from(!converged);
            let top = sim.state.bodies[bi].to_world(&top_local).x - top_x0;
            let drift = 100.0 * top / rig.measure_z_m;
            curve.push(CurvePoint { top_mm: top * 1e3, drift_pct: drift, force_kn: force(&sim) * 1e-3, converged });
            observe(drift, converged, &sim);
            half.step(top, &now_for_reading);
            if top >= reading.0 {
                reading = (top, now_for_reading);
                half.keep();
            }
        }
    }
    let ids: Vec<String> = sim.state.bodies.iter().map(|b| b.id.clone()).collect();
    let anchor = sim.state.bodies[bi].hold.dof().expect("set").anchor_world(&beam_ref);
    let mechanism = half.mechanism(&ref_joints, &ids, bi, anchor, &reference, &reading);
    let work =
        Work { unconverged, retried, steps: sim.state.steps, dt_s: sim.dt(), t0, vertical_modulus_mpa, excursion };
    Ok(result_of(&rig, params, curve, mechanism, &reading.1, work))
}

/// The share of an increment's beam displacement by which a body must move from every
/// joint neighbour to have walked alone \[0.1\] (a body moving with a neighbour departs from
/// it by the joint's deformation only, orders of magnitude less).
const WALK_SHARE: f64 = 0.1;

/// The most a block may walk from every one of its joint neighbours in one increment of a
/// quasi-static path ([`super::excursion::JointNeighbours::largest_walk`]), m: the
/// mechanism's relative motion plus the joints' own deformation.
///
/// The actuator drives every motion of the wall: its parts turn about points of the wall
/// (a toe, a crack's foot) or slide along its joints, by at most `dθ = du / lever` (`du` the
/// actuator's increment, over the lever it acts over). A block turned by `dθ` about a point
/// within the rig's diagonal `D` (wall and beam, the farthest two points) moves by at most
/// `dθ D` at its centroid and turns by `dθ`, which the walk counts at the block's radius
/// (at most `D`): `2 D du / lever` (at least `2 du`, the beam's own translation). A block's
/// joints deform elastically by at most the slip
/// displacement of the stiffest-slipping joint under the vertical stress, `μ σ0 / Ks` (the
/// largest over the materials). A block that walked farther in one increment was thrown
/// by the relaxation (squeezed out of a closing crack, or twisted in its bed by a swing)
/// to an equilibrium the loading would not reach.
#[derive(Debug, Clone, Copy)]
struct WalkBound {
    /// Twice the diagonal over the lever, ≥ 2.
    spread: f64,
    /// The largest `μ σ0 / Ks`, m.
    slip_m: f64,
}

impl WalkBound {
    /// The bound of the rig `rig` under the vertical stress `sigma0_mpa` (MPa), the drift
    /// imposed over `lever` (m).
    fn of(rig: &Rig, sigma0_mpa: f64, lever: f64) -> WalkBound {
        let e = rig.layout.bounds().extent();
        let spread = 2.0 * (e.x.hypot(e.z) / lever).max(1.0);
        let slip_m = rig
            .layout
            .materials
            .iter()
            .map(|m| m.friction.tan().max(1e-3) * sigma0_mpa * 1e6 / m.ks)
            .fold(0.0, f64::max);
        WalkBound { spread, slip_m }
    }

    /// The bound for an increment `du` (m) of the actuator, m.
    fn at(&self, du: f64) -> f64 {
        self.spread * du.abs() + self.slip_m
    }
}

/// The share of a block's own load (its weight and the magnitudes of its contact forces)
/// its out-of-balance force may reach at equilibrium \[0.1\]: a loose block with more is
/// accelerating at a tenth of gravity, in flight or sliding, however small it is beside the
/// wall's mean (the unbalanced-force ratio's); a loaded block is held to the same share of
/// what it carries.
pub const BLOCK_IMBALANCE_SHARE: f64 = 0.1;

/// Whether every free body but `beam` has an out-of-balance force of at most
/// [`BLOCK_IMBALANCE_SHARE`] of its own load.
fn every_block_balanced(sim: &Simulation, beam: usize) -> bool {
    let g = sim.state.gravity_magnitude;
    let mut load: Vec<f64> = sim.state.bodies.iter().map(|b| b.mass * g).collect();
    for c in &sim.state.contacts {
        let f = c.force.norm();
        load[c.b] += f;
        if let Some(a) = c.a {
            load[a] += f;
        }
    }
    sim.state
        .bodies
        .iter()
        .enumerate()
        .all(|(k, b)| k == beam || b.fixed() || sim.unbalanced(k).0.norm() <= BLOCK_IMBALANCE_SHARE * load[k])
}

/// The least relative motion that counts as walking alone, m \[10 µm\]: above the elastic
/// deformation of a joint in one increment.
const WALK_FLOOR_M: f64 = 1e-5;

/// A loose body carries at most this many times its own weight in contact forces \[10\]
/// (a block of a wall under vertical stress carries hundreds of times its weight).
const LOOSE_LOAD_RATIO: f64 = 10.0;

/// The carrier of body `k` if it is loose (its contact forces add up to at most
/// [`LOOSE_LOAD_RATIO`] times its weight): the body that presses on it hardest
/// (`Some(None)`: the table or a fixed block). `None` for a body that is not loose.
fn loose_carrier(sim: &Simulation, k: usize) -> Option<Option<usize>> {
    let load: f64 = sim.state.contacts.iter().filter(|c| c.b == k || c.a == Some(k)).map(|c| c.force.norm()).sum();
    let weight = sim.state.bodies[k].mass * sim.state.gravity_magnitude;
    (load <= LOOSE_LOAD_RATIO * weight).then(|| hardest_pressing(sim, k))
}

/// The body that presses on body `k` hardest (the largest contact force between the two;
/// `None`: the table or a fixed block, or no contact).
fn hardest_pressing(sim: &Simulation, k: usize) -> Option<usize> {
    let mut best: (f64, Option<usize>) = (0.0, None);
    let mut by: std::collections::BTreeMap<Option<usize>, f64> = std::collections::BTreeMap::new();
    for c in &sim.state.contacts {
        let other = if c.b == k {
            c.a
        } else if c.a == Some(k) {
            Some(c.b)
        } else {
            continue;
        };
        let other = other.filter(|&j| !sim.state.bodies[j].fixed());
        *by.entry(other).or_default() += c.force.norm();
    }
    for (other, f) in by {
        if f > best.0 {
            best = (f, other);
        }
    }
    best.1
}

/// Replaces the predicted motion (`dpos`, `drot`: centroid translation, rotation vector) of
/// each body that has a carrier (`carriers[k] = Some(c)`) by its carrier's predicted rigid
/// motion applied to it (`c = None`: no motion).
fn carry_with(dpos: &mut [Vec3], drot: &mut [Vec3], carriers: &[Option<Option<usize>>], sim: &Simulation) {
    let (p0, r0) = (dpos.to_vec(), drot.to_vec());
    for (k, c) in carriers.iter().enumerate() {
        match c {
            None => {}
            Some(None) => {
                dpos[k] = Vec3::zeros();
                drot[k] = Vec3::zeros();
            }
            Some(Some(j)) => {
                let arm = sim.state.bodies[k].pos - sim.state.bodies[*j].pos;
                let q = nalgebra::UnitQuaternion::from_scaled_axis(r0[*j]);
                dpos[k] = p0[*j] + (q * arm - arm);
                drot[k] = r0[*j];
            }
        }
    }
}

/// The poses of the bodies: centroid (m) and rotation, in the simulation's body order.
pub(crate) type Poses = Vec<(Vec3, nalgebra::UnitQuaternion<f64>)>;

/// The mechanism read between the poses `reference` and those at the largest positive
/// displacement (`scale`, m, the displacement from `reference`; `at`, the poses); `anchor`
/// the beam's anchor (m, world) at `reference`. Read by [`HalfCycle::mechanism`] for both
/// drivers.
fn mechanism_at_reading(
    ref_joints: &[MechanismJoint],
    ids: &[String],
    beam: usize,
    anchor: Vec3,
    reference: &Poses,
    scale: f64,
    at: &Poses,
) -> InPlaneMechanism {
    let motion = |k: usize, x: &Vec3| -> Vec3 {
        let (p0, q0) = reference[k];
        let (p1, q1) = at[k];
        p1 + (q1 * q0.inverse()) * (x - p0) - x
    };
    let turn = |k: usize| (at[k].1 * reference[k].1.inverse()).scaled_axis().y;
    read_mechanism(ref_joints, ids, beam, anchor, scale.max(0.0), motion, turn)
}

/// The start of the positive half-cycle that leads to the mechanism's reading: the poses
/// where the displacement last came up through zero before its largest positive value (the
/// state under the vertical force for a monotonic run). The mechanism of a cyclic run is the
/// motion of that half-cycle, as a laboratory reads the mechanism a push opens, not the
/// residual slips the earlier cycles left.
pub(crate) struct HalfCycle {
    /// The last upward crossing: its displacement (m) and poses.
    start: (f64, Poses),
    /// The crossing of the reading kept.
    kept: (f64, Poses),
    /// The last displacement seen, m.
    last: f64,
}

impl HalfCycle {
    /// Starting at the reference state.
    pub(crate) fn new(reference: &Poses) -> HalfCycle {
        HalfCycle { start: (0.0, reference.clone()), kept: (0.0, reference.clone()), last: 0.0 }
    }

    /// Sees an increment's displacement `top` (m) and poses.
    pub(crate) fn step(&mut self, top: f64, now: &Poses) {
        if self.last < 0.0 && top >= 0.0 {
            self.start = (top, now.clone());
        }
        self.last = top;
    }

    /// The reading moved to the current increment: its half-cycle's start is kept.
    pub(crate) fn keep(&mut self) {
        self.kept = self.start.clone();
    }

    /// The mechanism read between the kept start and `reading` ([`mechanism_at_reading`];
    /// `anchor` and `reference` those under the vertical force, the anchor moved with the
    /// beam, body `beam`, to the start).
    pub(crate) fn mechanism(
        &self,
        ref_joints: &[MechanismJoint],
        ids: &[String],
        beam: usize,
        anchor: Vec3,
        reference: &Poses,
        reading: &(f64, Poses),
    ) -> InPlaneMechanism {
        let (u0, base) = (&self.kept.0, &self.kept.1);
        let anchor = anchor + (base[beam].0 - reference[beam].0);
        mechanism_at_reading(ref_joints, ids, beam, anchor, base, reading.0 - u0, &reading.1)
    }
}

/// What a driver's run cost, for its [`InPlaneResult`].
pub(crate) struct Work {
    /// Static solves (increments) that did not converge.
    pub unconverged: usize,
    /// Increments solved again from their start.
    pub retried: usize,
    /// Engine steps.
    pub steps: u64,
    /// Time step, s.
    pub dt_s: f64,
    /// When the run started.
    pub t0: Instant,
    /// The wall's vertical modulus read in the vertical loading phase, MPa (NaN: none).
    pub vertical_modulus_mpa: f64,
    /// The largest excursion of a block from its course over the history.
    pub excursion: Excursion,
}

/// The largest excursion of a block from its course over a history
/// ([`super::excursion`]), and the block.
#[derive(Debug, Clone, Default)]
pub(crate) struct Excursion {
    /// The largest excursion, m.
    pub largest_m: f64,
    /// The block's id (empty: none).
    pub block: String,
}

impl Excursion {
    /// Reads the poses `now` against `reference` and keeps the largest.
    pub(crate) fn read(
        &mut self,
        neighbours: &super::excursion::JointNeighbours,
        reference: &Poses,
        now: &Poses,
        layout: &Layout,
    ) {
        let (e, k) = neighbours.largest(reference, now);
        if e > self.largest_m {
            self.largest_m = e;
            self.block = k.map_or_else(String::new, |k| layout.blocks[k].id.clone());
        }
    }
}

/// NaN, for serde's defaults.
fn nan() -> f64 {
    f64::NAN
}

/// The result of a driver's run: the curve's per-direction outputs (the negative direction
/// of a cyclic history only), the mechanism, the poses at the reading and the rig's
/// references.
pub(crate) fn result_of(
    rig: &Rig,
    params: &InPlaneParams,
    mut curve: Vec<CurvePoint>,
    mechanism: InPlaneMechanism,
    at: &Poses,
    work: Work,
) -> InPlaneResult {
    let wall_curve = curve.clone();
    rig.add_vertical_load_rig(&mut curve);
    InPlaneResult {
        positive: direction(&curve, 1.0),
        negative: if params.history == History::Cyclic { direction(&curve, -1.0) } else { None },
        curve,
        wall_curve,
        vertical_load_rig: Box::new(rig.layout.vertical_load_rig),
        vertical_force_n: rig.vertical_force_n,
        mechanism,
        poses_at_reading: at.iter().map(|(p, q)| (*p, q.scaled_axis())).collect(),
        vertical_force_kn: rig.vertical_force_n * 1e-3,
        n_total_kn: rig.n_total_n() * 1e-3,
        rocking_force_kn: rig.rocking_force_n(params.beam_rotation) * 1e-3,
        length_m: rig.length_m,
        height_m: rig.height_m,
        thickness_m: rig.thickness_m,
        shear_span_m: rig.anchor_z_m,
        measuring_height_m: rig.measure_z_m,
        wall_vertical_modulus_mpa: work.vertical_modulus_mpa,
        largest_block_excursion_mm: work.excursion.largest_m * 1e3,
        excursion_block: work.excursion.block,
        mirror: (params.mirror_reading && params.history == History::Monotonic)
            .then(|| Box::new(Mirror { wall_curve: None })),
        unconverged: work.unconverged,
        retried: work.retried,
        steps: work.steps,
        dt_s: work.dt_s,
        wall_time_s: work.t0.elapsed().as_secs_f64(),
    }
}
