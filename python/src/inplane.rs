//! The in-plane shear–compression test of one layout (`drystone::protocol::InPlane`), with
//! the GIL released while it runs: its function of the compiled module, `_in_plane`, which
//! `drystone.in_plane` wraps.

use crate::errors::{guard, input_error, Place};
use crate::model::{from_json, PyLayout};
use crate::protocols::{self, drystone_python_solver_error};
use drystone::protocol::run as run_protocol;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Adds the in-plane test's function to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_in_plane, m)?)?;
    Ok(())
}

/// Runs the in-plane shear–compression test; see `drystone.in_plane`. By the penalty DEM
/// (the curve) or limit analysis (`solver="limit"`: the peak force and the mechanism).
#[pyfunction]
#[pyo3(signature = (layout, solver = None, params = None))]
pub fn _in_plane<'py>(
    py: Python<'py>,
    layout: &Bound<'py, PyLayout>,
    solver: Option<&Bound<'py, PyAny>>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    use drystone::protocol::{InPlane, InPlaneRun};
    let solver = protocols::solver(py, solver)?;
    let ip: drystone::loading::inplane::InPlaneParams = protocols::params(py, params, "in-plane parameters")?;
    let l = &layout.get().layout;
    let run = py.detach(|| {
        guard(|| {
            run_protocol(&InPlane(ip), l, solver, &mut ()).map_err(|e| drystone_python_solver_error(&e.to_string()))
        })
    })?;
    py.check_signals()?;
    let out = PyDict::new(py);
    let failed = |e: &drystone::loading::inplane::InPlaneError| {
        use drystone::loading::inplane::InPlaneError as E;
        match e {
            E::Parameter(_)
            | E::ShearSpan { .. }
            | E::MeasuringPoint { .. }
            | E::NotLevel { .. }
            | E::Solver(_)
            | E::Beam(_) => input_error(e.to_string(), Place::default()),
            _ => drystone_python_solver_error(&e.to_string()),
        }
    };
    let method = run.method().name();
    match run {
        InPlaneRun::Penalty(r) | InPlaneRun::Nscd(r) => {
            let r = r.map_err(|e| failed(&e))?;
            out.set_item("method", method)?;
            out.set_item("result", from_json(py, &serde_json::to_string(&r).unwrap_or_default())?)?;
            out.set_item("top_mm", PyArray1::from_vec(py, r.curve.iter().map(|c| c.top_mm).collect()))?;
            out.set_item("drift_pct", PyArray1::from_vec(py, r.curve.iter().map(|c| c.drift_pct).collect()))?;
            out.set_item("force_kn", PyArray1::from_vec(py, r.curve.iter().map(|c| c.force_kn).collect()))?;
        }
        InPlaneRun::Limit(r) => {
            let r = r.map_err(|e| failed(&e))?;
            out.set_item("method", method)?;
            out.set_item("result", from_json(py, &serde_json::to_string(&r).unwrap_or_default())?)?;
        }
    }
    Ok(out)
}
