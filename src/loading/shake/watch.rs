//! What a shaking-table run measures from its bodies after every step of the motion
//! (either solver): the rocking rotation, the drift of the top monitor points, the fallen
//! blocks and the recorded history, and the result they make with the run's work.

use super::{ShakeHistory, ShakeParams, ShakeResult};
use crate::dem::state::Body;
use crate::dem::SolverKind;
use crate::ground::Motion;
use crate::layout::Layout;
use crate::loading::monitors::{monitor_points_of, MonitorPoint};
use crate::math::Vec3;

/// The work of a run, for its result.
pub(super) struct Work {
    pub(super) simulated_s: f64,
    pub(super) dt_s: f64,
    pub(super) steps: u64,
    pub(super) iterations: u64,
    pub(super) unconverged_steps: u64,
    pub(super) max_natural_residual: f64,
    pub(super) wall_time_s: f64,
}

/// What a run measures, from the bodies after every step of the motion (either solver).
pub(super) struct Watch<'m> {
    monitors: Vec<MonitorPoint>,
    reference: Vec<Vec3>,
    /// Each body's place when the motion starts: centroid, orientation, height.
    places: Vec<(Vec3, nalgebra::UnitQuaternion<f64>, f64)>,
    height: f64,
    fall: f64,
    motion: &'m Motion,
    /// Simulated duration of the motion, s.
    pub(super) motion_s: f64,
    history_dt_s: f64,
    stop_at_collapse: bool,
    history: ShakeHistory,
    next_record: f64,
    max_rot: f64,
    max_drift: f64,
    collapse_time: Option<f64>,
}

impl<'m> Watch<'m> {
    /// The measures of a run whose motion starts with the bodies `bodies`.
    pub(super) fn new(layout: &Layout, bodies: &[Body], motion: &'m Motion, params: &ShakeParams) -> Watch<'m> {
        let monitors: Vec<MonitorPoint> = monitor_points_of(layout, bodies);
        let reference: Vec<Vec3> = monitors.iter().map(|m| bodies[m.body].to_world(&m.local)).collect();
        let places = bodies.iter().map(|b| (b.pos, b.rot, b.shape.aabb().extent().z)).collect();
        Watch {
            monitors,
            reference,
            places,
            height: layout.bounds().extent().z,
            fall: params.fall_rotation_deg.to_radians(),
            motion,
            motion_s: params.duration_s.map_or(motion.duration_s(), |d| d.min(motion.duration_s())),
            history_dt_s: params.history_dt_s,
            stop_at_collapse: params.stop_at_collapse,
            history: ShakeHistory::default(),
            next_record: 0.0,
            max_rot: 0.0,
            max_drift: 0.0,
            collapse_time: None,
        }
    }

    /// Blocks fallen: turned by more than the fall rotation from their place, or dropped
    /// by more than half their height.
    fn fallen(&self, bodies: &[Body]) -> usize {
        bodies
            .iter()
            .zip(&self.places)
            .filter(|(b, (pos, rot, hz))| {
                !b.fixed() && ((b.rot * rot.inverse()).angle() > self.fall || pos.z - b.pos.z > 0.5 * hz)
            })
            .count()
    }

    /// The drift: the largest |y displacement| of the monitor points over the height.
    fn drift(&self, bodies: &[Body]) -> f64 {
        self.monitors
            .iter()
            .zip(&self.reference)
            .map(|(m, r)| (bodies[m.body].to_world(&m.local) - r).y.abs())
            .fold(0.0, f64::max)
            / self.height
    }

    /// The largest |rotation about x| of a free block, rad.
    fn rocking(&self, bodies: &[Body]) -> f64 {
        bodies
            .iter()
            .zip(&self.places)
            .filter(|(b, _)| !b.fixed())
            .map(|(b, (_, rot, _))| (b.rot * rot.inverse()).scaled_axis().x.abs())
            .fold(0.0, f64::max)
    }

    /// Takes the bodies after a step ending at `t` (s from the start of the motion): the
    /// maxima, the history (and `observe`) at its times, the first fall. True when the run
    /// should stop (a block fell and the run stops at collapse).
    pub(super) fn after_step(&mut self, t: f64, bodies: &[Body], observe: &mut dyn FnMut(f64, &[Body])) -> bool {
        let (rot, dr) = (self.rocking(bodies), self.drift(bodies));
        self.max_rot = self.max_rot.max(rot);
        self.max_drift = self.max_drift.max(dr);
        if t + 1e-12 >= self.next_record {
            self.history.time_s.push(t);
            self.history.base_g.push(if t <= self.motion_s { self.motion.horizontal_at(t) } else { 0.0 });
            self.history.drift.push(dr);
            self.history.rotation_deg.push(rot.to_degrees());
            self.next_record += self.history_dt_s;
            observe(t, bodies);
        }
        if self.collapse_time.is_none() && self.fallen(bodies) > 0 {
            self.collapse_time = Some(t);
            if self.stop_at_collapse {
                return true;
            }
        }
        false
    }

    /// The result of the run that ended with `bodies`.
    pub(super) fn result(self, solver: SolverKind, bodies: &[Body], work: Work) -> ShakeResult {
        ShakeResult {
            solver,
            motion: self.motion.name.clone(),
            pga_g: self.motion.pga_g(),
            overturned: self.collapse_time.is_some(),
            collapse_time_s: self.collapse_time,
            max_rotation_deg: self.max_rot.to_degrees(),
            max_drift: self.max_drift,
            residual_drift: self.drift(bodies),
            blocks_fallen: self.fallen(bodies),
            blocks: self.places.len(),
            height_m: self.height,
            simulated_s: work.simulated_s,
            dt_s: work.dt_s,
            steps: work.steps,
            iterations: work.iterations,
            unconverged_steps: work.unconverged_steps,
            max_natural_residual: work.max_natural_residual,
            wall_time_s: work.wall_time_s,
            history: self.history,
        }
    }
}
