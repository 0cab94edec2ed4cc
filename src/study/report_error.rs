//! The error of writing a study's report: a table, a plot, a paper section or a file.

use super::paper::PaperError;
use crate::io::plot;
use crate::io::table::TableError;
use crate::io::FileError;
use std::path::PathBuf;

/// Report errors.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// Writing a table.
    #[error(transparent)]
    Table(#[from] TableError),
    /// Writing a plot.
    #[error(transparent)]
    Plot(#[from] plot::PlotError),
    /// The section of a paper study.
    #[error(transparent)]
    Paper(#[from] PaperError),
    /// Writing a file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

impl From<FileError> for ReportError {
    fn from(e: FileError) -> Self {
        ReportError::Io { path: e.path, source: e.source }
    }
}
