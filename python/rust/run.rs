//! Running a solve from Python: on a worker thread with the GIL released and Ctrl-C checked
//! ([`run_interruptible`]), in a pool of the requested threads ([`with_threads`]), with the
//! contact geometry's warnings raised as Python warnings ([`warn_contact`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use pyo3::exceptions::{PyRuntimeError, PyUserWarning};
use pyo3::prelude::*;

use contactdd_ddm::contact::check as contact_check;
use contactdd_ddm::SetupError;

use crate::error::panic_error;

/// How often the waiting thread checks for Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a worker thread with the GIL released. The calling thread checks for signals
/// every [`SIGNAL_POLL`]; on the first one it sets the cancel flag passed to `work` and keeps
/// waiting for `work` to return. Returns `work`'s value and the signal's exception, if any. A
/// panic in `work` becomes a `RuntimeError`.
pub fn run_interruptible<T, F>(py: Python<'_>, work: F) -> PyResult<(T, Option<PyErr>)>
where
    T: Send,
    F: FnOnce(&AtomicBool) -> T + Send,
{
    let cancel = AtomicBool::new(false);
    let done = AtomicBool::new(false);
    let (out, interrupt) = py.detach(|| {
        let caller = std::thread::current();
        std::thread::scope(|s| {
            let worker = s.spawn(|| {
                let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(&cancel)));
                done.store(true, Ordering::Release);
                caller.unpark();
                out
            });
            let mut interrupt = None;
            while !done.load(Ordering::Acquire) {
                std::thread::park_timeout(SIGNAL_POLL);
                if interrupt.is_none() && !done.load(Ordering::Acquire) {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        cancel.store(true, Ordering::Relaxed);
                        interrupt = Some(e);
                    }
                }
            }
            let out = match worker.join() {
                Ok(out) => out,
                Err(payload) => Err(payload),
            };
            (out, interrupt)
        })
    });
    match out {
        Ok(v) => Ok((v, interrupt)),
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
