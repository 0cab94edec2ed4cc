//! The shaking table: the wall on a base that moves with a prescribed acceleration, the
//! question the tilting table stands in for (Santa-Cruz et al. 2021, §1: "a pseudo-static
//! analysis as a preliminary approach to a dynamic problem").
//!
//! The base (the table and every fixed block) accelerates by `a_g(t)` along +y, the
//! out-of-plane axis, and optionally along +z ([`crate::ground::Motion`]); the wall is
//! followed in the frame of the table, loaded by its weight and the d'Alembert force
//! `−m a_g` of every block. Two time integrations (docs/shake.md says when each applies):
//!
//! * `nscd` (the default): non-smooth contact dynamics (`nscd`: Moreau–Jean,
//!   rigid blocks, Coulomb friction, Newton's impact law with restitution 0 by default, the
//!   impact dissipation of Housner's rocking block). The rigid limit: the joints' Kn and Ks
//!   are not used.
//! * `penalty`: the penalty DEM (`dem::Simulation`: sub-contact springs Kn, Ks, Coulomb
//!   slip) integrated by explicit central differences with true masses (no density
//!   scaling) and no local damping (a relaxation device that would absorb the motion); the
//!   impacts dissipate through normal contact dashpots set by a coefficient of restitution
//!   ([`crate::dem::PenaltyParams::contact_restitution`], [`crate::dem::damping`]); the time step is the
//!   critical step of the joint stiffness and the dashpots times `timestep_safety`
//!   (`run_shake_penalty` below). Finite joint stiffness: the joints'
//!   closure and elastic rocking.
//!
//! The other penalty kinds (`newton`, `implicit`, `accelerated`, `relaxation`) are static methods and
//! are refused, as is `limit`.
//!
//! What is measured, per run: whether the wall **overturned** (a block has fallen: turned
//! by more than [`ShakeParams::fall_rotation_deg`] from its place, or dropped by more than
//! half its height) and when; the largest **rocking rotation** of any block about x; the
//! largest and the residual **drift** (the top monitor points' y displacement relative to
//! the table over the wall height); the number of fallen blocks.
//!
//! Before the motion starts the wall settles under gravity on the still table
//! ([`ShakeParams::settle_s`], by the same integration); the motion's time 0 is the end of
//! that settling.

mod penalty;
mod watch;

pub use penalty::penalty_step;

use super::settle::{settle, SettleError};
use super::tilt::TiltError;
use crate::dem::state::Body;
use crate::dem::{DemError, MovedKey, MovedValue, Simulation, SolverKind, SolverParams};
use crate::ground::{Motion, G, MAX_MOTION_DURATION_S};
use crate::layout::Layout;
use crate::math::Vec3;
use crate::nscd::{NscdError, NscdSimulation};
use crate::range::{check_ranges, OutOfRange};
use penalty::shake_penalty;
use serde::{Deserialize, Serialize};
use std::time::Instant;
use watch::{Watch, Work};

/// Shaking-table parameters. Defaults in brackets.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ShakeParams {
    /// Simulated time after the motion ends (free rocking and the wall coming to rest), s
    /// \[2\].
    pub tail_s: f64,
    /// Simulated time of the motion, s; `None`: the whole motion \[None\].
    pub duration_s: Option<f64>,
    /// Settling under gravity on the still table before the motion, s \[0.05\].
    pub settle_s: f64,
    /// A block has fallen when it has turned by more than this from its place, degrees
    /// \[45\] (or dropped by more than half its height).
    pub fall_rotation_deg: f64,
    /// End the run at the first fallen block \[true\] (the collapse time is known then;
    /// incremental dynamic analysis needs no more).
    pub stop_at_collapse: bool,
    /// Drive the vertical component of a motion that has one \[true\].
    pub vertical: bool,
    /// Interval of the recorded history, s \[0.01\].
    pub history_dt_s: f64,
    /// Deprecated: `[solver.penalty] contact_restitution`
    /// (`crate::dem::PenaltyParams::contact_restitution`), which this key still sets, with
    /// a warning \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_restitution: Option<f64>,
    /// Deprecated: `[solver.penalty] step_fraction`
    /// (`crate::dem::PenaltyParams::step_fraction`), which this key still sets, with a
    /// warning \[unset\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub penalty_step_fraction: Option<f64>,
}

impl Default for ShakeParams {
    fn default() -> Self {
        ShakeParams {
            tail_s: 2.0,
            duration_s: None,
            settle_s: 0.05,
            fall_rotation_deg: 45.0,
            stop_at_collapse: true,
            vertical: true,
            history_dt_s: 0.01,
            contact_restitution: None,
            penalty_step_fraction: None,
        }
    }
}

impl ShakeParams {
    /// Checks ranges.
    ///
    /// # Errors
    /// The first key out of range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        let d = self.duration_s.unwrap_or(1.0);
        check_ranges(&[
            (
                "tail_s",
                self.tail_s,
                self.tail_s >= 0.0 && self.tail_s <= MAX_MOTION_DURATION_S,
                "in [0, 3600] (an hour)",
            ),
            ("duration_s", d, d > 0.0 && d <= MAX_MOTION_DURATION_S, "in (0, 3600] (an hour)"),
            (
                "settle_s",
                self.settle_s,
                self.settle_s >= 0.0 && self.settle_s <= MAX_MOTION_DURATION_S,
                "in [0, 3600] (an hour)",
            ),
            (
                "fall_rotation_deg",
                self.fall_rotation_deg,
                self.fall_rotation_deg > 0.0 && self.fall_rotation_deg < 180.0,
                "in (0, 180)",
            ),
            ("history_dt_s", self.history_dt_s, self.history_dt_s > 0.0, "> 0"),
        ])?;
        self.moved().iter().try_for_each(MovedKey::check)
    }

    /// These parameters without the former keys ([`Self::moved`]), once they are applied
    /// to the solver's settings.
    pub fn without_moved(self) -> ShakeParams {
        ShakeParams { contact_restitution: None, penalty_step_fraction: None, ..self }
    }

    /// The penalty settings written under this table's former keys (deprecated; see
    /// [`MovedKey`]), in field order.
    pub fn moved(&self) -> Vec<MovedKey> {
        [
            self.contact_restitution.map(|v| MovedKey::new("contact_restitution", MovedValue::ContactRestitution(v))),
            self.penalty_step_fraction.map(|v| MovedKey::new("penalty_step_fraction", MovedValue::StepFraction(v))),
        ]
        .into_iter()
        .flatten()
        .collect()
    }
}

/// The recorded history of a run, sampled every [`ShakeParams::history_dt_s`].
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ShakeHistory {
    /// Time from the start of the motion, s.
    pub time_s: Vec<f64>,
    /// Horizontal base acceleration, g.
    pub base_g: Vec<f64>,
    /// Drift: the largest |y displacement| of the top monitor points relative to the table,
    /// over the wall height, –.
    pub drift: Vec<f64>,
    /// The largest |rotation about x| of any block, degrees.
    pub rotation_deg: Vec<f64>,
}

/// Outcome of a shaking-table run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShakeResult {
    /// The solver (`nscd` or `penalty`).
    pub solver: SolverKind,
    /// The motion's name.
    pub motion: String,
    /// Its peak ground acceleration (horizontal), g.
    pub pga_g: f64,
    /// A block fell.
    pub overturned: bool,
    /// When the first block fell, s from the start of the motion (`None` if none did).
    pub collapse_time_s: Option<f64>,
    /// The largest |rotation about x| (the out-of-plane rocking axis) of any block over
    /// the run, degrees.
    pub max_rotation_deg: f64,
    /// The largest drift over the run (top displacement relative to the table / height).
    pub max_drift: f64,
    /// The drift at the end of the run.
    pub residual_drift: f64,
    /// Blocks fallen at the end of the run.
    pub blocks_fallen: usize,
    /// Blocks of the layout.
    pub blocks: usize,
    /// Wall height H (z extent of the layout), m.
    pub height_m: f64,
    /// Simulated time of the motion and tail, s (less where the run stopped at collapse).
    pub simulated_s: f64,
    /// Time step, s (`penalty`: the last one; it only shrinks as contacts change).
    pub dt_s: f64,
    /// Steps taken (settling included).
    pub steps: u64,
    /// NSGS sweeps in all (0 for `penalty`).
    pub iterations: u64,
    /// Steps whose natural-map residual is above `natural_tolerance`, settling included
    /// (`nscd`, whatever the step solver; 0 for `penalty`): the criterion of
    /// [`Self::max_natural_residual`], over the same steps.
    pub unconverged_steps: u64,
    /// The largest natural-map residual of a step, settling included (`nscd`; 0 for `penalty`),
    /// dimensionless: how far the worst step's impulses are from a solution of its
    /// Signorini–Coulomb problem, whatever the stopping rule
    /// (`nscd::nsgs::natural_residual`; docs/nscd.md).
    #[serde(default)]
    pub max_natural_residual: f64,
    /// Wall-clock time, s (not part of the deterministic output).
    pub wall_time_s: f64,
    /// The recorded history.
    pub history: ShakeHistory,
}

/// Most time steps a shaking-table run may take \[1e8\] (settling, motion and tail): at the
/// default 1 ms step, 28 hours of simulated time; a run that would take more is refused
/// before it starts, with its count.
pub const MAX_SHAKE_STEPS: f64 = 1e8;

/// Checks the step count of a run of `motion` under `params` at the step `dt_s` (s).
///
/// # Errors
/// [`ShakeError::TooLong`] with the count, the step and the simulated time.
pub fn check_steps(motion: &Motion, params: &ShakeParams, dt_s: f64) -> Result<(), ShakeError> {
    let motion_s = params.duration_s.map_or(motion.duration_s(), |d| d.min(motion.duration_s()));
    let simulated = params.settle_s + motion_s + params.tail_s;
    let steps = simulated / dt_s;
    if !(steps <= MAX_SHAKE_STEPS) {
        return Err(ShakeError::TooLong(format!(
            "{steps:.3e} steps of {dt_s:.3e} s for {simulated:.4e} s simulated (settling {} s, motion {motion_s:.4e} s, \
             tail {} s); the limit is {MAX_SHAKE_STEPS:.0e} steps: shorten the motion (duration_s), the tail \
             (tail_s) or lengthen the step",
            params.settle_s, params.tail_s
        )));
    }
    Ok(())
}

/// Errors of the shaking-table protocol.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum ShakeError {
    /// The non-smooth solver failed (a parameter, a joint with strength, a blow-up).
    #[error(transparent)]
    Nscd(#[from] NscdError),
    /// The penalty integration blew up (a time step too large for the joints).
    #[error(transparent)]
    Dem(#[from] DemError),
    /// A shaking parameter is out of range.
    #[error("parameter {0}")]
    Parameter(OutOfRange),
    /// The motion is empty or its sampling interval is not positive.
    #[error("motion {0}: empty, or its sampling interval is not > 0")]
    BadMotion(String),
    /// The run would take more than [`MAX_SHAKE_STEPS`] steps (the count in words).
    #[error("the shaking-table run is too long: {0}")]
    TooLong(String),
    /// The layout does not stand as given under gravity alone on the still table (the
    /// tilting table's check at α = 0, [`check_stands_rigid`], [`check_stands_penalty`]).
    #[error(transparent)]
    DoesNotStand(SettleError),
    /// The solver chosen does not shake (`protocol::run_shake`): the protocol seam's refusal
    /// (`protocol::Unsupported`: a cascade of static solves of the penalty DEM, or limit
    /// analysis), as text.
    #[error("{0}")]
    Unsupported(String),
}

/// Checks what every shaking run checks first, whatever its method: the parameters and
/// the motion (not empty, a positive sampling interval).
///
/// # Errors
/// [`ShakeError::Parameter`], [`ShakeError::BadMotion`].
fn check_shake(motion: &Motion, params: &ShakeParams) -> Result<(), ShakeError> {
    params.validate().map_err(ShakeError::Parameter)?;
    if motion.horizontal_g.is_empty() || !(motion.dt_s > 0.0) {
        return Err(ShakeError::BadMotion(motion.name.clone()));
    }
    Ok(())
}

/// The shaking-table test of `layout` under `motion` by the penalty DEM in explicit
/// dynamics (its joint and contact settings from `solver`; local damping and density
/// scaling are not used; contact dashpots of `solver.penalty.contact_restitution`): the driver of
/// the shaking table's penalty way (`protocol::shake`), which the protocol seam calls once
/// it has chosen the method. The bodies (layout order, table frame) go to
/// `observe(time_s, bodies)` at every recorded time of the history (time from the start of
/// the motion). Observing changes nothing. Run a shaking test through
/// `protocol::run_shake` (or `protocol::Protocol::run`), which chooses the method.
///
/// # Errors
/// [`ShakeError`]: a bad parameter or motion, a wall that does not stand
/// ([`check_stands_penalty`]), a run too long, a blow-up (a study's status row).
pub fn run_shake_penalty(
    layout: &Layout,
    solver: SolverParams,
    motion: &Motion,
    params: &ShakeParams,
    observe: &mut dyn FnMut(f64, &[Body]),
) -> Result<ShakeResult, ShakeError> {
    check_shake(motion, params)?;
    check_stands_penalty(layout, &solver)?;
    shake_penalty(layout, solver, motion, params, observe)
}

/// The shaking-table test of `layout` under `motion` by non-smooth contact dynamics
/// (Moreau–Jean, its settings `solver.nscd`): the driver of the shaking table's nscd way
/// (`protocol::shake`), observed as [`run_shake_penalty`].
///
/// # Errors
/// [`ShakeError`]: a bad parameter or motion, a run too long ([`check_steps`]), a wall that
/// does not stand ([`check_stands_rigid`]), the solver's own error.
pub fn run_shake_nscd(
    layout: &Layout,
    solver: SolverParams,
    motion: &Motion,
    params: &ShakeParams,
    observe: &mut dyn FnMut(f64, &[Body]),
) -> Result<ShakeResult, ShakeError> {
    check_shake(motion, params)?;
    if solver.nscd.dt_s > 0.0 {
        check_steps(motion, params, solver.nscd.dt_s)?;
    }
    check_stands_rigid(layout, &solver)?;
    shake_nscd(layout, solver, motion, params, observe)
}

/// The shaking table by non-smooth contact dynamics ([`run_shake_nscd`], once the
/// motion's steps and the wall's standing are checked).
fn shake_nscd(
    layout: &Layout,
    solver: SolverParams,
    motion: &Motion,
    params: &ShakeParams,
    observe: &mut dyn FnMut(f64, &[Body]),
) -> Result<ShakeResult, ShakeError> {
    let t0 = Instant::now();
    let nscd = &solver.nscd;
    let mut sim = NscdSimulation::new(layout, nscd)?;
    let h = nscd.dt_s;
    let still = |_: f64| Vec3::zeros();
    let settle_steps = (params.settle_s / h).round() as u64;
    // A step is unconverged when its natural-map residual is above the tolerance, the
    // criterion the report prints beside the largest residual, whatever the step solver
    // and its sweeps' own norm; both count the settling steps too.
    let tolerance = nscd.natural_tolerance;
    let mut unconverged = 0u64;
    let mut natural = 0.0f64;
    for _ in 0..settle_steps {
        let step = sim.step(still)?;
        if !(step.natural_residual <= tolerance) {
            unconverged += 1;
        }
        natural = natural.max(step.natural_residual);
    }
    let start = sim.time();
    let mut watch = Watch::new(layout, sim.bodies(), motion, params);
    let motion_s = watch.motion_s;
    let total = motion_s + params.tail_s;
    let vertical = params.vertical && motion.vertical_g.is_some();
    // The record's mean over each step, not its values at the step's ends: a step coarser
    // than the record's sampling receives its impulse exactly (a short peak is neither
    // multiplied to the step's length nor missed between two steps).
    let mean = |t0: f64, t1: f64| base_mean(motion, motion_s, vertical, t0 - start, t1 - start);
    let steps = (total / h).ceil() as u64;
    for _ in 0..steps {
        let step = sim.step_mean(mean)?;
        if !(step.natural_residual <= tolerance) {
            unconverged += 1;
        }
        natural = natural.max(step.natural_residual);
        if watch.after_step(sim.time() - start, sim.bodies(), observe) {
            break;
        }
    }
    Ok(watch.result(
        SolverKind::Nscd,
        sim.bodies(),
        Work {
            simulated_s: sim.time() - start,
            dt_s: h,
            steps: sim.steps(),
            iterations: sim.iterations(),
            unconverged_steps: unconverged,
            max_natural_residual: natural,
            wall_time_s: t0.elapsed().as_secs_f64(),
        },
    ))
}

/// Checks that `layout` stands as given on the still table by the tilting table's rule at
/// α = 0 for non-smooth contact dynamics: the rigid check
/// ([`super::tilt_nscd::check_stands_rigid`]: every free block touches something and the
/// wall released under gravity comes to rest), with `solver.nscd`. The check runs on its
/// own copy: the shaking run is not changed by it.
///
/// # Errors
/// [`ShakeError::DoesNotStand`] naming the block (untouched, or moved and how far);
/// [`ShakeError::Parameter`], [`ShakeError::Nscd`] or [`ShakeError::Dem`] for what the
/// solver refuses.
pub fn check_stands_rigid(layout: &Layout, solver: &SolverParams) -> Result<(), ShakeError> {
    super::tilt_nscd::check_stands_rigid(layout, &solver.nscd).map_err(|e| match e {
        TiltError::DoesNotStand(s) => ShakeError::DoesNotStand(s),
        TiltError::Dem(d) => ShakeError::Dem(d),
        TiltError::Nscd(n) => ShakeError::Nscd(n),
        TiltError::Parameter(p) => ShakeError::Parameter(p),
        TiltError::Unsupported(u) => ShakeError::Unsupported(u),
        // No pressure is involved in the rigid check; kept for completeness.
        TiltError::NoLoad(n) => ShakeError::Parameter(OutOfRange::new(
            "pressure_base_pa",
            n.pressure_base_pa,
            "a pressure that loads the wall",
        )),
    })
}

/// Checks that `layout` stands as given on the still table by the tilting table's rule at
/// α = 0 for the penalty DEM: the settling of [`super::settle::settle`] by dynamic
/// relaxation with the solver's contact settings, the default local damping and density
/// scaling, and the solver's static tolerance and step budget ([`SolverParams::penalty`]): no
/// block may move more than the closure of its joints explains. The check runs on its own
/// copy: the shaking run is not changed by it.
///
/// # Errors
/// [`ShakeError::DoesNotStand`] naming the block (moved, and how far);
/// [`ShakeError::Parameter`] or [`ShakeError::Dem`] for what the solver refuses.
pub fn check_stands_penalty(layout: &Layout, solver: &SolverParams) -> Result<(), ShakeError> {
    let d = SolverParams::default();
    let sp = SolverParams { damping: d.damping, density_scaling: d.density_scaling, ..*solver };
    sp.validate().map_err(ShakeError::Parameter)?;
    let mut sim = Simulation::new(layout, sp);
    settle(&mut sim, layout, sp.penalty.tolerance, sp.penalty.max_steps).map_err(|e| match e {
        SettleError::Dem(d) => ShakeError::Dem(d),
        other => ShakeError::DoesNotStand(other),
    })
}

/// The base acceleration (m/s², table frame: y horizontal, z vertical) at time `tm` (s) from
/// the start of the motion: the motion's components in standard g times [`G`], zero after
/// `motion_s`; the vertical one only if `vertical`.
pub(super) fn base_acceleration(motion: &Motion, motion_s: f64, vertical: bool, tm: f64) -> Vec3 {
    if tm > motion_s {
        return Vec3::zeros();
    }
    let z = if vertical { motion.vertical_at(tm) } else { 0.0 };
    Vec3::new(0.0, motion.horizontal_at(tm), z) * G
}

/// The mean base acceleration over `[t0, t1]` (m/s², table frame; s from the start of the
/// motion), as [`base_acceleration`]: the motion's mean over the part of the interval
/// before `motion_s` ([`Motion::horizontal_mean`]), zero after, over the whole interval.
pub(super) fn base_mean(motion: &Motion, motion_s: f64, vertical: bool, t0: f64, t1: f64) -> Vec3 {
    if !(t1 > t0) {
        return base_acceleration(motion, motion_s, vertical, t0);
    }
    let hi = t1.min(motion_s);
    if !(hi > t0) {
        return Vec3::zeros();
    }
    let share = (hi - t0) / (t1 - t0);
    let z = if vertical { motion.vertical_mean(t0, hi) } else { 0.0 };
    Vec3::new(0.0, motion.horizontal_mean(t0, hi), z) * (G * share)
}
