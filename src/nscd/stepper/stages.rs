//! The stages of a swept step of the Moreau–Jean scheme (the module doc of
//! [`super`]): the work arrays loaded from the bodies, the rows and Signorini terms of
//! every contact point, the free velocities under the smooth loads (weight, base
//! acceleration, external loads, end-restraint springs, ropes, gyroscopic torque), the
//! contact impulses by the sweeps and the gradient, and the θ-update of the poses.

use super::NscdSimulation;
use crate::math::{Mat3, Vec3};
use crate::nscd::delassus::{PointRows, TABLE};
use crate::nscd::held::Held;
use crate::nscd::nsgs::{self, BodyState};
use crate::nscd::{apgd, cone, NscdError, NscdParams, StepSolver};

impl NscdSimulation {
    /// Copies the bodies' poses, velocities and inverse inertias into the work arrays.
    pub(super) fn load_state(&mut self) {
        for (k, b) in self.bodies.iter().enumerate() {
            self.x[k] = b.pos;
            self.vel[k] = b.vel;
            self.angvel[k] = b.angvel;
            self.inv_i[k] = if b.fixed() { Mat3::zeros() } else { b.rot_mat * b.inv_inertia * b.rot_mat.transpose() };
        }
        for (k, b) in self.bodies.iter().enumerate() {
            if let Some(c) = b.hold.dof() {
                self.inv_i[k] = Mat3::zeros();
                self.held[k] = Some(Held::new(c, b, self.params.dt_s));
            }
        }
    }

    /// Stage 2: rows and Signorini terms of every point at the start of the step.
    pub(super) fn build_rows(&mut self) {
        let (h, theta, e) = (self.params.dt_s, self.params.theta, self.params.restitution);
        let constrained = self.constrained();
        self.rows.clear();
        for c in &self.points {
            let (pa, pb) = c.world_points(&self.bodies);
            let n = c.normal(&self.bodies);
            let gap = (pb - pa).dot(&n);
            let mut rows =
                PointRows::new(c.a.unwrap_or(TABLE), c.b, 0.5 * (pa + pb), n, &self.x, &self.inv_m, &self.inv_i, c.mu);
            let un = rows.velocity(&self.vel, &self.angvel).x;
            let mut bias = if gap > 0.0 { (gap + h * (1.0 - theta) * un).max(0.0) / (h * theta) } else { 0.0 };
            if gap + h * un <= 0.0 && un < 0.0 {
                bias += e * un;
            }
            rows.bias = bias;
            if constrained {
                rows.couple(&self.held);
            }
            self.rows.push(rows);
        }
    }

    /// Stage 3: the velocities the smooth forces give by the end of the step.
    pub(super) fn free_velocities(&mut self, h: f64, a_g: Vec3) {
        self.rope_loads_predicted(h);
        for k in 0..self.bodies.len() {
            if self.bodies[k].fixed() {
                continue;
            }
            let (f, t) = self.smooth_load(k, a_g, self.angvel[k]);
            if let Some(held) = &self.held[k] {
                let (v, w) = held.project(&self.vel[k], &self.angvel[k]);
                let (dv, dw) = held.apply(&(h * f), &(h * t));
                self.vel[k] = v + dv;
                self.angvel[k] = w + dw;
                continue;
            }
            self.vel[k] += h * self.inv_m[k].component_mul(&f);
            self.angvel[k] += h * (self.inv_i[k] * t);
        }
    }

    /// The ropes' forces and moments on every body at the current poses, into
    /// `rope_force` and `rope_torque` (nothing without ropes).
    pub(super) fn rope_loads(&mut self) {
        if !self.ropes.is_empty() {
            self.rope_force.fill(Vec3::zeros());
            self.rope_torque.fill(Vec3::zeros());
            for rope in &self.ropes {
                rope.add_forces(&self.bodies, &mut self.rope_force, &mut self.rope_torque);
            }
        }
    }

    /// The ropes' forces and moments for the free velocities of a step of length `h`, into
    /// `rope_force` and `rope_torque`: at the poses advanced by `(1 − θ) h v⁻` (each body by
    /// its velocities at the start of the step), not at the start of the step. The rope is
    /// an explicit force in the θ-step; taken at the start of the step, a spring `k` on a
    /// mass `m` gains energy every step (the step's matrix has determinant
    /// `1 + (1 − θ) h² k / m`, so that at θ = 1/2 a stiff rope's oscillation grows without
    /// bound whatever the step), while at the advanced poses the determinant is 1 and the
    /// step is stable for `h √(k/m) < 2` (with θ = 1 the poses are those of the start).
    fn rope_loads_predicted(&mut self, h: f64) {
        if self.ropes.is_empty() {
            return;
        }
        let c = (1.0 - self.params.theta) * h;
        for (p, b) in self.rope_bodies.iter_mut().zip(&self.bodies) {
            p.pos = b.pos;
            p.rot = b.rot;
            p.rot_mat = b.rot_mat;
            if !b.fixed() && c > 0.0 {
                p.pos += c * b.vel;
                p.rotate(c * b.angvel);
            }
        }
        self.rope_force.fill(Vec3::zeros());
        self.rope_torque.fill(Vec3::zeros());
        for rope in &self.ropes {
            rope.add_forces(&self.rope_bodies, &mut self.rope_force, &mut self.rope_torque);
        }
    }

    /// The smooth load on free body `k` (N, and N·m about its centroid; table frame): its
    /// weight and the d'Alembert force of the base acceleration `a_g`, the external load,
    /// its end-restraint spring, the ropes (from [`Self::rope_loads`]) and the gyroscopic
    /// torque `−ω × I ω` of the angular velocity `w`.
    pub(super) fn smooth_load(&self, k: usize, a_g: Vec3, w: Vec3) -> (Vec3, Vec3) {
        let b = &self.bodies[k];
        let mut f = (self.gravity - a_g) * b.mass + self.external_force[k];
        if let Some(kk) = self.spring[k] {
            f.y -= kk * (b.pos.y - b.pos0.y);
        }
        let iw = b.rot_mat * b.inertia * b.rot_mat.transpose();
        let mut t = self.external_torque[k] - w.cross(&(iw * w));
        if !self.ropes.is_empty() {
            f += self.rope_force[k];
            t += self.rope_torque[k];
        }
        (f, t)
    }

    /// Stage 4: the warm start (the impulses of the last step applied) and the NSGS
    /// sweeps ([`nsgs::solve`]), then the gradient ([`apgd::solve`]) by
    /// [`NscdParams::step_solver`], and a step the gradient leaves at its limit finished
    /// by [`cone::solve`]; returns (sweeps and iterations, converged, velocity
    /// residual in m/s, quadratic residual, natural-map residual).
    pub(super) fn nsgs(&mut self) -> (u32, bool, f64, f64, f64) {
        self.impulse.clear();
        self.impulse.extend(self.points.iter().map(|c| c.impulse));
        for (r, rows) in self.impulse.iter().zip(&self.rows) {
            rows.apply(r, &mut self.vel, &mut self.angvel, &self.inv_m, &self.inv_i, &self.held);
        }
        let gh = self.gravity_magnitude * self.params.dt_s;
        let mut bodies = BodyState {
            vel: &mut self.vel,
            angvel: &mut self.angvel,
            inv_m: &self.inv_m,
            inv_i: &self.inv_i,
            held: &self.held,
            radius: &self.radius,
        };
        let p = &self.params;
        // The natural-map residual, when the gradient's stopping rule read it.
        let mut natural = None;
        let out = match p.step_solver {
            StepSolver::Nsgs => {
                nsgs::solve(&self.plan, &self.rows, &mut self.impulse, &mut bodies, p, gh, &mut self.nsgs_scratch)
            }
            StepSolver::Apgd => {
                let sweeps =
                    (p.apgd_after_solves / self.rows.len().max(1) as f64).ceil().min(f64::from(p.max_iterations));
                let first = NscdParams { max_iterations: sweeps as u32, ..*p };
                let swept = (first.max_iterations > 0).then(|| {
                    nsgs::solve(
                        &self.plan,
                        &self.rows,
                        &mut self.impulse,
                        &mut bodies,
                        &first,
                        gh,
                        &mut self.nsgs_scratch,
                    )
                });
                // The sweeps' own norm is not the criterion of a step of motion: a step
                // they end is converged only if its natural-map residual meets
                // `natural_tolerance`, else the gradient takes it from there.
                let solved = match &swept {
                    Some(out) if out.converged => {
                        let r = nsgs::natural_residual(&self.rows, &self.impulse, bodies.vel, bodies.angvel, gh);
                        natural = Some(r);
                        r <= p.natural_tolerance
                    }
                    _ => false,
                };
                match swept {
                    Some(out) if solved => out,
                    _ => {
                        let done = swept.map_or(0, |o| o.sweeps);
                        let left = p.max_iterations.saturating_sub(done);
                        let out = apgd::solve(
                            &self.rows,
                            &mut self.impulse,
                            &mut bodies,
                            p.natural_tolerance,
                            left,
                            gh,
                            &mut self.apgd,
                        );
                        // The steps the gradient leaves at its limit: finished as cone
                        // programs (the sweeps count the gradient's iterations).
                        let out = if out.converged {
                            out
                        } else {
                            let finished =
                                cone::solve(&self.rows, &mut self.impulse, &mut bodies, p.natural_tolerance, gh);
                            nsgs::SweepOutcome { sweeps: out.sweeps, ..finished }
                        };
                        natural = Some(out.quad);
                        nsgs::SweepOutcome { sweeps: done + out.sweeps, ..out }
                    }
                }
            }
        };
        let natural =
            natural.unwrap_or_else(|| nsgs::natural_residual(&self.rows, &self.impulse, &self.vel, &self.angvel, gh));
        for (c, r) in self.points.iter_mut().zip(&self.impulse) {
            c.impulse = *r;
        }
        (out.sweeps, out.converged, out.residual_m_per_s, out.quad, natural)
    }

    /// Stage 5: the θ-update of the poses; the new velocities into the bodies.
    pub(super) fn advance(&mut self, h: f64, theta: f64) -> Result<(), NscdError> {
        for (k, b) in self.bodies.iter_mut().enumerate() {
            if b.fixed() {
                continue;
            }
            let (v, w) = (self.vel[k], self.angvel[k]);
            b.pos += h * (theta * v + (1.0 - theta) * b.vel);
            b.rotate(h * (theta * w + (1.0 - theta) * b.angvel));
            b.vel = v;
            b.angvel = w;
            if let Some(c) = b.hold.dof().copied() {
                c.place(b);
            }
            if !(b.pos.iter().all(|c| c.is_finite())
                && v.iter().all(|c| c.is_finite())
                && w.iter().all(|c| c.is_finite()))
            {
                return Err(NscdError::NonFinite { id: b.id.clone(), step: self.steps, dt_s: h });
            }
        }
        self.time += h;
        self.steps += 1;
        Ok(())
    }
}
