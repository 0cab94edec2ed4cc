//! The shaking table: the wall on a base that moves with a prescribed acceleration, the
//! question the tilting table stands in for (Santa-Cruz et al. 2021, §1: "a pseudo-static
//! analysis as a preliminary approach to a dynamic problem").
//!
//! The base (the table and every fixed block) accelerates by `a_g(t)` along +y, the
//! out-of-plane axis, and optionally along +z ([`crate::ground::Motion`]); the wall is
//! followed in the frame of the table, loaded by its weight and the d'Alembert force
//! `−m a_g` of every block. Time integration is by non-smooth contact dynamics
//! (`dem::drivers::nscd`: Moreau–Jean, rigid blocks, Coulomb friction, Newton's impact law
//! with restitution 0 by default, the impact dissipation of Housner's rocking block). It
//! is the rigid limit: the joints' Kn and Ks are not used.
//!
//! The penalty DEM's local damping (0.8) is a relaxation device that would absorb the
//! motion: it does not run this protocol (`--solver penalty` is refused); a penalty
//! integration with contact damping set by a restitution coefficient is not part of this
//! build.
//!
//! What is measured, per run: whether the wall **overturned** (a block has fallen: turned
//! by more than [`ShakeParams::fall_rotation_deg`] from its place, or dropped by more than
//! half its height) and when; the largest **rocking rotation** of any block about x; the
//! largest and the residual **drift** (the top monitor points' y displacement relative to
//! the table over the wall height); the number of fallen blocks.
//!
//! Before the motion starts the wall settles under gravity on the still table
//! ([`ShakeParams::settle_s`]); the motion's time 0 is the end of that settling.

use super::monitors::{monitor_points_of, MonitorPoint};
use crate::dem::drivers::nscd::{NscdError, NscdSimulation};
use crate::dem::{SolverKind, SolverParams};
use crate::ground::{Motion, G};
use crate::layout::Layout;
use crate::math::Vec3;
use crate::range::{check_ranges, OutOfRange};
use serde::{Deserialize, Serialize};
use std::time::Instant;

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
            ("tail_s", self.tail_s, self.tail_s >= 0.0 && self.tail_s.is_finite(), ">= 0"),
            ("duration_s", d, d > 0.0 && d.is_finite(), "> 0"),
            ("settle_s", self.settle_s, self.settle_s >= 0.0 && self.settle_s.is_finite(), ">= 0"),
            (
                "fall_rotation_deg",
                self.fall_rotation_deg,
                self.fall_rotation_deg > 0.0 && self.fall_rotation_deg < 180.0,
                "in (0, 180)",
            ),
            ("history_dt_s", self.history_dt_s, self.history_dt_s > 0.0, "> 0"),
        ])
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
    /// The solver (`nscd`).
    pub solver: String,
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
    /// Time step, s.
    pub dt_s: f64,
    /// Steps taken (settling included).
    pub steps: u64,
    /// NSGS sweeps in all.
    pub iterations: u64,
    /// Steps whose NSGS sweeps did not meet the tolerance.
    pub unconverged_steps: u64,
    /// Wall-clock time, s (not part of the deterministic output).
    pub wall_time_s: f64,
    /// The recorded history.
    pub history: ShakeHistory,
}

/// Errors of the shaking-table protocol.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum ShakeError {
    /// The non-smooth solver failed (a parameter, a joint with strength, a blow-up).
    #[error(transparent)]
    Nscd(#[from] NscdError),
    /// A shaking parameter is out of range.
    #[error("parameter {0}")]
    Parameter(OutOfRange),
    /// The motion is empty or its sampling interval is not positive.
    #[error("motion {0}: empty, or its sampling interval is not > 0")]
    BadMotion(String),
    /// The solver chosen cannot run this protocol.
    #[error(
        "solver {0} cannot run the shaking table: its local damping is a relaxation device, not the impact's \
         dissipation; use --solver nscd (non-smooth contact dynamics)"
    )]
    Unsupported(SolverKind),
}

/// Runs the shaking-table test of `layout` under `motion` with the non-smooth solver
/// (`solver.kind` must be [`SolverKind::Nscd`]; its settings are `solver.nscd`).
///
/// # Errors
/// [`ShakeError`]: a bad parameter or motion, a solver other than `nscd`, or the solver's
/// own error (a blow-up becomes a status row in a study).
pub fn run_shake(
    layout: &Layout,
    solver: SolverParams,
    motion: &Motion,
    params: &ShakeParams,
) -> Result<ShakeResult, ShakeError> {
    run_shake_observed(layout, solver, motion, params, &mut |_, _| {})
}

/// As [`run_shake`], handing the state to `observe(time_s, state)` at every recorded time
/// of the history (time from the start of the motion). Observing changes nothing.
///
/// # Errors
/// As [`run_shake`].
pub fn run_shake_observed(
    layout: &Layout,
    solver: SolverParams,
    motion: &Motion,
    params: &ShakeParams,
    observe: &mut dyn FnMut(f64, &NscdSimulation),
) -> Result<ShakeResult, ShakeError> {
    params.validate().map_err(ShakeError::Parameter)?;
    if solver.kind != SolverKind::Nscd {
        return Err(ShakeError::Unsupported(solver.kind));
    }
    if motion.horizontal_g.is_empty() || !(motion.dt_s > 0.0) {
        return Err(ShakeError::BadMotion(motion.name.clone()));
    }
    let t0 = Instant::now();
    let nscd = &solver.nscd;
    let mut sim = NscdSimulation::new(layout, nscd)?;
    let h = nscd.dt_s;
    let height = layout.bounds().extent().z;
    let still = |_: f64| Vec3::zeros();
    let settle_steps = (params.settle_s / h).round() as u64;
    let mut unconverged = 0u64;
    for _ in 0..settle_steps {
        if !sim.step(still)?.converged {
            unconverged += 1;
        }
    }
    let start = sim.time();
    let monitors: Vec<MonitorPoint> = monitor_points_of(layout, sim.bodies());
    let reference: Vec<Vec3> = monitors.iter().map(|m| sim.bodies()[m.body].to_world(&m.local)).collect();
    let places: Vec<(Vec3, nalgebra::UnitQuaternion<f64>, f64)> =
        sim.bodies().iter().map(|b| (b.pos, b.rot, b.shape.aabb().extent().z)).collect();
    let motion_s = params.duration_s.map_or(motion.duration_s(), |d| d.min(motion.duration_s()));
    let total = motion_s + params.tail_s;
    let vertical = params.vertical && motion.vertical_g.is_some();
    let base = |t: f64| -> Vec3 {
        let tm = t - start;
        if tm > motion_s {
            return Vec3::zeros();
        }
        let z = if vertical { motion.vertical_at(tm) } else { 0.0 };
        Vec3::new(0.0, motion.horizontal_at(tm), z) * G
    };
    let fall = params.fall_rotation_deg.to_radians();
    let fallen = |sim: &NscdSimulation| -> usize {
        sim.bodies()
            .iter()
            .zip(&places)
            .filter(|(b, (pos, rot, hz))| {
                !b.fixed && ((b.rot * rot.inverse()).angle() > fall || pos.z - b.pos.z > 0.5 * hz)
            })
            .count()
    };
    let drift = |sim: &NscdSimulation| -> f64 {
        monitors
            .iter()
            .zip(&reference)
            .map(|(m, r)| (sim.bodies()[m.body].to_world(&m.local) - r).y.abs())
            .fold(0.0, f64::max)
            / height
    };
    let rocking = |sim: &NscdSimulation| -> f64 {
        sim.bodies()
            .iter()
            .zip(&places)
            .filter(|(b, _)| !b.fixed)
            .map(|(b, (_, rot, _))| (b.rot * rot.inverse()).scaled_axis().x.abs())
            .fold(0.0, f64::max)
    };
    let mut history = ShakeHistory::default();
    let mut next_record = 0.0;
    let (mut max_rot, mut max_drift) = (0.0_f64, 0.0_f64);
    let mut collapse_time = None;
    let steps = (total / h).ceil() as u64;
    for _ in 0..steps {
        let step = sim.step(base)?;
        if !step.converged {
            unconverged += 1;
        }
        let t = sim.time() - start;
        let (rot, dr) = (rocking(&sim), drift(&sim));
        max_rot = max_rot.max(rot);
        max_drift = max_drift.max(dr);
        if t + 1e-12 >= next_record {
            history.time_s.push(t);
            history.base_g.push(if t <= motion_s { motion.horizontal_at(t) } else { 0.0 });
            history.drift.push(dr);
            history.rotation_deg.push(rot.to_degrees());
            next_record += params.history_dt_s;
            observe(t, &sim);
        }
        if collapse_time.is_none() && fallen(&sim) > 0 {
            collapse_time = Some(t);
            if params.stop_at_collapse {
                break;
            }
        }
    }
    Ok(ShakeResult {
        solver: SolverKind::Nscd.name().to_string(),
        motion: motion.name.clone(),
        pga_g: motion.pga_g(),
        overturned: collapse_time.is_some(),
        collapse_time_s: collapse_time,
        max_rotation_deg: max_rot.to_degrees(),
        max_drift,
        residual_drift: drift(&sim),
        blocks_fallen: fallen(&sim),
        blocks: layout.blocks.len(),
        height_m: height,
        simulated_s: sim.time() - start,
        dt_s: h,
        steps: sim.steps(),
        iterations: sim.iterations(),
        unconverged_steps: unconverged,
        wall_time_s: t0.elapsed().as_secs_f64(),
        history,
    })
}
