//! The protocol seam: one type through which a study, the discrepancy analysis or the
//! command line runs a loading protocol on one realization's layout.
//!
//! A [`Protocol`] is a protocol with its parameters; [`Protocol::run`] runs it on a layout
//! by the method the solver selects — the penalty DEM, nscd or limit analysis, as the one
//! compatibility table ([`crate::loading::support`]) allows — and returns a [`ProtocolRun`] (the
//! method's result, or the error that ended it, which a study turns into a status row).
//! Adding a protocol is one module in `loading/` (its parameters, result and driver), one
//! variant here and in [`ProtocolRun`], its row of the table; see CONTRIBUTING.md.

use crate::dem::{Method, SolverParams};
use crate::layout::Layout;
use crate::limit::{limit_lateral, limit_tilt, LimitError, LimitResult};
use crate::loading::lateral::{run_lateral, LateralError, LateralParams, LateralResult};
use crate::loading::lateral_nscd::{run_lateral_nscd, LateralLimit};
use crate::loading::lateral_pushover::{run_lateral_pushover, LateralPushover};
use crate::loading::mechanism::MechanismReading;
use crate::loading::monitors::TopMonitor;
use crate::loading::shake::{run_shake, ShakeError, ShakeParams, ShakeResult};
use crate::loading::support::{self, Loading, Unsupported};
use crate::loading::tilt::{run_tilt, TiltError, TiltParams, TiltResult};
use crate::units::m_to_cm;
use serde::Serialize;

/// A loading protocol with its parameters.
#[derive(Debug, Clone, PartialEq)]
pub enum Protocol {
    /// The tilting table to collapse (`loading::tilt`), quasi-statically or rolled by hand
    /// (`TiltParams::by_hand`).
    Tilt(TiltParams),
    /// The static lateral (trapezoidal pressure) load, solved to equilibrium
    /// (`loading::lateral`), or pushed over to collapse (`LateralParams::pushover`).
    Lateral(LateralParams),
    /// The shaking table under one ground motion (`loading::shake`).
    Shake {
        /// Shaking-table parameters.
        params: ShakeParams,
        /// The base motion, as it is applied (already scaled to its level).
        motion: Box<crate::ground::Motion>,
    },
}

/// What one run of a protocol came to: the result of the method that ran it, or the error
/// that ended it. Which variant a run gives is a function of the protocol and the method
/// ([`Protocol::run`]).
#[derive(Debug, Clone, PartialEq)]
pub enum ProtocolRun {
    /// The tilting table by the penalty DEM or nscd (quasi-static or rolled by hand).
    Tilt(Result<TiltResult, TiltError>),
    /// The static lateral load by the penalty DEM.
    Lateral(Result<LateralResult, LateralError>),
    /// The lateral pushover by the penalty DEM: the service load (λ = 1) first; if it ran,
    /// the pushover to collapse and the limit analysis of the same load beside it.
    Pushover {
        /// The static lateral load at λ = 1.
        service: Result<LateralResult, LateralError>,
        /// The penalty pushover and the rigid limit analysis (`None` when the service load
        /// did not run).
        collapse: Option<Box<(Result<LateralPushover, LateralError>, Result<LimitResult, LimitError>)>>,
    },
    /// The lateral pushover by nscd: the rigid collapse multiplier by bisection.
    RigidPushover(Result<LateralLimit, TiltError>),
    /// The tilting table or the lateral load by limit analysis.
    Limit(Result<LimitResult, LimitError>),
    /// The shaking table by nscd or the penalty DEM.
    Shake(Result<ShakeResult, ShakeError>),
    /// The solver does not run the protocol ([`support::check`]).
    Unsupported(Unsupported),
}

/// What a run gives to compare with measured data (`drystone discrepancy`): the collapse
/// angle with its bracket, the top displacements at every stable state, the failure
/// mechanism ([`ProtocolRun::observed`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Observed {
    /// Collapse angle α_max, degrees (`max_angle_deg` if the wall stood); `None` under the
    /// lateral load (no collapse angle).
    pub collapse_deg: Option<f64>,
    /// The first unstable tilt above α_max, degrees (`None` if the wall stood).
    pub first_unstable_deg: Option<f64>,
    /// Stable tilts, degrees (under the lateral load: `[0.0]`, the equilibrium under the
    /// load, or none if the wall found none).
    pub tilt_deg: Vec<f64>,
    /// Left, centre and right top displacements at each stable tilt, cm (out of plane, +y:
    /// the side the wall falls to; NaN for a point the layout has no monitor at).
    pub top_cm: Vec<[f64; 3]>,
    /// The failure mechanism as a person would read it (`None` if the wall stood).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mechanism: Option<MechanismReading>,
}

impl Protocol {
    /// The protocol's name in study files (`protocol = "..."`) and tables.
    pub fn name(&self) -> &'static str {
        match self {
            Protocol::Tilt(_) => "tilt",
            Protocol::Lateral(_) => "lateral",
            Protocol::Shake { .. } => "shake",
        }
    }

    /// Its row of the compatibility table ([`support::methods`]).
    pub fn kind(&self) -> Loading {
        match self {
            Protocol::Tilt(p) if p.by_hand.is_some() => Loading::TiltByHand,
            Protocol::Tilt(_) => Loading::Tilt,
            Protocol::Lateral(p) if p.pushover => Loading::Pushover,
            Protocol::Lateral(_) => Loading::Lateral,
            Protocol::Shake { .. } => Loading::Shake,
        }
    }

    /// The tilting table's parameters, for the tilting table.
    pub fn tilt(&self) -> Option<&TiltParams> {
        match self {
            Protocol::Tilt(t) => Some(t),
            Protocol::Lateral(_) | Protocol::Shake { .. } => None,
        }
    }

    /// The protocol run to compare with measured data ([`ProtocolRun::observed`]): the
    /// tilting table as it is; the lateral load at its service level (λ = 1: a pushover is
    /// compared without pushing it over). The shaking table has no observable to compare.
    ///
    /// # Errors
    /// Why the protocol has nothing to compare.
    pub fn observed(&self) -> Result<Protocol, &'static str> {
        match self {
            Protocol::Tilt(t) => Ok(Protocol::Tilt(*t)),
            Protocol::Lateral(l) => Ok(Protocol::Lateral(LateralParams { pushover: false, ..*l })),
            Protocol::Shake { .. } => Err("the discrepancy analysis compares collapse angles and displacements of the tilting table or of the lateral load; the shaking table has neither"),
        }
    }

    /// Runs the protocol on `layout` with the solver `solver`: the method the solver kind
    /// selects ([`crate::dem::SolverKind::method`]), if the compatibility table
    /// ([`support::check`]) lets it run this protocol. Limit analysis runs with
    /// `solver.limit`.
    pub fn run(&self, layout: &Layout, solver: SolverParams) -> ProtocolRun {
        if let Err(e) = support::check(self.kind(), solver.kind) {
            return ProtocolRun::Unsupported(e);
        }
        let limit = solver.limit;
        // One arm per (protocol, method): a new method or protocol does not compile until
        // it has its arms here and its row in `support::methods`.
        match (self, solver.kind.method()) {
            (Protocol::Tilt(p), Method::Penalty | Method::Nscd) => ProtocolRun::Tilt(run_tilt(layout, solver, p)),
            (Protocol::Tilt(_), Method::Limit) => ProtocolRun::Limit(limit_tilt(layout, &solver, &limit)),
            (Protocol::Lateral(p), Method::Penalty) if p.pushover => {
                let service = run_lateral(layout, solver, p);
                let collapse = service.is_ok().then(|| {
                    Box::new((run_lateral_pushover(layout, solver, p), limit_lateral(layout, &solver, p, &limit)))
                });
                ProtocolRun::Pushover { service, collapse }
            }
            (Protocol::Lateral(p), Method::Penalty) => ProtocolRun::Lateral(run_lateral(layout, solver, p)),
            (Protocol::Lateral(p), Method::Nscd) => {
                ProtocolRun::RigidPushover(run_lateral_nscd(layout, &solver.nscd, p))
            }
            (Protocol::Lateral(p), Method::Limit) => ProtocolRun::Limit(limit_lateral(layout, &solver, p, &limit)),
            (Protocol::Shake { params, motion }, Method::Penalty | Method::Nscd) => {
                ProtocolRun::Shake(run_shake(layout, solver, motion, params))
            }
            (Protocol::Shake { .. }, Method::Limit) => {
                ProtocolRun::Unsupported(Unsupported { protocol: Loading::Shake, kind: solver.kind })
            }
        }
    }
}

impl ProtocolRun {
    /// Whether the run ended in an error because the layout did not stand as given under
    /// gravity alone (as opposed to a blow-up or a bad parameter).
    pub fn does_not_stand(&self) -> bool {
        match self {
            ProtocolRun::Tilt(r) => matches!(r, Err(TiltError::DoesNotStand(_))),
            ProtocolRun::RigidPushover(r) => matches!(r, Err(TiltError::DoesNotStand(_))),
            ProtocolRun::Lateral(r) | ProtocolRun::Pushover { service: r, .. } => {
                matches!(r, Err(LateralError::DoesNotStand(_)))
            }
            ProtocolRun::Shake(r) => matches!(r, Err(ShakeError::DoesNotStand(_))),
            ProtocolRun::Limit(r) => matches!(
                r,
                Err(LimitError::Untouched { .. }
                    | LimitError::Floating { .. }
                    | LimitError::Infeasible { .. }
                    | LimitError::DoesNotStand { .. })
            ),
            ProtocolRun::Unsupported(_) => false,
        }
    }

    /// What the run gives to compare with measured data: the tilting table's collapse angle,
    /// its bracket, the top displacements at every stable tilt and the failure mechanism; the
    /// lateral load's top displacements under the load, as one state at tilt 0° when the wall
    /// found an equilibrium (none when it did not: a displacement observation of it is then
    /// missing, as one above a tilting-table collapse). `None` for a run that ended in an
    /// error or gives nothing to compare (limit analysis, the pushover, the shaking table).
    pub fn observed(&self) -> Option<Observed> {
        match self {
            ProtocolRun::Tilt(Ok(t)) => Some(tilt_observed(t)),
            ProtocolRun::Lateral(Ok(r)) => Some(lateral_observed(r)),
            ProtocolRun::Tilt(Err(_))
            | ProtocolRun::Lateral(Err(_))
            | ProtocolRun::Pushover { .. }
            | ProtocolRun::RigidPushover(_)
            | ProtocolRun::Limit(_)
            | ProtocolRun::Shake(_)
            | ProtocolRun::Unsupported(_) => None,
        }
    }

    /// The error that ended the run, if any, as text.
    pub fn error(&self) -> Option<String> {
        match self {
            ProtocolRun::Tilt(Err(e)) | ProtocolRun::RigidPushover(Err(e)) => Some(e.to_string()),
            ProtocolRun::Lateral(Err(e)) | ProtocolRun::Pushover { service: Err(e), .. } => Some(e.to_string()),
            ProtocolRun::Limit(Err(e)) => Some(e.to_string()),
            ProtocolRun::Shake(Err(e)) => Some(e.to_string()),
            ProtocolRun::Unsupported(e) => Some(e.to_string()),
            ProtocolRun::Tilt(Ok(_))
            | ProtocolRun::RigidPushover(Ok(_))
            | ProtocolRun::Lateral(Ok(_))
            | ProtocolRun::Pushover { service: Ok(_), .. }
            | ProtocolRun::Limit(Ok(_))
            | ProtocolRun::Shake(Ok(_)) => None,
        }
    }
}

/// The observables of a tilting-table run ([`ProtocolRun::observed`]).
fn tilt_observed(t: &TiltResult) -> Observed {
    let idx = TopMonitor::ALL.map(|m| m.index_in(&t.monitors));
    let mut tilt_deg = Vec::new();
    let mut top_cm = Vec::new();
    for inc in t.increments.iter().filter(|i| i.stable) {
        tilt_deg.push(inc.alpha_deg);
        top_cm.push(idx.map(|i| i.map_or(f64::NAN, |i| m_to_cm(inc.displacement_m[i]))));
    }
    Observed {
        collapse_deg: Some(t.collapse_angle_deg()),
        first_unstable_deg: t.first_unstable_deg,
        tilt_deg,
        top_cm,
        mechanism: t.mechanism.reading,
    }
}

/// The observables of a lateral-load run ([`ProtocolRun::observed`]): no collapse angle, no
/// mechanism.
fn lateral_observed(r: &LateralResult) -> Observed {
    let idx = TopMonitor::ALL.map(|m| m.index_in(&r.monitors));
    let (tilt_deg, top_cm) = if r.equilibrium {
        (vec![0.0], vec![idx.map(|i| i.map_or(f64::NAN, |i| m_to_cm(r.displacement_m[i])))])
    } else {
        (vec![], vec![])
    };
    Observed { collapse_deg: None, first_unstable_deg: None, tilt_deg, top_cm, mechanism: None }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::BaseSliding;
    use crate::verify::{box_vertices, layout_of};

    /// Both protocols run through the seam as they run alone, bit for bit; a block floating
    /// above the table is refused by either as a layout that does not stand.
    #[test]
    fn the_seam_runs_each_protocol_as_it_runs_alone() {
        let l = layout_of(vec![box_vertices([0.0, -0.05, 0.0], [0.2, 0.05, 0.2])], 1e9, 5e8, 35.0, BaseSliding::Free);
        let tilt = TiltParams { resolution_deg: 0.5, ..TiltParams::default() };
        let ProtocolRun::Tilt(Ok(a)) = Protocol::Tilt(tilt).run(&l, SolverParams::default()) else { panic!() };
        let b = run_tilt(&l, SolverParams::default(), &tilt).unwrap();
        assert_eq!(
            (a.last_stable_deg, a.first_unstable_deg, a.steps),
            (b.last_stable_deg, b.first_unstable_deg, b.steps)
        );
        let lateral = LateralParams::default();
        let ProtocolRun::Lateral(Ok(c)) = Protocol::Lateral(lateral).run(&l, SolverParams::default()) else { panic!() };
        let d = run_lateral(&l, SolverParams::default(), &lateral).unwrap();
        assert_eq!((c.displacement_m, c.steps), (d.displacement_m, d.steps));
        let floating =
            layout_of(vec![box_vertices([0.0, -0.05, 0.1], [0.2, 0.05, 0.3])], 1e9, 5e8, 35.0, BaseSliding::Free);
        for p in [Protocol::Tilt(tilt), Protocol::Lateral(lateral)] {
            let run = p.run(&floating, SolverParams::default());
            assert!(run.does_not_stand(), "{}: {:?}", p.name(), run.error());
            assert!(run.error().unwrap().contains("touches nothing"), "{:?}", run.error());
        }
    }
}
