//! A semi-smooth Newton method for one static increment of the penalty DEM: the
//! incremental elasto-plastic problem of the joints solved with their consistent tangent,
//! globalised by a bound on each step from the joints' gaps, Anderson mixing of the steps
//! and a backtracking line search.
//!
//! # The increment as a return mapping
//!
//! The joint history of a sub-contact is its shear force (with its slip and bond state);
//! the normal force follows from the total closure and has none (`contact::law`). The
//! increment's start state (the poses and the history at entry: the last converged state,
//! or the secant prediction a protocol jumped to) is kept fixed, and every iterate
//! evaluates the contact forces from it with the TOTAL motion of the increment `Δq_k` in
//! one jump of [`Simulation::predict_deferred`]: the joints take the relative motion of
//! the whole increment as one shear increment, the trial force `T = Fs₀ − Ks A Δuₛ`, and
//! the Coulomb limit and the no-tension closure act on it once (the radial return of
//! computational plasticity, Simo & Hughes 1998, *Computational Inelasticity*, ch. 3;
//! Wriggers 2006, *Computational Contact Mechanics*, ch. 5). Restoring the start state and
//! making one jump is exact for this: a jump applies the relative motion of the bodies at
//! each sub-contact's centroid as one shear increment (a straight path), which is what a
//! return map from the converged state does. The history left by the solve is therefore
//! that of one jump from the start, whatever path the iterates took (the implicit
//! iteration, `super::implicit`, chains its jumps, so its joints' history follows the
//! iterates).
//!
//! # The consistent tangent
//!
//! `R(Δq)` is the out-of-balance force and moment of every free body (N, N·m about its
//! centroid, table frame) after the jump; Newton's step solves `K d = R` with `K = −∂R/∂q`
//! at the current iterate, assembled per body pair with the lever arms of the springs
//! (`tangent`):
//!
//! * the normal springs over the compressed part of each sub-contact triangle (clipped at
//!   the zero-closure line; the part carrying tension where a bonded joint has a tensile
//!   strength), integrated by the rule exact for quadratics (weights `a/12` at the
//!   vertices, `3a/4` at the centroid of each piece of area `a`), with the closure law's
//!   tangent `dq/du` at each point: exact for the linear law, zero where the joint is open
//!   (the piecewise-smooth Jacobian of the no-tension closure, Alart & Curnier 1991,
//!   *Comput. Methods Appl. Mech. Eng.* 92, 353, in its penalty form);
//! * the shear spring `Ks A (I − n nᵀ)` at the sub-contact's centroid where it sticks;
//!   where it slips, the derivative of the radial return `Fs = μ Fn T/|T|`:
//!   `μFn/|T| (I − n nᵀ − e eᵀ) Ks A` (`e = T/|T|`, the factor stored by the law as
//!   `SubContactState::return_scale`) and the coupling `μ e ⊗ ∂Fn/∂q` to the normal springs
//!   of the same sub-contact, which makes `K` non-symmetric;
//! * the end-restraint springs and the rigs' moments linear in the motion;
//! * held degrees of freedom as the jump holds them: a held rotation is left out, a held
//!   translation at an anchor off the centroid moves the centroid with the body's rotation
//!   (`K_red = Eᵀ K E` with that map `E`), which is how the load stage reports the
//!   out-of-balance moment of such a body.
//!
//! * the geometric stiffness, every term of the law as coded that moves with the poses
//!   (`tangent_blocks`): the forces act at the mid-points of the node pairs, whose arms
//!   move half with each body; the normal `n = (R_a n_a + R_b n_b)/|…|` turns with both
//!   bodies, and with it the normal force, the closures (by the offset `p_a − p_b` of
//!   each node's two points along the joint) and the trial shear force (the stored force
//!   projected onto the current plane, `slip::shear`: `δT = −n (δn·T) + Ks A (n·r) δn`,
//!   through the radial return); the jump's own rotation enters the shear increment
//!   `r = Δx_b + w_b × (x_c − x_b) − …` through its arms, and the rotation columns are
//!   taken with respect to the jump's rotation vector (`δθ = J(w) δw`, `J` the left
//!   Jacobian of SO(3));
//! * the lever of the shear force, whose point of application moves between the area
//!   centroid of the compressed part and the pressure centroid with the closures and the
//!   mobilised fraction (`contact::law::evaluate`), taken by central differences of the
//!   law's own rule.
//!
//! `K` is factorized by faer's sparse LU with partial pivoting (supernodal, COLAMD
//! ordering, run sequentially); every diagonal entry gets [`tangent::FLOOR`] of the largest
//! diagonal entry of its kind added, which matters only where the tangent is singular (a
//! body with no closed contact, a sliding or rocking mechanism).
//!
//! # Globalisation and ending
//!
//! The merit of a state is `φ = Σ |f|² + |t/ρ|²` (the out-of-balance forces and moments
//! over the body radius ρ). It rewards a step that breaks contacts: a sub-contact that opens
//! carries no force and so leaves no out-of-balance force, and a lightly loaded block (a
//! half-block under a lifted corner of the beam) thrown off its neighbours leaves only its
//! weight, which can be less than the imbalance of the wedged state it left. Two things
//! keep the iterates on the wall:
//!
//! * **The step is bounded by the joints' gaps** ([`NewtonSolve::opening_bound`], κ): no
//!   step may open a node of a contact by more than its gap now plus κ times the larger of
//!   the contact's largest closure and the mean closure of the state's closed nodes (the
//!   joints' elastic closure). The bound is a largest step length `s_max` along the
//!   direction, from the motion of each node linear in the step; the direction itself is
//!   kept, so the step stays one of descent. It is the step-length control of a trust
//!   region (Nocedal & Wright 2006, *Numerical Optimization*, ch. 4; Dennis & Schnabel
//!   1996, § 6.4) with the region measured in the joints' gaps rather than in the
//!   unknowns: the change of each contact's state that the tangent can foresee. An opened
//!   node is bounded again by its gap (a gap may at most double plus κ closures in one
//!   step), so a block cannot leave its neighbours in one step.
//! * **The Newton steps are mixed** ([`NewtonSolve::anderson_depth`]): the steps `d_k`
//!   taken at full length are combined by Anderson mixing (Anderson 1965, *J. ACM* 12, 547;
//!   Walker & Ni 2011, *SIAM J. Numer. Anal.* 49, 1715) as the implicit iteration combines
//!   its preconditioned steps (`super::implicit`). The tangent holds each sub-contact's
//!   stick/slip state and its open or closed nodes for the step; where those change
//!   between iterates the mixing takes the slow modes this leaves.
//!
//! An iteration first tries the mixed step at full length (where the gap bound allows it)
//! and takes it if it satisfies Armijo's condition `φ(1) ≤ (1 − 2σ) φ(0)`; otherwise it
//! clears the mixing's history and searches along the Newton direction `d`: `Δq ← Δq + s
//! d` at the first `s = s₀, s₀/2, s₀/4, …` (`s₀ = min(1, s_max)`, at most
//! [`NewtonSolve::max_halvings`] halvings) with `φ(s) ≤ (1 − 2σ s) φ(0)`, `σ = 1e-4`
//! (Dennis & Schnabel 1996, *Numerical Methods for Unconstrained Optimization and Nonlinear
//! Equations*, § 6.3).
//!
//! The solve ends at equilibrium (unbalanced-force ratio below the tolerance, the
//! criterion of every static solve), when no step length reduces the merit
//! ([`Unsolved::NoDescent`]: at and past a limit point the tangent is singular and its
//! direction runs along the mechanism, where the out-of-balance force does not fall), or
//! after [`NewtonSolve::max_iterations`]. The protocol's check is asked at equilibrium
//! only: an iterate between is not a state the wall passes through (the total increment is
//! one jump from its start), so a trial step that overshoots is no collapse. Unsolved, the
//! state is put back as it was at entry, so that the cascade's next stage starts where it
//! would have without this one.
//!
//! The assembly runs in contact order with ordered maps, and the factorization and solves
//! are sequential: the same bits on any number of threads.

mod globalise;
mod tangent;

use super::implicit::anderson::AndersonMixing;
use super::implicit::stiffness::Dofs;
use super::implicit::{flatten, unflatten, PoseIncrement, Solved, Unsolved};
use crate::dem::engine::Simulation;
use crate::math::Vec3;

/// Settings of the semi-smooth Newton solve of one increment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonSolve {
    /// Newton iterations (tangent factorizations) before giving up \[30\].
    pub max_iterations: u32,
    /// Halvings of the step length the line search tries before giving up \[8\].
    pub max_halvings: u32,
    /// Past Newton steps the Anderson mixing combines (0: plain Newton steps) \[8\].
    pub anderson_depth: u32,
    /// κ of the gap bound, –: no step opens a node of a contact by more than its gap plus κ
    /// times the larger of the contact's largest closure and the state's mean closure
    /// (`f64::INFINITY`: no bound) \[1\].
    pub opening_bound: f64,
}

impl Default for NewtonSolve {
    fn default() -> Self {
        NewtonSolve { max_iterations: 30, max_halvings: 8, anderson_depth: 8, opening_bound: 1.0 }
    }
}

/// Armijo's constant of the line search, –.
pub const ARMIJO: f64 = 1e-4;

/// The merit of a state: `Σ |f|² + |t/ρ|²` over the free bodies, N² (`f`, `t` the
/// out-of-balance force and moment of [`Simulation::unbalanced`], `ρ` the body radius).
fn merit(sim: &Simulation) -> f64 {
    sim.state
        .bodies
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.fixed())
        .map(|(k, b)| {
            let (f, t) = sim.unbalanced(k);
            f.norm_squared() + (t / b.radius).norm_squared()
        })
        .sum()
}

/// Solves the static increment of `sim` (its load set, its state at entry the start of
/// the increment) for an unbalanced-force ratio below `tol` by the semi-smooth Newton
/// method of the module doc, calling `check` on the equilibrium it finds; a reason from
/// `check` stops it there. At equilibrium or when stopped, `sim` is the last iterate (one
/// jump of the total increment from the state at entry; the inertial masses and the time
/// step brought up to date if contacts were re-detected); unsolved, it is left as it was
/// at entry. The count returned is of Newton iterations (tangent factorizations).
pub fn newton_increment<R>(
    sim: &mut Simulation,
    tol: f64,
    settings: &NewtonSolve,
    check: impl FnMut(&Simulation) -> Option<R>,
) -> Solved<R> {
    let (out, last) = iterate(sim, tol, settings, check);
    if let (Solved::Equilibrium(_) | Solved::Stopped(..), Some((cur, stale))) = (&out, last) {
        *sim = cur;
        if stale {
            sim.update_masses_and_step();
        }
    }
    out
}

/// `x + s d`, per body.
fn along(x: &PoseIncrement, d: &PoseIncrement, s: f64) -> PoseIncrement {
    (x.0.iter().zip(&d.0).map(|(a, b)| a + b * s).collect(), x.1.iter().zip(&d.1).map(|(a, b)| a + b * s).collect())
}

/// The iteration of [`newton_increment`] from `sim`, which it leaves as it is: how it
/// ended, and the last iterate with whether its jump re-detected contacts (`None` without
/// free bodies).
fn iterate<R>(
    sim: &Simulation,
    tol: f64,
    settings: &NewtonSolve,
    mut check: impl FnMut(&Simulation) -> Option<R>,
) -> (Solved<R>, Option<(Simulation, bool)>) {
    let nb = sim.state.bodies.len();
    let dofs = Dofs::new(sim);
    if dofs.n == 0 {
        return (Solved::Unsolved(Unsolved::NoFreeBodies, 0), None);
    }
    let zeros = vec![Vec3::zeros(); nb];
    let jump = |x: &PoseIncrement| {
        let mut s = sim.clone();
        let stale = s.predict_deferred(&x.0, &x.1).changed();
        s.assess_predicted();
        let phi = merit(&s);
        (s, stale, phi)
    };
    let depth = settings.anderson_depth as usize;
    let mut mixing = AndersonMixing::new(depth);
    let kappa = settings.opening_bound;
    let mut x: PoseIncrement = (zeros.clone(), zeros);
    let (mut cur, mut stale, mut phi) = jump(&x);
    for it in 0..settings.max_iterations {
        if cur.stats().unbalanced_ratio < tol {
            let out = match check(&cur) {
                Some(r) => Solved::Stopped(r, it),
                None => Solved::Equilibrium(it),
            };
            return (out, Some((cur, stale)));
        }
        let d = match tangent::newton_step(&cur, &x, &dofs) {
            Ok(d) => d,
            Err(e) => return (Solved::Unsolved(Unsolved::Factorization(e), it), Some((cur, stale))),
        };
        let mut accepted = None;
        // The mixed step at full length, where the gaps allow it.
        let mut s: f64 = 1.0;
        if depth > 0 {
            let m = unflatten(&mixing.next(flatten(&d, &cur)), &cur);
            let mixed = mixing.mixed();
            if globalise::opening_bound(&cur, &m, kappa) >= 1.0 {
                let xt = along(&x, &m, 1.0);
                let (trial, st, pt) = jump(&xt);
                if pt <= (1.0 - 2.0 * ARMIJO) * phi {
                    accepted = Some((trial, st, pt, xt));
                } else if !mixed {
                    // That was the Newton step at full length.
                    s = 0.5;
                }
            }
            if accepted.is_none() {
                mixing = AndersonMixing::new(depth);
            }
        }
        // The line search along the Newton direction, within the gap bound.
        if accepted.is_none() {
            s = s.min(globalise::opening_bound(&cur, &d, kappa));
            for _ in 0..=settings.max_halvings {
                let xt = along(&x, &d, s);
                let (trial, st, pt) = jump(&xt);
                if pt <= (1.0 - 2.0 * ARMIJO * s) * phi {
                    accepted = Some((trial, st, pt, xt));
                    break;
                }
                s *= 0.5;
            }
        }
        let Some((trial, st, pt, xt)) = accepted else {
            return (Solved::Unsolved(Unsolved::NoDescent, it + 1), Some((cur, stale)));
        };
        (cur, stale, phi, x) = (trial, st, pt, xt);
    }
    let out = if cur.stats().unbalanced_ratio < tol {
        match check(&cur) {
            Some(r) => Solved::Stopped(r, settings.max_iterations),
            None => Solved::Equilibrium(settings.max_iterations),
        }
    } else {
        Solved::Unsolved(Unsolved::Budget, settings.max_iterations)
    };
    (out, Some((cur, stale)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::{RunToEquilibrium, SolverParams};
    use crate::layout::BaseSliding;
    use crate::verify::{box_vertices, layout_of};

    /// A block `[x0, y0, z0]`–`[x1, y1, z1]` (m) on the table, φ 35°, Kn `kn` Pa/m, Ks Kn/2,
    /// settled under gravity.
    fn settled_on(min: [f64; 3], max: [f64; 3], kn: f64) -> Simulation {
        settled_with(min, max, kn, SolverParams::default().subcontact_subdivisions)
    }

    /// A block settled on the table on joints of `kn` (Ks = Kn/2, φ 35°), its contacts
    /// meshed with `subdivisions` sub-contact subdivisions.
    fn settled_with(min: [f64; 3], max: [f64; 3], kn: f64, subdivisions: u32) -> Simulation {
        let l = layout_of(vec![box_vertices(min, max)], kn, kn / 2.0, 35.0, BaseSliding::Free);
        let mut sim =
            Simulation::new(&l, SolverParams { subcontact_subdivisions: subdivisions, ..SolverParams::default() });
        assert!(sim.run_to_equilibrium(1e-9, 400_000).unwrap());
        sim
    }

    fn settled(min: [f64; 3], max: [f64; 3]) -> Simulation {
        settled_on(min, max, 1e8)
    }

    fn block() -> Simulation {
        settled([0.0, -0.1, 0.0], [0.3, 0.1, 0.1])
    }

    /// Tilted by 10° (below φ and the rocking limit), a settled block finds its new
    /// equilibrium in a few Newton iterations, and it is the one dynamic relaxation finds (the
    /// joint sticks, so the equilibrium does not depend on the path): the same pose to 1e-9 m
    /// and 1e-8 rad.
    #[test]
    fn a_block_below_its_friction_angle_converges_in_a_few_iterations_to_the_relaxed_equilibrium() {
        let mut sim = block();
        sim.set_tilt(10f64.to_radians());
        let mut dynamic = sim.clone();
        let out = newton_increment(&mut sim, 1e-9, &NewtonSolve::default(), |_| None::<()>);
        let Solved::Equilibrium(it) = out else { panic!("{out:?}") };
        assert!(it <= 6, "{it} iterations");
        assert!(dynamic.run_to_equilibrium(1e-9, 1_000_000).unwrap());
        let (a, b) = (&sim.state.bodies[0], &dynamic.state.bodies[0]);
        assert!((a.pos - b.pos).norm() < 1e-9, "{:?} against {:?}", a.pos, b.pos);
        assert!(a.rot.angle_to(&b.rot) < 1e-8);
    }

    /// Tilted past its friction angle (40° against φ 35°) a block has no equilibrium: the
    /// tangent is singular along the slide, no step length reduces the out-of-balance force,
    /// and the solve says so after one or two iterations (not the whole budget), leaving the
    /// state as it was.
    #[test]
    fn a_block_past_its_friction_angle_is_unsolved_at_once_and_left_as_it_was() {
        let mut sim = block();
        sim.set_tilt(40f64.to_radians());
        let before = sim.state.bodies.clone();
        let out = newton_increment(&mut sim, 1e-9, &NewtonSolve::default(), |_| None::<()>);
        let Solved::Unsolved(Unsolved::NoDescent, it) = out else { panic!("{out:?}") };
        assert!(it <= 3, "{it} iterations");
        assert_eq!(sim.state.bodies, before);
    }

    /// A slender rigid block (b = 0.1 m across the tilt, h = 0.4 m) rocks over at
    /// tan α = b/h (14.04°); on joints of finite stiffness earlier, since the block's rotation
    /// on its compressed strip adds to the eccentricity of its weight (on Kn 1e8 Pa/m already
    /// below 12°). On Kn 1e10 Pa/m at 13°, the resultant at 0.46 b/2 from the middle and
    /// nine tenths of the base lifted off, Newton converges to the equilibrium dynamic
    /// relaxation finds: in some twenty-five iterations, first while the base lifts off (the
    /// gap bound lets the lifting edge's gap at most double, plus a closure, in a step: from
    /// a closure of about 1e-6 m to the lift-off's 1e-4 m some seven steps, and the line
    /// search cuts steps besides), then quadratically. The same pose to 1e-6 m and
    /// 1e-5 rad (of a sway of 3e-4 m): the lifted part of the base slips, and the slip left
    /// depends on the path (one jump here, the relaxation's steps there).
    #[test]
    fn a_rocking_block_near_its_limit_converges() {
        let mut sim = settled_on([0.0, -0.05, 0.0], [0.3, 0.05, 0.4], 1e10);
        sim.set_tilt(13f64.to_radians());
        let mut dynamic = sim.clone();
        let out = newton_increment(&mut sim, 1e-9, &NewtonSolve::default(), |_| None::<()>);
        let Solved::Equilibrium(it) = out else { panic!("{out:?}") };
        assert!(it <= 28, "{it} iterations");
        assert!(dynamic.run_to_equilibrium(1e-9, 2_000_000).unwrap());
        let (a, b) = (&sim.state.bodies[0], &dynamic.state.bodies[0]);
        assert!((a.pos - b.pos).norm() < 1e-6, "{:?} against {:?}", a.pos, b.pos);
        assert!(a.rot.angle_to(&b.rot) < 1e-5, "{}", a.rot.angle_to(&b.rot));
    }

    /// The protocol's check sees equilibria only: the iterates between are trial points of
    /// one jump from the increment's start, not states the wall passes through, so a step
    /// that overshoots is no collapse. A block tilted by 10° takes a few iterates to its
    /// equilibrium; every state the check is shown is balanced to the tolerance, and the
    /// check is asked once.
    #[test]
    fn the_check_is_asked_at_equilibrium_only() {
        let mut sim = block();
        sim.set_tilt(10f64.to_radians());
        let tol = 1e-9;
        let mut seen = Vec::new();
        let out = newton_increment(&mut sim, tol, &NewtonSolve::default(), |s| {
            seen.push(s.stats().unbalanced_ratio);
            None::<()>
        });
        let Solved::Equilibrium(it) = out else { panic!("{out:?}") };
        assert!(it >= 2, "{it} iterations: nothing between");
        assert_eq!(seen.len(), 1, "{seen:?}");
        assert!(seen[0] < tol, "{seen:?}");
    }

    /// Close to its friction angle (33° against φ 35°) the joint carries the slope's load
    /// with its shear springs near the slip limit: Newton converges, to the equilibrium the
    /// statics give (the joint carries `W sin α` along the slope).
    #[test]
    fn the_slip_tangent_converges_where_some_sub_contacts_slip() {
        let mut sim = block();
        sim.set_tilt(33f64.to_radians());
        let out = newton_increment(&mut sim, 1e-9, &NewtonSolve::default(), |_| None::<()>);
        let Solved::Equilibrium(it) = out else { panic!("{out:?}") };
        assert!(it <= 12, "{it} iterations");
        // Equilibrium: the joint carries W sin α along the slope.
        let w = sim.state.bodies[0].mass * sim.state.gravity_magnitude;
        let fy: f64 = sim.state.contacts.iter().map(|c| c.force.y).sum();
        assert!((fy + w * 33f64.to_radians().sin()).abs() < 1e-6 * w, "{fy} against {}", w * 33f64.to_radians().sin());
    }

    /// The tangent at an iterate (a rocking block with its base partly lifted, a block on a
    /// slope near φ with a sub-contact slipping) against central differences of the jump from
    /// the increment's start: each column to 2 % of its largest entry (the geometric terms
    /// are checked to 1 % of their own size in `tangent::tests`), on one and on two
    /// sub-contact subdivisions. On two, sub-contacts lie wholly in the lifted part of the
    /// rocking base; they keep the shear they had when they opened, and the tangent counted
    /// their shear springs, which the law does not (K_xx 1.4996e6 against 7.498e5 N/m).
    #[test]
    fn the_tangent_is_the_derivative_of_the_jump() {
        let cases = [([0.0, -0.05, 0.0], [0.3, 0.05, 0.4], 12.0), ([0.0, -0.1, 0.0], [0.3, 0.1, 0.1], 33.0)];
        for ((min, max, tilt), mesh) in cases.into_iter().flat_map(|c| [(c, 1), (c, 2)]) {
            let mut sim = settled_with(min, max, 1e8, mesh);
            sim.set_tilt(f64::to_radians(tilt));
            let settings = NewtonSolve { max_iterations: 14, ..NewtonSolve::default() };
            let (_, last) = iterate(&sim, 1e-12, &settings, |_| None::<()>);
            let probe = last.unwrap().0;
            // The increment the probe reached, from `sim`.
            let b0 = &sim.state.bodies[0];
            let b1 = &probe.state.bodies[0];
            let x = (vec![b1.pos - b0.pos], vec![(b1.rot * b0.rot.inverse()).scaled_axis()]);
            let load = |dx: &PoseIncrement| {
                let mut s = sim.clone();
                s.predict_deferred(&[x.0[0] + dx.0[0]], &[x.1[0] + dx.1[0]]);
                s.assess_predicted();
                let (f, t) = s.unbalanced(0);
                [f.x, f.y, f.z, t.x, t.y, t.z]
            };
            let mut at = sim.clone();
            at.predict_deferred(&x.0, &x.1);
            at.assess_predicted();
            let blocks = tangent::tangent_blocks(&at, &x);
            for dof in 0..6 {
                let eps = if dof < 3 { 1e-9 } else { 1e-8 };
                let mut p = (vec![Vec3::zeros()], vec![Vec3::zeros()]);
                let mut m = p.clone();
                if dof < 3 {
                    p.0[0][dof] = eps;
                    m.0[0][dof] = -eps;
                } else {
                    p.1[0][dof - 3] = eps;
                    m.1[0][dof - 3] = -eps;
                }
                let (lp, lm) = (load(&p), load(&m));
                let fd: Vec<f64> = (0..6).map(|i| -(lp[i] - lm[i]) / (2.0 * eps)).collect();
                let col: Vec<f64> = (0..6).map(|i| blocks.diag[0][(i, dof)]).collect();
                let scale = col.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for i in 0..6 {
                    assert!(
                        (fd[i] - col[i]).abs() <= 0.02 * scale,
                        "{tilt}°, {mesh} subdivisions: K[{i}][{dof}] = {} against {}",
                        col[i],
                        fd[i]
                    );
                }
            }
        }
    }
}
