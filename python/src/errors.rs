//! The exceptions of the package and the library's errors mapped onto them.
//!
//! `DrystoneError` is the base; `InputError` is a file, key or value the library refused
//! (its `file`, `key` and `line` attributes set where the library's error names them, else
//! `None`); `SolverError` is a run that could not finish (the engine blew up, the layout
//! does not stand as given). The message is always the library's own `Display` text. A
//! panic inside the library never crosses into Python: [`guard`] turns it into a
//! `DrystoneError`.

use drystone::generator::GeneratorError;
use drystone::io::table::TableError;
use drystone::layout::LayoutError;
use drystone::loading::lateral::LateralError;
use drystone::loading::tilt::TiltError;
use drystone::study::StudyError;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use std::path::Path;

pyo3::create_exception!(
    drystone,
    DrystoneError,
    PyException,
    "Base of every error drystone raises; the message is the library's."
);
pyo3::create_exception!(
    drystone,
    InputError,
    DrystoneError,
    "A file, key or value drystone refused. Attributes `file`, `key`, `line` (None where the library does not name them)."
);
pyo3::create_exception!(
    drystone,
    SolverError,
    DrystoneError,
    "A run that could not finish: the engine blew up, or the layout does not stand as given."
);

/// Where an input error is: the file, the key and the 1-based line, each if known.
#[derive(Debug, Default, Clone)]
pub struct Place {
    /// The file.
    pub file: Option<String>,
    /// The key.
    pub key: Option<String>,
    /// The 1-based line.
    pub line: Option<usize>,
}

impl Place {
    /// The place of a file.
    pub fn file(path: &Path) -> Place {
        Place { file: Some(path.display().to_string()), ..Place::default() }
    }

    /// With the file.
    pub fn with_file(mut self, path: &Path) -> Place {
        self.file = Some(path.display().to_string());
        self
    }

    /// With the key.
    pub fn with_key(mut self, key: &str) -> Place {
        self.key = Some(key.to_string());
        self
    }

    /// The place with the line and the key of a TOML or JSON parser's message (`line N`,
    /// "unknown field `KEY`", "missing field `KEY`"), where it has them.
    pub fn parsed(mut self, message: &str) -> Place {
        self.line = line_of(message);
        if self.key.is_none() {
            self.key = field_of(message);
        }
        self
    }
}

/// The first `line N` of a parser's message.
fn line_of(message: &str) -> Option<usize> {
    let at = message.find("line ")?;
    message[at + 5..].split(|c: char| !c.is_ascii_digit()).next()?.parse().ok()
}

/// The field a serde message names: "unknown field `K`", "missing field `K`", "invalid
/// type ... for key `K`".
fn field_of(message: &str) -> Option<String> {
    for marker in ["unknown field `", "missing field `", "unknown variant `", "for key `"] {
        if let Some(at) = message.find(marker) {
            let rest = &message[at + marker.len()..];
            return rest.split('`').next().map(str::to_string);
        }
    }
    None
}

/// An `InputError` with its message and place.
pub fn input_error(message: impl std::fmt::Display, place: Place) -> PyErr {
    let err = InputError::new_err(message.to_string());
    Python::attach(|py| {
        let v = err.value(py);
        // Setting attributes on a fresh exception instance cannot fail but for memory.
        let _ = v.setattr("file", place.file);
        let _ = v.setattr("key", place.key);
        let _ = v.setattr("line", place.line);
    });
    err
}

/// A wall description's error: its file, and its key or line where it names them.
pub fn generator_error(e: &GeneratorError) -> PyErr {
    let place = match e {
        GeneratorError::Io { path, .. } => Place::file(path),
        GeneratorError::Parse { path, message } => Place::file(path).parsed(message),
        GeneratorError::Invalid { path, key, .. }
        | GeneratorError::UnknownDistribution { path, key, .. }
        | GeneratorError::Infeasible { path, key, .. } => Place::file(path).with_key(key),
        GeneratorError::Layout(_) => return DrystoneError::new_err(e.to_string()),
        _ => Place::default(),
    };
    input_error(e, place)
}

/// A layout's error: the file, key or block.
pub fn layout_error(e: &LayoutError) -> PyErr {
    let place = match e {
        LayoutError::Io { path, .. } => Place::file(path),
        LayoutError::Parse { path, message } => Place::file(path).parsed(message),
        LayoutError::Invalid { key, .. } => Place::default().with_key(key),
        LayoutError::Block { id, .. } | LayoutError::NotConvex { id, .. } => {
            Place::default().with_key(&format!("blocks[{id}]"))
        }
        _ => Place::default(),
    };
    input_error(e, place)
}

/// A study file's error: the file, and the key or line where the library names them.
pub fn study_error(e: &StudyError) -> PyErr {
    let place = match e {
        StudyError::Io { path, .. } => Place::file(path),
        StudyError::Parse { path, message } => Place::file(path).parsed(message),
        StudyError::Invalid { path, key, .. } | StudyError::Record { path, key, .. } => Place::file(path).with_key(key),
        StudyError::Wall { source, .. } => return generator_error(source),
        StudyError::Measured { path, source } => match source {
            TableError::Value { path, line, column, .. } => {
                Place { line: Some(*line), ..Place::file(path).with_key(column) }
            }
            TableError::Column { path, column, .. } => Place::file(path).with_key(column),
            TableError::Io { path, .. } | TableError::Polars { path, .. } => Place::file(path),
            _ => Place::file(path),
        },
        _ => Place::default(),
    };
    input_error(e, place)
}

/// A tilting-table error: bad parameters, a solver that cannot run it or a pushover load
/// that resolves to no force are input errors;
/// a blow-up or a layout that does not stand is a solver error.
pub fn tilt_error(e: &TiltError) -> PyErr {
    match e {
        TiltError::Parameter(_) | TiltError::Unsupported(_) | TiltError::Nscd(_) | TiltError::NoLoad(_) => {
            input_error(e, Place::default())
        }
        _ => SolverError::new_err(e.to_string()),
    }
}

/// A static lateral load error, as [`tilt_error`].
pub fn lateral_error(e: &LateralError) -> PyErr {
    match e {
        LateralError::Parameter(_) | LateralError::Unsupported(_) | LateralError::NoLoad(_) => {
            input_error(e, Place::default())
        }
        _ => SolverError::new_err(e.to_string()),
    }
}

/// Runs `f`, turning a panic of the library into a `DrystoneError` (a bug to report)
/// instead of letting it cross into Python.
pub fn guard<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            Err(DrystoneError::new_err(format!("internal error (a drystone bug, please report it): {what}")))
        }
    }
}
