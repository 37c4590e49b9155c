//! Running a solve from Python: on a worker thread with the GIL released and Ctrl-C checked
//! ([`run_interruptible`]), in a pool of the requested threads ([`with_threads`]), with the
//! contact geometry's warnings raised as Python warnings ([`warn_contact`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::Arc;
use std::time::Duration;

use pyo3::exceptions::{PyRuntimeError, PyUserWarning};
use pyo3::prelude::*;

use contactdd_ddm::contact::check as contact_check;
use contactdd_ddm::SetupError;

use crate::error::panic_error;

/// How often the waiting thread checks for Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a worker thread with the GIL released. The calling thread checks for signals
/// every [`SIGNAL_POLL`]; on the first one it sets the cancel flag passed to `work` and raises
/// the signal's exception at once, without waiting for `work`: a setup (assembly,
/// factorisation) that does not look at the flag goes on in the background until it ends, the
/// iteration after it stops at its first check of the flag, and the answer is dropped. A panic
/// in `work` becomes a `RuntimeError`.
pub fn run_interruptible<T, F>(py: Python<'_>, work: F) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce(&AtomicBool) -> T + Send + 'static,
{
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let (send, receive) = mpsc::channel();
    std::thread::Builder::new()
        .name("contactdd-solve".into())
        .spawn(move || {
            let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(&flag)));
            // The caller is gone after an interrupt: the answer is dropped.
            let _ = send.send(out);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start the solver thread: {e}")))?;
    let out = py.detach(move || loop {
        match receive.recv_timeout(SIGNAL_POLL) {
            Ok(out) => return Ok(out),
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "internal error in contactdd (please report it): the solver thread ended \
                     without an answer",
                ))
            }
            Err(RecvTimeoutError::Timeout) => {
                if let Err(e) = Python::attach(|py| py.check_signals()) {
                    cancel.store(true, Ordering::Relaxed);
                    return Err(e);
                }
            }
        }
    });
    match out? {
        Ok(v) => Ok(v),
        Err(payload) => Err(panic_error(payload)),
    }
}

/// Runs `f` in a rayon pool of `threads` workers (`None`: the global pool).
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> Result<T, SetupError> + Send,
) -> Result<T, SetupError> {
    match threads {
        None => f(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| {
                SetupError::Solver(format!("threads: cannot start {n} worker threads: {e}"))
            })?
            .install(f),
    }
}

/// The warnings about the contact geometry as Python `UserWarning`s (the errors among the
/// findings were raised by `prepare`).
pub fn warn_contact(py: Python<'_>, findings: &[contact_check::Finding]) -> PyResult<()> {
    let category = py.get_type::<PyUserWarning>();
    for f in findings.iter().filter(|f| !f.is_error()) {
        let message = std::ffi::CString::new(f.to_string().replace('\0', " "))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        PyErr::warn(py, &category, &message, 1)?;
    }
    Ok(())
}
