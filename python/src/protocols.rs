//! The tilting-table and static lateral load tests of one layout
//! (`drystone::prelude::{run_tilt, run_lateral}`), with the GIL released while they run.
//! Each returns a dict: the library's result as its JSON form (`"result"`) beside the
//! monitor histories as NumPy arrays; the Python side wraps it in a result class.

use crate::errors::{guard, input_error, lateral_error, tilt_error, Place};
use crate::model::{from_json, to_json, PyLayout};
use drystone::loading::lateral::LateralError;
use drystone::loading::tilt::TiltError;
use drystone::loading::tilt_hand::HandTilt;
use drystone::prelude::{run_tilt, LateralParams, SolverParams, TiltParams};
use drystone::protocol::{run as run_protocol, Lateral, LateralRun, Pushover, PushoverRun, Tilt, TiltRun};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::de::DeserializeOwned;

/// Adds the loading protocols' functions to the module: one per protocol, and
/// `_supports` (which method runs which protocol).
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_tilt, m)?)?;
    m.add_function(wrap_pyfunction!(_lateral, m)?)?;
    m.add_function(wrap_pyfunction!(_pushover, m)?)?;
    m.add_function(wrap_pyfunction!(_supports, m)?)?;
    Ok(())
}

/// A parameter struct of the library from a Python dict (its serde keys, unknown keys
/// refused); `what` names it in errors (`tilt parameters`, `solver`).
pub fn params<T: DeserializeOwned + Default>(
    py: Python<'_>,
    obj: Option<&Bound<'_, PyDict>>,
    what: &str,
) -> PyResult<T> {
    let Some(obj) = obj else { return Ok(T::default()) };
    let text = to_json(py, obj.as_any())?;
    serde_json::from_str(&text).map_err(|e| {
        let m = e.to_string();
        let mut place = Place::default().parsed(&m);
        place.line = None;
        let m = m.split(" at line ").next().unwrap_or(&m).to_string();
        input_error(format!("{what}: {m}"), place)
    })
}

/// A Python `DeprecationWarning` for each penalty setting given under a protocol's former
/// key (`drystone::dem::MovedKey`: `tolerance=` of `drystone.tilt` is now the `penalty`
/// dict of the solver); the library still applies it.
fn warn_moved(py: Python<'_>, moved: &[drystone::dem::MovedKey], table: &str) -> PyResult<()> {
    for m in moved {
        let text = std::ffi::CString::new(m.warning(table)).unwrap_or_default();
        PyErr::warn(py, &py.get_type::<pyo3::exceptions::PyDeprecationWarning>(), &text, 2)?;
    }
    Ok(())
}

/// The solver of a `solver` argument: None (the default penalty solver), a kind name
/// (`"nscd"`) or a dict of `SolverParams` keys.
pub fn solver(py: Python<'_>, obj: Option<&Bound<'_, PyAny>>) -> PyResult<SolverParams> {
    match obj {
        None => Ok(SolverParams::default()),
        Some(o) if o.is_none() => Ok(SolverParams::default()),
        Some(o) => {
            if let Ok(kind) = o.extract::<String>() {
                let d = PyDict::new(py);
                d.set_item("kind", kind)?;
                params(py, Some(&d), "solver")
            } else {
                let d = o.cast::<PyDict>().map_err(|_| {
                    input_error("solver: expected None, a solver name or a dict of solver parameters", Place::default())
                })?;
                params(py, Some(d), "solver")
            }
        }
    }
}

/// Runs the tilting-table test; see `drystone.tilt`. `by_hand`: a dict of `HandTilt`
/// keys (the table rolled by hand: `TiltParams::by_hand`, the nscd solver only).
#[pyfunction]
#[pyo3(signature = (layout, solver = None, params = None, by_hand = None))]
pub fn _tilt<'py>(
    py: Python<'py>,
    layout: &Bound<'py, PyLayout>,
    solver: Option<&Bound<'py, PyAny>>,
    params: Option<&Bound<'py, PyDict>>,
    by_hand: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let solver = self::solver(py, solver)?;
    let mut tp: TiltParams = self::params(py, params, "tilt parameters")?;
    warn_moved(py, &tp.moved(), "tilt")?;
    for w in tp.cascade_warnings("tilt") {
        let text = std::ffi::CString::new(w).unwrap_or_default();
        PyErr::warn(py, &py.get_type::<pyo3::exceptions::PyDeprecationWarning>(), &text, 2)?;
    }
    if let Some(d) = by_hand {
        tp.by_hand = Some(self::params::<HandTilt>(py, Some(d), "by_hand")?);
    }
    let l = &layout.get().layout;
    // The one choice of a method: the protocol seam (`drystone::protocol::run`), which runs
    // every method `drystone.supports("tilt", ...)` admits and refuses the others by the
    // same check; the table rolled by hand is its own protocol (`run_tilt` chooses it from
    // `by_hand`), run by nscd, the one method it admits.
    let run = py.detach(|| {
        guard(|| {
            Ok(match tp.by_hand {
                Some(_) => run_tilt(l, solver, &tp).map(|r| TiltRun::Nscd(Ok(r))),
                None => run_protocol(&Tilt(tp), l, solver, &mut ()).map_err(|e| TiltError::Unsupported(e.to_string())),
            })
        })
    })?;
    py.check_signals()?;
    let r = match run.map_err(|e| tilt_error(&e))? {
        TiltRun::Penalty(r) | TiltRun::Nscd(r) => r.map_err(|e| tilt_error(&e))?,
        TiltRun::Limit(r) => {
            let r = r.map_err(|e| crate::errors::SolverError::new_err(e.to_string()))?;
            return limit_tilt(py, &r);
        }
    };
    let out = PyDict::new(py);
    out.set_item("result", from_json(py, &serde_json::to_string(&r).unwrap_or_default())?)?;
    out.set_item("collapse_angle_deg", r.collapse_angle_deg())?;
    let m = r.monitors.len();
    out.set_item("alpha_deg", PyArray1::from_vec(py, r.increments.iter().map(|i| i.alpha_deg).collect()))?;
    out.set_item("stable", PyArray1::from_vec(py, r.increments.iter().map(|i| i.stable).collect()))?;
    out.set_item("increment_steps", PyArray1::from_vec(py, r.increments.iter().map(|i| i.steps).collect()))?;
    out.set_item(
        "unbalanced_ratio",
        PyArray1::from_vec(py, r.increments.iter().map(|i| i.unbalanced_ratio).collect()),
    )?;
    let rows: Vec<&[f64]> = r.increments.iter().map(|i| i.displacement_m.as_slice()).collect();
    out.set_item("displacement_m", matrix(&rows, m).into_pyarray(py))?;
    Ok(out)
}

/// The tilting table by limit analysis, in the keys of the path's result (`drystone.tilt`
/// with `solver="limit"`): the last stable and first unstable tilts both α_max = atan λ
/// (a bracket of zero width, reason `no_equilibrium`: no statically admissible state
/// exists above it, as a study's row has it), the mechanism from the dual, the interior-point
/// iterations; no increments, no monitors; `limit_analysis`: the whole analysis.
fn limit_tilt<'py>(py: Python<'py>, r: &drystone::limit::LimitResult) -> PyResult<Bound<'py, PyDict>> {
    let alpha = r.collapse_angle_deg.unwrap_or(f64::NAN);
    let v = serde_json::json!({
        "last_stable_deg": alpha, "first_unstable_deg": alpha,
        "collapse_reason": drystone::loading::tilt::CollapseReason::NoEquilibrium.name(),
        "bracket_reliable": true, "mechanism": r.mechanism, "monitors": [], "increments": [],
        "steps": 0, "iterations": r.solver_iterations, "dt_s": 0.0, "wall_time_s": r.wall_time_s,
        "limit_analysis": r,
    });
    let out = PyDict::new(py);
    out.set_item("result", from_json(py, &v.to_string())?)?;
    out.set_item("collapse_angle_deg", alpha)?;
    out.set_item("alpha_deg", PyArray1::<f64>::from_vec(py, vec![]))?;
    out.set_item("stable", PyArray1::<bool>::from_vec(py, vec![]))?;
    out.set_item("increment_steps", PyArray1::<u64>::from_vec(py, vec![]))?;
    out.set_item("unbalanced_ratio", PyArray1::<f64>::from_vec(py, vec![]))?;
    out.set_item("displacement_m", Array2::<f64>::zeros((0, 0)).into_pyarray(py))?;
    Ok(out)
}

/// Runs the static lateral load; see `drystone.lateral`.
#[pyfunction]
#[pyo3(signature = (layout, solver = None, params = None))]
pub fn _lateral<'py>(
    py: Python<'py>,
    layout: &Bound<'py, PyLayout>,
    solver: Option<&Bound<'py, PyAny>>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let solver = self::solver(py, solver)?;
    let lp: LateralParams = self::params(py, params, "lateral parameters")?;
    warn_moved(py, &lp.moved(), "lateral")?;
    if lp.pushover {
        let place = Place { key: Some("pushover".into()), ..Place::default() };
        return Err(input_error("pushover: drystone.lateral is the service test; use drystone.pushover", place));
    }
    let l = &layout.get().layout;
    // The one choice of a method: the protocol seam, which runs every method
    // `drystone.supports("lateral", ...)` admits and refuses the others by the same check.
    let run = py.detach(|| {
        guard(|| {
            Ok(run_protocol(&Lateral(lp), l, solver, &mut ()).map_err(|e| LateralError::Unsupported(e.to_string())))
        })
    })?;
    py.check_signals()?;
    let r = match run.map_err(|e| lateral_error(&e))? {
        LateralRun::Penalty(r) => r.map_err(|e| lateral_error(&e))?,
        LateralRun::Limit(r) => {
            let r = r.map_err(|e| crate::errors::SolverError::new_err(e.to_string()))?;
            return limit_lateral(py, &r);
        }
    };
    let out = PyDict::new(py);
    out.set_item("result", from_json(py, &serde_json::to_string(&r).unwrap_or_default())?)?;
    out.set_item("displacement_m", PyArray1::from_vec(py, r.displacement_m.clone()))?;
    out.set_item("resultant_n", PyArray1::from_vec(py, vec![r.resultant_n.x, r.resultant_n.y, r.resultant_n.z]))?;
    Ok(out)
}

/// The static lateral load by limit analysis, in the keys of the penalty DEM's result
/// (`drystone.lateral` with `solver="limit"`): whether the wall carries the pressure
/// (λ ≥ 1, as a study's row has it; else reason `no_equilibrium`), the pressure's resultant
/// and the weight; rigid blocks have no displacements (`None`), no monitors;
/// `limit_analysis`: the whole analysis (λ, the mechanism).
fn limit_lateral<'py>(py: Python<'py>, r: &drystone::limit::LimitResult) -> PyResult<Bound<'py, PyDict>> {
    let carries = r.load_multiplier >= 1.0;
    let v = serde_json::json!({
        "equilibrium": carries,
        "collapse_reason": (!carries).then_some(drystone::loading::tilt::CollapseReason::NoEquilibrium.name()),
        "monitors": [], "displacement_m": [], "max_displacement_m": null, "drift": null,
        "height_m": null, "width_m": null, "resultant_n": r.live_load_n, "weight_n": r.weight_n,
        "steps": 0, "dt_s": 0.0, "wall_time_s": r.wall_time_s, "limit_analysis": r,
    });
    let out = PyDict::new(py);
    out.set_item("result", from_json(py, &v.to_string())?)?;
    out.set_item("displacement_m", PyArray1::<f64>::from_vec(py, vec![]))?;
    let f = r.live_load_n;
    out.set_item("resultant_n", PyArray1::from_vec(py, vec![f.x, f.y, f.z]))?;
    Ok(out)
}

/// The limit analysis of the lateral pressure, in the keys of the penalty pushover's
/// result ([`rigid_pushover`]): λ stable and first unstable both λ.
fn limit_pushover(r: drystone::limit::LimitResult) -> serde_json::Value {
    serde_json::json!({
        "lambda_stable": r.load_multiplier, "lambda_unstable": r.load_multiplier,
        "mechanism": r.mechanism, "weight_n": r.weight_n, "steps": 0,
        "wall_time_s": r.wall_time_s, "limit_analysis": r,
    })
}

/// The rigid pushover (nscd) or the limit analysis of the lateral pressure (`result`, from
/// the rigid pushover with its step, or [`limit_pushover`]), in the keys of the penalty pushover's result:
/// λ stable and first unstable (limit analysis: both λ), the mechanism, the weight and the
/// work; no increments, no monitors.
fn rigid_pushover(py: Python<'_>, result: serde_json::Value) -> PyResult<Bound<'_, PyDict>> {
    let mut v = result;
    v["collapse_reason"] = serde_json::Value::Null;
    v["monitors"] = serde_json::json!([]);
    if v.get("dt_s").is_none() {
        v["dt_s"] = 0.0.into();
    }
    let out = PyDict::new(py);
    out.set_item("result", from_json(py, &v.to_string())?)?;
    out.set_item("load_multiplier", PyArray1::<f64>::from_vec(py, vec![]))?;
    out.set_item("stable", PyArray1::<bool>::from_vec(py, vec![]))?;
    out.set_item("displacement_m", Array2::<f64>::zeros((0, 0)).into_pyarray(py))?;
    Ok(out)
}

/// Runs the pushover of the lateral pressure by the solver's method (the penalty DEM's
/// increments, the rigid pushover of nscd, or limit analysis); see `drystone.pushover`.
#[pyfunction]
#[pyo3(signature = (layout, solver = None, params = None))]
pub fn _pushover<'py>(
    py: Python<'py>,
    layout: &Bound<'py, PyLayout>,
    solver: Option<&Bound<'py, PyAny>>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let solver = self::solver(py, solver)?;
    let lp: LateralParams = self::params(py, params, "lateral parameters")?;
    warn_moved(py, &lp.moved(), "lateral")?;
    let l = &layout.get().layout;
    // The one choice of a method: the protocol seam (`drystone::protocol::run`).
    let run = py.detach(|| {
        guard(|| run_protocol(&Pushover(lp), l, solver, &mut ()).map_err(|e| input_error(e, Place::default())))
    })?;
    let r = match run {
        PushoverRun::Penalty { service, collapse } => {
            service.map_err(|e| lateral_error(&e))?;
            match collapse {
                Some(c) => c.0.map_err(|e| lateral_error(&e))?,
                None => return Err(crate::errors::DrystoneError::new_err("the pushover did not run")),
            }
        }
        PushoverRun::Nscd(r) => {
            let mut v = serde_json::to_value(r.map_err(|e| tilt_error(&e))?).unwrap_or_default();
            v["dt_s"] = solver.nscd.dt_s.into();
            return rigid_pushover(py, v);
        }
        PushoverRun::Limit(r) => {
            let r = r.map_err(|e| crate::errors::SolverError::new_err(e.to_string()))?;
            return rigid_pushover(py, limit_pushover(r));
        }
    };
    py.check_signals()?;
    let out = PyDict::new(py);
    out.set_item("result", from_json(py, &serde_json::to_string(&r).unwrap_or_default())?)?;
    let m = r.monitors.len();
    out.set_item("load_multiplier", PyArray1::from_vec(py, r.increments.iter().map(|i| i.load_multiplier).collect()))?;
    out.set_item("stable", PyArray1::from_vec(py, r.increments.iter().map(|i| i.stable).collect()))?;
    let rows: Vec<&[f64]> = r.increments.iter().map(|i| i.displacement_m.as_slice()).collect();
    out.set_item("displacement_m", matrix(&rows, m).into_pyarray(py))?;
    Ok(out)
}

/// The (n, m) matrix of `rows` (n rows of m values; a missing value is NaN).
fn matrix(rows: &[&[f64]], m: usize) -> Array2<f64> {
    let flat: Vec<f64> =
        rows.iter().flat_map(|row| (0..m).map(move |k| row.get(k).copied().unwrap_or(f64::NAN))).collect();
    Array2::from_shape_vec((rows.len(), m), flat).unwrap_or_else(|_| Array2::zeros((0, m)))
}

/// Whether the solver kind `solver` runs the protocol `protocol` (`tilt`, `tilt_by_hand`,
/// `lateral`, `pushover`, `shake`), by the library's one compatibility table
/// (`protocol::check`); see `drystone.supports`. Returns `(runs, reason)`: the
/// reason a refusal gives, empty when it runs.
///
/// # Errors
/// `InputError` for an unknown protocol or solver name.
#[pyfunction]
pub fn _supports(protocol: &str, solver: &str) -> PyResult<(bool, String)> {
    use drystone::protocol::{check, Loading};
    let names: Vec<&str> = Loading::ALL.iter().map(|l| l.name()).collect();
    let p = Loading::from_name(protocol).ok_or_else(|| {
        input_error(format!("unknown protocol {protocol:?} (one of {})", names.join(", ")), Place::default())
    })?;
    let k: drystone::dem::SolverKind = solver.parse().map_err(|e: String| input_error(e, Place::default()))?;
    Ok(match check(p, k) {
        Ok(()) => (true, String::new()),
        Err(e) => (false, e.to_string()),
    })
}

/// A solver's refusal or a failed run, as `drystone.SolverError`.
pub fn drystone_python_solver_error(message: &str) -> PyErr {
    crate::errors::SolverError::new_err(message.to_string())
}
