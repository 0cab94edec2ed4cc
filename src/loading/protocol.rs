//! The protocol seam: one type through which a study, the discrepancy analysis or the
//! command line runs a loading protocol on one realization's layout.
//!
//! A [`Protocol`] is a protocol with its parameters; [`Protocol::run`] runs it on a layout
//! with the chosen solver and returns a [`ProtocolRun`] (the protocol's own result, or the
//! error that ended it, which a study turns into a status row). Adding a protocol is one
//! module in `loading/` (its parameters, result and driver), one variant here and in
//! [`ProtocolRun`], one command in `src/cli/`; see CONTRIBUTING.md.

use super::lateral::{run_lateral, LateralError, LateralParams, LateralResult};
use super::shake::{run_shake, ShakeError, ShakeParams, ShakeResult};
use super::tilt::{run_tilt, TiltError, TiltParams, TiltResult};
use crate::dem::SolverParams;
use crate::layout::Layout;

/// A loading protocol with its parameters.
#[derive(Debug, Clone, PartialEq)]
pub enum Protocol {
    /// The tilting table to collapse (`loading::tilt`).
    Tilt(TiltParams),
    /// The static lateral (trapezoidal pressure) load, solved to equilibrium
    /// (`loading::lateral`).
    Lateral(LateralParams),
    /// The shaking table under one ground motion (`loading::shake`; non-smooth contact
    /// dynamics only).
    Shake {
        /// Shaking-table parameters.
        params: ShakeParams,
        /// The base motion, as it is applied (already scaled to its level).
        motion: Box<crate::ground::Motion>,
    },
}

/// What one run of a protocol came to.
#[derive(Debug, Clone, PartialEq)]
pub enum ProtocolRun {
    /// The tilting table's result or error.
    Tilt(Result<TiltResult, TiltError>),
    /// The static lateral load's result or error.
    Lateral(Result<LateralResult, LateralError>),
    /// The shaking table's result or error.
    Shake(Result<ShakeResult, ShakeError>),
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

    /// Runs the protocol on `layout` with the solver `solver`.
    pub fn run(&self, layout: &Layout, solver: SolverParams) -> ProtocolRun {
        match self {
            Protocol::Tilt(p) => ProtocolRun::Tilt(run_tilt(layout, solver, p)),
            Protocol::Lateral(p) => ProtocolRun::Lateral(run_lateral(layout, solver, p)),
            Protocol::Shake { params, motion } => ProtocolRun::Shake(run_shake(layout, solver, motion, params)),
        }
    }
}

impl ProtocolRun {
    /// Whether the run ended in an error because the layout did not stand as given under
    /// gravity alone (as opposed to a blow-up or a bad parameter).
    pub fn does_not_stand(&self) -> bool {
        matches!(
            self,
            ProtocolRun::Tilt(Err(TiltError::DoesNotStand(_)))
                | ProtocolRun::Lateral(Err(LateralError::DoesNotStand(_)))
        )
    }

    /// The error that ended the run, if any, as text.
    pub fn error(&self) -> Option<String> {
        match self {
            ProtocolRun::Tilt(Err(e)) => Some(e.to_string()),
            ProtocolRun::Lateral(Err(e)) => Some(e.to_string()),
            ProtocolRun::Shake(Err(e)) => Some(e.to_string()),
            _ => None,
        }
    }
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
