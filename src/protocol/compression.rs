//! The vertical compression test: the wall between the foundation and the loading beam,
//! the vertical force cycled and then, optionally, raised; by the penalty DEM
//! (`loading::compression`: the wall's vertical modulus, the database's `Epc`, and its
//! compressive strength where the joints' law bounds the pressure). Non-smooth contact
//! dynamics and limit analysis do not run it: their contacts are rigid, so a wall has no
//! shortening to read a modulus from, and no pressure bound to read a strength from.

use super::contract::{ChosenBy, LoadingProtocol, Observables, RunOutcome, Way};
use super::observed::Observed;
use super::Protocol;
use crate::dem::Method;
use crate::loading::compression::{run_compression_penalty, CompressionError, CompressionParams, CompressionResult};

/// The compression test with its parameters (`[compression]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Compression(pub CompressionParams);

/// What a compression run gives.
#[derive(Debug, Clone, PartialEq)]
pub enum CompressionRun {
    /// The penalty DEM: the force–shortening curve and its readings.
    Penalty(Result<CompressionResult, CompressionError>),
}

impl LoadingProtocol for Compression {
    const NAME: &'static str = "compression";
    const DESCRIPTION: &'static str = "the vertical compression test";
    const MOTION: bool = false;
    const CHOSEN_BY: Option<ChosenBy> = None;
    // Its column group (`ensemble::compression_columns`) is written to its study's tables
    // only, not to every protocol's.
    const OPTIONAL_COLUMNS: bool = true;
    type Run = CompressionRun;

    const WAYS: &'static [Way<Self>] = &[Way {
        method: Method::Penalty,
        what: "vertical modulus and cycles (static solve per branch of the vertical force)",
        run: |p, layout, solver, observer| {
            CompressionRun::Penalty(run_compression_penalty(layout, *solver, &p.0, &mut |a, s, sim| {
                observer.state(a, s, sim)
            }))
        },
    }];

    /// The discrepancy analysis reads none of its outputs (the in-plane test's vertical
    /// modulus is compared there, from that test's vertical phase).
    fn compared(&self) -> Result<Protocol, &'static str> {
        Err("the compression test gives the discrepancy analysis nothing to compare: its modulus is read by the in-plane test's analysis (wall_vertical_modulus_mpa)")
    }

    /// Nothing to compare.
    fn observables(&self) -> Observables {
        Observables { outputs: &[], collapse_bracket_deg: None, state_step_deg: None }
    }
}

impl CompressionRun {
    /// The method that ran it: its variant's name.
    pub fn method(&self) -> Method {
        match self {
            CompressionRun::Penalty(_) => Method::Penalty,
        }
    }
}

impl RunOutcome for CompressionRun {
    /// Nothing to compare ([`LoadingProtocol::observables`]).
    fn observed(&self) -> Option<Observed> {
        None
    }
    fn error(&self) -> Option<String> {
        match self {
            CompressionRun::Penalty(Err(e)) => Some(e.to_string()),
            CompressionRun::Penalty(Ok(_)) => None,
        }
    }
    fn does_not_stand(&self) -> bool {
        match self {
            CompressionRun::Penalty(r) => r.as_ref().err().is_some_and(CompressionError::does_not_stand),
        }
    }
    fn refused(&self) -> bool {
        match self {
            CompressionRun::Penalty(r) => r.as_ref().err().is_some_and(CompressionError::is_refusal),
        }
    }
}
