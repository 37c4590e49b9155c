//! The `load-steps` and `monitor` keys of `[solver]`: the load factors of a load-step run and the
//! boundary whose mean displacement each step reports.

use contactdd_core::names::shown;
use contactdd_ddm::steps::{check_factors, equal_steps};
use contactdd_ddm::{Model, SetupError};

use crate::error::solver_error;
use crate::problem::{LoadStepsSpec, MonitorSpec};

/// The most load steps a file may ask for: each writes a set of VTU files.
pub const MAX_LOAD_STEPS: usize = 10_000;

/// A boundary of a body, by index and name (checked to exist).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Monitor {
    /// Body index.
    pub body: usize,
    /// Boundary name.
    pub boundary: String,
}

/// The load factors of `load-steps`.
pub(crate) fn load_steps(spec: &LoadStepsSpec) -> Result<Vec<f64>, SetupError> {
    let factors = match spec {
        LoadStepsSpec::Count(0) => {
            return Err(solver_error("load-steps", "must be at least 1, got 0"))
        }
        LoadStepsSpec::Count(n) if *n > MAX_LOAD_STEPS => {
            return Err(solver_error(
                "load-steps",
                format!("at most {MAX_LOAD_STEPS} steps, got {n}"),
            ))
        }
        LoadStepsSpec::Count(n) => equal_steps(*n),
        LoadStepsSpec::Factors(f) if f.len() > MAX_LOAD_STEPS => {
            return Err(solver_error(
                "load-steps",
                format!("at most {MAX_LOAD_STEPS} steps, got {}", f.len()),
            ))
        }
        LoadStepsSpec::Factors(f) => f.clone(),
    };
    check_factors(&factors).map_err(|m| solver_error("load-steps", m))?;
    Ok(factors)
}

/// The body index of a `monitor`, whose boundary must exist.
pub(crate) fn monitor(model: &Model, spec: &MonitorSpec) -> Result<Monitor, SetupError> {
    let body = model
        .bodies
        .iter()
        .position(|b| b.name == spec.body)
        .ok_or_else(|| solver_error("monitor", format!("no body named '{}'", shown(&spec.body))))?;
    model.bodies[body]
        .mesh
        .boundary(&spec.boundary)
        .map_err(|e| solver_error("monitor", format!("body '{}': {e}", shown(&spec.body))))?;
    Ok(Monitor {
        body,
        boundary: spec.boundary.clone(),
    })
}
