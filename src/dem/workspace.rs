//! The engine's workspace ([`Workspace`]): what a step of the penalty engine derives from the
//! state and the parameters and caches between steps (time step, joint table, detection
//! poses, out-of-balance forces), and the stages of a step as its methods: contact
//! detection, the contact pass, the load pass, integration.

use super::contact::forces::{contact_dashpot, contact_forces, effective_mass, NodeScratch};
use super::contact::geometry as cgeom;
use super::contact::law::JointParams;
use super::contact::types::{Contact, ContactNode, SubContact};
use super::damping::ContactDamping;
use super::error::DemError;
use super::integrator::{advance, advance_constrained, YConstraint};
use super::materials::JointTable;
use super::model::WallState;
use super::monitor::StepStats;
use super::params::{DensityScaling, SolverParams};
use super::timestep::{block_masses, density_scaling, set_closure_windows, step_for, Stiffness};
use crate::closure::Closure;
use crate::geometry::sweep::sweep_pairs;
use crate::layout::{EndRestraint, Layout};
use crate::math::Vec3;

/// What the re-detection of contacts before a jump or a step did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Redetection {
    /// No body moved past the re-detection threshold: no detection.
    None,
    /// Contacts detected afresh, the same contacts with every patch kept: the inertial
    /// masses and the time step stand.
    Unchanged,
    /// Contacts detected afresh and changed. After `Simulation::step` and
    /// `Simulation::predict` the inertial masses and the time step are already those of
    /// the new contacts; after `Simulation::predict_deferred` they are stale until
    /// `Simulation::update_masses_and_step`.
    Changed,
}

impl Redetection {
    /// The inertial masses and the time step need an update (contacts changed).
    pub fn changed(self) -> bool {
        self == Redetection::Changed
    }
}

/// The engine's workspace: what a step derives from the state and the parameters, and
/// caches between steps. Its methods are the stages of the step.
#[derive(Debug, Clone)]
pub(super) struct Workspace {
    /// Time step, s.
    pub(super) dt: f64,
    /// Statistics of the last step (or the last assessed jump).
    pub(super) stats: StepStats,
    /// Contact detections so far (the initial one included).
    pub(super) detections: u64,
    /// Largest density-scaling factor applied so far (1: none).
    pub(super) max_density_scale: f64,
    /// Out-of-balance force per body, N, table frame (contacts, then loads).
    pub(super) force: Vec<Vec3>,
    /// Out-of-balance moment per body about its centroid, N·m, table frame.
    pub(super) torque: Vec<Vec3>,
    /// Poses at the last detection.
    pub(super) detect_pos: Vec<Vec3>,
    pub(super) detect_rot: Vec<nalgebra::UnitQuaternion<f64>>,
    /// Joint parameters by material pair and joint family.
    pub(super) joints: JointTable,
    /// Per-node scratch of the contact pass.
    pub(super) scratch: Vec<NodeScratch>,
    /// Normal contact damping (true dynamics only; `None`: none, the default).
    pub(super) contact_damping: Option<ContactDamping>,
    /// Per-node lumped areas of the dashpot (scratch).
    pub(super) node_area: Vec<f64>,
    /// Each rope's deflection δ̄ (m) at the last update of the time step: the centre of
    /// the window its stiffness bound covers.
    pub(super) rope_window: Vec<f64>,
    /// Set by the contact pass when a sub-contact closed past its closure window
    /// ([`super::contact::types::SubContact::window_cap_m`]); the next step's redetection
    /// updates the time step.
    pub(super) closure_left_window: bool,
}

impl Workspace {
    pub(super) fn new(layout: &Layout, st: &WallState) -> Workspace {
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
            contact_damping: None,
            node_area: Vec::new(),
            rope_window: Vec::new(),
            closure_left_window: false,
        }
    }

    /// Stage 1: detects contacts afresh and carries the history of persisting
    /// sub-contacts over. A contact whose pair has barely moved relative to its patch keeps
    /// it (and its history: see [`SolverParams::patch_reuse_fraction`]); the
    /// separating-axis test of a pair without a contact stops at the first axis that
    /// separates the pair by more than the margin. Returns `Unchanged` or `Changed`; the
    /// masses and the time step are left to the caller.
    pub(super) fn detect(&mut self, st: &mut WallState, settings: &SolverParams, initial: bool) -> Redetection {
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
            if st.bodies[j].fixed() {
                continue;
            }
            match st.reusable(None, j, reuse_tol) {
                Some(c) => kept.push(c),
                None if boxes[j].min.z <= settings.contact_margin_m => fresh.push((None, j)),
                None => {}
            }
        }
        for (i, j) in sweep_pairs(&boxes, settings.contact_margin_m) {
            if st.bodies[i].fixed() && st.bodies[j].fixed() {
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
    pub(super) fn make_contact(
        &self,
        st: &WallState,
        a: Option<usize>,
        b: usize,
        p: cgeom::Patch,
        initial: bool,
    ) -> Contact {
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
        let subs = p.triangles.iter().map(|t| SubContact::new(t.nodes, t.area, &joint, bonded)).collect();
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
    pub(super) fn update_masses_and_step(&mut self, st: &mut WallState, params: &SolverParams) {
        set_closure_windows(&st.bodies, &mut st.contacts);
        self.closure_left_window = false;
        let mut stiffness = Stiffness::new(&st.bodies, &st.contacts);
        // A rope's deflection is checked at every detection (`rope_left_window`), and a
        // bearer moves at most the re-detection threshold between two: the bound covers
        // twice that either side.
        let reach = params.redetect_fraction * params.contact_margin_m;
        stiffness.add_restraints(&st.bodies, &st.restraint, &st.ropes, 2.0 * reach);
        self.rope_window = st.ropes.iter().map(|r| r.deflection(&st.bodies)).collect();
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
        let lambda = stiffness.max_eigenvalue(&st.bodies);
        let Some(dt) = step_for(lambda, params.timestep_safety, params.damping) else {
            return;
        };
        let dt = match &self.contact_damping {
            None => dt,
            Some(d) => dt * d.step_factor(lambda.sqrt(), damping_rate(st, d)),
        };
        // Static solutions take the step of the current masses; dynamics only ever shrink it,
        // so that a run keeps one time base.
        self.dt = if params.density_scaling.is_on() { dt } else { self.dt.min(dt) };
    }

    /// Whether a rope's deflection has left the window `[δ̄ − reach, δ̄ + reach]` its
    /// stiffness bound was taken over at the last update of the time step
    /// ([`Stiffness::add_restraints`]).
    fn rope_left_window(&self, st: &WallState, params: &SolverParams) -> bool {
        let reach = params.redetect_fraction * params.contact_margin_m;
        st.ropes.iter().zip(&self.rope_window).any(|(r, &d0)| (r.deflection(&st.bodies) - d0).abs() > reach)
    }

    /// Whether a body moved, since the last detection, more than
    /// [`SolverParams::redetect_fraction`] of the contact margin (translation plus rotation
    /// times its radius).
    pub(super) fn needs_detection(&self, st: &WallState, params: &SolverParams) -> bool {
        let limit = params.redetect_fraction * params.contact_margin_m;
        st.bodies.iter().enumerate().any(|(k, b)| {
            if b.fixed() {
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
    pub(super) fn redetect(&mut self, st: &mut WallState, params: &SolverParams, deferred: bool) -> Redetection {
        // A sub-contact closed past the window of its closure law's tangent the step was
        // taken over (`Stiffness::new`): the step follows, as it follows a rope. A deferred
        // redetection leaves the flag to the next step.
        let closure_left = !deferred && std::mem::take(&mut self.closure_left_window);
        if !self.needs_detection(st, params) {
            if closure_left {
                self.update_masses_and_step(st, params);
            }
            return Redetection::None;
        }
        let mut r = self.detect(st, params, false);
        if r == Redetection::Unchanged && (closure_left || self.rope_left_window(st, params)) {
            // The contacts stand but a rope's stiffness bound no longer covers its deflection,
            // or a closure law's tangent bound no longer covers a sub-contact's closure.
            r = Redetection::Changed;
        }
        if r.changed() && !deferred {
            self.update_masses_and_step(st, params);
        }
        r
    }

    /// Stages 2 and 3: clears the force accumulators and evaluates every contact at the
    /// current pose, with the shear increments of the velocities `v Δt` (the motion since
    /// the last evaluation), plus, with contact damping on ([`super::damping`]), each
    /// contact's normal dashpots against the velocities of the step; returns the sum of the
    /// contact force magnitudes (N) and the number of contacts carrying force.
    #[inline(always)]
    pub(super) fn contact_pass(&mut self, st: &mut WallState, params: &SolverParams) -> (f64, usize) {
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
                None => contact_forces::<false>(c, bb, bb, dt, quad, &mut self.scratch, &mut self.closure_left_window),
                Some(i) => contact_forces::<true>(
                    c,
                    &bodies[i],
                    bb,
                    dt,
                    quad,
                    &mut self.scratch,
                    &mut self.closure_left_window,
                ),
            };
            let (fsum, ta, tb) = match &self.contact_damping {
                None => (fsum, ta, tb),
                Some(d) => {
                    let area: f64 = c.subs.iter().map(|s| s.area).sum();
                    let m = effective_mass(c.a.map(|i| &bodies[i]), bb);
                    match m {
                        Some(m) if area > 0.0 => {
                            let cp = d.dashpot_pressure(c.joint.kn_bound(), area, m);
                            let (fd, tad, tbd) = match c.a {
                                None => contact_dashpot::<false>(c, bb, bb, cp, &self.scratch, &mut self.node_area),
                                Some(i) => {
                                    contact_dashpot::<true>(c, &bodies[i], bb, cp, &self.scratch, &mut self.node_area)
                                }
                            };
                            (fsum + fd, ta + tad, tb + tbd)
                        }
                        _ => (fsum, ta, tb),
                    }
                }
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

    /// Stage 4: adds the loads (weight, end-restraint springs, rope restraints, external
    /// forces and torques) to the contact forces of the last contact pass; returns the sum
    /// of the free bodies' out-of-balance loads `|F| + |T|/r` (N) and their number.
    #[inline(always)]
    pub(super) fn load_pass(&mut self, st: &WallState) -> (f64, usize) {
        for rope in &st.ropes {
            rope.add_forces(&st.bodies, &mut self.force, &mut self.torque);
        }
        let mut sum_unbalanced = 0.0;
        let mut free = 0usize;
        for (k, b) in st.bodies.iter().enumerate() {
            if b.fixed() {
                continue;
            }
            let mut f = self.force[k] + st.gravity * b.mass + st.external_force[k];
            self.torque[k] += st.external_torque[k];
            if let Some(EndRestraint::Spring(kk)) = st.restraint[k] {
                f.y -= kk * (b.pos.y - b.pos0.y);
            }
            if let Some(c) = b.hold.dof() {
                c.react(b, &mut f, &mut self.torque[k]);
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
    pub(super) fn integrate(&mut self, st: &mut WallState, params: &SolverParams) -> Result<f64, DemError> {
        let dt = self.dt;
        let damping = params.damping;
        let mut ke = 0.0;
        for (k, b) in st.bodies.iter_mut().enumerate() {
            let y = if matches!(st.restraint[k], Some(EndRestraint::Rigid)) {
                YConstraint::Held
            } else {
                YConstraint::Free
            };
            match b.hold.dof().copied() {
                None => advance(b, self.force[k], self.torque[k], dt, damping, y),
                Some(c) => advance_constrained(b, self.force[k], self.torque[k], dt, damping, &c),
            }
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
    pub(super) fn monitor(
        &mut self,
        (sum_contact, active): (f64, usize),
        (sum_unbalanced, free): (f64, usize),
        ke: f64,
    ) {
        let mean_unbalanced = if free > 0 { sum_unbalanced / free as f64 } else { 0.0 };
        let mean_contact = if active > 0 { sum_contact / active as f64 } else { 0.0 };
        self.stats = StepStats::new(mean_unbalanced, mean_contact, ke, active);
    }
}

/// The largest damping rate of the contact dashpots, `λ_max(M⁻¹ C)` (1/s, an upper
/// estimate): the dashpots assembled as the normal springs of the time step's stiffness
/// (`dem::timestep::Stiffness`, the same nodes, areas and arms), each contact's spring
/// pressure its dashpot pressure `c_p` and no shear, against the true masses.
fn damping_rate(st: &WallState, d: &ContactDamping) -> f64 {
    let dashpots: Vec<Contact> = st
        .contacts
        .iter()
        .filter_map(|c| {
            let area: f64 = c.subs.iter().map(|s| s.area).sum();
            let m = effective_mass(c.a.map(|i| &st.bodies[i]), &st.bodies[c.b])?;
            (area > 0.0).then(|| {
                let kn = d.dashpot_pressure(c.joint.kn_bound(), area, m);
                let joint = JointParams { kn, ks: 0.0, closure: Closure::Linear, ..c.joint };
                Contact { joint, ..c.clone() }
            })
        })
        .collect();
    Stiffness::new(&st.bodies, &dashpots).max_eigenvalue(&st.bodies)
}
