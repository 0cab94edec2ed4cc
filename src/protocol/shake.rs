//! The shaking table under one ground motion (`loading::shake`): by the penalty DEM in
//! explicit dynamics with contact dashpots, or by non-smooth contact dynamics (Moreau–Jean).
//! A motion: no cascade of static solves applies; limit analysis does not shake.

use super::contract::{Instants, LoadingProtocol, Observables, Way};
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
    /// Non-smooth contact dynamics: rocking and impacts of rigid blocks without the
    /// penalty DEM's contact dashpots to calibrate (docs/shake.md).
    const DEFAULT_SOLVER: SolverKind = SolverKind::Nscd;
    type Run = Result<ShakeResult, ShakeError>;

    fn way(method: Method) -> Option<Way<Self>> {
        match method {
            Method::Penalty => Some(Way {
                what: "explicit dynamics with contact damping",
                run: |p, layout, solver, observer| {
                    run_shake_penalty(layout, *solver, &p.motion, &p.params, &mut |t, b| observer.instant(t, b))
                },
            }),
            Method::Nscd => Some(Way {
                what: "non-smooth contact dynamics",
                run: |p, layout, solver, observer| {
                    run_shake_nscd(layout, *solver, &p.motion, &p.params, &mut |t, b| observer.instant(t, b))
                },
            }),
            Method::Limit => None,
        }
    }

    /// None to compare (the discrepancy analysis refuses the shaking table,
    /// [`Shake::compared`]).
    fn observables(&self) -> Observables {
        Observables { collapse_bracket_deg: None, state_step_deg: None, mechanism: false }
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
