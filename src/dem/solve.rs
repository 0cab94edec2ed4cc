//! The solver seam: the one place where a protocol's wall is brought to equilibrium, and
//! where the solver a user chose is resolved.
//!
//! A protocol (settling, a tilting-table increment, the static lateral load) asks for a
//! static solution with [`solve_static`] and gets one typed [`SolveOutcome`]: how it ended
//! ([`End`]), which stage ended it ([`SolveStage`]), the steps and iterations taken, and, where
//! the implicit iteration gave up, its cause ([`Unsolved`]). The penalty cascade is owned
//! here:
//!
//! 1. the semi-smooth Newton solve of the increment (`dem::drivers::newton`: every iterate
//!    one jump of the total increment from the state as placed, the consistent tangent of
//!    the joints, each step bounded by the joints' gaps and Anderson-mixed, a backtracking
//!    line search; the protocol's check asked at equilibrium only); where it ends unsolved the state is put back
//!    as placed, and the cause is kept in the outcome;
//! 2. the implicit iteration (`dem::drivers::implicit`: the factorized stiffness of the
//!    contact springs as preconditioner, Anderson mixing), from the state as placed;
//! 3. if it stalls, the probe of its drift (`dem::drivers::accelerate::probe_along`): when
//!    the out-of-balance force pushes the wall along the drift all the way to the probe's
//!    reach, no equilibrium lies near the path ([`End::Unstable`] with that drift);
//! 4. dynamic relaxation with local damping (`dem::drivers::relax`), with the secant
//!    acceleration of slow creep and its stability indicator, probed along the path ahead.
//!
//! Which stages run is the solver's choice ([`SolverKind`](super::method::SolverKind), `[solver] kind` in a study,
//! `--solver` on the command line), resolved against the protocol's own default
//! ([`SolverKind::cascade`](super::method::SolverKind::cascade)). A solver that is not a penalty method (non-smooth contact
//! dynamics, limit analysis) replaces the whole protocol run, not this function: see
//! [`SolverKind::is_penalty`](super::method::SolverKind::is_penalty).

use super::drivers::accelerate::{probe_along, Ahead, SecantAcceleration};
use super::drivers::implicit::{implicit_relaxation, ImplicitSolve, PoseIncrement, Solved, Unsolved};
use super::drivers::newton::{newton_increment, NewtonSolve};
use super::drivers::relax::{dynamic_relaxation, dynamic_relaxation_probed, Relaxed, Tolerance};
use super::method::Cascade;
use super::motion::{largest_motion, BodyPose};
use super::{DemError, Simulation};

/// What one static solve is asked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticSolve {
    /// The stages to run.
    pub cascade: Cascade,
    /// Equilibrium when the unbalanced-force ratio is below this, –.
    pub tolerance: f64,
    /// Equilibrium also needs every body's local unbalanced-force ratio below this, –
    /// ([`Simulation::largest_local_ratio`]; `None`, the default: not checked). A stage
    /// that reaches the global tolerance with a body still out of balance hands over to the
    /// next, dynamic relaxation last.
    pub local_tolerance: Option<f64>,
    /// Step budget of the dynamic relaxation.
    pub max_steps: u64,
    /// Settings of the secant acceleration (with `cascade.accelerate`).
    pub acceleration: SecantAcceleration,
    /// Settings of the implicit iteration (with `cascade.implicit`).
    pub implicit: ImplicitSolve,
    /// Settings of the semi-smooth Newton solve (with `cascade.newton`).
    pub newton: NewtonSolve,
    /// Reach of the probes, m: the largest body motion from the start of the solve up to
    /// which a probe looks for an equilibrium along the motion (the protocol's collapse
    /// displacement). `None`: no probes (the stability indicator alone ends an accelerated
    /// relaxation, and a stalled implicit iteration hands over to dynamic relaxation).
    pub reach: Option<f64>,
}

impl StaticSolve {
    /// The static solve of the penalty settings `penalty` (its tolerance, step budget,
    /// acceleration and implicit settings) with the stages `cascade` and the probes' reach
    /// `reach` (m; `None`: no probes).
    pub fn of(penalty: &super::PenaltyParams, cascade: Cascade, reach: Option<f64>) -> StaticSolve {
        StaticSolve {
            cascade,
            tolerance: penalty.tolerance,
            local_tolerance: None,
            max_steps: penalty.max_steps,
            acceleration: penalty.acceleration,
            implicit: penalty.implicit_solve,
            newton: NewtonSolve::default(),
            reach,
        }
    }

    /// Plain dynamic relaxation to `tolerance` within `max_steps` steps, no probes: the
    /// settling under gravity of every protocol.
    pub fn relaxation(tolerance: f64, max_steps: u64) -> StaticSolve {
        StaticSolve {
            cascade: Cascade::RELAXATION,
            tolerance,
            local_tolerance: None,
            max_steps,
            acceleration: SecantAcceleration::default(),
            implicit: ImplicitSolve::default(),
            newton: NewtonSolve::default(),
            reach: None,
        }
    }
}

/// Relaxation to equilibrium as a method of a [`Simulation`] (the seam owns it; the engine
/// knows no driver): `use drystone::dem::RunToEquilibrium`.
pub trait RunToEquilibrium {
    /// Runs until the unbalanced-force ratio falls below `tol` (returns `Ok(true)`) or
    /// `max_steps` have been taken (`Ok(false)`): [`solve_static`] with
    /// [`StaticSolve::relaxation`] and no stop check.
    ///
    /// # Errors
    /// [`DemError::NonFinite`].
    fn run_to_equilibrium(&mut self, tol: f64, max_steps: u64) -> Result<bool, DemError>;
}

impl RunToEquilibrium for Simulation {
    fn run_to_equilibrium(&mut self, tol: f64, max_steps: u64) -> Result<bool, DemError> {
        let out = solve_static(self, &StaticSolve::relaxation(tol, max_steps), &[], |_| None::<()>)?;
        Ok(out.end == End::Equilibrium)
    }
}

/// The stage of the cascade that ended a static solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolveStage {
    /// The semi-smooth Newton solve.
    Newton,
    /// The implicit iteration (or the probe of its drift).
    Implicit,
    /// Dynamic relaxation.
    Relaxation,
}

/// How a static solve ended.
#[derive(Debug, Clone, PartialEq)]
pub enum End<R> {
    /// The unbalanced-force ratio fell below the tolerance.
    Equilibrium,
    /// The protocol's stop check returned this reason.
    Stopped(R),
    /// The step budget ran out: neither an equilibrium nor a collapse established.
    Budget,
    /// No equilibrium near the path: the stability indicator fired (or the implicit
    /// iteration stalled) and the probe found none within its reach. With the direction of
    /// collapse, per body a translation (m) and a rotation vector (rad), table frame.
    Unstable(PoseIncrement),
}

/// The one outcome of a static solve.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveOutcome<R> {
    /// How it ended.
    pub end: End<R>,
    /// The stage that ended it.
    pub stage: SolveStage,
    /// Dynamic-relaxation steps taken.
    pub steps: u64,
    /// Newton and implicit iterations taken.
    pub iterations: u32,
    /// Of `iterations`, the Newton iterations.
    pub newton_iterations: u32,
    /// Why the Newton solve handed over, where it ran and did not end the solve.
    pub newton_unsolved: Option<Unsolved>,
    /// Why the implicit iteration handed over, where it ran and did not end the solve.
    pub unsolved: Option<Unsolved>,
}

/// Brings `sim` (its loads set, its state placed) to equilibrium by the stages of
/// `solve.cascade`, calling `check` (after every implicit iteration, and every
/// `dem::drivers::relax::CHECK_EVERY` steps of dynamic relaxation) for a protocol's reason
/// to stop. `start` is the pose of every body from which the probes' reach is measured
/// (the protocol's last stable state).
///
/// # Errors
/// [`DemError::NonFinite`] when a body's state blows up in dynamic relaxation.
pub fn solve_static<R>(
    sim: &mut Simulation,
    solve: &StaticSolve,
    start: &[BodyPose],
    mut check: impl FnMut(&Simulation) -> Option<R>,
) -> Result<SolveOutcome<R>, DemError> {
    let mut iterations = 0;
    let mut unsolved = None;
    let (mut newton_iterations, mut newton_unsolved) = (0, None);
    if solve.cascade.newton {
        let end = |end, it| SolveOutcome {
            end,
            stage: SolveStage::Newton,
            steps: 0,
            iterations: it,
            newton_iterations: it,
            newton_unsolved: None,
            unsolved: None,
        };
        match newton_increment(sim, solve.tolerance, &solve.newton, &mut check) {
            Solved::Equilibrium(it) if locally_balanced(sim, solve) => return Ok(end(End::Equilibrium, it)),
            Solved::Equilibrium(it) => {
                newton_iterations = it;
                iterations = it;
            }
            Solved::Stopped(reason, it) => return Ok(end(End::Stopped(reason), it)),
            Solved::Unsolved(cause, it) => {
                (newton_iterations, newton_unsolved) = (it, Some(cause));
                iterations = it;
            }
        }
    }
    let implicit_end = |end, it| SolveOutcome {
        end,
        stage: SolveStage::Implicit,
        steps: 0,
        iterations: newton_iterations + it,
        newton_iterations,
        newton_unsolved: newton_unsolved.clone(),
        unsolved: None,
    };
    if solve.cascade.implicit {
        match implicit_relaxation(sim, solve.tolerance, &solve.implicit, &mut check) {
            Solved::Equilibrium(it) if locally_balanced(sim, solve) => return Ok(implicit_end(End::Equilibrium, it)),
            Solved::Equilibrium(it) => iterations += it,
            Solved::Stopped(reason, it) => return Ok(implicit_end(End::Stopped(reason), it)),
            Solved::Unsolved(Unsolved::Stalled, it) => {
                iterations += it;
                unsolved = Some(Unsolved::Stalled);
                if let Some(limit) = solve.reach {
                    // The iterates drifted from the start without finding an equilibrium:
                    // if the out-of-balance force pushes the wall along that drift all the
                    // way to the collapse displacement, no equilibrium lies near the path.
                    let (dpos, drot): PoseIncrement = sim
                        .state
                        .bodies
                        .iter()
                        .zip(start)
                        .map(|(b, (x0, q0))| (b.pos - x0, (b.rot * q0.inverse()).scaled_axis()))
                        .unzip();
                    let reach = (limit - largest_motion(sim, start)).max(0.0);
                    if probe_along(sim, &dpos, &drot, reach, f64::INFINITY) == Ahead::NoEquilibrium {
                        return Ok(implicit_end(End::Unstable((dpos, drot)), it));
                    }
                }
            }
            Solved::Unsolved(cause, it) => {
                iterations += it;
                unsolved = Some(cause);
            }
        }
    }
    let (tol, budget) = (Tolerance { global: solve.tolerance, local: solve.local_tolerance }, solve.max_steps);
    let relaxed = match (solve.cascade.accelerate, solve.reach) {
        (true, Some(reach)) => dynamic_relaxation_probed(sim, tol, budget, solve.acceleration, reach, check)?,
        (true, None) => dynamic_relaxation(sim, tol, budget, Some(solve.acceleration), check)?,
        (false, _) => dynamic_relaxation(sim, tol, budget, None, check)?,
    };
    let (end, steps) = match relaxed {
        Relaxed::Equilibrium(steps) => (End::Equilibrium, steps),
        Relaxed::Stopped(reason, steps) => (End::Stopped(reason), steps),
        Relaxed::Budget(steps) => (End::Budget, steps),
        Relaxed::Unstable(steps, direction) => (End::Unstable(direction), steps),
    };
    Ok(SolveOutcome {
        end,
        stage: SolveStage::Relaxation,
        steps,
        iterations,
        newton_iterations,
        newton_unsolved,
        unsolved,
    })
}

/// Whether every body of `sim` is balanced by the local tolerance of `solve` (always, with
/// none).
fn locally_balanced(sim: &Simulation, solve: &StaticSolve) -> bool {
    solve.local_tolerance.is_none_or(|l| sim.largest_local_ratio().0 < l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::SolverParams;
    use crate::layout::BaseSliding;
    use crate::verify::{box_vertices, layout_of};

    fn block() -> Simulation {
        let l = layout_of(vec![box_vertices([0.0, -0.1, 0.0], [0.3, 0.1, 0.1])], 1e8, 5e7, 35.0, BaseSliding::Free);
        Simulation::new(&l, SolverParams::default())
    }

    fn solve(cascade: Cascade) -> StaticSolve {
        StaticSolve {
            cascade,
            tolerance: 1e-6,
            local_tolerance: None,
            max_steps: 100_000,
            acceleration: SecantAcceleration::default(),
            implicit: ImplicitSolve::default(),
            newton: NewtonSolve::default(),
            reach: Some(0.01),
        }
    }

    /// Every cascade settles a block on its base to the same equilibrium (its weight on
    /// the Winkler joint: closure W / (Kn A)), and says which stage ended the solve.
    #[test]
    fn every_cascade_finds_the_same_equilibrium() {
        let closure_exact = {
            let s = block();
            let b = &s.state.bodies[0];
            b.mass * 9.81 / (1e8 * 0.3 * 0.2)
        };
        for (cascade, stage) in [
            (Cascade::FULL, SolveStage::Newton),
            (Cascade::NEWTON_RELAXATION, SolveStage::Newton),
            (Cascade::IMPLICIT, SolveStage::Implicit),
            (Cascade { newton: false, implicit: false, accelerate: true }, SolveStage::Relaxation),
            (Cascade::RELAXATION, SolveStage::Relaxation),
        ] {
            let mut sim = block();
            let start = crate::dem::motion::poses(&sim);
            let z0 = sim.state.bodies[0].pos.z;
            let out = solve_static(&mut sim, &solve(cascade), &start, |_| None::<()>).unwrap();
            assert_eq!(out.end, End::Equilibrium, "{cascade:?}");
            assert_eq!(out.stage, stage, "{cascade:?}");
            assert_eq!(out.iterations > 0, cascade.implicit || cascade.newton, "{cascade:?}");
            assert_eq!(out.newton_iterations > 0, cascade.newton, "{cascade:?}");
            assert_eq!(out.steps > 0, !(cascade.implicit || cascade.newton), "{cascade:?}");
            let closure = z0 - sim.state.bodies[0].pos.z;
            assert!((closure / closure_exact - 1.0).abs() < 0.02, "{cascade:?}: {closure} vs {closure_exact}");
        }
    }

    /// A protocol's stop reason ends the solve in whichever stage is running; the budget
    /// ends dynamic relaxation as `Budget`.
    #[test]
    fn a_stop_check_and_the_budget_end_the_solve() {
        let mut sim = block();
        let start = crate::dem::motion::poses(&sim);
        let out = solve_static(&mut sim, &solve(Cascade::IMPLICIT), &start, |_| Some("stop")).unwrap();
        assert_eq!((out.end, out.stage), (End::Stopped("stop"), SolveStage::Implicit));
        let mut sim = block();
        let out = solve_static(&mut sim, &solve(Cascade::FULL), &start, |_| Some("stop")).unwrap();
        assert_eq!((out.end, out.stage), (End::Stopped("stop"), SolveStage::Newton));
        let mut sim = block();
        let tight = StaticSolve { tolerance: 1e-14, max_steps: 7, ..solve(Cascade::RELAXATION) };
        let out = solve_static(&mut sim, &tight, &start, |_| None::<()>).unwrap();
        assert_eq!((out.end, out.steps), (End::Budget, 7));
    }
}
