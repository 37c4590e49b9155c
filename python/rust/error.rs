//! The Python exceptions of contactdd and the mapping of the Rust errors onto them, variant by
//! variant:
//!
//! - a file that cannot be read ([`LoadError::Io`], or a Gmsh mesh file named by a problem that
//!   cannot be read) becomes `contactdd.ContactddIOError`, both a `ContactddError` and an
//!   `OSError` (its `errno` is the system's, when there is one);
//! - every other [`SetupError`](contactdd_ddm::SetupError) and [`LoadError`] (a bad problem file,
//!   bad arrays, unknown names, a body that cannot be factorised) becomes
//!   `contactdd.ContactddError`, a `ValueError`; so does an argument that does not convert to
//!   its Rust type (`contactdd/_arguments.py` translates Python's `TypeError` and
//!   `OverflowError`);
//! - a solve that does not converge raises `contactdd.ConvergenceError`, both a `ContactddError`
//!   and a `RuntimeError`, whose `result` attribute holds the partial result (see
//!   [`convergence_error`]);
//! - a panic inside the solver (a bug) becomes a `RuntimeError` instead of reaching Python as a
//!   `PanicException`.
//!
//! The message is always the one the command line prints.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};
use pyo3::{create_exception, PyErr};

use contactdd_core::GmshError;
use contactdd_io::LoadError;

create_exception!(
    contactdd,
    ContactddError,
    PyValueError,
    "Bad input: a problem file, array, name or setting that contactdd cannot use.\n\n\
     The message is the one the command line prints, e.g.\n\
     ``body 'lower': supports[0]: no boundary named 'rigth' (known: bottom, left, right, top)``.\n\n\
     Also raised for an argument of the wrong type or out of range, with the argument's name \
     and its value shown compactly: ``max_iter: expected a whole number ≥ 0, got -1``."
);

const CONVERGENCE_ERROR_DOC: &str = "The domain decomposition iteration did not converge.\n\n\
     Both a :class:`ContactddError` and a ``RuntimeError``. ``result`` holds the partial \
     :class:`contactdd.Result` (its last iterate, history and message). Pass ``check=False`` to \
     :func:`contactdd.solve` to get the result without an exception.";

const IO_ERROR_DOC: &str = "A problem file or a mesh file it names cannot be read.\n\n\
     Both a :class:`ContactddError` and an ``OSError`` (``errno`` is set when the system gave \
     one); the message is the one the command line prints.";

/// `ContactddIOError(ContactddError, OSError)` and `ConvergenceError(ContactddError,
/// RuntimeError)`, created once each.
static IO_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static CONVERGENCE_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// A subclass of `ContactddError` and `other` named `name`, created once in `cell`.
/// `create_exception!` takes one base only, so the class is made by calling `type` with both.
fn two_bases<'py>(
    py: Python<'py>,
    cell: &'static PyOnceLock<Py<PyType>>,
    name: &str,
    other: Bound<'py, PyType>,
    doc: &str,
) -> PyResult<&'py Bound<'py, PyType>> {
    cell.get_or_try_init(py, || {
        let bases = PyTuple::new(py, [py.get_type::<ContactddError>(), other])?;
        let dict = PyDict::new(py);
        dict.set_item("__module__", "contactdd")?;
        dict.set_item("__doc__", doc)?;
        let class = py.get_type::<PyType>().call1((name, bases, dict))?;
        Ok(class.cast_into::<PyType>()?.unbind())
    })
    .map(|t| t.bind(py))
}

/// The `ContactddIOError` class.
pub fn io_error_type(py: Python<'_>) -> PyResult<&Bound<'_, PyType>> {
    let os = py.get_type::<PyOSError>();
    two_bases(py, &IO_ERROR, "ContactddIOError", os, IO_ERROR_DOC)
}

/// The `ConvergenceError` class.
pub fn convergence_error_type(py: Python<'_>) -> PyResult<&Bound<'_, PyType>> {
    let runtime = py.get_type::<PyRuntimeError>();
    two_bases(
        py,
        &CONVERGENCE_ERROR,
        "ConvergenceError",
        runtime,
        CONVERGENCE_ERROR_DOC,
    )
}

/// The I/O error behind `e`, if `e` is a file that cannot be read.
fn io_cause(e: &LoadError) -> Option<&std::io::Error> {
    match e {
        LoadError::Io { source, .. } => Some(source),
        LoadError::Gmsh {
            source: GmshError::Io { source, .. },
            ..
        } => Some(source),
        LoadError::InFile { error, .. } => io_cause(error),
        LoadError::Toml { .. } | LoadError::Gmsh { .. } | LoadError::Setup(_) => None,
    }
}

/// A setup or load error as its Python exception: `ContactddIOError` for a file that cannot be
/// read, `ContactddError` otherwise.
pub fn setup_error(e: impl Into<LoadError>) -> PyErr {
    let e = e.into();
    let message = e.to_string();
    match io_cause(&e) {
        None => ContactddError::new_err(message),
        Some(io) => {
            let errno = io.raw_os_error();
            Python::attach(|py| os_error(py, message, errno))
        }
    }
}

/// A `ContactddIOError` with `message` and `errno`. Only `errno` is set, not `strerror` or
/// `filename`: with those, `OSError.__str__` would replace the message by its own format.
pub fn os_error(py: Python<'_>, message: String, errno: Option<i32>) -> PyErr {
    let make = || -> PyResult<PyErr> {
        let err = PyErr::from_value(io_error_type(py)?.call1((message.as_str(),))?);
        if let Some(errno) = errno {
            err.value(py).setattr("errno", errno)?;
        }
        Ok(err)
    };
    make().unwrap_or_else(|e| e)
}

/// Any displayable input error as a `ContactddError`.
pub fn input_error(message: impl std::fmt::Display) -> PyErr {
    ContactddError::new_err(message.to_string())
}

/// A `ConvergenceError` with the partial result attached as `.result`.
pub fn convergence_error(py: Python<'_>, message: &str, result: Py<PyAny>) -> PyErr {
    let make = || -> PyResult<PyErr> {
        let err = PyErr::from_value(convergence_error_type(py)?.call1((message,))?);
        err.value(py).setattr("result", result)?;
        Ok(err)
    };
    // Creating the class or setting an attribute cannot fail short of memory exhaustion; if it
    // does, raise that error instead.
    make().unwrap_or_else(|e| e)
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

/// The error of a planar load of the file `path`: for a problem in space, the message that says
/// which reader takes it.
pub fn planar_file(e: LoadError, path: &std::path::Path) -> PyErr {
    match std::fs::read_to_string(path) {
        Ok(text) => planar_text(e, &text, &path.display().to_string()),
        Err(_) => setup_error(e),
    }
}

/// The error of a planar load of `text` (named `source`): for a problem in space
/// (`dimension = 3`), the message that says which reader takes it.
pub fn planar_text(e: LoadError, text: &str, source: &str) -> PyErr {
    if contactdd_io::solid_problem::is_solid_text(text) {
        return input_error(format!(
            "{source}: a problem in space (dimension = 3): read it with \
             contactdd.space.Problem.from_toml or from_toml_str"
        ));
    }
    setup_error(e)
}
