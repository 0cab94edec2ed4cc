//! The static lateral (trapezoidal pressure) load at its service level (λ = 1): solved to
//! equilibrium by the penalty DEM (`loading::lateral`), or checked by limit analysis
//! (whether the collapse load multiplier reaches 1, `limit::limit_lateral`).

use super::contract::{ChosenBy, LoadingProtocol, Observables, Output, RunOutcome, States, Way};
use super::observed::Observed;
use super::{run, Protocol};
use crate::dem::{Method, Simulation, SolverParams};
use crate::layout::Layout;
use crate::limit::{limit_lateral, LimitError, LimitResult};
use crate::loading::lateral::{run_lateral_penalty, LateralError, LateralParams, LateralResult};

/// The static lateral load with its parameters (`[lateral]`; `pushover` is not read: the
/// pushover is a protocol of its own, [`super::pushover::Pushover`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lateral(pub LateralParams);

/// What a lateral-load run gives: the equilibrium under the load (penalty DEM), or the
/// load multiplier of limit analysis.
#[derive(Debug, Clone, PartialEq)]
pub enum LateralRun {
    /// The penalty DEM: the displacements under the load, or the collapse under it.
    Penalty(Result<LateralResult, LateralError>),
    /// Limit analysis: the collapse load multiplier λ (the wall stands the load if λ ≥ 1).
    Limit(Result<LimitResult, LimitError>),
}

impl LoadingProtocol for Lateral {
    const NAME: &'static str = "lateral";
    const DESCRIPTION: &'static str = "the static lateral load";
    const MOTION: bool = false;
    const CHOSEN_BY: Option<ChosenBy> = None;
    type Run = LateralRun;

    const WAYS: &'static [Way<Self>] = &[
        Way {
            method: Method::Penalty,
            what: "equilibrium under the load",
            run: |p, layout, solver, observer| {
                LateralRun::Penalty(run_lateral_penalty(layout, *solver, &p.0, &mut |a, s, sim| {
                    observer.state(a, s, sim)
                }))
            },
        },
        Way {
            method: Method::Limit,
            what: "whether λ ≥ 1",
            run: |p, layout, solver, _| LateralRun::Limit(limit_lateral(layout, solver, &p.0, &solver.limit)),
        },
    ];

    fn compared(&self) -> Result<Protocol, &'static str> {
        Ok(Protocol::Lateral(*self))
    }

    /// The displacements of the one equilibrium under the load, at tilt 0; no collapse
    /// angle, no mechanism.
    fn observables(&self) -> Observables {
        Observables { outputs: &[Output::Displacements], collapse_bracket_deg: None, state_step_deg: None }
    }
}

impl LateralRun {
    /// The method that ran it: its variant's name.
    pub fn method(&self) -> Method {
        match self {
            LateralRun::Penalty(_) => Method::Penalty,
            LateralRun::Limit(_) => Method::Limit,
        }
    }
}

impl RunOutcome for LateralRun {
    fn observed(&self) -> Option<Observed> {
        match self {
            LateralRun::Penalty(r) => r.observed(),
            LateralRun::Limit(r) => r.observed(),
        }
    }
    fn error(&self) -> Option<String> {
        match self {
            LateralRun::Penalty(r) => r.error(),
            LateralRun::Limit(r) => r.error(),
        }
    }
    fn does_not_stand(&self) -> bool {
        match self {
            LateralRun::Penalty(r) => r.does_not_stand(),
            LateralRun::Limit(r) => r.does_not_stand(),
        }
    }
    fn limit(&self) -> Option<&Result<LimitResult, LimitError>> {
        match self {
            LateralRun::Limit(r) => Some(r),
            LateralRun::Penalty(_) => None,
        }
    }
}

/// Runs the static lateral load test of a layout at its service level by the penalty DEM
/// (the method every penalty `solver.kind` selects), through the protocol seam.
///
/// # Errors
/// [`LateralError::DoesNotStand`] if the layout does not stand as given under gravity,
/// [`LateralError::Dem`] if the state blows up, [`LateralError::Parameter`] for bad
/// parameters, [`LateralError::Unsupported`] for a solver that does not give the
/// equilibrium (nscd, limit analysis). A wall that collapses under the load is a result
/// (`equilibrium` false), not an error.
pub fn run_lateral(
    layout: &Layout,
    solver: SolverParams,
    params: &LateralParams,
) -> Result<LateralResult, LateralError> {
    run_lateral_observed(layout, solver, params, &mut |_, _, _| {})
}

/// As [`run_lateral`], handing the states of the test to `observe(load_factor, stable,
/// state)`: the settled state under gravity alone (load factor 0), then the state at the
/// end of the loaded solve (load factor 1; stable if it is an equilibrium). Observing
/// changes nothing in the test.
///
/// # Errors
/// As [`run_lateral`].
pub fn run_lateral_observed(
    layout: &Layout,
    solver: SolverParams,
    params: &LateralParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<LateralResult, LateralError> {
    match run(&Lateral(*params), layout, solver, &mut States(observe)) {
        Ok(LateralRun::Penalty(r)) => r,
        Ok(LateralRun::Limit(_)) => Err(LateralError::Unsupported(
            "limit analysis gives the lateral load's collapse load multiplier, not its equilibrium: \
             run `Protocol::Lateral` through `Protocol::run` for it"
                .to_string(),
        )),
        Err(e) => Err(LateralError::Unsupported(e.to_string())),
    }
}
