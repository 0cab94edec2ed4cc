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
//!    the two material points, then [`law::evaluate`]; forces summed per contact and then per
//!    body, serially in contact order (so the sum never depends on a thread count).
//! 4. **Loads**: gravity (table frame), end-restraint springs, external forces.
//! 5. **Damping and integration** ([`super::integrator`]).
//! 6. **Monitor**: unbalanced-force ratio and kinetic energy ([`super::monitor`]).
//!
//! A simulation is single-threaded and deterministic; ensembles parallelize over
//! realizations.

use super::contact::forces::{contact_forces, unit, NodeScratch};
use super::contact::geometry as cgeom;
use super::contact::law::{self, SubContactState};
pub use super::contact::types::{Contact, ContactNode, SubContact};
pub use super::dispatch::Isa;
use super::integrator::{advance, YConstraint};
use super::materials::JointTable;
use super::monitor::StepStats;
use super::params::{DensityScaling, SolverParams};
use super::state::Body;
use super::timestep::{block_masses, density_scaling, step_for, Stiffness};
use crate::geometry::sweep::sweep_pairs;
use crate::layout::{EndRestraint, Layout};
use crate::Vec3;
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

/// One simulation.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// Bodies, in layout order.
    pub bodies: Vec<Body>,
    /// Contacts, sorted by (A, B) with the table first.
    pub contacts: Vec<Contact>,
    /// Solver parameters.
    pub params: SolverParams,
    /// Gravity, m/s², table frame.
    pub gravity: Vec3,
    /// External force per body at its centroid, N, table frame (lateral loads).
    pub external_force: Vec<Vec3>,
    /// External torque per body about its centroid, N·m, table frame.
    pub external_torque: Vec<Vec3>,
    /// End restraint per body.
    pub restraint: Vec<Option<EndRestraint>>,
    /// Time step, s.
    pub dt: f64,
    /// Simulated time, s.
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Statistics of the last step.
    pub stats: StepStats,
    /// Number of contact re-detections so far.
    pub detections: u64,
    /// Largest density-scaling factor applied so far (1: none).
    pub max_density_scale: f64,
    gravity_magnitude: f64,
    force: Vec<Vec3>,
    torque: Vec<Vec3>,
    detect_pos: Vec<Vec3>,
    detect_rot: Vec<nalgebra::UnitQuaternion<f64>>,
    joints: JointTable,
    scratch: Vec<NodeScratch>,
    /// While set, a re-detection leaves the inertial masses and the time step to
    /// [`Simulation::end_deferral`] (the implicit iterations take no step).
    defer_step_update: bool,
    step_update_pending: bool,
}

impl Simulation {
    /// Builds the simulation of a checked layout at rest, gravity straight down
    /// (table level), and detects the initial contacts.
    pub fn new(layout: &Layout, params: SolverParams) -> Simulation {
        let bodies: Vec<Body> = layout
            .blocks
            .iter()
            .map(|b| Body::new(b.id.clone(), &b.shape, layout.materials[b.material].density, b.material, b.fixed))
            .collect();
        let n = bodies.len();
        let joints = JointTable::new(layout);
        let mut restraint = vec![None; n];
        for &(i, r) in &layout.end_restraints {
            restraint[i] = Some(r);
        }
        let mut sim = Simulation {
            detect_pos: bodies.iter().map(|b| b.pos).collect(),
            detect_rot: bodies.iter().map(|b| b.rot).collect(),
            bodies,
            contacts: Vec::new(),
            params,
            gravity: Vec3::new(0.0, 0.0, -layout.gravity),
            external_force: vec![Vec3::zeros(); n],
            external_torque: vec![Vec3::zeros(); n],
            restraint,
            dt: f64::INFINITY,
            time: 0.0,
            steps: 0,
            stats: StepStats::default(),
            detections: 0,
            max_density_scale: 1.0,
            gravity_magnitude: layout.gravity,
            force: vec![Vec3::zeros(); n],
            torque: vec![Vec3::zeros(); n],
            joints,
            scratch: Vec::new(),
            defer_step_update: false,
            step_update_pending: false,
        };
        sim.detect_contacts(true);
        if !sim.dt.is_finite() {
            // Nothing touches: a step from the free-fall of the smallest block over its size.
            sim.dt = 1e-4;
        }
        sim
    }

    /// Sets the table tilt α (rad): gravity becomes `g (0, sin α, −cos α)` in the table
    /// frame (the out-of-plane load is `W sin α`; Santa-Cruz et al. 2021, Eq. 1 with sine and cosine in
    /// their places).
    pub fn set_tilt(&mut self, alpha: f64) {
        self.gravity = Vec3::new(0.0, alpha.sin(), -alpha.cos()) * self.gravity_magnitude;
    }

    /// Detects contacts afresh and carries the history of persisting sub-contacts over. A
    /// contact whose pair has barely moved relative to its patch keeps it (and its history:
    /// see [`SolverParams::patch_reuse_fraction`]); the separating-axis test of a pair
    /// without a contact stops at the first axis that separates the pair by more than the
    /// margin.
    fn detect_contacts(&mut self, initial: bool) {
        let settings = &self.params;
        // Bounding boxes from the vertices at the current pose; a body's full geometry is
        // only built when one of its pairs is detected afresh.
        let boxes: Vec<_> = self
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
        for j in 0..self.bodies.len() {
            if self.bodies[j].fixed {
                continue;
            }
            match self.reusable(None, j, reuse_tol) {
                Some(c) => kept.push(c),
                None if boxes[j].min.z <= settings.contact_margin_m => fresh.push((None, j)),
                None => {}
            }
        }
        for (i, j) in sweep_pairs(&boxes, settings.contact_margin_m) {
            if self.bodies[i].fixed && self.bodies[j].fixed {
                continue;
            }
            match self.reusable(Some(i), j, reuse_tol) {
                Some(c) => kept.push(c),
                None => fresh.push((Some(i), j)),
            }
        }
        let mut shapes: Vec<Option<crate::geometry::ConvexBlock>> = vec![None; self.bodies.len()];
        for &(a, b) in &fresh {
            for k in a.into_iter().chain([b]) {
                if shapes[k].is_none() {
                    shapes[k] = Some(self.bodies[k].world_shape());
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
                new.push(self.make_contact(a, b, p, initial));
            }
        }
        // The same contacts as before, every patch kept: the masses and the step stand.
        let unchanged = !initial && new.is_empty() && kept.len() == self.contacts.len();
        if !initial {
            self.transfer_history(&mut new);
        }
        new.extend(kept);
        new.sort_by_key(|c| c.key());
        self.contacts = new;
        for (k, b) in self.bodies.iter().enumerate() {
            self.detect_pos[k] = b.pos;
            self.detect_rot[k] = b.rot;
        }
        if unchanged {
            self.detections += 1;
            return;
        }
        if self.defer_step_update {
            self.step_update_pending = true;
        } else {
            self.update_masses_and_step();
        }
        self.detections += 1;
    }

    /// Defers the update of the inertial masses and the time step at re-detections until
    /// [`Simulation::end_deferral`] (for iterations that take no dynamic step; the jumps of
    /// [`Simulation::predict`] do not depend on the step).
    pub(crate) fn defer_step_updates(&mut self) {
        self.defer_step_update = true;
    }

    /// Ends [`Simulation::defer_step_updates`]: sets the masses and the time step of the
    /// current contacts if a re-detection happened meanwhile.
    pub(crate) fn end_deferral(&mut self) {
        self.defer_step_update = false;
        if std::mem::take(&mut self.step_update_pending) {
            self.update_masses_and_step();
        }
    }

    /// Sets the inertial masses (density scaling, scalar or block) and the time step from
    /// the stiffness of the current contacts at the current poses.
    fn update_masses_and_step(&mut self) {
        let stiffness = Stiffness::new(&self.bodies, &self.contacts);
        if self.params.density_scaling.is_on() {
            let (target, scale) = density_scaling(stiffness.body_eigenvalues());
            for (b, s) in self.bodies.iter_mut().zip(&scale) {
                b.inertia_scale_inv = 1.0 / s;
                b.block_mass = None;
            }
            self.max_density_scale = self.max_density_scale.max(scale.iter().cloned().fold(1.0, f64::max));
            if let (DensityScaling::Block { mass_floor }, true) = (self.params.density_scaling, target > 0.0) {
                let held: Vec<bool> = self.restraint.iter().map(|r| matches!(r, Some(EndRestraint::Rigid))).collect();
                let masses = block_masses(&stiffness, &self.bodies, target, mass_floor, &held);
                for (b, m) in self.bodies.iter_mut().zip(masses) {
                    b.block_mass = m;
                }
            }
        }
        let Some(dt) =
            step_for(stiffness.max_eigenvalue(&self.bodies), self.params.timestep_safety, self.params.damping)
        else {
            return;
        };
        // Static solutions take the step of the current masses; dynamics only ever shrink it,
        // so that a run keeps one time base.
        self.dt = if self.params.density_scaling.is_on() { dt } else { self.dt.min(dt) };
    }

    /// B's pose relative to A (the table for `None`): B's centroid in A's body frame and
    /// B's rotation relative to A's.
    fn relative_pose(&self, a: Option<usize>, b: usize) -> (Vec3, nalgebra::UnitQuaternion<f64>) {
        let bb = &self.bodies[b];
        match a {
            None => (bb.pos, bb.rot),
            Some(i) => {
                let ba = &self.bodies[i];
                (ba.to_body(&bb.pos), ba.rot.inverse() * bb.rot)
            }
        }
    }

    /// The current contact of the pair, if its bodies have moved relative to each other by
    /// less than `tol` (m, at B's extremities) since its patch was made.
    fn reusable(&self, a: Option<usize>, b: usize, tol: f64) -> Option<Contact> {
        if tol <= 0.0 {
            return None;
        }
        let key = (a.map_or(0, |i| i + 1), b);
        let k = self.contacts.binary_search_by_key(&key, |o| o.key()).ok()?;
        let c = &self.contacts[k];
        let (t, q) = self.relative_pose(a, b);
        let dt = (t - c.made_at.0).norm();
        // Rotation angle θ from the quaternion dot product, |q·q₀| = cos(θ/2) (as in
        // `needs_detection`, an upper bound for small θ).
        let dot = q.coords.dot(&c.made_at.1.coords).abs().min(1.0);
        let dr = 2.0 * (2.0 * (1.0 - dot)).sqrt() * self.bodies[b].radius;
        (dt + dr < tol).then(|| c.clone())
    }

    fn make_contact(&self, a: Option<usize>, b: usize, p: cgeom::Patch, initial: bool) -> Contact {
        let joint = self.joints.joint(a, b, &p.normal);
        let bonded = initial && joint.has_strength();
        let bb = &self.bodies[b];
        let nodes = p
            .nodes
            .iter()
            .map(|q| ContactNode {
                on_a: match a {
                    None => q.on_a,
                    Some(i) => self.bodies[i].to_body(&q.on_a),
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
            Some(i) => self.bodies[i].rot_mat.transpose() * p.normal,
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
            made_at: self.relative_pose(a, b),
        }
    }

    /// Table-frame positions of a node's two material points (on A, on B).
    pub fn node_points(&self, c: &Contact, nd: &ContactNode) -> (Vec3, Vec3) {
        let pa = match c.a {
            None => nd.on_a,
            Some(i) => self.bodies[i].to_world(&nd.on_a),
        };
        (pa, self.bodies[c.b].to_world(&nd.on_b))
    }

    /// Table-frame centroid of a sub-contact (mid-plane), m.
    pub fn sub_centroid(&self, c: &Contact, s: &SubContact) -> Vec3 {
        s.nodes.iter().fold(Vec3::zeros(), |acc, &k| {
            let (pa, pb) = self.node_points(c, &c.nodes[k as usize]);
            acc + (pa + pb) / 6.0
        })
    }

    /// Normal gaps (m) at the three nodes of a sub-contact, along the current normal.
    pub fn sub_gaps(&self, c: &Contact, s: &SubContact) -> [f64; 3] {
        let n = self.contact_normal(c);
        s.nodes.map(|k| {
            let (pa, pb) = self.node_points(c, &c.nodes[k as usize]);
            (pb - pa).dot(&n)
        })
    }

    /// Current unit normal of a contact (A → B, table frame): the mean of the detection
    /// normal carried by each body.
    pub fn contact_normal(&self, c: &Contact) -> Vec3 {
        let na = match c.a {
            None => c.normal_a,
            Some(i) => self.bodies[i].rot_mat * c.normal_a,
        };
        unit(na + self.bodies[c.b].rot_mat * c.normal_b)
    }

    fn transfer_history(&self, new: &mut [Contact]) {
        let old = &self.contacts;
        for c in new.iter_mut() {
            let Ok(k) = old.binary_search_by_key(&c.key(), |o| o.key()) else { continue };
            let o = &old[k];
            let old_pts: Vec<Vec3> = o.subs.iter().map(|s| self.sub_centroid(o, s)).collect();
            let mut fresh = Vec::with_capacity(c.subs.len());
            for s in &c.subs {
                let x = self.sub_centroid(c, s);
                let nearest = old_pts
                    .iter()
                    .enumerate()
                    .min_by(|(_, p), (_, q)| (*p - x).norm_squared().total_cmp(&(*q - x).norm_squared()))
                    .map(|(i, _)| i);
                let mut st = s.state;
                if let Some(i) = nearest {
                    let os = &o.subs[i];
                    st.bonded = os.state.bonded;
                    st.shear = os.state.shear * (s.area / os.area.max(1e-300));
                }
                fresh.push(st);
            }
            for (s, st) in c.subs.iter_mut().zip(fresh) {
                s.state = st;
            }
        }
    }

    /// Switches the density scaling: rebuilds the inertial masses and the time step, and
    /// stops every body (velocities of a relaxation under one set of fictitious masses are a
    /// kick under another).
    pub fn set_density_scaling(&mut self, scaling: DensityScaling) {
        if self.params.density_scaling != scaling {
            self.params.density_scaling = scaling;
            self.update_masses_and_step();
            for b in &mut self.bodies {
                b.vel = Vec3::zeros();
                b.angvel = Vec3::zeros();
            }
        }
    }

    fn needs_detection(&self) -> bool {
        let limit = self.params.redetect_fraction * self.params.contact_margin_m;
        self.bodies.iter().enumerate().any(|(k, b)| {
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

    /// Steps 2 and 3: clears the force accumulators and evaluates every contact at the
    /// current pose, with the shear increments of the velocities `v Δt` (the motion since
    /// the last evaluation); returns the sum of the contact force magnitudes (N) and the
    /// number of contacts carrying force.
    #[inline(always)]
    fn contact_pass(&mut self) -> (f64, usize) {
        self.force.iter_mut().for_each(|f| *f = Vec3::zeros());
        self.torque.iter_mut().for_each(|t| *t = Vec3::zeros());
        // 3. Contact geometry and law.
        let dt = self.dt;
        let quad = self.params.quadrature;
        let mut sum_contact = 0.0;
        let mut active = 0usize;
        for c in &mut self.contacts {
            let bb = &self.bodies[c.b];
            let (fsum, ta, tb) = match c.a {
                None => contact_forces::<false>(c, bb, bb, dt, quad, &mut self.scratch),
                Some(i) => contact_forces::<true>(c, &self.bodies[i], bb, dt, quad, &mut self.scratch),
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

    /// The out-of-balance force (N) and moment about the centroid (N·m) on body `k` after the
    /// last step, table frame: contact forces, weight, restraint and external loads before
    /// damping (zero for a fixed body; the y force of a rigidly end-restrained body is held
    /// and reads zero).
    pub fn unbalanced(&self, k: usize) -> (Vec3, Vec3) {
        if self.bodies[k].fixed {
            return (Vec3::zeros(), Vec3::zeros());
        }
        let mut f = self.force[k];
        if self.restraint[k] == Some(EndRestraint::Rigid) {
            f.y = 0.0;
        }
        (f, self.torque[k])
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
    /// re-detected first if the jump moved a body past the re-detection threshold.
    ///
    /// # Panics
    /// If `dpos` or `drot` do not have one entry per body.
    pub fn predict(&mut self, dpos: &[Vec3], drot: &[Vec3]) {
        assert_eq!(dpos.len(), self.bodies.len(), "one translation per body");
        assert_eq!(drot.len(), self.bodies.len(), "one rotation per body");
        let mut jump = vec![(Vec3::zeros(), Vec3::zeros()); self.bodies.len()];
        for (k, b) in self.bodies.iter_mut().enumerate() {
            if b.fixed {
                continue;
            }
            let mut d = dpos[k];
            if self.restraint[k] == Some(EndRestraint::Rigid) {
                d.y = 0.0;
            }
            b.pos += d;
            b.rotate(drot[k]);
            jump[k] = (d, drot[k]);
        }
        // Re-detection may change the time step (density scaling): the velocities below
        // use the step the contact pass will use.
        if self.needs_detection() {
            self.detect_contacts(false);
        }
        // The jump as one step's velocities: the contact pass reads the shear increments as
        // `v Δt`.
        let dt = self.dt;
        for (b, (d, w)) in self.bodies.iter_mut().zip(&jump) {
            b.vel = d / dt;
            b.angvel = w / dt;
        }
        self.contact_pass();
        for b in &mut self.bodies {
            b.vel = Vec3::zeros();
            b.angvel = Vec3::zeros();
        }
    }

    /// Step 4: adds the loads (weight, end-restraint springs, external forces and torques)
    /// to the contact forces of the last contact pass; returns the sum of the free bodies'
    /// out-of-balance loads `|F| + |T|/r` (N) and their number.
    #[inline(always)]
    fn load_pass(&mut self) -> (f64, usize) {
        let mut sum_unbalanced = 0.0;
        let mut free = 0usize;
        for (k, b) in self.bodies.iter().enumerate() {
            if b.fixed {
                continue;
            }
            let mut f = self.force[k] + self.gravity * b.mass + self.external_force[k];
            self.torque[k] += self.external_torque[k];
            if let Some(EndRestraint::Spring(kk)) = self.restraint[k] {
                f.y -= kk * (b.pos.y - b.pos0.y);
            }
            self.force[k] = f;
            let mut fu = f;
            if self.restraint[k] == Some(EndRestraint::Rigid) {
                fu.y = 0.0;
            }
            // Out-of-balance moment counted as a force at the body's radius, so that a
            // block rotating about an edge is not mistaken for one at rest.
            sum_unbalanced += fu.norm() + self.torque[k].norm() / b.radius;
            free += 1;
        }
        (sum_unbalanced, free)
    }

    /// The out-of-balance statistics of the state [`Simulation::predict`] has just placed
    /// (its contact pass is the jump's): adds the loads and sets [`Simulation::stats`]
    /// (kinetic energy 0) and the out-of-balance loads read by [`Simulation::unbalanced`].
    pub(crate) fn assess_predicted(&mut self) -> StepStats {
        let mut sum_contact = 0.0;
        let mut active = 0usize;
        for c in &self.contacts {
            let mag = c.force.norm();
            if mag > 0.0 {
                sum_contact += mag;
                active += 1;
            }
        }
        let (sum_unbalanced, free) = self.load_pass();
        let mean_unbalanced = if free > 0 { sum_unbalanced / free as f64 } else { 0.0 };
        let mean_contact = if active > 0 { sum_contact / active as f64 } else { 0.0 };
        self.stats = StepStats::new(mean_unbalanced, mean_contact, 0.0, active);
        self.stats
    }

    /// Advances one step (see the module doc for the order).
    ///
    /// The step is compiled three times: for the baseline x86-64 instruction set, with AVX2
    /// and with AVX-512 enabled; the best one the CPU supports is taken (runtime detection,
    /// [`Isa::best`]). All three perform the same IEEE-754 operations in the same order (Rust
    /// never fuses a multiply and an add on its own, and square root and division are
    /// correctly rounded in every instruction set), so the results are the same bit for bit
    /// on any x86-64 machine; only the speed differs (about 5 % on the SBL tilt;
    /// `BENCHMARKS.md`). Tested by `tests/dispatch.rs`.
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
        // 1. Update contacts.
        if self.needs_detection() {
            self.detect_contacts(false);
        }
        // 2. Clear forces; 3. contact geometry and law.
        let (sum_contact, active) = self.contact_pass();
        let dt = self.dt;
        // 4. Loads.
        let (sum_unbalanced, free) = self.load_pass();
        // 5. Damping and integration.
        let damping = self.params.damping;
        let mut ke = 0.0;
        for (k, b) in self.bodies.iter_mut().enumerate() {
            let y = if matches!(self.restraint[k], Some(EndRestraint::Rigid)) {
                YConstraint::Held
            } else {
                YConstraint::Free
            };
            advance(b, self.force[k], self.torque[k], dt, damping, y);
            if !(b.pos.iter().all(|v| v.is_finite())
                && b.angvel.iter().all(|v| v.is_finite())
                && b.vel.iter().all(|v| v.is_finite()))
            {
                return Err(DemError::NonFinite { id: b.id.clone(), step: self.steps, dt_s: dt });
            }
            ke += 0.5 * b.mass * b.vel.norm_squared();
        }
        self.time += dt;
        self.steps += 1;
        // 6. Monitor.
        let mean_unbalanced = if free > 0 { sum_unbalanced / free as f64 } else { 0.0 };
        let mean_contact = if active > 0 { sum_contact / active as f64 } else { 0.0 };
        self.stats = StepStats::new(mean_unbalanced, mean_contact, ke, active);
        Ok(())
    }

    /// Total energy bookkeeping: (kinetic, gravitational potential relative to the
    /// reference configuration, elastic energy stored in the joints), J.
    pub fn energies(&self) -> (f64, f64, f64) {
        let ke: f64 = self.bodies.iter().map(|b| b.kinetic_energy()).sum();
        let pe: f64 = self.bodies.iter().map(|b| -b.mass * self.gravity.dot(&(b.pos - b.pos0))).sum();
        let el: f64 = self
            .contacts
            .iter()
            .flat_map(|c| {
                c.subs.iter().map(move |s| {
                    law::normal_energy(&c.joint, self.sub_gaps(c, s), s.area)
                        + law::shear_energy(&c.joint, &s.state, s.area)
                })
            })
            .sum();
        (ke, pe, el)
    }

    /// Name of a contact's joint: `table/ID` or `ID_A/ID_B`.
    pub fn joint_name(&self, c: &Contact) -> String {
        match c.a {
            None => format!("table/{}", self.bodies[c.b].id),
            Some(i) => format!("{}/{}", self.bodies[i].id, self.bodies[c.b].id),
        }
    }
}
