//! The error of the engine's step.

use thiserror::Error;

/// Engine errors.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum DemError {
    /// A body's state became NaN or infinite: the run blew up.
    #[error("block {id} has a non-finite state at step {step} (time step {dt_s:e} s): the run blew up")]
    NonFinite {
        /// Block id.
        id: String,
        /// Step number.
        step: u64,
        /// Time step, s.
        dt_s: f64,
    },
}
