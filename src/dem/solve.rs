//! The solver seam: the one place where a protocol's wall is brought to equilibrium, and
//! where the solver a user chose is resolved.
//!
//! A protocol (settling, a tilting-table increment, the static lateral load) asks for a
//! static solution with [`solve_static`] and gets one typed [`Outcome`]: how it ended
//! ([`End`]), which stage ended it ([`Stage`]), the steps and iterations taken, and, where
//! the implicit iteration gave up, its cause ([`Unsolved`]). The penalty cascade is owned
//! here:
//!
//! 1. the implicit iteration (`dem::drivers::implicit`: the factorized stiffness of the
//!    contact springs as preconditioner, Anderson mixing), from the state as placed;
//! 2. if it stalls, the probe of its drift (`dem::drivers::accelerate::probe_along`): when
//!    the out-of-balance force pushes the wall along the drift all the way to the probe's
//!    reach, no equilibrium lies near the path ([`End::Unstable`] with that drift);
//! 3. dynamic relaxation with local damping (`dem::drivers::relax`), with the secant
//!    acceleration of slow creep and its stability indicator, probed along the path ahead.
//!
//! Which stages run is the solver's choice ([`SolverKind`], `[solver] kind` in a study,
//! `--solver` on the command line), resolved against the protocol's own default
//! ([`SolverKind::cascade`]). A solver that is not a penalty method (non-smooth contact
//! dynamics, limit analysis) replaces the whole protocol run, not this function: see
//! [`SolverKind::is_penalty`].

use super::drivers::accelerate::{probe_along, Ahead, SecantAcceleration};
use super::drivers::implicit::{implicit_relaxation, ImplicitSolve, PoseIncrement, Solved, Unsolved};
use super::drivers::relax::{dynamic_relaxation, dynamic_relaxation_probed, Relaxed};
use super::motion::{largest_motion, BodyPose};
use super::{DemError, Simulation};
use serde::{Deserialize, Serialize};

/// The solver a protocol runs on: `[solver] kind = "..."` in a study, `--solver NAME` on
/// `drystone tilt`, `lateral` and `bench`. Default [`SolverKind::Penalty`].
///
/// The first four are the penalty DEM (3DEC-style sub-contact springs, Kn and Ks from the
/// layout) and differ only in how a static state is found ([`Cascade`]); their results
/// agree within one bracket of the protocol, their costs differ (BENCHMARKS.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    /// The penalty DEM with each protocol's default cascade: the tilting table runs the
    /// implicit iteration, its stall probe and accelerated dynamic relaxation; settling and
    /// the static lateral load run plain dynamic relaxation.
    #[default]
    Penalty,
    /// The penalty DEM, every stage: implicit iteration → stall probe → accelerated,
    /// probed dynamic relaxation.
    Implicit,
    /// The penalty DEM, accelerated and probed dynamic relaxation without the implicit
    /// iteration (formerly `--no-implicit`, `implicit = false` in `[tilt]`).
    Accelerated,
    /// The penalty DEM, plain dynamic relaxation with local damping (formerly
    /// `--no-implicit --no-accelerate`).
    Relaxation,
    /// Non-smooth contact dynamics (Moreau–Jean; rigid joints: Kn and Ks are not used).
    Nscd,
    /// Limit analysis (lower-bound statics of rigid blocks; rigid joints).
    Limit,
}

impl SolverKind {
    /// Every solver kind.
    pub const ALL: [SolverKind; 6] = [
        SolverKind::Penalty,
        SolverKind::Implicit,
        SolverKind::Accelerated,
        SolverKind::Relaxation,
        SolverKind::Nscd,
        SolverKind::Limit,
    ];

    /// Its name in files and on the command line (the serde name).
    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Penalty => "penalty",
            SolverKind::Implicit => "implicit",
            SolverKind::Accelerated => "accelerated",
            SolverKind::Relaxation => "relaxation",
            SolverKind::Nscd => "nscd",
            SolverKind::Limit => "limit",
        }
    }

    /// The kind of a name, `None` for an unknown one.
    pub fn from_name(name: &str) -> Option<SolverKind> {
        SolverKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Whether it is the penalty DEM (joints of finite stiffness, static states from
    /// [`solve_static`]).
    pub fn is_penalty(self) -> bool {
        self.cascade(Cascade::FULL).is_some()
    }

    /// The stages of a static solve for a protocol whose default is `protocol_default`;
    /// `None` for a solver that is not a penalty method.
    pub fn cascade(self, protocol_default: Cascade) -> Option<Cascade> {
        match self {
            SolverKind::Penalty => Some(protocol_default),
            SolverKind::Implicit => Some(Cascade::FULL),
            SolverKind::Accelerated => Some(Cascade { implicit: false, accelerate: true }),
            SolverKind::Relaxation => Some(Cascade::RELAXATION),
            SolverKind::Nscd | SolverKind::Limit => None,
        }
    }
}

impl std::fmt::Display for SolverKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for SolverKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        SolverKind::from_name(s).ok_or_else(|| {
            let names: Vec<&str> = SolverKind::ALL.iter().map(|k| k.name()).collect();
            format!("unknown solver {s:?} (one of {})", names.join(", "))
        })
    }
}

/// The stages of the penalty cascade that a static solve runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cascade {
    /// The implicit iteration first (and the probe of its drift where it stalls).
    pub implicit: bool,
    /// The secant acceleration and stability indicator in dynamic relaxation.
    pub accelerate: bool,
}

impl Cascade {
    /// Every stage.
    pub const FULL: Cascade = Cascade { implicit: true, accelerate: true };
    /// Plain dynamic relaxation.
    pub const RELAXATION: Cascade = Cascade { implicit: false, accelerate: false };
}

/// What one static solve is asked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticSolve {
    /// The stages to run.
    pub cascade: Cascade,
    /// Equilibrium when the unbalanced-force ratio is below this, –.
    pub tolerance: f64,
    /// Step budget of the dynamic relaxation.
    pub max_steps: u64,
    /// Settings of the secant acceleration (with `cascade.accelerate`).
    pub acceleration: SecantAcceleration,
    /// Settings of the implicit iteration (with `cascade.implicit`).
    pub implicit: ImplicitSolve,
    /// Reach of the probes, m: the largest body motion from the start of the solve up to
    /// which a probe looks for an equilibrium along the motion (the protocol's collapse
    /// displacement). `None`: no probes (the stability indicator alone ends an accelerated
    /// relaxation, and a stalled implicit iteration hands over to dynamic relaxation).
    pub reach: Option<f64>,
}

impl StaticSolve {
    /// Plain dynamic relaxation to `tolerance` within `max_steps` steps, no probes: the
    /// settling under gravity of every protocol.
    pub fn relaxation(tolerance: f64, max_steps: u64) -> StaticSolve {
        StaticSolve {
            cascade: Cascade::RELAXATION,
            tolerance,
            max_steps,
            acceleration: SecantAcceleration::default(),
            implicit: ImplicitSolve::default(),
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
pub enum Stage {
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
pub struct Outcome<R> {
    /// How it ended.
    pub end: End<R>,
    /// The stage that ended it.
    pub stage: Stage,
    /// Dynamic-relaxation steps taken.
    pub steps: u64,
    /// Implicit iterations taken.
    pub iterations: u32,
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
) -> Result<Outcome<R>, DemError> {
    let mut iterations = 0;
    let mut unsolved = None;
    if solve.cascade.implicit {
        match implicit_relaxation(sim, solve.tolerance, &solve.implicit, &mut check) {
            Solved::Equilibrium(it) => return Ok(implicit_end(End::Equilibrium, it)),
            Solved::Stopped(reason, it) => return Ok(implicit_end(End::Stopped(reason), it)),
            Solved::Unsolved(Unsolved::Stalled, it) => {
                iterations = it;
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
                iterations = it;
                unsolved = Some(cause);
            }
        }
    }
    let (tol, budget) = (solve.tolerance, solve.max_steps);
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
    Ok(Outcome { end, stage: Stage::Relaxation, steps, iterations, unsolved })
}

fn implicit_end<R>(end: End<R>, iterations: u32) -> Outcome<R> {
    Outcome { end, stage: Stage::Implicit, steps: 0, iterations, unsolved: None }
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
            max_steps: 100_000,
            acceleration: SecantAcceleration::default(),
            implicit: ImplicitSolve::default(),
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
            (Cascade::FULL, Stage::Implicit),
            (Cascade { implicit: false, accelerate: true }, Stage::Relaxation),
            (Cascade::RELAXATION, Stage::Relaxation),
        ] {
            let mut sim = block();
            let start = crate::dem::motion::poses(&sim);
            let z0 = sim.state.bodies[0].pos.z;
            let out = solve_static(&mut sim, &solve(cascade), &start, |_| None::<()>).unwrap();
            assert_eq!(out.end, End::Equilibrium, "{cascade:?}");
            assert_eq!(out.stage, stage, "{cascade:?}");
            assert_eq!(out.iterations > 0, cascade.implicit, "{cascade:?}");
            assert_eq!(out.steps > 0, !cascade.implicit, "{cascade:?}");
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
        let out = solve_static(&mut sim, &solve(Cascade::FULL), &start, |_| Some("stop")).unwrap();
        assert_eq!((out.end, out.stage), (End::Stopped("stop"), Stage::Implicit));
        let mut sim = block();
        let tight = StaticSolve { tolerance: 1e-14, max_steps: 7, ..solve(Cascade::RELAXATION) };
        let out = solve_static(&mut sim, &tight, &start, |_| None::<()>).unwrap();
        assert_eq!((out.end, out.steps), (End::Budget, 7));
    }

    /// The names round-trip and the penalty kinds resolve against the protocol's default.
    #[test]
    fn solver_names_and_cascades() {
        for k in SolverKind::ALL {
            assert_eq!(k.name().parse::<SolverKind>().unwrap(), k);
        }
        assert!("rigid".parse::<SolverKind>().unwrap_err().contains("nscd"));
        assert_eq!(SolverKind::Penalty.cascade(Cascade::RELAXATION), Some(Cascade::RELAXATION));
        assert_eq!(SolverKind::Implicit.cascade(Cascade::RELAXATION), Some(Cascade::FULL));
        assert!(!SolverKind::Nscd.is_penalty() && !SolverKind::Limit.is_penalty());
        assert!(SolverKind::Relaxation.is_penalty());
    }
}
