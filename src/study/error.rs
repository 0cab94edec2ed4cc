//! The error of reading and resolving a study or suite file.

use crate::io::table::TableError;
use crate::protocol::Unsupported;
use std::path::{Path, PathBuf};
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

/// Why a study (or suite) name cannot be used as a directory name
/// (`check_name`).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum NameError {
    /// Empty or blank.
    #[error("must not be empty")]
    Empty,
    /// `.` or `..`.
    #[error("{name:?} is not a usable directory name")]
    Reserved {
        /// The name.
        name: String,
    },
    /// A path separator or a control character.
    #[error(
        "{name:?} contains {character:?}; a study name is used as a directory name and must not contain / or \\ or control characters"
    )]
    Character {
        /// The name.
        name: String,
        /// The first character at fault.
        character: char,
    },
}

/// Why a `[[calibrate]]` step does not fit its study
/// (`check_calibration`); each names the key.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CalibrationSpecError {
    /// `parameter` is not one the calibration can search.
    #[error("parameter: expects kn_pa_per_m or friction_deg, got {0:?}")]
    Parameter(String),
    /// `lower`, `upper` not finite with lower < upper.
    #[error("lower, upper: need finite lower < upper, got {lower} .. {upper}")]
    Interval {
        /// `lower` as given.
        lower: f64,
        /// `upper` as given.
        upper: f64,
    },
    /// A Kn interval reaching 0 or below, Pa/m.
    #[error("lower: Kn must be > 0, got {0}")]
    KnLower(f64),
    /// A friction-angle interval outside (0, 90) degrees.
    #[error("lower, upper: φ must be in (0, 90) degrees, got {lower} .. {upper}")]
    FrictionInterval {
        /// `lower` as given, degrees.
        lower: f64,
        /// `upper` as given, degrees.
        upper: f64,
    },
    /// `tolerance` not a finite number > 0.
    #[error("tolerance: must be a finite number > 0")]
    Tolerance,
    /// `group` or a `carry_to` entry that is no group of the study.
    #[error("group {0:?} is not a group of the study")]
    UnknownGroup(String),
    /// The group has no measured collapse angle to calibrate against.
    #[error("group {group:?}: no measured collapse angle for {measured:?} in [measured] collapse")]
    NoMeasurement {
        /// The step's group.
        group: String,
        /// The measured-data group it reads.
        measured: String,
    },
}

/// What a study lacks for the paper comparison it names in `paper`
/// (`check_paper`).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{paper} needs {need}")]
pub struct PaperSpecError {
    /// The paper study (`joint_arrangement`, `length_height`, `kn_phi`).
    pub paper: &'static str,
    /// What it needs, as a phrase (`protocol = "lateral"`, `a sweep over length_m`, ...).
    pub need: &'static str,
}

/// Builds [`StudyError::Invalid`] for one file.
pub(super) struct Invalid<'a>(pub(super) &'a Path);

impl Invalid<'_> {
    pub(super) fn at(&self, key: &str, reason: String) -> StudyError {
        StudyError::Invalid { path: self.0.to_owned(), key: key.into(), reason }
    }

    pub(super) fn wall(&self, group: &str, source: crate::generator::GeneratorError) -> StudyError {
        StudyError::Wall { path: self.0.to_owned(), group: group.into(), source: Box::new(source) }
    }
}

/// The refusal of a study's `[solver] kind` for its protocol ([`crate::protocol::check`]),
/// at the key that chooses them ([`crate::protocol::Loading::refusal_key`]: `tilt.by_hand` for the table
/// rolled by hand, else `solver.kind`).
pub(super) fn unsupported(invalid: &Invalid, e: Unsupported) -> StudyError {
    let key = e.protocol.refusal_key();
    invalid.at(key, format!("{e}: give [solver] kind = one of these"))
}
