//! Implicit relaxation of the static increments: an iteration preconditioned by the
//! factorized stiffness of the contact springs and accelerated by Anderson mixing, with
//! dynamic relaxation ([`super::relax`]) taking over where it does not converge (near
//! collapse).
//!
//! # The iteration
//!
//! Dynamic relaxation needs hundreds of steps per increment because its explicit steps
//! see the stiffness one body at a time (the condition number of the SBL wall's assembled
//! stiffness is about 550 even after block density scaling). Here each iteration applies
//! the whole assembled stiffness at once. With `R_k` the out-of-balance force and moment of
//! every free body (N, N·m about its centroid, table frame) at iterate `k`, and `K` the
//! stiffness below,
//!
//! ```text
//! f_k = K⁻¹ R_k                                   (sparse Cholesky solve)
//! γ   = argmin ‖f_k − ΔF γ‖                       (the last m differences of f)
//! Δx_k = f_k − (ΔX + ΔF) γ                        (Anderson type II, mixing 1)
//! ```
//!
//! (Anderson 1965, *J. ACM* 12, 547; Walker & Ni 2011, *SIAM J. Numer. Anal.* 49, 1715: on a
//! linear problem the iterates are those of GMRES preconditioned by `K`). Rotations enter
//! the least squares times the body radius, so that both halves are lengths.
//!
//! Every iterate is one jump of [`Simulation::predict`] from the one before: the joints
//! take the iterate's relative motion as their shear increment, the Coulomb limit and the
//! no-tension closure act on it as they act on a step of dynamic relaxation, and the
//! joints' history follows the iterates' path. The iteration is therefore dynamic
//! relaxation with the stiffness matrix for a mass matrix (each elastic mode then takes
//! one iteration) and Anderson mixing for damping.
//!
//! `K` is the stiffness of every sub-contact spring, open or closed, as the critical time
//! step sees it ([`crate::dem::timestep`]), but with the springs where the joint law acts:
//! normal springs integrated exactly over each triangle (weights `A/12` at the nodes and
//! `3A/4` at the centroid, the rule exact for the quadratic integrand) with the stiffness
//! `max(dq/du, Kn)` of the closure law at each point
//! ([`crate::dem::contact::law::NormalParams::tangent`]), and the shear spring `Ks A` at the
//! centroid, where the law takes the shear increment. It bounds the tangent of the state
//! from above (an open or slipping joint is stiffer in `K` than it is; a hyperbolic joint
//! stiffens further only as it closes further), so the iteration approaches each
//! equilibrium from the stiff side rather than overshooting it; the modes it over-stiffens
//! (slip, opening joints, rocking) are what the Anderson mixing resolves. It is factorized once per increment, after every
//! re-detection of contacts and every [`ImplicitSolve::refactor_every`] iterations.
//!
//! The iteration ends at equilibrium (unbalanced-force ratio below the tolerance), when
//! the protocol's check stops it (a collapse criterion), when the ratio grows tenfold
//! (the state is then put back where the iteration started), when the ratio has not
//! gone below 0.9 of its lowest value for [`ImplicitSolve::stall_window`] iterations, or
//! after [`ImplicitSolve::max_iterations`]. A trial tilted past the collapse tilt has no
//! equilibrium to converge to: its iterates wander with the ratio at 10–100 times the
//! tolerance (the spring stiffness does not see the mechanism), and the stall rule hands
//! it to dynamic relaxation, whose collapse criteria decide it, instead of spending the
//! whole iteration budget.
//!
//! The sparse factorization is faer's simplicial Cholesky with an approximate minimum
//! degree ordering, run sequentially; the simplicial factorization and the sparse
//! triangular solves are scalar code (no runtime choice of SIMD kernels), so a test gives
//! the same bits on any number of threads and any x86-64 machine, as the explicit step
//! does. The numeric factorization is faer's up-looking algorithm with what it derives
//! from the pattern alone (the permuted matrix's structure, each row's elimination reach)
//! computed once per pattern rather than at every factorization: the same operations in
//! the same order, the same factor bit for bit.

pub(in crate::dem::drivers) mod anderson;
pub(in crate::dem::drivers) mod stiffness;

use crate::dem::engine::Simulation;
use crate::math::Vec3;
use anderson::AndersonMixing;
use stiffness::{Dofs, Factor};

pub use crate::dem::penalty::ImplicitSolve;

/// The fraction of the lowest unbalanced-force ratio reached so far that an iterate must
/// go below to count as progress ([`ImplicitSolve::stall_window`]).
pub const STALL_PROGRESS: f64 = 0.9;

/// How an implicit relaxation ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Solved<R> {
    /// The unbalanced-force ratio fell below the tolerance after this many iterations.
    Equilibrium(u32),
    /// The stop check returned its reason after this many iterations.
    Stopped(R, u32),
    /// No equilibrium, for the cause given, after this many iterations.
    Unsolved(Unsolved, u32),
}

/// Why an implicit relaxation found no equilibrium.
#[derive(Debug, Clone, PartialEq)]
pub enum Unsolved {
    /// No free degree of freedom (every body fixed): nothing to iterate on.
    NoFreeBodies,
    /// [`ImplicitSolve::max_iterations`] ran out; the state is the last iterate.
    Budget,
    /// No progress for [`ImplicitSolve::stall_window`] iterations: the iterates wander
    /// with the unbalanced-force ratio far from the tolerance (a trial past the collapse
    /// tilt, whose mechanism the spring stiffness cannot follow) or on a plateau just
    /// above it; the state is the last iterate.
    Stalled,
    /// The stiffness could not be assembled or factorized (the sparse Cholesky
    /// factorization's error, as faer gives it); the state is the last iterate.
    Factorization(String),
    /// The unbalanced-force ratio grew tenfold above where it started, or turned
    /// non-finite; the state is put back where the iteration started.
    Diverged,
    /// The Newton direction of the semi-smooth Newton iteration
    /// ([`crate::dem::drivers::newton`]) did not reduce the out-of-balance force within the
    /// line search's halvings: a limit point (the tangent singular, no equilibrium near)
    /// or a change of the contact states the tangent did not foresee; the state is put
    /// back where the iteration started.
    NoDescent,
}

/// A pose increment: per body, translation (m) and rotation vector (rad), table frame.
pub type PoseIncrement = (Vec<Vec3>, Vec<Vec3>);

/// Relaxes `sim` (its load set, its state placed) towards an unbalanced-force ratio below
/// `tol` by the preconditioned, Anderson-mixed iteration of the module doc, calling `check`
/// after every iteration; a reason from `check` stops it. Every iterate is a jump of
/// [`Simulation::predict`] from the one before (the bodies end at rest), so the joints'
/// history follows the iterates' path as it follows the steps of dynamic relaxation. The
/// inertial masses and the time step are brought up to date at the end if contacts were
/// re-detected meanwhile, so dynamic relaxation can go on from the state.
pub fn implicit_relaxation<R>(
    sim: &mut Simulation,
    tol: f64,
    settings: &ImplicitSolve,
    check: impl FnMut(&Simulation) -> Option<R>,
) -> Solved<R> {
    let mut stale = false;
    let out = iterate(sim, tol, settings, check, &mut stale);
    if stale {
        sim.update_masses_and_step();
    }
    out
}

/// The iteration of [`implicit_relaxation`], its jumps leaving the inertial masses and the time step to
/// the end; `stale` is set when a re-detection changed the contacts of the state left.
fn iterate<R>(
    sim: &mut Simulation,
    tol: f64,
    settings: &ImplicitSolve,
    mut check: impl FnMut(&Simulation) -> Option<R>,
    stale: &mut bool,
) -> Solved<R> {
    let nb = sim.state.bodies.len();
    let dofs = Dofs::new(sim);
    if dofs.n == 0 {
        return Solved::Unsolved(Unsolved::NoFreeBodies, 0);
    }
    let zeros = vec![Vec3::zeros(); nb];
    *stale |= sim.predict_deferred(&zeros, &zeros).changed();
    sim.assess_predicted();
    let start = (sim.clone(), *stale);
    let limit = 10.0 * sim.stats().unbalanced_ratio.max(tol);
    let depth = settings.anderson_depth as usize;
    let mut mixing = AndersonMixing::new(depth);
    let mut factor: Option<Factor> = None;
    let mut since = 0;
    let mut detections = sim.detections();
    let (mut best, mut best_at) = (f64::INFINITY, 0);
    for it in 0..settings.max_iterations {
        let ratio = sim.stats().unbalanced_ratio;
        if !(ratio <= limit) {
            (*sim, *stale) = start;
            return Solved::Unsolved(Unsolved::Diverged, it);
        }
        if ratio < tol {
            return Solved::Equilibrium(it);
        }
        if ratio < STALL_PROGRESS * best {
            (best, best_at) = (ratio, it);
        } else if it - best_at >= settings.stall_window {
            return Solved::Unsolved(Unsolved::Stalled, it);
        }
        if factor.is_none() || since >= settings.refactor_every || sim.detections() != detections {
            factor = match Factor::new(sim, &dofs) {
                Ok(f) => Some(f),
                Err(e) => return Solved::Unsolved(Unsolved::Factorization(e), it),
            };
            since = 0;
            detections = sim.detections();
            // Differences taken under another preconditioner do not mix.
            mixing = AndersonMixing::new(depth);
        }
        let f = factor.as_ref().expect("set above");
        since += 1;
        let fk = flatten(&f.solve(sim, &dofs), sim);
        let step = unflatten(&mixing.next(fk), sim);
        *stale |= sim.predict_deferred(&step.0, &step.1).changed();
        sim.assess_predicted();
        if let Some(r) = check(sim) {
            return Solved::Stopped(r, it + 1);
        }
    }
    if sim.stats().unbalanced_ratio < tol {
        Solved::Equilibrium(settings.max_iterations)
    } else {
        Solved::Unsolved(Unsolved::Budget, settings.max_iterations)
    }
}

/// A pose increment as one vector, rotations times the body radius (m).
pub(in crate::dem::drivers) fn flatten(d: &PoseIncrement, sim: &Simulation) -> Vec<f64> {
    let mut v = Vec::with_capacity(6 * d.0.len());
    for (k, b) in sim.state.bodies.iter().enumerate() {
        v.extend_from_slice(d.0[k].as_slice());
        v.extend((d.1[k] * b.radius).iter());
    }
    v
}

/// The inverse of [`flatten`].
pub(in crate::dem::drivers) fn unflatten(v: &[f64], sim: &Simulation) -> PoseIncrement {
    sim.state
        .bodies
        .iter()
        .enumerate()
        .map(|(k, b)| {
            (
                Vec3::new(v[6 * k], v[6 * k + 1], v[6 * k + 2]),
                Vec3::new(v[6 * k + 3], v[6 * k + 4], v[6 * k + 5]) / b.radius,
            )
        })
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::{RunToEquilibrium, SolverParams};
    use crate::layout::BaseSliding;
    use crate::verify::{box_vertices, layout_of};

    fn settled_block() -> Simulation {
        let l = layout_of(vec![box_vertices([0.0, -0.1, 0.0], [0.3, 0.1, 0.1])], 1e8, 5e7, 35.0, BaseSliding::Free);
        let mut sim = Simulation::new(&l, SolverParams::default());
        assert!(sim.run_to_equilibrium(1e-9, 400_000).unwrap());
        sim
    }

    /// Tilted by 10° (below φ and the rocking limit), a settled block finds its new
    /// equilibrium in a few iterations, and it is the one dynamic relaxation finds: the
    /// same pose to 1e-9 m and 1e-8 rad.
    #[test]
    fn the_iteration_converges_to_the_equilibrium_dynamic_relaxation_finds() {
        let mut sim = settled_block();
        sim.set_tilt(10f64.to_radians());
        let mut dynamic = sim.clone();
        let out = implicit_relaxation(&mut sim, 1e-9, &ImplicitSolve::default(), |_| None::<()>);
        let Solved::Equilibrium(it) = out else { panic!("{out:?}") };
        assert!(it <= 30, "{it} iterations");
        assert!(dynamic.run_to_equilibrium(1e-9, 1_000_000).unwrap());
        let (a, b) = (&sim.state.bodies[0], &dynamic.state.bodies[0]);
        assert!((a.pos - b.pos).norm() < 1e-9, "{:?} against {:?}", a.pos, b.pos);
        assert!(a.rot.angle_to(&b.rot) < 1e-8);
    }

    /// Tilted past its friction angle (40° against φ 35°) a block has no equilibrium: the
    /// iterates slide on with the ratio where it was, and the iteration gives up after the
    /// stall window, not at the end of the budget.
    #[test]
    fn an_iteration_without_progress_stalls_before_the_budget() {
        let mut sim = settled_block();
        sim.set_tilt(40f64.to_radians());
        let settings = ImplicitSolve { stall_window: 20, ..ImplicitSolve::default() };
        let out = implicit_relaxation(&mut sim, 1e-9, &settings, |_| None::<()>);
        let Solved::Unsolved(Unsolved::Stalled, it) = out else { panic!("{out:?}") };
        assert!((20..100).contains(&it), "{it} iterations");
        assert!(sim.stats().unbalanced_ratio > 1e-3);
    }

    /// The causes of no equilibrium are told apart: the iteration budget, and no free
    /// body to iterate on.
    #[test]
    fn an_unsolved_iteration_says_why() {
        let mut sim = settled_block();
        sim.set_tilt(10f64.to_radians());
        let one = ImplicitSolve { max_iterations: 1, ..ImplicitSolve::default() };
        assert_eq!(implicit_relaxation(&mut sim, 1e-12, &one, |_| None::<()>), Solved::Unsolved(Unsolved::Budget, 1));
        let mut l = layout_of(vec![box_vertices([0.0, -0.1, 0.0], [0.3, 0.1, 0.1])], 1e8, 5e7, 35.0, BaseSliding::Free);
        l.blocks[0].fixed = true;
        let mut fixed = Simulation::new(&l, SolverParams::default());
        let out = implicit_relaxation(&mut fixed, 1e-9, &ImplicitSolve::default(), |_| None::<()>);
        assert_eq!(out, Solved::Unsolved(Unsolved::NoFreeBodies, 0));
    }
}
