//! The error of reading and resolving a study or suite file.

use crate::io::table::TableError;
use std::path::PathBuf;
use thiserror::Error;

/// Study errors, each naming the file and the key at fault.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum StudyError {
    /// The file could not be read.
    #[error("cannot read study file {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Not valid study TOML (syntax, unknown key, wrong type, missing key).
    #[error("study file {path}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// serde's message.
        message: String,
    },
    /// A value is out of range.
    #[error("study file {path}: {key}: {reason}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The key.
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// A wall description of a group failed.
    #[error("study file {path}: group {group}: {source}")]
    Wall {
        /// The study file.
        path: PathBuf,
        /// The group.
        group: String,
        /// The generator's error.
        source: Box<crate::generator::GeneratorError>,
    },
    /// A ground-motion record of a shaking study was refused (its file and line named by
    /// the [`crate::ground::RecordError`]).
    #[error("study file {path}: {key}: {source}")]
    Record {
        /// The study file.
        path: PathBuf,
        /// The key that names the record, `shake.records[i]`.
        key: String,
        /// The record's error.
        source: crate::ground::RecordError,
    },
    /// A measured-data file failed.
    #[error("study file {path}: measured data: {source}")]
    Measured {
        /// The study file.
        path: PathBuf,
        /// The table error.
        source: TableError,
    },
}
