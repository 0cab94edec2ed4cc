//! `drystone._drystone`: the compiled part of the Python package `drystone` (PyO3, abi3
//! for CPython ≥ 3.9). The public Python API lives in `python/drystone/__init__.py`, which
//! wraps these classes and functions; the classes are the library's own types
//! (`drystone::prelude`), the results its own result types as dicts and NumPy arrays.

mod compression;
mod errors;
mod inplane;
mod model;
mod protocols;
mod study;

use pyo3::prelude::*;

/// The compiled module.
#[pymodule]
fn _drystone(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("DrystoneError", py.get_type::<errors::DrystoneError>())?;
    m.add("InputError", py.get_type::<errors::InputError>())?;
    m.add("SolverError", py.get_type::<errors::SolverError>())?;
    m.add_class::<model::PyWall>()?;
    m.add_class::<model::PyLayout>()?;
    m.add_class::<study::PyStudy>()?;
    protocols::register(m)?;
    inplane::register(m)?;
    compression::register(m)?;
    m.add_function(wrap_pyfunction!(study::_run_study, m)?)?;
    m.add_function(wrap_pyfunction!(study::_discrepancy, m)?)?;
    m.add_function(wrap_pyfunction!(study::_effects, m)?)?;
    Ok(())
}
