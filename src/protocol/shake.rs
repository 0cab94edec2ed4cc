//! The shaking table under one ground motion (`loading::shake`): by the penalty DEM in
//! explicit dynamics with contact dashpots, or by non-smooth contact dynamics (Moreau–Jean).
//! A motion: no cascade of static solves applies; limit analysis does not shake. Beside
//! its row of the compatibility table ([`Shake::way`]), what differs by method on the
//! shaking table is here too: the step a study checks each motion against
//! ([`step_rule`]), the coefficient `--restitution` sets ([`restitutions`]) and what a run's
//! report says of the method ([`method_notes`]).

use super::contract::{ChosenBy, Instants, LoadingProtocol, Observables, Way};
use super::{run, Protocol};
use crate::dem::state::Body;
use crate::dem::{Method, SolverKind, SolverParams};
use crate::ground::Motion;
use crate::layout::Layout;
use crate::loading::shake::{run_shake_nscd, run_shake_penalty, ShakeError, ShakeParams, ShakeResult};

/// The shaking table under one motion, as it is applied (already scaled to its level).
#[derive(Debug, Clone, PartialEq)]
pub struct Shake {
    /// Shaking-table parameters (`[shake]`).
    pub params: ShakeParams,
    /// The base motion.
    pub motion: Box<Motion>,
}

impl LoadingProtocol for Shake {
    const NAME: &'static str = "shake";
    const DESCRIPTION: &'static str = "the shaking table";
    const MOTION: bool = true;
    const CHOSEN_BY: Option<ChosenBy> = None;
    /// Non-smooth contact dynamics: rocking and impacts of rigid blocks without the
    /// penalty DEM's contact dashpots to calibrate (docs/shake.md).
    const DEFAULT_SOLVER: SolverKind = SolverKind::Nscd;
    type Run = Result<ShakeResult, ShakeError>;

    const WAYS: &'static [Way<Self>] = &[
        Way {
            method: Method::Penalty,
            what: "explicit dynamics with contact damping",
            run: |p, layout, solver, observer| {
                run_shake_penalty(layout, *solver, &p.motion, &p.params, &mut |t, b| observer.instant(t, b))
            },
        },
        Way {
            method: Method::Nscd,
            what: "Moreau–Jean time stepping",
            run: |p, layout, solver, observer| {
                run_shake_nscd(layout, *solver, &p.motion, &p.params, &mut |t, b| observer.instant(t, b))
            },
        },
    ];

    /// None to compare (the discrepancy analysis refuses the shaking table,
    /// [`Shake::compared`]).
    fn observables(&self) -> Observables {
        Observables { outputs: &[], collapse_bracket_deg: None, state_step_deg: None }
    }

    fn shaking(&self) -> Option<(&ShakeParams, &Motion)> {
        Some((&self.params, &self.motion))
    }

    fn compared(&self) -> Result<Protocol, &'static str> {
        Err("the discrepancy analysis compares collapse angles and displacements of the tilting table or of the lateral load; the shaking table has neither")
    }
}

/// Runs the shaking-table test of `layout` under `motion` by the method `solver.kind`
/// selects (nscd, or the penalty DEM in explicit dynamics), through the protocol seam,
/// handing the bodies (layout order, table frame) to `observe(time_s, bodies)` at every
/// recorded time of the history. Observing changes nothing.
///
/// # Errors
/// [`ShakeError`]: a bad parameter or motion, a solver that does not shake
/// ([`ShakeError::Unsupported`]), or the solver's own error (a blow-up becomes a status
/// row in a study).
pub fn run_shake_observed(
    layout: &Layout,
    solver: SolverParams,
    motion: &Motion,
    params: &ShakeParams,
    observe: &mut dyn FnMut(f64, &[Body]),
) -> Result<ShakeResult, ShakeError> {
    let shake = Shake { params: *params, motion: Box::new(motion.clone()) };
    run(&shake, layout, solver, &mut Instants(observe)).unwrap_or_else(|e| Err(ShakeError::Unsupported(e.to_string())))
}

/// As [`run_shake_observed`], observing nothing.
///
/// # Errors
/// As [`run_shake_observed`].
pub fn run_shake(
    layout: &Layout,
    solver: SolverParams,
    motion: &Motion,
    params: &ShakeParams,
) -> Result<ShakeResult, ShakeError> {
    run_shake_observed(layout, solver, motion, params, &mut |_, _| {})
}

/// How the method a solver selects steps through a motion, for the checks a study makes
/// before it runs ([`step_rule`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepRule {
    /// The step at which a study's step pulses are sampled, s: nscd's own step; for the
    /// penalty DEM, whose step is far smaller and reads the motion by linear interpolation,
    /// nscd's step capped at 1 ms.
    pub pulse_dt_s: f64,
    /// The method's own fixed step, s, that every motion is checked against as it is read
    /// (nscd's `dt_s`, when positive); `None` otherwise.
    pub fixed_dt_s: Option<f64>,
    /// Whether the step follows from each realization's masses and joint stiffnesses (the
    /// penalty DEM's critical step), so that a study checks it once the groups are resolved.
    pub from_walls: bool,
}

/// The step rule of the solver `solver` on the shaking table ([`StepRule`]); `None` for a
/// solver that does not shake (a cascade of static solves, limit analysis: refused by
/// [`super::check`]).
pub fn step_rule(solver: &SolverParams) -> Option<StepRule> {
    let dt = solver.nscd.dt_s;
    match solver.kind {
        SolverKind::Nscd => {
            Some(StepRule { pulse_dt_s: dt, fixed_dt_s: Some(dt).filter(|&d| d > 0.0), from_walls: false })
        }
        SolverKind::Penalty => Some(StepRule { pulse_dt_s: dt.min(1e-3), fixed_dt_s: None, from_walls: true }),
        SolverKind::Newton
        | SolverKind::Implicit
        | SolverKind::Accelerated
        | SolverKind::Relaxation
        | SolverKind::Limit => None,
    }
}

/// The restitution coefficients `(nscd's, the penalty DEM's contact dashpots')` with the
/// impacts' restitution `e` (`--restitution`, `None`: the defaults) set where the method
/// the solver kind `kind` selects reads it on the shaking table. A kind that does not
/// shake reads it as the penalty DEM does, so that its range is checked before the seam
/// refuses the kind ([`super::check`]).
pub fn restitutions(kind: SolverKind, e: Option<f64>) -> (f64, f64) {
    let nscd = crate::nscd::NscdParams::default().restitution;
    let contact = crate::dem::PenaltyParams::default().contact_restitution;
    match kind {
        SolverKind::Nscd => (e.unwrap_or(nscd), contact),
        SolverKind::Penalty
        | SolverKind::Newton
        | SolverKind::Implicit
        | SolverKind::Accelerated
        | SolverKind::Relaxation
        | SolverKind::Limit => (nscd, e.unwrap_or(contact)),
    }
}

/// What a shaking study's report says of the solver that ran it (`[solver] kind`): the
/// method and its settings, in a clause.
pub fn study_notes(solver: &SolverParams) -> String {
    let kind = solver.kind;
    let method = kind.method().describe();
    match kind.method() {
        Method::Penalty => format!(
            "solver `{kind}`: {method}, explicit dynamics with contact dashpots of restitution {} (the joints' Kn and Ks as given)",
            solver.penalty.contact_restitution
        ),
        Method::Nscd => {
            let nscd = &solver.nscd;
            format!(
                "solver `{kind}`: {method}, time step {} s, restitution {}, NSGS tolerance {} in at most {} sweeps per step (rigid blocks: the joints' Kn and Ks are not used)",
                nscd.dt_s, nscd.restitution, nscd.tolerance, nscd.max_iterations
            )
        }
        // Limit analysis does not shake: the seam refuses it before any run.
        Method::Limit => format!("solver `{kind}`: {method}"),
    }
}

/// What a shaking-table run's report says of the method that ran it: its work and solver
/// lines, and the field its JSON report adds (`drystone shake`).
#[derive(Debug, Clone, PartialEq)]
pub struct MethodNotes {
    /// The steps taken and the time they took, in a line.
    pub work: String,
    /// The method and what it reads of the joints, in a line.
    pub solver: String,
    /// The JSON report's field on the joints (name, value), if any.
    pub json: Option<(&'static str, serde_json::Value)>,
}

/// The notes of the result `r` run by `solver` ([`MethodNotes`]).
pub fn method_notes(solver: &SolverParams, r: &ShakeResult) -> MethodNotes {
    let time = format!("{:.2} s simulated; wall time {:.2} s", r.simulated_s, r.wall_time_s);
    match solver.kind.method() {
        Method::Penalty => {
            let e = solver.penalty.contact_restitution;
            MethodNotes {
                work: format!("{} steps of {:.2e} s, {time}", r.steps, r.dt_s),
                solver: format!(
                    "penalty (explicit dynamics, the joints' Kn and Ks, contact dashpots of restitution {e})"
                ),
                json: Some(("contact_restitution", e.into())),
            }
        }
        Method::Nscd => MethodNotes {
            work: format!(
                "{} steps of {:.1e} s ({} NSGS sweeps, {} unconverged: natural-map residual above {:.0e}, largest {:.1e}, settling included), {time}",
                r.steps, r.dt_s, r.iterations, r.unconverged_steps, solver.nscd.natural_tolerance, r.max_natural_residual
            ),
            solver: "nscd (rigid blocks: the joints' Kn and Ks are not used)".into(),
            json: Some(("rigid_joints", "the joints' Kn and Ks are not used (rigid blocks)".into())),
        },
        // Limit analysis does not shake: the seam refuses it before there is a result.
        Method::Limit => MethodNotes { work: String::new(), solver: solver.kind.to_string(), json: None },
    }
}
