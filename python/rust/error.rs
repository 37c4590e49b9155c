//! The Python exceptions of contactdd and the mapping of the Rust errors onto them.
//!
//! - every [`SetupError`](contactdd_ddm::SetupError) and [`LoadError`] (a bad problem file, bad
//!   arrays, unknown names, a body that cannot be factorised) becomes `contactdd.ContactddError`, a `ValueError`, with the same message the
//!   command line prints;
//! - a solve that does not converge raises `contactdd.ConvergenceError`, a `RuntimeError`, whose
//!   `result` attribute holds the partial result (see [`convergence_error`]);
//! - a panic inside the solver (a bug) becomes a `RuntimeError` instead of reaching Python as a
//!   `PanicException`.

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::{create_exception, PyErr};

use contactdd_io::LoadError;

create_exception!(
    contactdd,
    ContactddError,
    PyValueError,
    "Bad input: a problem file, array, name or setting that contactdd cannot use.\n\n\
     The message is the one the command line prints, e.g.\n\
     ``body 'lower': supports[0]: no boundary named 'rigth' (known: bottom, left, right, top)``."
);

create_exception!(
    contactdd,
    ConvergenceError,
    PyRuntimeError,
    "The domain decomposition iteration did not converge.\n\n\
     ``result`` holds the partial :class:`contactdd.Result` (its last iterate, history and \
     message). Pass ``check=False`` to :func:`contactdd.solve` to get the result without an \
     exception."
);

/// A setup or load error as a `ContactddError`.
pub fn setup_error(e: impl Into<LoadError>) -> PyErr {
    ContactddError::new_err(e.into().to_string())
}

/// Any displayable input error as a `ContactddError`.
pub fn input_error(message: impl std::fmt::Display) -> PyErr {
    ContactddError::new_err(message.to_string())
}

/// A `ConvergenceError` with the partial result attached as `.result`.
pub fn convergence_error(py: Python<'_>, message: &str, result: Py<PyAny>) -> PyErr {
    let err = ConvergenceError::new_err(message.to_string());
    // Setting an attribute on a fresh exception instance cannot fail short of memory exhaustion;
    // if it does, raise that error instead.
    match err.value(py).setattr("result", result) {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// A panic payload (a bug in contactdd) as a `RuntimeError`.
pub fn panic_error(payload: Box<dyn std::any::Any + Send>) -> PyErr {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    PyRuntimeError::new_err(format!(
        "internal error in contactdd (please report it): {what}"
    ))
}
