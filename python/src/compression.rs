//! The vertical compression test of one layout (`drystone::protocol::Compression`), with the
//! GIL released while it runs: its function of the compiled module, `_compression`, which
//! `drystone.compression` wraps.

use crate::errors::{guard, input_error, Place};
use crate::model::{from_json, PyLayout};
use crate::protocols::{self, drystone_python_solver_error};
use drystone::protocol::run as run_protocol;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Adds the compression test's function to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_compression, m)?)?;
    Ok(())
}

/// Runs the vertical compression test; see `drystone.compression`. By the penalty DEM (the
/// only method that runs it: the others' contacts are rigid).
#[pyfunction]
#[pyo3(signature = (layout, solver = None, params = None))]
pub fn _compression<'py>(
    py: Python<'py>,
    layout: &Bound<'py, PyLayout>,
    solver: Option<&Bound<'py, PyAny>>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    use drystone::loading::compression::{CompressionError as E, CompressionParams};
    use drystone::protocol::{Compression, CompressionRun};
    let solver = protocols::solver(py, solver)?;
    let p: CompressionParams = protocols::params(py, params, "compression parameters")?;
    let l = &layout.get().layout;
    let run = py.detach(|| {
        guard(|| {
            run_protocol(&Compression(p), l, solver, &mut ()).map_err(|e| drystone_python_solver_error(&e.to_string()))
        })
    })?;
    py.check_signals()?;
    let method = run.method().name();
    let CompressionRun::Penalty(r) = run;
    let r = r.map_err(|e| match e {
        E::Parameter(_) | E::Solver(_) | E::RigTerms(_) => input_error(e.to_string(), Place::default()),
        _ => drystone_python_solver_error(&e.to_string()),
    })?;
    let out = PyDict::new(py);
    out.set_item("method", method)?;
    out.set_item("result", from_json(py, &serde_json::to_string(&r).unwrap_or_default())?)?;
    out.set_item("stress_mpa", PyArray1::from_vec(py, r.curve.iter().map(|c| c.stress_mpa).collect()))?;
    out.set_item("shortening_mm", PyArray1::from_vec(py, r.curve.iter().map(|c| c.shortening_mm).collect()))?;
    out.set_item("force_kn", PyArray1::from_vec(py, r.curve.iter().map(|c| c.force_kn).collect()))?;
    Ok(out)
}
