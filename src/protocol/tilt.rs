//! The tilting table to collapse (Santa-Cruz et al. 2021, §2.2 and §5.3): tilted
//! quasi-statically by the penalty DEM (`loading::tilt`, any cascade of static solves), at
//! the rigid limit by non-smooth contact dynamics (`loading::tilt_nscd`), or by limit
//! analysis (α_max = atan λ, `limit::limit_tilt`).

use super::contract::{ChosenBy, LoadingProtocol, Observables, Output, RunOutcome, States, Way};
use super::observed::Observed;
use super::tilt_by_hand::TiltByHand;
use super::{run, Protocol};
use crate::dem::{Method, Simulation, SolverParams};
use crate::layout::Layout;
use crate::limit::{limit_tilt, LimitError, LimitResult};
use crate::loading::tilt::{run_tilt_penalty, TiltError, TiltParams, TiltResult};
use crate::loading::tilt_nscd::run_tilt_nscd;

/// The tilting table, tilted quasi-statically to collapse, with its parameters (`[tilt]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tilt(pub TiltParams);

/// What a tilting-table run gives: the path to collapse (penalty DEM or nscd), or the load
/// multiplier of limit analysis.
#[derive(Debug, Clone, PartialEq)]
pub enum TiltRun {
    /// The penalty DEM: the tilting path (the collapse bracket, the stable states and the
    /// mechanism).
    Penalty(Result<TiltResult, TiltError>),
    /// Non-smooth contact dynamics: the rigid blocks' tilting path, in the penalty DEM's
    /// result.
    Nscd(Result<TiltResult, TiltError>),
    /// Limit analysis: α_max = atan λ.
    Limit(Result<LimitResult, LimitError>),
}

impl LoadingProtocol for Tilt {
    const NAME: &'static str = "tilt";
    const DESCRIPTION: &'static str = "the tilting table";
    const MOTION: bool = false;
    const CHOSEN_BY: Option<ChosenBy> = None;
    type Run = TiltRun;

    const WAYS: &'static [Way<Self>] = &[
        Way {
            method: Method::Penalty,
            what: "collapse angle (bisection of static states)",
            run: |p, layout, solver, observer| {
                TiltRun::Penalty(run_tilt_penalty(layout, *solver, &p.0, &mut |a, s, sim| observer.state(a, s, sim)))
            },
        },
        Way {
            method: Method::Nscd,
            what: "rigid collapse angle",
            run: |p, layout, solver, _| TiltRun::Nscd(run_tilt_nscd(layout, &solver.nscd, &p.0)),
        },
        Way {
            method: Method::Limit,
            what: "α_max = atan λ",
            run: |_, layout, solver, _| TiltRun::Limit(limit_tilt(layout, solver, &solver.limit)),
        },
    ];

    fn compared(&self) -> Result<Protocol, &'static str> {
        Ok(Protocol::Tilt(*self))
    }

    fn observables(&self) -> Observables {
        Observables::of_tilt(&self.0)
    }

    fn tilt(&self) -> Option<&TiltParams> {
        Some(&self.0)
    }
}

impl TiltRun {
    /// The method that ran it: its variant's name.
    pub fn method(&self) -> Method {
        match self {
            TiltRun::Penalty(_) => Method::Penalty,
            TiltRun::Nscd(_) => Method::Nscd,
            TiltRun::Limit(_) => Method::Limit,
        }
    }
}

impl RunOutcome for TiltRun {
    fn observed(&self) -> Option<Observed> {
        match self {
            TiltRun::Penalty(r) | TiltRun::Nscd(r) => r.observed(),
            TiltRun::Limit(r) => r.observed(),
        }
    }
    fn error(&self) -> Option<String> {
        match self {
            TiltRun::Penalty(r) | TiltRun::Nscd(r) => r.error(),
            TiltRun::Limit(r) => r.error(),
        }
    }
    fn does_not_stand(&self) -> bool {
        match self {
            TiltRun::Penalty(r) | TiltRun::Nscd(r) => r.does_not_stand(),
            TiltRun::Limit(r) => r.does_not_stand(),
        }
    }
    fn limit(&self) -> Option<&Result<LimitResult, LimitError>> {
        match self {
            TiltRun::Limit(r) => Some(r),
            TiltRun::Penalty(_) | TiltRun::Nscd(_) => None,
        }
    }
}

impl Observables {
    /// The tilting table's: the collapse angle to its resolution, displacements at the
    /// multiples of its increment, the mechanism.
    pub fn of_tilt(t: &TiltParams) -> Observables {
        Observables {
            outputs: &[Output::CollapseAngle, Output::Displacements, Output::Mechanism],
            collapse_bracket_deg: Some(t.resolution_deg),
            state_step_deg: Some(t.step_deg),
        }
    }
}

/// Runs the tilting-table test of a layout to collapse, by the method `solver.kind`
/// selects (the penalty DEM, nscd; `params.by_hand`: the table rolled by hand, by nscd),
/// through the protocol seam.
///
/// The returned bracket `[last_stable_deg, first_unstable_deg]` contains the collapse
/// angle α_max to `params.resolution_deg`.
///
/// ```
/// use drystone::dem::SolverParams;
/// use drystone::layout::BaseSliding;
/// use drystone::loading::tilt::TiltParams;
/// use drystone::protocol::run_tilt;
/// use drystone::verify::{box_vertices, layout_of};
///
/// // A block 0.1125 m deep (y) and 0.375 m tall on stiff joints (Kn 1e11 Pa/m, φ 60°)
/// // topples near the rigid limit tan α = b / h = 0.3 (16.70°), below it by the elastic
/// // rotation of its base joint (the no-tension Winkler solution: 16.31°, `drystone verify`).
/// let block = box_vertices([0.0, -0.05625, 0.0], [0.3, 0.05625, 0.375]);
/// let layout = layout_of(vec![block], 1e11, 5e10, 60.0, BaseSliding::Free);
/// let params = TiltParams { resolution_deg: 0.0625, ..TiltParams::default() };
/// let r = run_tilt(&layout, SolverParams::default(), &params)?;
/// let up = r.first_unstable_deg.unwrap();
/// assert!(r.last_stable_deg <= 16.31 + 0.02 && up >= 16.31 - 0.02, "{} {up}", r.last_stable_deg);
/// // The load multiplier at collapse, λ = tan α_max, against the rigid limit b / h.
/// assert!((r.collapse_angle_deg().to_radians().tan() - 0.3).abs() < 0.01);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`TiltError::DoesNotStand`] if the layout does not stand as given at α = 0 (a block
/// touching nothing, no equilibrium, or a block that moved while settling),
/// [`TiltError::Dem`] if the state blows up, [`TiltError::Parameter`] for bad parameters,
/// [`TiltError::Unsupported`] for a solver that does not give the path (limit analysis, or
/// one the compatibility table refuses).
pub fn run_tilt(layout: &Layout, solver: SolverParams, params: &TiltParams) -> Result<TiltResult, TiltError> {
    run_tilt_observed(layout, solver, params, &mut |_, _, _| {})
}

/// As [`run_tilt`], handing every state of the test by the penalty DEM to
/// `observe(alpha_deg, stable, state)` as it is reached
/// (`loading::tilt::run_tilt_penalty`); the other methods hand over nothing. Observing
/// changes nothing in the test.
///
/// # Errors
/// As [`run_tilt`].
pub fn run_tilt_observed(
    layout: &Layout,
    solver: SolverParams,
    params: &TiltParams,
    observe: &mut dyn FnMut(f64, bool, &Simulation),
) -> Result<TiltResult, TiltError> {
    let refused = |e: super::Unsupported| TiltError::Unsupported(e.to_string());
    let mut observer = States(observe);
    if let Some(hand) = params.by_hand {
        return run(&TiltByHand { tilt: *params, hand }, layout, solver, &mut observer).map_err(refused)?;
    }
    match run(&Tilt(*params), layout, solver, &mut observer).map_err(refused)? {
        TiltRun::Penalty(r) | TiltRun::Nscd(r) => r,
        TiltRun::Limit(_) => Err(TiltError::Unsupported(
            "limit analysis gives the tilting table's collapse load multiplier, not its path: \
             run `Protocol::Tilt` through `Protocol::run` for it"
                .to_string(),
        )),
    }
}
