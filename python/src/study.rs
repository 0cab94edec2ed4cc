//! Studies from Python: `Study` (a checked study file), `_run_study` (the ensemble into a
//! run directory with its journal, as `drystone run` does, with progress and Ctrl-C), the
//! discrepancy analysis and the effect library.
//!
//! A run happens on a thread of its own with the GIL released; the calling thread waits
//! for rows, hands each to the progress callback and checks for signals between them. On
//! Ctrl-C (or an exception of the callback) it asks the run to stop
//! (`run_into_observed` returning false): no further realization starts, those running
//! finish and are journaled, and the exception is raised; `resume=True` continues.

use crate::errors::{guard, input_error, study_error, DrystoneError, Place, SolverError};
use crate::model::{from_json, to_json};
use drystone::discrepancy::{DiscrepancyError, Settings};
use drystone::effects::Library;
use drystone::ensemble::row::RealizationRow;
use drystone::ensemble::Shard;
use drystone::io::table::realizations_frame;
use drystone::study::discrepancy::{analyse, input_of, write_analysis, AnalysisError};
use drystone::study::Study;
use drystone::study::{run_into_observed, HeldDir, OutputError, RunMode, StudyRun};
use numpy::PyArray1;
use polars::prelude::{Column, DataType};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// How often the waiting thread looks for Ctrl-C while no row arrives.
const SIGNAL_POLL: Duration = Duration::from_millis(100);

/// Reads a study and applies `realizations` as `drystone run --realizations` does.
fn load(path: &Path, realizations: Option<u64>) -> PyResult<Study> {
    let mut st = Study::from_file(path).map_err(|e| study_error(&e))?;
    if let Some(n) = realizations {
        let place = Place::file(path).with_key("realizations");
        if n == 0 {
            return Err(input_error("realizations must be at least 1", place));
        }
        st.realizations = n;
        if let Err(reason) = st.check_items() {
            return Err(input_error(format!("realizations {n}: {}: {reason}", path.display()), place));
        }
    }
    Ok(st)
}

/// A rayon pool of `threads` workers (None or 0: one per core).
fn pool(threads: Option<usize>) -> PyResult<rayon::ThreadPool> {
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let n = threads.filter(|n| *n > 0).unwrap_or(cores);
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map_err(|e| DrystoneError::new_err(format!("cannot start {n} threads: {e}")))
}

/// A checked study file: groups of walls, realizations, seed, protocol, sweep, measured
/// data.
#[pyclass(module = "drystone", name = "Study", frozen)]
pub struct PyStudy {
    study: Study,
}

#[pymethods]
impl PyStudy {
    /// Reads and checks a study file (TOML), with `realizations` per group and sweep point
    /// instead of the file's if given.
    #[staticmethod]
    #[pyo3(signature = (path, realizations = None))]
    fn from_toml(py: Python<'_>, path: PathBuf, realizations: Option<u64>) -> PyResult<PyStudy> {
        py.detach(|| guard(|| load(&path, realizations).map(|study| PyStudy { study })))
    }

    /// The study's name (the default output directory is `out/<name>`).
    #[getter]
    fn name(&self) -> String {
        self.study.name.clone()
    }

    /// The study file.
    #[getter]
    fn path(&self) -> PathBuf {
        self.study.path.clone()
    }

    /// The master seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.study.seed
    }

    /// Realizations per group and sweep point.
    #[getter]
    fn realizations(&self) -> u64 {
        self.study.realizations
    }

    /// The protocol: `tilt`, `lateral` or `shake`.
    #[getter]
    fn protocol(&self) -> String {
        self.study.protocol.name().to_string()
    }

    /// Group names, in file order.
    #[getter]
    fn groups(&self) -> Vec<String> {
        self.study.groups.iter().map(|g| g.name.clone()).collect()
    }

    /// Sweep point labels (one empty label without a sweep).
    #[getter]
    fn points(&self) -> Vec<String> {
        self.study.points.iter().map(|p| drystone::study::point_label(p)).collect()
    }

    /// Work items (realizations of every group at every sweep point).
    #[getter]
    fn items(&self) -> usize {
        self.study.items().len()
    }

    /// The study's discrepancy settings (its `[discrepancy]` table with the defaults).
    #[getter]
    fn discrepancy_settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        from_json(py, &serde_json::to_string(&self.study.discrepancy).unwrap_or_default())
    }

    fn __repr__(&self) -> String {
        let s = &self.study;
        format!(
            "Study(name={:?}, seed={}, realizations={}, groups={:?}, items={})",
            s.name,
            s.seed,
            s.realizations,
            s.groups.iter().map(|g| g.name.as_str()).collect::<Vec<_>>(),
            s.items().len()
        )
    }
}

/// What the progress callback gets of a finished row.
struct Note {
    index: u64,
    group: String,
    realization: u64,
    status: String,
    collapse_angle_deg: Option<f64>,
}

impl Note {
    fn of(r: &RealizationRow) -> Note {
        Note {
            index: r.index,
            group: r.group.clone(),
            realization: r.realization,
            status: r.status.as_str().to_string(),
            collapse_angle_deg: r.collapse.collapse_angle_deg,
        }
    }

    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("index", self.index)?;
        d.set_item("group", &self.group)?;
        d.set_item("realization", self.realization)?;
        d.set_item("status", &self.status)?;
        d.set_item("collapse_angle_deg", self.collapse_angle_deg)?;
        Ok(d)
    }
}

/// Runs a study into its run directory; see `drystone.run_study`.
#[pyfunction]
#[pyo3(signature = (study, realizations = None, out = None, threads = None, shard = None, resume = false, force = false, progress = None))]
#[allow(clippy::too_many_arguments)]
pub fn _run_study<'py>(
    py: Python<'py>,
    study: PathBuf,
    realizations: Option<u64>,
    out: Option<PathBuf>,
    threads: Option<usize>,
    shard: Option<String>,
    resume: bool,
    force: bool,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let st = py.detach(|| guard(|| load(&study, realizations)))?;
    let shard = match shard {
        None => Shard::ALL,
        Some(s) => Shard::parse(&s).map_err(|e| input_error(e, Place::default().with_key("shard")))?,
    };
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&st.name));
    let pool = pool(threads)?;
    let total = shard.select(&st.items()).len();
    let mode = RunMode { resume, force };
    let cancel = AtomicBool::new(false);
    let (tx, mut rx) = mpsc::channel::<Note>();
    let (joined, stop) = std::thread::scope(|s| {
        let (st, study, dir, cancel, pool) = (&st, &study, &dir, &cancel, &pool);
        let worker = s.spawn(move || {
            let tx = tx;
            let observe = |row: &RealizationRow| {
                let _ = tx.send(Note::of(row));
                !cancel.load(Ordering::SeqCst)
            };
            let run = || run_into_observed(st, study, shard, dir, mode, &observe);
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| pool.install(run)))
        });
        let mut stop: Option<PyErr> = None;
        let mut done = 0usize;
        loop {
            let (back, msg) = py.detach(move || {
                let m = rx.recv_timeout(SIGNAL_POLL);
                (rx, m)
            });
            rx = back;
            match msg {
                Ok(note) => {
                    done += 1;
                    if let (None, Some(cb)) = (&stop, &progress) {
                        if let Err(e) = note.to_dict(py).and_then(|d| cb.call1((done, total, d))) {
                            cancel.store(true, Ordering::SeqCst);
                            stop = Some(e);
                        }
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            if stop.is_none() {
                if let Err(e) = py.check_signals() {
                    cancel.store(true, Ordering::SeqCst);
                    stop = Some(e);
                }
            }
        }
        (py.detach(|| worker.join()), stop)
    });
    if let Some(e) = stop {
        return Err(e);
    }
    let run = match joined {
        Ok(Ok(r)) => r,
        Ok(Err(panic)) | Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            return Err(DrystoneError::new_err(format!("internal error (a drystone bug, please report it): {what}")));
        }
    };
    let run = run.map_err(|e| output_error(&e))?;
    outcome(py, &st, &dir, shard, run)
}

/// An error of the run directory: a refused journal or file names its file.
fn output_error(e: &OutputError) -> PyErr {
    match e {
        OutputError::File { path, .. } => input_error(e, Place::file(path)),
        _ => DrystoneError::new_err(e.to_string()),
    }
}

/// The dict the Python side turns into a `StudyResult`.
fn outcome<'py>(py: Python<'py>, st: &Study, dir: &Path, shard: Shard, run: StudyRun) -> PyResult<Bound<'py, PyDict>> {
    let frame = realizations_frame(&run.rows, true).map_err(|e| DrystoneError::new_err(e.to_string()))?;
    let names = PyList::empty(py);
    let dtypes = PyList::empty(py);
    let columns = PyDict::new(py);
    for c in frame.columns() {
        let (dtype, values) = column(py, c)?;
        names.append(c.name().as_str())?;
        dtypes.append(dtype)?;
        columns.set_item(c.name().as_str(), values)?;
    }
    let d = PyDict::new(py);
    d.set_item("names", names)?;
    d.set_item("dtypes", dtypes)?;
    d.set_item("columns", columns)?;
    d.set_item("out", dir)?;
    d.set_item("text", run.text)?;
    d.set_item("resumed", run.resumed)?;
    d.set_item("complete", shard.n == 1)?;
    d.set_item("name", &st.name)?;
    d.set_item("seed", st.seed)?;
    d.set_item("realizations", st.realizations)?;
    Ok(d)
}

/// A column of the realizations frame as (dtype name, values): u64 as a NumPy array,
/// optional numbers and text as lists (None for a missing value), series as lists of
/// float lists.
fn column<'py>(py: Python<'py>, c: &Column) -> PyResult<(&'static str, Bound<'py, PyAny>)> {
    let bad = |e: polars::error::PolarsError| DrystoneError::new_err(format!("column {}: {e}", c.name()));
    let s = c.as_materialized_series();
    Ok(match s.dtype() {
        DataType::UInt64 => {
            let ca = s.u64().map_err(bad)?;
            if ca.null_count() == 0 {
                ("u64", PyArray1::from_vec(py, ca.into_no_null_iter().collect()).into_any())
            } else {
                ("u64", ca.iter().collect::<Vec<Option<u64>>>().into_pyobject(py)?.into_any())
            }
        }
        DataType::Float64 => {
            let ca = s.f64().map_err(bad)?;
            ("f64", ca.iter().collect::<Vec<Option<f64>>>().into_pyobject(py)?.into_any())
        }
        DataType::String => {
            let ca = s.str().map_err(bad)?;
            let v: Vec<Option<String>> = ca.iter().map(|v| v.map(str::to_string)).collect();
            ("str", v.into_pyobject(py)?.into_any())
        }
        DataType::List(_) => {
            let ca = s.list().map_err(bad)?;
            let mut v: Vec<Vec<f64>> = Vec::with_capacity(ca.len());
            for i in 0..ca.len() {
                let inner = match ca.get_as_series(i) {
                    Some(x) => x.f64().map_err(bad)?.iter().map(|v| v.unwrap_or(f64::NAN)).collect(),
                    None => vec![],
                };
                v.push(inner);
            }
            ("list[f64]", v.into_pyobject(py)?.into_any())
        }
        other => return Err(DrystoneError::new_err(format!("column {}: unexpected type {other}", c.name()))),
    })
}

/// The discrepancy analysis of a study; see `drystone.discrepancy`.
#[pyfunction]
#[pyo3(signature = (study, settings = None, realizations = None, out = None, threads = None))]
pub fn _discrepancy<'py>(
    py: Python<'py>,
    study: PathBuf,
    settings: Option<&Bound<'py, PyDict>>,
    realizations: Option<u64>,
    out: Option<PathBuf>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    let st = py.detach(|| guard(|| Study::from_file(&study).map_err(|e| study_error(&e))))?;
    let mut s = st.discrepancy.clone();
    if let Some(d) = settings {
        s = overlay(py, &s, d)?;
    }
    if let Some(n) = realizations {
        if n == 0 {
            return Err(input_error("realizations must be at least 1", Place::default().with_key("realizations")));
        }
        s.realizations = n;
        s.extension_realizations = s.extension_realizations.max(n + 3);
    }
    let place = Place::file(&study).with_key("discrepancy");
    s.validate().map_err(|e| input_error(format!("{}: {e}", study.display()), place.clone()))?;
    // Its groups and observations the way its protocol declares, as `drystone discrepancy`
    // reads them (`study::discrepancy::input_of`).
    let input = input_of(&st, s).map_err(|e| input_failure(e, &place))?;
    // The output directory is held from before the analysis to the end, as by
    // `drystone discrepancy`: a second command on it is refused.
    let held = match &out {
        Some(dir) => Some(py.detach(|| {
            guard(|| {
                std::fs::create_dir_all(dir).map_err(|e| DrystoneError::new_err(format!("{}: {e}", dir.display())))?;
                HeldDir::acquire(dir).map_err(|e| DrystoneError::new_err(e.to_string()))
            })
        })?),
        None => None,
    };
    let pool = pool(threads)?;
    let done = py.detach(|| {
        guard(|| {
            pool.install(|| analyse(&st, input, &drystone::discrepancy::quiet)).map_err(|e| analysis_failure(e, &place))
        })
    })?;
    py.check_signals()?;
    if let Some(held) = &held {
        py.detach(|| {
            guard(|| write_analysis(held, &st, &done).map(|_| ()).map_err(|e| DrystoneError::new_err(e.to_string())))
        })?;
    }
    from_json(py, &done.json().to_string())
}

/// The error of reading a study into its analysis: the study file's key at fault where the
/// error names one ([`AnalysisError::file_key`]), else at `place` (the study's
/// `[discrepancy]`; measured rows name their file and line in the message).
fn input_failure(e: AnalysisError, place: &Place) -> PyErr {
    let place = e.file_key().map_or_else(|| place.clone(), |(path, key)| Place::file(path).with_key(key));
    input_error(&e, place)
}

/// The error of an analysis run: the analysis's own ([`discrepancy_error`]), or its held
/// reading's study refused ([`input_failure`]).
fn analysis_failure(e: AnalysisError, place: &Place) -> PyErr {
    match e {
        AnalysisError::Analysis(e) => discrepancy_error(e),
        other => input_failure(other, place),
    }
}

/// The settings with the keys of `d` put over them (unknown keys refused, naming the key).
fn overlay(py: Python<'_>, s: &Settings, d: &Bound<'_, PyDict>) -> PyResult<Settings> {
    let given: serde_json::Value = serde_json::from_str(&to_json(py, d.as_any())?)
        .map_err(|e| input_error(format!("discrepancy settings: {e}"), Place::default()))?;
    let mut v = serde_json::to_value(s).map_err(|e| DrystoneError::new_err(e.to_string()))?;
    if let (Some(base), Some(add)) = (v.as_object_mut(), given.as_object()) {
        for (k, x) in add {
            base.insert(k.clone(), x.clone());
        }
    }
    serde_json::from_value(v).map_err(|e| {
        let m = e.to_string();
        input_error(format!("discrepancy settings: {m}"), Place::default().parsed(&m))
    })
}

/// Bad measured data or effects are input errors; the rest, a run that could not finish.
fn discrepancy_error(e: DiscrepancyError) -> PyErr {
    match e {
        DiscrepancyError::Observations { .. } | DiscrepancyError::Effect(_) => input_error(&e, Place::default()),
        other => SolverError::new_err(other.to_string()),
    }
}

/// The effect library (the built-ins, and a study's effect files when `study` is given):
/// one dict per effect, with its parameters.
#[pyfunction]
#[pyo3(signature = (study = None))]
pub fn _effects<'py>(py: Python<'py>, study: Option<PathBuf>) -> PyResult<Bound<'py, PyAny>> {
    let library = match study {
        Some(p) => Study::from_file(&p).map_err(|e| study_error(&e))?.library,
        None => Library::builtin(),
    };
    let defs: Vec<serde_json::Value> = library
        .all()
        .iter()
        .map(|d| {
            let mut v = serde_json::to_value(&**d).unwrap_or_default();
            let mut stages: Vec<_> = d.steps.iter().map(|s| s.stage()).collect();
            stages.sort();
            stages.dedup();
            if let Some(o) = v.as_object_mut() {
                o.insert("stages".into(), serde_json::to_value(stages).unwrap_or_default());
            }
            v
        })
        .collect();
    from_json(py, &serde_json::Value::Array(defs).to_string())
}
