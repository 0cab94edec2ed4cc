//! The crate error: one variant per module error.

use thiserror::Error;

/// Any drystone error.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum Error {
    /// Bad layout file or layout value.
    #[error(transparent)]
    Layout(#[from] crate::layout::LayoutError),
    /// Bad geometry.
    #[error(transparent)]
    Geometry(#[from] crate::geometry::GeometryError),
    /// Bad wall description or distribution, or an infeasible realization.
    #[error(transparent)]
    Generator(#[from] crate::generator::GeneratorError),
    /// The engine blew up.
    #[error(transparent)]
    Dem(#[from] crate::dem::DemError),
    /// Bad protocol or solver parameter.
    #[error("parameter {key} = {value}: {reason}")]
    Parameter {
        /// The parameter.
        key: String,
        /// Its value.
        value: String,
        /// What is wrong.
        reason: String,
    },
}
