//! The tilting table rolled by hand in increments (`tilt.by_hand`): each increment run as a
//! motion whose stop kicks the wall, by non-smooth contact dynamics
//! (`loading::tilt_hand`). A motion: no cascade of static solves applies.

use super::contract::{Choice, ChosenBy, LoadingProtocol, Observables, Way};
use super::Protocol;
use crate::dem::Method;
use crate::loading::tilt::hand::HandTilt;
use crate::loading::tilt::{TiltError, TiltParams, TiltResult};
use crate::loading::tilt_hand::run_tilt_by_hand;

/// The tilting table rolled by hand: the tilting table's parameters and the hand's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TiltByHand {
    /// The tilting table's parameters (`[tilt]`: the increment, resolution, largest tilt).
    pub tilt: TiltParams,
    /// How the hand rolls the table (`[tilt] by_hand = { ... }`).
    pub hand: HandTilt,
}

impl LoadingProtocol for TiltByHand {
    const NAME: &'static str = "tilt_by_hand";
    const DESCRIPTION: &'static str = "the tilting table rolled by hand (tilt.by_hand)";
    const MOTION: bool = true;
    const CHOSEN_BY: Option<ChosenBy> = Some(ChosenBy { table: "tilt", key: "by_hand", value: Choice::Table });
    const REFUSAL_KEY: &'static str = "tilt.by_hand";
    type Run = Result<TiltResult, TiltError>;

    const WAYS: &'static [Way<Self>] = &[Way {
        method: Method::Nscd,
        what: "the rolled table's motion",
        run: |p, layout, solver, _| run_tilt_by_hand(layout, &solver.nscd, &p.tilt, &p.hand),
    }];

    fn compared(&self) -> Result<Protocol, &'static str> {
        Ok(Protocol::TiltByHand(*self))
    }

    fn observables(&self) -> Observables {
        Observables::of_tilt(&self.tilt)
    }

    fn tilt(&self) -> Option<&TiltParams> {
        Some(&self.tilt)
    }
}
