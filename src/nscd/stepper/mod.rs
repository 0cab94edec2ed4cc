//! The Moreau–Jean step of the non-smooth solver ([`NscdSimulation`]).
//!
//! # One step of length h (Jean 1999, §3; Acary & Brogliato 2008, §10.1)
//!
//! 1. **Contacts**, re-detected only when a body has moved more than
//!    [`NscdParams::redetect_fraction`] of the contact margin since the last detection;
//!    each new point starts from the impulse of the nearest old point of its pair (warm
//!    start).
//! 2. **Rows** of every point at the poses of the start of the step ([`PointRows`]), and
//!    its Signorini term `b`: a closed point (gap g ≤ 0) has `b = 0` (no interpenetration
//!    velocity); an open one may close within the step, `b = max(g + h (1 − θ) uₙ⁻, 0) /
//!    (h θ)`, so that the θ-update of the positions brings it at most to contact; a point
//!    that closes within the step also gets Newton's term `b += e min(uₙ⁻, 0)` (restitution
//!    e, [`NscdParams::restitution`]).
//! 3. **Free velocities**: `v_free = v⁻ + h M⁻¹ F(t + θ h)`, F the weight (tilted gravity),
//!    the d'Alembert force of the base acceleration `−m a_g` (the bodies are followed in
//!    the frame of the table, which moves with acceleration `a_g(t)`: the table is then a
//!    boundary body at rest, and every displacement is relative to it), end-restraint
//!    springs, external loads, and the gyroscopic torque `−ω × I ω`.
//! 4. **NSGS** ([`super::nsgs`]): the impulses of the last step applied (warm start), then
//!    sweeps over the points in their fixed order, each solving its local Coulomb problem
//!    ([`super::local::solve`]) with the current velocities of the other points' bodies
//!    and writing its impulse change back, until the sweep meets [`NscdParams::norm`]
//!    (by default [`super::NsgsNorm::Adaptive`]: the largest change over a sweep of the
//!    velocity of a block point, `max_k (‖Δv_k‖ + ‖Δω_k‖ R_k)`, below `tolerance × g h`,
//!    or, after `quad_after_solves` local solves, the quadratic norm below
//!    `quad_tolerance`) or reaches [`NscdParams::max_iterations`]. (A norm on the
//!    velocities first, not on the impulses: the impulses of a statically indeterminate
//!    wall may drift among equivalent solutions while the motion has converged.) With
//!    [`super::StepSolver::Apgd`] (the default; trials use the sweeps alone) the sweeps get
//!    [`NscdParams::apgd_after_solves`] local solves, and a step they leave with a
//!    natural-map residual above [`NscdParams::natural_tolerance`] (whether or not they met
//!    their own norm) continues by the accelerated projected gradient ([`super::apgd`])
//!    until the residual is at most that tolerance. A step of a wall
//!    at rest under a load it carries is certified by statics instead ([`super::rest`]).
//! 5. **Positions**: `x⁺ = x⁻ + h (θ v⁺ + (1 − θ) v⁻)`, the rotation likewise (rotation
//!    vector in the table frame).
//!
//! An end restraint that is rigid holds the block's centroid in y (its inverse mass in y
//! is zero); a spring restraint is a smooth force, and so is a rope restraint
//! ([`crate::dem::rope`], at the poses advanced by `(1 − θ) h v⁻`). Fixed blocks and the
//! table are boundary bodies (zero inverse mass).

mod stages;

use super::apgd;
use super::contacts::{detect, ContactPoint};
use super::delassus::PointRows;
use super::held::Held;
use super::nsgs::{self, SweepPlan};
use super::rest::{Certificate, Statics};
use super::{NscdError, NscdParams, RestRule};
use crate::dem::constraint::{DofConstraint, Hold};
use crate::dem::materials::JointTable;
use crate::dem::rope::RopeLoad;
use crate::dem::state::Body;
use crate::layout::{EndRestraint, Layout};
use crate::math::{Mat3, Vec3};
use nalgebra::UnitQuaternion;

/// What one step did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NscdStep {
    /// NSGS sweeps.
    pub iterations: u32,
    /// The step met its solver's criterion: with [`super::StepSolver::Apgd`], its
    /// natural-map residual is at most [`NscdParams::natural_tolerance`] (a certified step
    /// is exact); with [`super::StepSolver::Nsgs`], the sweeps met their norm.
    pub converged: bool,
    /// The largest change of a block point's velocity over the last sweep, m/s.
    pub residual_m_per_s: f64,
    /// The quadratic norm of the last sweep ([`super::NsgsNorm::Quad`]), dimensionless, when
    /// the stopping rule read it (the quadratic norm; the adaptive one from the sweep that
    /// admits it); 0 otherwise.
    pub quad_residual: f64,
    /// The natural-map residual of the step's contact problem at its end
    /// ([`nsgs::natural_residual`]), dimensionless: how far the impulses are from a
    /// solution, whatever the stopping rule (0 for a certified step, exact).
    pub natural_residual: f64,
    /// The step was certified at rest by statics ([`super::rest`]): no sweeps, every block
    /// still at rest.
    pub certified: bool,
    /// Contact points carrying an impulse at the end of the step.
    pub active: usize,
    /// Contacts were re-detected before the step.
    pub redetected: bool,
}

/// A rigid-block simulation by non-smooth contact dynamics (see the module doc): the
/// bodies (poses, velocities), the contact points with their impulses, the loads, and the
/// time.
#[derive(Debug, Clone)]
pub struct NscdSimulation {
    bodies: Vec<Body>,
    points: Vec<ContactPoint>,
    /// The order of the NSGS sweeps (the contact polygons), built at each detection.
    plan: SweepPlan,
    /// The impulses of the points during the sweeps (scratch, N·s).
    impulse: Vec<Vec3>,
    nsgs_scratch: nsgs::NsgsScratch,
    apgd: apgd::ApgdScratch,
    rows: Vec<PointRows>,
    vel: Vec<Vec3>,
    angvel: Vec<Vec3>,
    radius: Vec<f64>,
    x: Vec<Vec3>,
    inv_m: Vec<Vec3>,
    inv_i: Vec<Mat3>,
    /// The mobility of each constrained body over the current step ([`Held`]).
    held: Vec<Option<Held>>,
    spring: Vec<Option<f64>>,
    ropes: Vec<RopeLoad>,
    /// The ropes' forces (N) and moments (N·m) per body (scratch of the free velocities).
    rope_force: Vec<Vec3>,
    rope_torque: Vec<Vec3>,
    /// The bodies at the poses the ropes' forces of a step are taken at (scratch; empty
    /// without ropes): see [`Self::rope_loads_predicted`].
    rope_bodies: Vec<Body>,
    gravity: Vec3,
    gravity_magnitude: f64,
    external_force: Vec<Vec3>,
    external_torque: Vec<Vec3>,
    joints: JointTable,
    params: NscdParams,
    detect_pos: Vec<Vec3>,
    detect_rot: Vec<UnitQuaternion<f64>>,
    time: f64,
    steps: u64,
    iterations: u64,
    detections: u64,
    last: NscdStep,
    /// The rest certificate of the current contact points, poses and dead load, with the
    /// poses, gravity and external loads it was made at.
    certificate: Option<(Certificate, Vec<Vec3>, Vec3, Vec<Vec3>, Vec<Vec3>)>,
    /// Steps certified at rest, and cone programs solved for certificates.
    certified_steps: u64,
    certificate_programs: u64,
    /// The step at which the last certificate was made (a new one waits
    /// [`RECERTIFY_STEPS`] steps).
    certificate_step: Option<u64>,
    /// The rows were built with every body at rest (velocities exactly zero).
    rows_at_rest: bool,
}

/// Steps between two attempts at a new rest certificate (each is two cone programs).
const RECERTIFY_STEPS: u64 = 100;

impl NscdSimulation {
    /// The simulation of a checked layout at rest in its reference configuration, gravity
    /// straight down (table level), its contact points detected.
    ///
    /// # Errors
    /// [`NscdError::Parameter`] for a parameter out of range, [`NscdError::Crushing`] for a
    /// joint whose faces crush, [`NscdError::Cohesion`] for a joint in contact with cohesion
    /// or tensile strength.
    pub fn new(layout: &Layout, params: &NscdParams) -> Result<NscdSimulation, NscdError> {
        params.validate().map_err(NscdError::Parameter)?;
        if let Some((joint, strength_pa)) = layout.crushing_joint() {
            return Err(NscdError::Crushing { joint, strength_pa });
        }
        let bodies = crate::dem::state::bodies_of(layout);
        let n = bodies.len();
        let mut spring = vec![None; n];
        let mut inv_m: Vec<Vec3> =
            bodies.iter().map(|b| if b.fixed() { Vec3::zeros() } else { Vec3::repeat(1.0 / b.mass) }).collect();
        for &(i, r) in &layout.end_restraints {
            match r {
                EndRestraint::Rigid => inv_m[i].y = 0.0,
                EndRestraint::Spring(k) => spring[i] = Some(k),
            }
        }
        let mut sim = NscdSimulation {
            vel: vec![Vec3::zeros(); n],
            angvel: vec![Vec3::zeros(); n],
            radius: bodies.iter().map(|b| b.radius).collect(),
            x: bodies.iter().map(|b| b.pos).collect(),
            inv_i: vec![Mat3::zeros(); n],
            inv_m,
            held: vec![None; n],
            spring,
            ropes: RopeLoad::of_layout(layout, &bodies),
            rope_force: vec![Vec3::zeros(); n],
            rope_torque: vec![Vec3::zeros(); n],
            rope_bodies: if layout.ropes.is_empty() { Vec::new() } else { bodies.clone() },
            gravity: Vec3::new(0.0, 0.0, -layout.gravity),
            gravity_magnitude: layout.gravity,
            external_force: vec![Vec3::zeros(); n],
            external_torque: vec![Vec3::zeros(); n],
            joints: JointTable::new(layout),
            params: *params,
            detect_pos: bodies.iter().map(|b| b.pos).collect(),
            detect_rot: bodies.iter().map(|b| b.rot).collect(),
            bodies,
            points: Vec::new(),
            plan: SweepPlan::default(),
            impulse: Vec::new(),
            nsgs_scratch: nsgs::NsgsScratch::default(),
            apgd: apgd::ApgdScratch::default(),
            rows: Vec::new(),
            time: 0.0,
            steps: 0,
            iterations: 0,
            detections: 0,
            last: NscdStep::default(),
            certificate: None,
            certified_steps: 0,
            certificate_programs: 0,
            certificate_step: None,
            rows_at_rest: false,
        };
        sim.redetect()?;
        Ok(sim)
    }

    /// The parameters.
    pub fn params(&self) -> &NscdParams {
        &self.params
    }

    /// The bodies (poses: centroid `pos`, orientation `rot` from the reference
    /// configuration; velocities `vel`, `angvel` at the end of the last step), layout order.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The contact points with the impulses of the last step, in their fixed order.
    pub fn contact_points(&self) -> &[ContactPoint] {
        &self.points
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// NSGS sweeps taken in all.
    pub fn iterations(&self) -> u64 {
        self.iterations
    }

    /// Contact detections so far (the initial one included).
    pub fn detections(&self) -> u64 {
        self.detections
    }

    /// What the last step did.
    pub fn last_step(&self) -> NscdStep {
        self.last
    }

    /// Steps certified at rest by statics ([`super::rest`]) so far, and the cone programs
    /// their certificates took.
    pub fn certified_steps(&self) -> (u64, u64) {
        (self.certified_steps, self.certificate_programs)
    }

    /// Magnitude of gravity, m/s².
    pub fn gravity_magnitude(&self) -> f64 {
        self.gravity_magnitude
    }

    /// Sets the table tilt α (rad): gravity `g (0, sin α, −cos α)` in the table frame, as
    /// the penalty engine's `WallState::set_tilt`.
    pub fn set_tilt(&mut self, alpha: f64) {
        self.gravity = Vec3::new(0.0, alpha.sin(), -alpha.cos()) * self.gravity_magnitude;
    }

    /// External force (N, at the centroid) and torque (N·m, about it) per body, table
    /// frame, constant until changed.
    pub fn set_external(&mut self, force: &[Vec3], torque: &[Vec3]) {
        self.external_force.copy_from_slice(force);
        self.external_torque.copy_from_slice(torque);
    }

    /// Constrains the degrees of freedom of body `i` (not fixed) by `constraint`
    /// ([`super::held`]): its held translations and rotations leave the velocity unknowns,
    /// and a held translation's target, moved by [`Self::constraint_mut`] between steps, is
    /// an imposed displacement that each step reaches at the velocity it implies. The
    /// constraint states every held degree of freedom of the body: it takes the place of a
    /// rigid end restraint's hold of `y` on the same body.
    ///
    /// # Panics
    /// If `i` is out of range.
    pub fn constrain(&mut self, i: usize, constraint: DofConstraint) {
        self.bodies[i].hold = Hold::Dof(constraint);
        self.inv_m[i] = Vec3::zeros();
        self.rows_at_rest = false;
    }

    /// The constraint of body `i`, if any.
    pub fn constraint(&self, i: usize) -> Option<&DofConstraint> {
        self.bodies[i].hold.dof()
    }

    /// The constraint of body `i`, to move its targets ([`DofConstraint::set_target`]).
    pub fn constraint_mut(&mut self, i: usize) -> Option<&mut DofConstraint> {
        self.bodies[i].hold.dof_mut()
    }

    /// Whether some body is constrained per degree of freedom.
    fn constrained(&self) -> bool {
        self.bodies.iter().any(|b| b.hold.dof().is_some())
    }

    /// Kinetic energy, J (relative to the table).
    pub fn kinetic_energy(&self) -> f64 {
        self.bodies.iter().map(Body::kinetic_energy).sum()
    }

    /// The largest speed of a point of a free block, `|v| + |ω| R` (R its radius), m/s.
    pub fn max_point_speed(&self) -> f64 {
        self.bodies.iter().filter(|b| !b.fixed()).map(|b| b.vel.norm() + b.angvel.norm() * b.radius).fold(0.0, f64::max)
    }

    /// Rotation of body `i` from its reference configuration, as a rotation vector (rad,
    /// table frame); its x component is the rocking rotation about the out-of-plane axis.
    pub fn rotation_vector(&self, i: usize) -> Vec3 {
        self.bodies[i].rot.scaled_axis()
    }

    /// Puts every body at rest (velocities zero) where it is.
    pub fn stop(&mut self) {
        for b in &mut self.bodies {
            b.vel = Vec3::zeros();
            b.angvel = Vec3::zeros();
        }
    }

    /// Sets the velocity (m/s) and angular velocity (rad/s, table frame) of body `i`.
    pub fn set_velocity(&mut self, i: usize, vel: Vec3, angvel: Vec3) {
        self.rows_at_rest = false;
        self.bodies[i].vel = vel;
        self.bodies[i].angvel = angvel;
    }

    /// Moves body `i` rigidly: rotation vector `phi` (rad, table frame) about the point
    /// `pivot` (m, table frame), then the translation `shift` (m). Contacts are re-detected
    /// before the next step.
    pub fn displace(&mut self, i: usize, pivot: Vec3, phi: Vec3, shift: Vec3) {
        let b = &mut self.bodies[i];
        let r = crate::dem::state::rotation_increment(phi);
        b.pos = pivot + r * (b.pos - pivot) + shift;
        b.rotate(phi);
        self.detect_pos[i] = Vec3::repeat(f64::INFINITY);
    }

    /// Takes the impulses of `other` (a simulation of the same layout with the same
    /// contact points) as the warm start of the next step; does nothing if the points
    /// differ.
    pub fn warm_start_from(&mut self, other: &NscdSimulation) {
        if self.points.len() == other.points.len()
            && self.points.iter().zip(&other.points).all(|(a, b)| a.key() == b.key() && a.on_b == b.on_b)
        {
            for (a, b) in self.points.iter_mut().zip(&other.points) {
                a.impulse = b.impulse;
            }
        }
    }

    /// The mean contact force of the last step on B of every contact point (impulse / h,
    /// N, table frame), in the order of [`Self::contact_points`]; zeros before the first
    /// step.
    pub fn point_forces(&self) -> Vec<Vec3> {
        let h = self.params.dt_s;
        if self.rows.len() != self.points.len() {
            return vec![Vec3::zeros(); self.points.len()];
        }
        self.points.iter().zip(&self.rows).map(|(c, r)| r.frame * c.impulse / h).collect()
    }

    fn needs_detection(&self) -> bool {
        let limit = self.params.redetect_fraction * self.params.contact_margin_m;
        self.bodies.iter().enumerate().any(|(k, b)| {
            if b.fixed() {
                return false;
            }
            let dx = (b.pos - self.detect_pos[k]).norm();
            let c = b.rot.coords.dot(&self.detect_rot[k].coords).abs().min(1.0);
            dx + 2.0 * (2.0 * (1.0 - c)).sqrt() * b.radius > limit
        })
    }

    fn redetect(&mut self) -> Result<(), NscdError> {
        let carry = self.params.contact_margin_m;
        self.points =
            detect(&self.bodies, &self.joints, &self.params.patch(), &self.points, carry, self.params.polygon_points)?;
        self.plan = SweepPlan::new(self.points.iter().map(ContactPoint::key));
        for (k, b) in self.bodies.iter().enumerate() {
            self.detect_pos[k] = b.pos;
            self.detect_rot[k] = b.rot;
        }
        self.detections += 1;
        Ok(())
    }

    /// One step of length [`NscdParams::dt_s`] with the base (table) accelerating by
    /// `base(t)` (m/s², table frame; e.g. `|_| Vec3::zeros()` for a table at rest).
    ///
    /// # Errors
    /// [`NscdError::Cohesion`] at a re-detection that meets a joint with strength,
    /// [`NscdError::NonFinite`] if a body's state blows up.
    pub fn step(&mut self, base: impl Fn(f64) -> Vec3) -> Result<NscdStep, NscdError> {
        let theta = self.params.theta;
        self.step_mean(|t0, t1| base(t1) * theta + base(t0) * (1.0 - theta))
    }

    /// One step as [`Self::step`], with the base acceleration of the step given as
    /// `mean(t, t + h)` (m/s², table frame): what acts over the step from `t` to `t + h`, as
    /// a record's mean over it ([`crate::ground::Motion::horizontal_mean`]), so that a step
    /// longer than the record's sampling receives its impulse exactly. [`Self::step`] is
    /// this with the θ-weighted values at the step's ends.
    ///
    /// # Errors
    /// As [`Self::step`].
    pub fn step_mean(&mut self, mean: impl Fn(f64, f64) -> Vec3) -> Result<NscdStep, NscdError> {
        let (h, theta) = (self.params.dt_s, self.params.theta);
        let redetected = self.needs_detection();
        if redetected {
            self.redetect()?;
        }
        let a_g = mean(self.time, self.time + h);
        // After a certified step the poses are those the rows were built at; if every
        // velocity was zero then too, the rows would be rebuilt identical.
        let reuse = self.rows_at_rest && self.last.certified && !redetected;
        if reuse && self.params.rest == RestRule::Certify && self.at_rest() {
            if let Some(step) = self.certified(a_g, h, redetected) {
                return Ok(step);
            }
        }
        self.load_state();
        self.build_rows();
        self.rows_at_rest =
            self.bodies.iter().all(|b| b.fixed() || (b.vel == Vec3::zeros() && b.angvel == Vec3::zeros()));
        if !reuse && self.params.rest == RestRule::Certify && self.at_rest() {
            if let Some(step) = self.certified(a_g, h, redetected) {
                return Ok(step);
            }
        }
        self.free_velocities(h, a_g);
        let (iterations, converged, residual, quad, natural) = self.nsgs();
        self.advance(h, theta)?;
        let active = self.points.iter().filter(|p| p.impulse.x > 0.0).count();
        self.iterations += u64::from(iterations);
        self.last = NscdStep {
            iterations,
            converged,
            residual_m_per_s: residual,
            quad_residual: quad,
            natural_residual: natural,
            certified: false,
            active,
            redetected,
        };
        Ok(self.last)
    }

    /// Every free block slower than [`NscdParams::rest_velocity_ratio`] `× g h`.
    fn at_rest(&self) -> bool {
        self.max_point_speed() <= self.params.rest_velocity_ratio * self.gravity_magnitude * self.params.dt_s
    }

    /// The step of a wall at rest under the base acceleration `a_g`, certified by statics
    /// ([`super::rest`]), or `None` (the step is then swept). The certificate is that of the
    /// current contact points, poses and dead load; a new one is made when they changed,
    /// at most once per [`RECERTIFY_STEPS`] steps.
    fn certified(&mut self, a_g: Vec3, h: f64, redetected: bool) -> Option<NscdStep> {
        // The statics of the certificate know no per-degree-of-freedom constraint.
        if self.constrained() {
            return None;
        }
        let valid = !redetected
            && self.certificate.as_ref().is_some_and(|(_, pos, g, f, t)| {
                *g == self.gravity
                    && *f == self.external_force
                    && *t == self.external_torque
                    && pos.len() == self.bodies.len()
                    && pos.iter().zip(&self.bodies).all(|(p, b)| *p == b.pos)
            });
        if !valid {
            if self.certificate_step.is_some_and(|s| self.steps < s + RECERTIFY_STEPS) {
                return None;
            }
            self.certificate_step = Some(self.steps);
            let pos = self.bodies.iter().map(|b| b.pos).collect();
            self.certificate = Some((
                Certificate::default(),
                pos,
                self.gravity,
                self.external_force.clone(),
                self.external_torque.clone(),
            ));
        }
        let (cert, ..) = self.certificate.as_ref()?;
        if cert.needs_programs(a_g) {
            self.prepare_certificate(a_g);
        }
        let (cert, ..) = self.certificate.as_ref()?;
        let forces = cert.forces(a_g)?;
        // The impulses must lie in the full cones (they lie in the reduced ones to the
        // program's tolerance) and act only at closed points.
        let admissible = forces.iter().zip(&self.rows).all(|(f, r)| {
            *f == Vec3::zeros()
                || (r.bias * self.params.theta * h <= super::rest::GAP_TOLERANCE
                    && f.x >= 0.0
                    && (f.y * f.y + f.z * f.z).sqrt() <= r.mu * f.x)
        });
        if !admissible {
            return None;
        }
        for (c, f) in self.points.iter_mut().zip(&forces) {
            c.impulse = f * h;
        }
        for b in &mut self.bodies {
            b.vel = Vec3::zeros();
            b.angvel = Vec3::zeros();
        }
        self.time += h;
        self.steps += 1;
        self.certified_steps += 1;
        let active = self.points.iter().filter(|p| p.impulse.x > 0.0).count();
        self.last = NscdStep {
            iterations: 0,
            converged: true,
            residual_m_per_s: 0.0,
            quad_residual: 0.0,
            natural_residual: 0.0,
            certified: true,
            active,
            redetected,
        };
        Some(self.last)
    }

    /// Solves the cone programs the certificate needs for `a_g`, with the statics of the
    /// wall at rest: the dead load of every body (weight, external loads, end-restraint
    /// springs and ropes at the current poses), its masses and restraints.
    fn prepare_certificate(&mut self, a_g: Vec3) {
        self.rope_loads();
        let dead: Vec<(Vec3, Vec3)> = (0..self.bodies.len())
            .map(|k| {
                if self.bodies[k].fixed() {
                    (Vec3::zeros(), Vec3::zeros())
                } else {
                    self.smooth_load(k, Vec3::zeros(), Vec3::zeros())
                }
            })
            .collect();
        let mass: Vec<f64> = self.bodies.iter().map(|b| b.mass).collect();
        let free: Vec<bool> = self.bodies.iter().map(|b| !b.fixed()).collect();
        let held_y: Vec<bool> = self.inv_m.iter().zip(&self.bodies).map(|(m, b)| !b.fixed() && m.y == 0.0).collect();
        let statics = Statics {
            rows: &self.rows,
            mass: &mass,
            free: &free,
            held_y: &held_y,
            dead: &dead,
            length_scale: self.radius.iter().fold(0.0, |m, r| m.max(*r)),
            gravity: self.gravity_magnitude,
            closing: self.params.theta * self.params.dt_s,
            gap_tolerance: super::rest::GAP_TOLERANCE,
        };
        if let Some((cert, ..)) = self.certificate.as_mut() {
            let before = cert.programs;
            cert.prepare(&statics, a_g);
            self.certificate_programs += u64::from(cert.programs - before);
        }
    }
}
