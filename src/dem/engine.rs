//! The DEM engine: one simulation of one layout.
//!
//! # The step, in order (written once, here)
//!
//! 1. **Update contacts** if some body moved, since the last detection, more than
//!    [`SolverParams::redetect_fraction`] of the contact margin (translation plus rotation
//!    times its radius): broad phase ([`crate::geometry::sweep`]), narrow phase
//!    ([`super::contact::geometry`]), sub-contact history carried over, time step checked.
//! 2. **Clear forces.**
//! 3. **Contact geometry and law**: for every sub-contact, its gap and shear increment from
//!    the two material points, then [`super::contact::law::evaluate`]; forces summed per contact and then per
//!    body, serially in contact order (so the sum never depends on a thread count).
//! 4. **Loads**: gravity (table frame), end-restraint springs, external forces.
//! 5. **Damping and integration** ([`super::integrator`]).
//! 6. **Monitor**: unbalanced-force ratio and kinetic energy ([`super::monitor`]).
//!
//! A simulation is single-threaded and deterministic; ensembles parallelize over
//! realizations.
//!
//! # State, parameters, workspace
//!
//! A [`Simulation`] is three parts (as rapier keeps its bodies, its
//! `IntegrationParameters` and its pipeline apart): the model state ([`WallState`]:
//! bodies, contacts with their history, loads, time), the parameters ([`SolverParams`]),
//! and the engine's workspace (forces and moments, per-node scratch, the detection cache,
//! the joint table, the time step and the last step's statistics), whose methods are the
//! stages above. Drivers ([`super::drivers`]) run the engine through its public methods
//! and read its state; nothing outside this module writes the workspace.

use super::contact::forces::{contact_forces, NodeScratch};
use super::contact::geometry as cgeom;
use super::contact::law::SubContactState;
pub use super::contact::types::{Contact, ContactNode, SubContact};
pub use super::dispatch::Isa;
use super::integrator::{advance, YConstraint};
use super::materials::JointTable;
pub use super::model::WallState;
use super::monitor::StepStats;
use super::params::{DensityScaling, SolverParams};
use super::timestep::{block_masses, density_scaling, step_for, Stiffness};
use crate::geometry::sweep::sweep_pairs;
use crate::layout::{EndRestraint, Layout};
use crate::math::Vec3;
use thiserror::Error;

/// Engine errors.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum DemError {
    /// A body's state became NaN or infinite: the run blew up.
    #[error("block {id} has a non-finite state at step {step} (time step {dt_s:e} s): the run blew up")]
    NonFinite {
        /// Block id.
        id: String,
        /// Step number.
        step: u64,
        /// Time step, s.
        dt_s: f64,
    },
}

/// What the re-detection of contacts before a jump or a step did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Redetection {
    /// No body moved past the re-detection threshold: no detection.
    None,
    /// Contacts detected afresh, the same contacts with every patch kept: the inertial
    /// masses and the time step stand.
    Unchanged,
    /// Contacts detected afresh and changed. After [`Simulation::step`] and
    /// [`Simulation::predict`] the inertial masses and the time step are already those of
    /// the new contacts; after [`Simulation::predict_deferred`] they are stale until
    /// [`Simulation::update_masses_and_step`].
    Changed,
}

impl Redetection {
    /// The inertial masses and the time step need an update (contacts changed).
    pub fn changed(self) -> bool {
        self == Redetection::Changed
    }
}

/// One simulation: the model state, the solver parameters and the engine's workspace.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The model state: bodies, contacts, loads, time.
    pub state: WallState,
    params: SolverParams,
    work: Workspace,
}

/// The engine's workspace: what a step derives from the state and the parameters, and
/// caches between steps. Its methods are the stages of the step.
#[derive(Debug, Clone)]
struct Workspace {
    /// Time step, s.
    dt: f64,
    /// Statistics of the last step (or the last assessed jump).
    stats: StepStats,
    /// Contact detections so far (the initial one included).
    detections: u64,
    /// Largest density-scaling factor applied so far (1: none).
    max_density_scale: f64,
    /// Out-of-balance force per body, N, table frame (contacts, then loads).
    force: Vec<Vec3>,
    /// Out-of-balance moment per body about its centroid, N·m, table frame.
    torque: Vec<Vec3>,
    /// Poses at the last detection.
    detect_pos: Vec<Vec3>,
    detect_rot: Vec<nalgebra::UnitQuaternion<f64>>,
    /// Joint parameters by material pair and joint family.
    joints: JointTable,
    /// Per-node scratch of the contact pass.
    scratch: Vec<NodeScratch>,
}

impl Workspace {
    fn new(layout: &Layout, st: &WallState) -> Workspace {
        let n = st.bodies.len();
        Workspace {
            dt: f64::INFINITY,
            stats: StepStats::default(),
            detections: 0,
            max_density_scale: 1.0,
            force: vec![Vec3::zeros(); n],
            torque: vec![Vec3::zeros(); n],
            detect_pos: st.bodies.iter().map(|b| b.pos).collect(),
            detect_rot: st.bodies.iter().map(|b| b.rot).collect(),
            joints: JointTable::new(layout),
            scratch: Vec::new(),
        }
    }

    /// Stage 1: detects contacts afresh and carries the history of persisting
    /// sub-contacts over. A contact whose pair has barely moved relative to its patch keeps
    /// it (and its history: see [`SolverParams::patch_reuse_fraction`]); the
    /// separating-axis test of a pair without a contact stops at the first axis that
    /// separates the pair by more than the margin. Returns `Unchanged` or `Changed`; the
    /// masses and the time step are left to the caller.
    fn detect(&mut self, st: &mut WallState, settings: &SolverParams, initial: bool) -> Redetection {
        // Bounding boxes from the vertices at the current pose; a body's full geometry is
        // only built when one of its pairs is detected afresh.
        let boxes: Vec<_> = st
            .bodies
            .iter()
            .map(|b| {
                let pts: Vec<Vec3> = b.shape.vertices.iter().map(|v| b.to_world(v)).collect();
                crate::geometry::Aabb::from_points(&pts)
            })
            .collect();
        let reuse_tol = if initial {
            -1.0
        } else {
            settings.patch_reuse_fraction * settings.redetect_fraction * settings.contact_margin_m
        };
        let mut kept = Vec::new();
        let mut fresh: Vec<(Option<usize>, usize)> = Vec::new();
        // Table contacts first (key 0), then pairs in (i, j) order.
        for j in 0..st.bodies.len() {
            if st.bodies[j].fixed {
                continue;
            }
            match st.reusable(None, j, reuse_tol) {
                Some(c) => kept.push(c),
                None if boxes[j].min.z <= settings.contact_margin_m => fresh.push((None, j)),
                None => {}
            }
        }
        for (i, j) in sweep_pairs(&boxes, settings.contact_margin_m) {
            if st.bodies[i].fixed && st.bodies[j].fixed {
                continue;
            }
            match st.reusable(Some(i), j, reuse_tol) {
                Some(c) => kept.push(c),
                None => fresh.push((Some(i), j)),
            }
        }
        let mut shapes: Vec<Option<crate::geometry::ConvexBlock>> = vec![None; st.bodies.len()];
        for &(a, b) in &fresh {
            for k in a.into_iter().chain([b]) {
                if shapes[k].is_none() {
                    shapes[k] = Some(st.bodies[k].world_shape());
                }
            }
        }
        let shape = |k: usize| shapes[k].as_ref().expect("built above");
        let patch_params = settings.patch();
        let mut new = Vec::new();
        for &(a, b) in &fresh {
            let patch = match a {
                None => cgeom::table_block(shape(b), &patch_params),
                Some(i) => cgeom::block_block(shape(i), shape(b), &patch_params),
            };
            if let Some(p) = patch {
                new.push(self.make_contact(st, a, b, p, initial));
            }
        }
        // The same contacts as before, every patch kept: the masses and the step stand.
        let unchanged = !initial && new.is_empty() && kept.len() == st.contacts.len();
        if !initial {
            st.transfer_history(&mut new);
        }
        new.extend(kept);
        new.sort_by_key(|c| c.key());
        st.contacts = new;
        for (k, b) in st.bodies.iter().enumerate() {
            self.detect_pos[k] = b.pos;
            self.detect_rot[k] = b.rot;
        }
        self.detections += 1;
        if unchanged {
            Redetection::Unchanged
        } else {
            Redetection::Changed
        }
    }

    /// A contact of the pair (A, B) on the patch `p`, its joint from the joint table, its
    /// sub-contacts at rest (bonded at the initial detection if the joint has strength).
    fn make_contact(&self, st: &WallState, a: Option<usize>, b: usize, p: cgeom::Patch, initial: bool) -> Contact {
        let joint = self.joints.joint(a, b, &p.normal);
        let bonded = initial && joint.has_strength();
        let bb = &st.bodies[b];
        let nodes = p
            .nodes
            .iter()
            .map(|q| ContactNode {
                on_a: match a {
                    None => q.on_a,
                    Some(i) => st.bodies[i].to_body(&q.on_a),
                },
                on_b: bb.to_body(&q.on_b),
            })
            .collect();
        let subs = p
            .triangles
            .iter()
            .map(|t| SubContact { nodes: t.nodes, area: t.area, state: SubContactState::new(bonded) })
            .collect();
        let normal_a = match a {
            None => p.normal,
            Some(i) => st.bodies[i].rot_mat.transpose() * p.normal,
        };
        Contact {
            a,
            b,
            joint,
            normal_a,
            normal_b: bb.rot_mat.transpose() * p.normal,
            nodes,
            subs,
            force: Vec3::zeros(),
            made_at: st.relative_pose(a, b),
        }
    }

    /// Sets the inertial masses (density scaling, scalar or block) and the time step from
    /// the stiffness of the current contacts at the current poses.
    fn update_masses_and_step(&mut self, st: &mut WallState, params: &SolverParams) {
        let stiffness = Stiffness::new(&st.bodies, &st.contacts);
        if params.density_scaling.is_on() {
            let (target, scale) = density_scaling(stiffness.body_eigenvalues());
            for (b, s) in st.bodies.iter_mut().zip(&scale) {
                b.inertia_scale_inv = 1.0 / s;
                b.block_mass = None;
            }
            self.max_density_scale = self.max_density_scale.max(scale.iter().cloned().fold(1.0, f64::max));
            if let (DensityScaling::Block { mass_floor }, true) = (params.density_scaling, target > 0.0) {
                let held: Vec<bool> = st.restraint.iter().map(|r| matches!(r, Some(EndRestraint::Rigid))).collect();
                let masses = block_masses(&stiffness, &st.bodies, target, mass_floor, &held);
                for (b, m) in st.bodies.iter_mut().zip(masses) {
                    b.block_mass = m;
                }
            }
        }
        let Some(dt) = step_for(stiffness.max_eigenvalue(&st.bodies), params.timestep_safety, params.damping) else {
            return;
        };
        // Static solutions take the step of the current masses; dynamics only ever shrink it,
        // so that a run keeps one time base.
        self.dt = if params.density_scaling.is_on() { dt } else { self.dt.min(dt) };
    }

    /// Whether a body moved, since the last detection, more than
    /// [`SolverParams::redetect_fraction`] of the contact margin (translation plus rotation
    /// times its radius).
    fn needs_detection(&self, st: &WallState, params: &SolverParams) -> bool {
        let limit = params.redetect_fraction * params.contact_margin_m;
        st.bodies.iter().enumerate().any(|(k, b)| {
            if b.fixed {
                return false;
            }
            let dx = (b.pos - self.detect_pos[k]).norm();
            // Rotation angle θ since detection from the quaternion dot product:
            // |q·q₀| = cos(θ/2), so θ ≈ 2√(2(1 − |q·q₀|)) for small θ (an upper bound).
            let c = b.rot.coords.dot(&self.detect_rot[k].coords).abs().min(1.0);
            let dr = 2.0 * (2.0 * (1.0 - c)).sqrt() * b.radius;
            dx + dr > limit
        })
    }

    /// Stage 1 when needed: re-detects if a body moved past the threshold, and updates the
    /// masses and the time step of changed contacts unless `deferred`.
    fn redetect(&mut self, st: &mut WallState, params: &SolverParams, deferred: bool) -> Redetection {
        if !self.needs_detection(st, params) {
            return Redetection::None;
        }
        let r = self.detect(st, params, false);
        if r.changed() && !deferred {
            self.update_masses_and_step(st, params);
        }
        r
    }

    /// Stages 2 and 3: clears the force accumulators and evaluates every contact at the
    /// current pose, with the shear increments of the velocities `v Δt` (the motion since
    /// the last evaluation); returns the sum of the contact force magnitudes (N) and the
    /// number of contacts carrying force.
    #[inline(always)]
    fn contact_pass(&mut self, st: &mut WallState, params: &SolverParams) -> (f64, usize) {
        self.force.iter_mut().for_each(|f| *f = Vec3::zeros());
        self.torque.iter_mut().for_each(|t| *t = Vec3::zeros());
        // 3. Contact geometry and law.
        let dt = self.dt;
        let quad = params.quadrature;
        let mut sum_contact = 0.0;
        let mut active = 0usize;
        let bodies = &st.bodies;
        for c in &mut st.contacts {
            let bb = &bodies[c.b];
            let (fsum, ta, tb) = match c.a {
                None => contact_forces::<false>(c, bb, bb, dt, quad, &mut self.scratch),
                Some(i) => contact_forces::<true>(c, &bodies[i], bb, dt, quad, &mut self.scratch),
            };
            c.force = fsum;
            let mag = fsum.norm();
            if mag > 0.0 {
                sum_contact += mag;
                active += 1;
            }
            self.force[c.b] += fsum;
            self.torque[c.b] += tb;
            if let Some(i) = c.a {
                self.force[i] -= fsum;
                self.torque[i] += ta;
            }
        }
        (sum_contact, active)
    }

    /// Stage 4: adds the loads (weight, end-restraint springs, external forces and
    /// torques) to the contact forces of the last contact pass; returns the sum of the free
    /// bodies' out-of-balance loads `|F| + |T|/r` (N) and their number.
    #[inline(always)]
    fn load_pass(&mut self, st: &WallState) -> (f64, usize) {
        let mut sum_unbalanced = 0.0;
        let mut free = 0usize;
        for (k, b) in st.bodies.iter().enumerate() {
            if b.fixed {
                continue;
            }
            let mut f = self.force[k] + st.gravity * b.mass + st.external_force[k];
            self.torque[k] += st.external_torque[k];
            if let Some(EndRestraint::Spring(kk)) = st.restraint[k] {
                f.y -= kk * (b.pos.y - b.pos0.y);
            }
            self.force[k] = f;
            let mut fu = f;
            if st.restraint[k] == Some(EndRestraint::Rigid) {
                fu.y = 0.0;
            }
            // Out-of-balance moment counted as a force at the body's radius, so that a
            // block rotating about an edge is not mistaken for one at rest.
            sum_unbalanced += fu.norm() + self.torque[k].norm() / b.radius;
            free += 1;
        }
        (sum_unbalanced, free)
    }

    /// Stage 5: damping and central-difference integration of every body; returns the
    /// kinetic energy (J) and advances the time.
    ///
    /// # Errors
    /// [`DemError::NonFinite`] if a body's state blows up.
    #[inline(always)]
    fn integrate(&mut self, st: &mut WallState, params: &SolverParams) -> Result<f64, DemError> {
        let dt = self.dt;
        let damping = params.damping;
        let mut ke = 0.0;
        for (k, b) in st.bodies.iter_mut().enumerate() {
            let y = if matches!(st.restraint[k], Some(EndRestraint::Rigid)) {
                YConstraint::Held
            } else {
                YConstraint::Free
            };
            advance(b, self.force[k], self.torque[k], dt, damping, y);
            if !(b.pos.iter().all(|v| v.is_finite())
                && b.angvel.iter().all(|v| v.is_finite())
                && b.vel.iter().all(|v| v.is_finite()))
            {
                return Err(DemError::NonFinite { id: b.id.clone(), step: st.steps, dt_s: dt });
            }
            ke += 0.5 * b.mass * b.vel.norm_squared();
        }
        st.time += dt;
        st.steps += 1;
        Ok(ke)
    }

    /// Stage 6: the step's statistics from the sums of stages 3 to 5.
    fn monitor(&mut self, (sum_contact, active): (f64, usize), (sum_unbalanced, free): (f64, usize), ke: f64) {
        let mean_unbalanced = if free > 0 { sum_unbalanced / free as f64 } else { 0.0 };
        let mean_contact = if active > 0 { sum_contact / active as f64 } else { 0.0 };
        self.stats = StepStats::new(mean_unbalanced, mean_contact, ke, active);
    }
}

impl Simulation {
    /// Builds the simulation of a checked layout at rest, gravity straight down
    /// (table level), and detects the initial contacts.
    pub fn new(layout: &Layout, params: SolverParams) -> Simulation {
        let state = WallState::new(layout);
        let work = Workspace::new(layout, &state);
        let mut sim = Simulation { state, params, work };
        sim.work.detect(&mut sim.state, &sim.params, true);
        sim.work.update_masses_and_step(&mut sim.state, &sim.params);
        if !sim.work.dt.is_finite() {
            // Nothing touches: a step from the free-fall of the smallest block over its size.
            sim.work.dt = 1e-4;
        }
        sim
    }

    /// The solver parameters.
    pub fn params(&self) -> &SolverParams {
        &self.params
    }

    /// The time step, s.
    pub fn dt(&self) -> f64 {
        self.work.dt
    }

    /// Statistics of the last step (or of the jump [`Simulation::assess_predicted`]
    /// assessed).
    pub fn stats(&self) -> StepStats {
        self.work.stats
    }

    /// Contact detections so far, the initial one included.
    pub fn detections(&self) -> u64 {
        self.work.detections
    }

    /// Largest density-scaling factor applied so far (1: none).
    pub fn max_density_scale(&self) -> f64 {
        self.work.max_density_scale
    }

    /// Sets the local damping coefficient (dimensionless, in [0, 1); 0: undamped
    /// dynamics), for runs that follow true dynamics after a relaxation.
    pub fn set_damping(&mut self, damping: f64) {
        self.params.damping = damping;
    }

    /// Fixes the time step (s) until the next re-detection of changed contacts, which sets
    /// it from the stiffness again (for integrator tests with a known step).
    pub fn set_time_step(&mut self, dt: f64) {
        self.work.dt = dt;
    }

    /// Sets the table tilt α (rad); see [`WallState::set_tilt`].
    pub fn set_tilt(&mut self, alpha: f64) {
        self.state.set_tilt(alpha);
    }

    /// Switches the density scaling: rebuilds the inertial masses and the time step, and
    /// stops every body (velocities of a relaxation under one set of fictitious masses are a
    /// kick under another).
    pub fn set_density_scaling(&mut self, scaling: DensityScaling) {
        if self.params.density_scaling != scaling {
            self.params.density_scaling = scaling;
            self.update_masses_and_step();
            for b in &mut self.state.bodies {
                b.vel = Vec3::zeros();
                b.angvel = Vec3::zeros();
            }
        }
    }

    /// Sets the inertial masses (density scaling, scalar or block) and the time step from
    /// the stiffness of the current contacts at the current poses: what a re-detection of
    /// changed contacts does, for a driver that deferred it
    /// ([`Simulation::predict_deferred`]).
    pub fn update_masses_and_step(&mut self) {
        self.work.update_masses_and_step(&mut self.state, &self.params);
    }

    /// The out-of-balance force (N) and moment about the centroid (N·m) on body `k` after the
    /// last step, table frame: contact forces, weight, restraint and external loads before
    /// damping (zero for a fixed body; the y force of a rigidly end-restrained body is held
    /// and reads zero).
    pub fn unbalanced(&self, k: usize) -> (Vec3, Vec3) {
        if self.state.bodies[k].fixed {
            return (Vec3::zeros(), Vec3::zeros());
        }
        let mut f = self.work.force[k];
        if self.state.restraint[k] == Some(EndRestraint::Rigid) {
            f.y = 0.0;
        }
        (f, self.work.torque[k])
    }

    /// Moves the free bodies by a predicted increment of their pose and starts them at
    /// rest there: a predictor for quasi-static continuation (the secant predictor of
    /// path-following solvers, e.g. the previous increment's motion scaled to this
    /// increment's load step). `dpos[k]` is body k's centroid translation (m, table frame)
    /// and `drot[k]` its rotation vector (rad, table frame: `q ← exp(drot) q`), one per body
    /// in body order; fixed bodies ignore theirs, and a rigidly end-restrained body the y
    /// component of its translation.
    ///
    /// The joints follow the jump as they follow any step: every contact is evaluated once
    /// at the predicted pose with the relative motion of the jump as its shear increment
    /// (the incremental shear force is path dependent; the jump is a straight path). The
    /// next [`Simulation::step`] relaxes the predicted state to equilibrium. Contacts are
    /// re-detected first if the jump moved a body past the re-detection threshold, and
    /// the inertial masses and the time step follow changed contacts; returns what the
    /// re-detection did.
    ///
    /// # Panics
    /// If `dpos` or `drot` do not have one entry per body.
    pub fn predict(&mut self, dpos: &[Vec3], drot: &[Vec3]) -> Redetection {
        self.jump(dpos, drot, false)
    }

    /// [`Simulation::predict`] for iterations that take no dynamic step: a re-detection
    /// leaves the inertial masses and the time step as they were (the jump does not depend
    /// on them), and a returned [`Redetection::Changed`] tells the caller to call
    /// [`Simulation::update_masses_and_step`] before the next [`Simulation::step`].
    ///
    /// # Panics
    /// If `dpos` or `drot` do not have one entry per body.
    pub fn predict_deferred(&mut self, dpos: &[Vec3], drot: &[Vec3]) -> Redetection {
        self.jump(dpos, drot, true)
    }

    fn jump(&mut self, dpos: &[Vec3], drot: &[Vec3], deferred: bool) -> Redetection {
        let st = &mut self.state;
        assert_eq!(dpos.len(), st.bodies.len(), "one translation per body");
        assert_eq!(drot.len(), st.bodies.len(), "one rotation per body");
        let mut jump = vec![(Vec3::zeros(), Vec3::zeros()); st.bodies.len()];
        for (k, b) in st.bodies.iter_mut().enumerate() {
            if b.fixed {
                continue;
            }
            let mut d = dpos[k];
            if st.restraint[k] == Some(EndRestraint::Rigid) {
                d.y = 0.0;
            }
            b.pos += d;
            b.rotate(drot[k]);
            jump[k] = (d, drot[k]);
        }
        // Re-detection may change the time step (density scaling): the velocities below
        // use the step the contact pass will use.
        let r = self.work.redetect(&mut self.state, &self.params, deferred);
        // The jump as one step's velocities: the contact pass reads the shear increments as
        // `v Δt`.
        let dt = self.work.dt;
        for (b, (d, w)) in self.state.bodies.iter_mut().zip(&jump) {
            b.vel = d / dt;
            b.angvel = w / dt;
        }
        self.work.contact_pass(&mut self.state, &self.params);
        for b in &mut self.state.bodies {
            b.vel = Vec3::zeros();
            b.angvel = Vec3::zeros();
        }
        r
    }

    /// The out-of-balance statistics of the state [`Simulation::predict`] has just placed
    /// (its contact pass is the jump's): adds the loads and sets [`Simulation::stats`]
    /// (kinetic energy 0) and the out-of-balance loads read by [`Simulation::unbalanced`].
    pub fn assess_predicted(&mut self) -> StepStats {
        let mut sum_contact = 0.0;
        let mut active = 0usize;
        for c in &self.state.contacts {
            let mag = c.force.norm();
            if mag > 0.0 {
                sum_contact += mag;
                active += 1;
            }
        }
        let loads = self.work.load_pass(&self.state);
        self.work.monitor((sum_contact, active), loads, 0.0);
        self.work.stats
    }

    /// Advances one step (see the module doc for the order).
    ///
    /// The step is compiled three times: for the baseline x86-64 instruction set, with AVX2
    /// and with AVX-512 enabled; the best one the CPU supports is taken (runtime detection,
    /// [`Isa::best`]). All three perform the same IEEE-754 operations in the same order (Rust
    /// never fuses a multiply and an add on its own, and square root and division are
    /// correctly rounded in every instruction set), so the results are the same bit for bit
    /// on any x86-64 machine; only the speed may differ. Tested by `tests/dispatch.rs`.
    ///
    /// # Errors
    /// [`DemError::NonFinite`] if a body's state blows up.
    pub fn step(&mut self) -> Result<(), DemError> {
        match self.step_with(Isa::best()) {
            Some(r) => r,
            None => self.step_impl(),
        }
    }

    /// [`Simulation::step`] compiled for the given instruction set; `None` (and no step
    /// taken) if this CPU does not support it. For tests and benchmarks: `step` picks the
    /// best by itself.
    #[doc(hidden)]
    pub fn step_with(&mut self, isa: Isa) -> Option<Result<(), DemError>> {
        if !isa.available() {
            return None;
        }
        Some(match isa {
            Isa::Portable => self.step_impl(),
            // SAFETY: `isa.available()` checked every feature the clone is compiled for.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { self.step_avx2() },
            // SAFETY: as above.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => unsafe { self.step_avx512() },
            #[cfg(not(target_arch = "x86_64"))]
            _ => self.step_impl(),
        })
    }

    /// [`Simulation::step`] compiled with AVX-512.
    ///
    /// # Safety
    /// The CPU must support AVX-512F, AVX-512VL, AVX2 and FMA ([`Isa::Avx512`] available).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx2,fma")]
    unsafe fn step_avx512(&mut self) -> Result<(), DemError> {
        self.step_impl()
    }

    /// [`Simulation::step`] compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA ([`Isa::Avx2`] available).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn step_avx2(&mut self) -> Result<(), DemError> {
        self.step_impl()
    }

    #[inline(always)]
    fn step_impl(&mut self) -> Result<(), DemError> {
        let (st, p, w) = (&mut self.state, &self.params, &mut self.work);
        // 1. Update contacts.
        w.redetect(st, p, false);
        // 2. Clear forces; 3. contact geometry and law.
        let contacts = w.contact_pass(st, p);
        // 4. Loads.
        let loads = w.load_pass(st);
        // 5. Damping and integration.
        let ke = w.integrate(st, p)?;
        // 6. Monitor.
        w.monitor(contacts, loads, ke);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::RunToEquilibrium;
    use crate::layout::BaseSliding;
    use crate::verify::{box_vertices, layout_of};

    const KN: f64 = 1e8;

    /// A 0.3 × 0.2 × 0.1 m block (x, y, z) on the table, φ 35°, Kn 1e8 Pa/m, Ks Kn/2.
    fn block_on_table() -> (Layout, f64) {
        let l = layout_of(vec![box_vertices([0.0, -0.1, 0.0], [0.3, 0.1, 0.1])], KN, KN / 2.0, 35.0, BaseSliding::Free);
        (l, 0.3 * 0.2)
    }

    /// Stages 3 and 4 at equilibrium: the contact force on a block resting on the table
    /// balances its weight (a conservation law), the out-of-balance load reads zero, and
    /// the uniform Winkler closure is `W / (Kn A)` (linear law, every node closed).
    #[test]
    fn the_contact_of_a_settled_block_carries_its_weight_by_the_winkler_closure() {
        let (l, area) = block_on_table();
        let mut sim = Simulation::new(&l, SolverParams::default());
        assert!(sim.run_to_equilibrium(1e-10, 400_000).unwrap());
        let w = sim.state.bodies[0].mass * sim.state.gravity_magnitude;
        let total: Vec3 = sim.state.contacts.iter().map(|c| c.force).sum();
        assert!((total - Vec3::new(0.0, 0.0, w)).norm() < 1e-6 * w, "{total:?} against {w} N");
        let (f, t) = sim.unbalanced(0);
        assert!(f.norm() < 1e-6 * w && t.norm() < 1e-6 * w * 0.3, "{f:?} {t:?}");
        let settle = sim.state.bodies[0].pos0.z - sim.state.bodies[0].pos.z;
        let exact = w / (KN * area);
        assert!((settle - exact).abs() < 1e-4 * exact, "settlement {settle:e} m against {exact:e} m");
    }

    /// A re-detection is an event: a jump within the re-detection distance detects
    /// nothing; one past it detects, and with density scaling the masses and the time step
    /// follow the new contacts at once, or, deferred, only when the caller asks, to the
    /// same bits.
    #[test]
    fn a_jump_hands_back_its_redetection_and_a_deferred_update_gives_the_same_bits() {
        let blocks =
            vec![box_vertices([0.0, -0.1, 0.0], [0.3, 0.1, 0.1]), box_vertices([0.0, -0.1, 0.1], [0.3, 0.1, 0.2])];
        let l = layout_of(blocks, KN, KN / 2.0, 35.0, BaseSliding::Free);
        let mut sim = Simulation::new(&l, SolverParams::default());
        assert!(sim.run_to_equilibrium(1e-8, 400_000).unwrap());
        let zero = vec![Vec3::zeros(); 2];
        let n = sim.detections();
        assert_eq!(sim.clone().predict(&zero, &zero), Redetection::None);
        // The top block pushed 0.1 m along y: the bed joint loses half its area.
        let shift = vec![Vec3::zeros(), Vec3::new(0.0, 0.1, 0.0)];
        let mut now = sim.clone();
        let mut later = sim.clone();
        assert_eq!(now.predict(&zero, &shift), Redetection::Changed);
        assert_eq!(now.detections(), n + 1);
        assert_eq!(later.predict_deferred(&zero, &shift), Redetection::Changed);
        assert_eq!(later.dt().to_bits(), sim.dt().to_bits(), "a deferred jump keeps the step");
        assert_ne!(now.dt().to_bits(), sim.dt().to_bits(), "half the bed joint: another step");
        later.update_masses_and_step();
        assert_eq!(later.dt().to_bits(), now.dt().to_bits());
        for (a, b) in later.state.bodies.iter().zip(&now.state.bodies) {
            assert_eq!(a, b);
        }
    }

    /// Stage 5 without contacts: a block released above the table falls as the
    /// central-difference scheme integrates a constant acceleration, exactly:
    /// `z(t) = z₀ − g t²/2` when `v(−Δt/2) = g Δt/2`.
    #[test]
    fn a_free_block_falls_by_the_closed_form_of_the_scheme() {
        let l = layout_of(vec![box_vertices([0.0, 0.0, 0.5], [0.2, 0.2, 0.6])], KN, KN / 2.0, 30.0, BaseSliding::Free);
        let mut sim = Simulation::new(&l, SolverParams { damping: 0.0, ..SolverParams::default() });
        assert!(sim.state.contacts.is_empty());
        sim.set_time_step(1e-3);
        let g = sim.state.gravity;
        sim.state.bodies[0].vel = -g * 0.5e-3;
        let z0 = sim.state.bodies[0].pos.z;
        for _ in 0..100 {
            sim.step().unwrap();
        }
        let t = sim.state.time;
        assert_eq!(sim.state.steps, 100);
        let drop = z0 - sim.state.bodies[0].pos.z;
        assert!((drop - 0.5 * g.norm() * t * t).abs() < 1e-12, "{drop} m after {t} s");
        assert_eq!(sim.stats().active_contacts, 0);
    }
}
