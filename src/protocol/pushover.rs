//! The lateral load pushed over to collapse (`lateral.pushover`): its collapse load
//! multiplier λ, by the penalty DEM in increments of λ on the tilting table's stable path
//! (`loading::lateral_pushover`, after the service load, with limit analysis beside it), at
//! the rigid limit by nscd in bisection (`loading::lateral_nscd`), or by limit analysis
//! (`limit::limit_lateral`).

use super::contract::{Choice, ChosenBy, LoadingProtocol, Observables, RunOutcome, Way};
use super::lateral::Lateral;
use super::observed::Observed;
use super::Protocol;
use crate::dem::Method;
use crate::limit::{limit_lateral, LimitError, LimitResult};
use crate::loading::lateral::{run_lateral_penalty, LateralError, LateralParams, LateralResult};
use crate::loading::lateral_nscd::{run_lateral_nscd, LateralLimit};
use crate::loading::lateral_pushover::{run_lateral_pushover_observed, LateralPushover};
use crate::loading::tilt::TiltError;

/// The lateral pushover with the lateral load's parameters (`[lateral]`, `pushover =
/// true`; `pushover_resolution` the rigid pushover's bracket).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pushover(pub LateralParams);

/// The penalty pushover and the rigid limit analysis of the same load beside it.
pub type Collapse = (Result<LateralPushover, LateralError>, Result<LimitResult, LimitError>);

/// What a pushover gives, by method.
#[derive(Debug, Clone, PartialEq)]
pub enum PushoverRun {
    /// The penalty DEM: the service load (λ = 1) first; if it ran, the pushover to collapse
    /// and the limit analysis of the same load beside it.
    Penalty {
        /// The static lateral load at λ = 1.
        service: Result<LateralResult, LateralError>,
        /// The penalty pushover and the rigid limit analysis (`None` when the service load
        /// did not run).
        collapse: Option<Box<Collapse>>,
    },
    /// nscd: the rigid collapse multiplier by bisection.
    Nscd(Result<LateralLimit, TiltError>),
    /// Limit analysis: the collapse load multiplier λ.
    Limit(Result<LimitResult, LimitError>),
}

impl LoadingProtocol for Pushover {
    const NAME: &'static str = "pushover";
    const DESCRIPTION: &'static str = "the lateral pushover (lateral.pushover)";
    const MOTION: bool = false;
    const CHOSEN_BY: Option<ChosenBy> = Some(ChosenBy { table: "lateral", key: "pushover", value: Choice::True });
    const OPTIONAL_COLUMNS: bool = true;
    type Run = PushoverRun;

    const WAYS: &'static [Way<Self>] = &[
        Way {
            method: Method::Penalty,
            what: "λ by increments (and λ of limit analysis beside it)",
            run: |p, layout, solver, observer| {
                let service = run_lateral_penalty(layout, *solver, &p.0, &mut |_, _, _| {});
                let collapse = service.is_ok().then(|| {
                    let pushed = run_lateral_pushover_observed(layout, *solver, &p.0, &mut |a, s, sim| {
                        observer.state(a, s, sim)
                    });
                    Box::new((pushed, limit_lateral(layout, solver, &p.0, &solver.limit)))
                });
                PushoverRun::Penalty { service, collapse }
            },
        },
        Way {
            method: Method::Nscd,
            what: "rigid λ by bisection",
            run: |p, layout, solver, _| PushoverRun::Nscd(run_lateral_nscd(layout, &solver.nscd, &p.0)),
        },
        Way {
            method: Method::Limit,
            what: "λ",
            run: |p, layout, solver, _| PushoverRun::Limit(limit_lateral(layout, solver, &p.0, &solver.limit)),
        },
    ];

    /// The lateral load at its service level (λ = 1): a pushover is compared without
    /// pushing it over.
    fn compared(&self) -> Result<Protocol, &'static str> {
        Ok(Protocol::Lateral(Lateral(LateralParams { pushover: false, ..self.0 })))
    }

    /// Those of the lateral load at its service level ([`Pushover::compared`]).
    fn observables(&self) -> Observables {
        Lateral(self.0).observables()
    }
}

impl PushoverRun {
    /// The method that ran it: its variant's name.
    pub fn method(&self) -> Method {
        match self {
            PushoverRun::Penalty { .. } => Method::Penalty,
            PushoverRun::Nscd(_) => Method::Nscd,
            PushoverRun::Limit(_) => Method::Limit,
        }
    }
}

impl RunOutcome for PushoverRun {
    /// Nothing: a pushover is compared at its service level ([`Pushover::compared`]).
    fn observed(&self) -> Option<Observed> {
        None
    }
    fn error(&self) -> Option<String> {
        match self {
            PushoverRun::Penalty { service, .. } => service.error(),
            PushoverRun::Nscd(r) => r.error(),
            PushoverRun::Limit(r) => r.error(),
        }
    }
    fn does_not_stand(&self) -> bool {
        match self {
            PushoverRun::Penalty { service, .. } => service.does_not_stand(),
            PushoverRun::Nscd(r) => r.does_not_stand(),
            PushoverRun::Limit(r) => r.does_not_stand(),
        }
    }
    fn limit(&self) -> Option<&Result<LimitResult, LimitError>> {
        match self {
            PushoverRun::Limit(r) => Some(r),
            PushoverRun::Penalty { .. } | PushoverRun::Nscd(_) => None,
        }
    }
}
