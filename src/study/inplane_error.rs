//! The errors of the in-plane study ([`super::inplane`]), each naming its file and key.

use std::path::PathBuf;

/// Errors of the in-plane study, each naming its file and key.
#[derive(Debug, thiserror::Error)]
pub enum InPlaneStudyError {
    /// A file could not be read or parsed.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A key's value is refused.
    #[error("{path}: {key}: {message}")]
    Invalid {
        /// The study file.
        path: PathBuf,
        /// The key.
        key: String,
        /// Why.
        message: String,
    },
    /// An output could not be written.
    #[error("{0}")]
    Write(String),
    /// The study file refused by the study core (naming its file and key).
    #[error(transparent)]
    Study(#[from] super::StudyError),
    /// The run directory refused by the study core (its journal, naming the file, line and
    /// field or the difference of the runs).
    #[error(transparent)]
    Output(#[from] super::shards::OutputError),
}
