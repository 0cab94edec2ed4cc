//! The error of reading and writing tables (realizations, measured data, summaries).

use std::path::PathBuf;
use thiserror::Error;

/// Table I/O errors.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum TableError {
    /// File system error.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Polars error (format, schema).
    #[error("{path}: {message}")]
    Polars {
        /// The file.
        path: PathBuf,
        /// The message.
        message: String,
    },
    /// A value of a row that cannot be used.
    #[error("{path}: line {line}, column {column}: {message}")]
    Value {
        /// The file.
        path: PathBuf,
        /// 1-based line (the header is line 1).
        line: usize,
        /// The column.
        column: String,
        /// What is wrong.
        message: String,
    },
    /// A column is missing or has the wrong type.
    #[error("{path}: column {column}: {message}")]
    Column {
        /// The file.
        path: PathBuf,
        /// The column.
        column: String,
        /// What is wrong.
        message: String,
    },
}
