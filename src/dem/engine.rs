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
//!    With contact damping on (true dynamics: [`Simulation::set_contact_damping`]) each
//!    contact's normal dashpots are added ([`super::damping`]).
//! 4. **Loads**: gravity (table frame), end-restraint springs, rope restraints
//!    ([`super::rope`]), external forces.
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

pub use super::contact::types::Contact;
use super::damping::ContactDamping;
pub use super::dispatch::Isa;
pub use super::error::DemError;
pub use super::model::WallState;
use super::monitor::StepStats;
use super::params::{DensityScaling, SolverParams};
pub use super::workspace::Redetection;
use super::workspace::Workspace;
use crate::layout::{EndRestraint, Layout};
use crate::math::Vec3;

/// One simulation: the model state, the solver parameters and the engine's workspace.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The model state: bodies, contacts, loads, time.
    pub state: WallState,
    params: SolverParams,
    work: Workspace,
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

    /// Sets the normal contact damping of true dynamics (a dashpot per contact from a
    /// coefficient of restitution, [`super::damping`]; `None`: none, the default) and the
    /// time step for it (the step only shrinks). For dynamics with true masses and no
    /// local damping (`density_scaling = off`, `damping = 0`): the shaking table with the
    /// penalty solver.
    pub fn set_contact_damping(&mut self, damping: Option<ContactDamping>) {
        self.work.contact_damping = damping;
        self.update_masses_and_step();
    }

    /// The normal contact damping ([`Simulation::set_contact_damping`]).
    pub fn contact_damping(&self) -> Option<ContactDamping> {
        self.work.contact_damping
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
        if self.state.bodies[k].fixed() {
            return (Vec3::zeros(), Vec3::zeros());
        }
        let mut f = self.work.force[k];
        if self.state.restraint[k] == Some(EndRestraint::Rigid) {
            f.y = 0.0;
        }
        // A constrained body's held components were taken out in the load stage.
        (f, self.work.torque[k])
    }

    /// The load each body carries after the last step, N, in body order: its weight plus
    /// the magnitudes of its contact forces (the yardstick of a block's own balance).
    pub fn carried_loads(&self) -> Vec<f64> {
        let g = self.state.gravity_magnitude;
        let mut load: Vec<f64> = self.state.bodies.iter().map(|b| b.mass * g).collect();
        for c in &self.state.contacts {
            let f = c.force.norm();
            load[c.b] += f;
            if let Some(a) = c.a {
                load[a] += f;
            }
        }
        load
    }

    /// The largest **local unbalanced-force ratio** after the last step and its body: per
    /// free body, its out-of-balance load `|F| + |T| / r` (the net force, N, plus the net
    /// moment about its centroid, N·m, over its radius r, m: the unbalanced-force ratio's
    /// measure, [`super::monitor::StepStats`]) over the load it carries, its weight plus the
    /// magnitudes of its contact forces (N). The global ratio is a mean over the wall, so a
    /// lightly loaded block that is still moving (a half-stone rocking back onto its bed,
    /// a loose block sliding) hides under the wall's forces; the local ratio sees it
    /// (3DEC and FLAC3D's `ratio-local`, Itasca 2019). `(0, None)` with no free body; a
    /// body that carries nothing and is pushed reads infinity.
    pub fn largest_local_ratio(&self) -> (f64, Option<usize>) {
        let load = self.carried_loads();
        let mut worst = (0.0, None);
        for (k, b) in self.state.bodies.iter().enumerate() {
            if b.fixed() {
                continue;
            }
            let (f, t) = self.unbalanced(k);
            let out = f.norm() + if b.radius > 0.0 { t.norm() / b.radius } else { 0.0 };
            let ratio = if load[k] > 0.0 {
                out / load[k]
            } else if out > 0.0 {
                f64::INFINITY
            } else {
                0.0
            };
            if ratio > worst.0 {
                worst = (ratio, Some(k));
            }
        }
        worst
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
            if b.fixed() {
                continue;
            }
            let mut d = dpos[k];
            if st.restraint[k] == Some(EndRestraint::Rigid) {
                d.y = 0.0;
            }
            let mut w = drot[k];
            let constraint = b.hold.dof().copied();
            if let Some(c) = &constraint {
                c.hold_velocities(&mut d, &mut w);
            }
            b.pos += d;
            b.rotate(w);
            if let Some(c) = &constraint {
                // The anchor's placement is part of the jump the joints see.
                let before = b.pos - d;
                c.place(b);
                d = b.pos - before;
            }
            jump[k] = (d, w);
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
        self.jump_contact_pass();
        for b in &mut self.state.bodies {
            b.vel = Vec3::zeros();
            b.angvel = Vec3::zeros();
        }
        r
    }

    /// The contact pass of a jump, compiled per instruction set as the step is (the widest
    /// one this CPU runs; the same bits as the baseline's, see [`Simulation::step`]).
    fn jump_contact_pass(&mut self) {
        match Isa::best() {
            // SAFETY: `Isa::best` returns only a variant this CPU supports.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => unsafe { self.contact_pass_avx512() },
            // SAFETY: as above.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { self.contact_pass_avx2() },
            _ => {
                self.work.contact_pass(&mut self.state, &self.params);
            }
        }
    }

    /// The contact pass compiled with AVX-512.
    ///
    /// # Safety
    /// The CPU must support AVX-512F, AVX-512VL, AVX2 and FMA ([`Isa::Avx512`] available).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx2,fma")]
    unsafe fn contact_pass_avx512(&mut self) {
        self.work.contact_pass(&mut self.state, &self.params);
    }

    /// The contact pass compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA ([`Isa::Avx2`] available).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn contact_pass_avx2(&mut self) {
        self.work.contact_pass(&mut self.state, &self.params);
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
    /// on any x86-64 machine; only the speed may differ. Tested by `tests/suite/dispatch.rs`.
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
