//! The collapse load multiplier of the lateral pressure at the rigid limit (pushover), by
//! non-smooth contact dynamics (`nscd`).
//!
//! The pressure of [`LateralParams`] (trapezoidal over the height, on the exposed faces
//! facing −y, computed on the reference configuration as [`super::lateral`] does, by
//! [`pressure_loads`]) is scaled by a load multiplier λ and applied as a dead load with
//! gravity straight down; each trial releases the wall from rest in its reference
//! configuration and judges it as the rigid tilting table does ([`super::tilt_nscd`]:
//! at rest, or a block past the per-increment displacement, or a motion that keeps
//! growing). λ is doubled from 1 until a trial is unstable, then bisected to a relative
//! width `resolution`. The collapse multiplier lies in `[lambda_stable, lambda_unstable]`.

use super::lateral::{pressure_loads, LateralParams};
use super::mechanism::Mechanism;
use super::tilt::{TiltError, TiltParams};
use super::tilt_nscd::{read_mechanism, released, stood, tilt_error, touches_something, TrialLimits};
use crate::dem::{Simulation, SolverParams};
use crate::layout::Layout;
use crate::math::Vec3;
use crate::nscd::{NscdParams, NscdSimulation};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Largest load multiplier tried.
pub const MAX_LOAD_MULTIPLIER: f64 = 1e6;

/// Outcome of a rigid pushover.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LateralLimit {
    /// Largest multiplier of the pressure found stable.
    pub lambda_stable: f64,
    /// Smallest multiplier found unstable (`None`: stood up to [`MAX_LOAD_MULTIPLIER`]).
    pub lambda_unstable: Option<f64>,
    /// Resultant of the pressure at λ = 1 (table frame, N): y is the lateral force.
    pub resultant_n: Vec3,
    /// Weight of the movable blocks, N.
    pub weight_n: f64,
    /// Loaded faces.
    pub loaded_faces: usize,
    /// The collapse mechanism (read as the tilting table's).
    pub mechanism: Option<Mechanism>,
    /// Trials run.
    pub trials: usize,
    /// Time steps in all.
    pub steps: u64,
    /// Wall-clock time, s (not deterministic).
    pub wall_time_s: f64,
}

/// Runs the rigid pushover of a layout under the lateral pressure of `lateral` (see the
/// module doc), bisected until the bracket's relative width is at most
/// `lateral.pushover_resolution` (unset: [`super::lateral::RIGID_PUSHOVER_RESOLUTION`]).
///
/// # Errors
/// As [`super::tilt_nscd::run_tilt_nscd`]; [`TiltError::Parameter`] for a lateral
/// parameter out of range; [`TiltError::NoLoad`] for a pressure that
/// loads no face.
pub fn run_lateral_nscd(
    layout: &Layout,
    params: &NscdParams,
    lateral: &LateralParams,
) -> Result<LateralLimit, TiltError> {
    lateral.validate().map_err(TiltError::Parameter)?;
    super::lateral::check_pushover_load(lateral).map_err(TiltError::Parameter)?;
    let resolution = lateral.rigid_pushover_resolution();
    let t0 = Instant::now();
    let base = NscdSimulation::new(layout, &params.for_trials()).map_err(tilt_error)?;
    let reader = Simulation::new(layout, SolverParams::default());
    let b = layout.bounds();
    let (loads, loaded_faces) =
        pressure_loads(&reader, b.min.z, b.max.z, lateral.pressure_base_pa, lateral.pressure_top_pa);
    super::lateral::check_pushover_force(lateral, &loads, loaded_faces).map_err(TiltError::NoLoad)?;
    let (force, torque): (Vec<Vec3>, Vec<Vec3>) = loads.into_iter().unzip();
    let resultant_n = force.iter().fold(Vec3::zeros(), |s, f| s + f);
    let weight_n = base.bodies().iter().filter(|b| !b.fixed()).map(|b| b.mass).sum::<f64>() * base.gravity_magnitude();
    let inc_limit = 0.05 * b.extent().y;
    let limits =
        TrialLimits::of(layout, &base, inc_limit, TiltParams::default().collapse_displacement_fraction * b.extent().y);
    let scaled =
        |l: f64| (force.iter().map(|f| f * l).collect::<Vec<_>>(), torque.iter().map(|t| t * l).collect::<Vec<_>>());
    let (mut trials, mut steps) = (0usize, 0u64);
    let mut run = |l: f64, warm: &NscdSimulation| {
        let (f, t) = scaled(l);
        let r = released(&base, warm, &limits, |s| s.set_external(&f, &t)).map_err(tilt_error);
        if let Ok(tr) = &r {
            trials += 1;
            steps += tr.steps;
        }
        r
    };
    touches_something(&base, params)?;
    let first = run(0.0, &base)?;
    stood(&base, &first)?;
    let (mut lo, mut stable) = (0.0, first.sim);
    let mut hi: Option<(f64, NscdSimulation)> = None;
    let mut l = 1.0;
    while l <= MAX_LOAD_MULTIPLIER {
        let t = run(l, &stable)?;
        if t.reason.is_none() {
            lo = l;
            stable = t.sim;
            l *= 2.0;
        } else {
            hi = Some((l, t.sim));
            break;
        }
    }
    if let Some((mut up, mut failed)) = hi.take() {
        while up - lo > resolution * up {
            let mid = 0.5 * (lo + up);
            let t = run(mid, &stable)?;
            if t.reason.is_none() {
                lo = mid;
                stable = t.sim;
            } else {
                up = mid;
                failed = t.sim;
            }
        }
        hi = Some((up, failed));
    }
    let mechanism = hi.as_ref().map(|(_, failed)| read_mechanism(&reader, &base, &stable, failed, inc_limit));
    Ok(LateralLimit {
        lambda_stable: lo,
        lambda_unstable: hi.map(|(u, _)| u),
        resultant_n,
        weight_n,
        loaded_faces,
        mechanism,
        trials,
        steps,
        wall_time_s: t0.elapsed().as_secs_f64(),
    })
}
