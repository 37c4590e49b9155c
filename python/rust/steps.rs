//! The `load_steps` and `monitor` options (the `load-steps` and `monitor` keys of a `[solver]`
//! table) from Python values, checked as a problem file's are.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};

use contactdd_core::ElasticBody;
use contactdd_ddm::steps::{check_factors, equal_steps};
use contactdd_ddm::SetupError;
use contactdd_io::problem::{LoadStepsSpec, MonitorSpec};
use contactdd_io::setup::{Monitor, MAX_LOAD_STEPS};

use crate::error::setup_error;
use crate::schema::parse;

fn steps_error(message: impl std::fmt::Display) -> PyErr {
    setup_error(SetupError::Solver(format!("load_steps: {message}")))
}

fn monitor_error(message: impl std::fmt::Display) -> PyErr {
    setup_error(SetupError::Solver(format!("monitor: {message}")))
}

/// A `load_steps` value: a number N of equal steps, or the list of load factors; checked as the
/// `load-steps` key of a problem file is.
pub fn load_steps_spec(obj: &Bound<'_, PyAny>) -> PyResult<LoadStepsSpec> {
    let spec = match obj.extract::<usize>() {
        Ok(n) => LoadStepsSpec::Count(n),
        Err(_) => LoadStepsSpec::Factors(
            obj.extract::<Vec<f64>>()
                .map_err(|_| steps_error("give a number of steps or a list of load factors"))?,
        ),
    };
    factors(&spec)?;
    Ok(spec)
}

/// The load factors of a `load-steps` value: 1 to [`MAX_LOAD_STEPS`] of them, each positive and
/// finite.
pub fn factors(spec: &LoadStepsSpec) -> PyResult<Vec<f64>> {
    let factors = match spec {
        LoadStepsSpec::Count(0) => return Err(steps_error("must be at least 1, got 0")),
        LoadStepsSpec::Count(n) if *n > MAX_LOAD_STEPS => {
            return Err(steps_error(format!(
                "at most {MAX_LOAD_STEPS} steps, got {n}"
            )))
        }
        LoadStepsSpec::Count(n) => equal_steps(*n),
        LoadStepsSpec::Factors(f) if f.len() > MAX_LOAD_STEPS => {
            return Err(steps_error(format!(
                "at most {MAX_LOAD_STEPS} steps, got {}",
                f.len()
            )))
        }
        LoadStepsSpec::Factors(f) => f.clone(),
    };
    check_factors(&factors).map_err(steps_error)?;
    Ok(factors)
}

/// A `load-steps` value as Python data: the number of steps or the list of factors.
pub fn load_steps_to_py<'py>(py: Python<'py>, spec: &LoadStepsSpec) -> PyResult<Bound<'py, PyAny>> {
    Ok(match spec {
        LoadStepsSpec::Count(n) => n.into_pyobject(py)?.into_any(),
        LoadStepsSpec::Factors(f) => PyList::new(py, f)?.into_any(),
    })
}

/// A `monitor` value: ``{"body": ..., "boundary": ...}`` (the problem file's table) or a pair
/// ``(body, boundary)``.
pub fn monitor_spec(obj: &Bound<'_, PyAny>) -> PyResult<MonitorSpec> {
    let is_pair = (obj.is_instance_of::<PyTuple>() || obj.is_instance_of::<PyList>())
        && obj.len()? == 2
        && obj
            .try_iter()?
            .all(|item| item.is_ok_and(|i| i.is_instance_of::<PyString>()));
    if is_pair {
        let (body, boundary): (String, String) = obj.extract()?;
        return Ok(MonitorSpec { body, boundary });
    }
    if !obj.is_instance_of::<PyDict>() {
        return Err(monitor_error(
            "give {\"body\": name, \"boundary\": name} or a pair (body, boundary)",
        ));
    }
    parse::<MonitorSpec>(obj, "monitor")?.map_err(|m| setup_error(SetupError::Solver(m)))
}

/// A `monitor` value as Python data: the dict of the problem file's table.
pub fn monitor_to_py<'py>(py: Python<'py>, spec: &MonitorSpec) -> PyResult<Bound<'py, PyAny>> {
    let d = PyDict::new(py);
    d.set_item("body", &spec.body)?;
    d.set_item("boundary", &spec.boundary)?;
    Ok(d.into_any())
}

/// The monitored boundary among `bodies`: the body must exist and have the boundary.
pub fn monitor(bodies: &[ElasticBody], spec: &MonitorSpec) -> PyResult<Monitor> {
    let body = bodies
        .iter()
        .position(|b| b.name == spec.body)
        .ok_or_else(|| monitor_error(format!("no body named '{}'", spec.body)))?;
    bodies[body]
        .mesh
        .boundary(&spec.boundary)
        .map_err(|e| monitor_error(format!("body '{}': {e}", spec.body)))?;
    Ok(Monitor {
        body,
        boundary: spec.boundary.clone(),
    })
}
