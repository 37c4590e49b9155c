//! # contactdd-python
//!
//! The `contactdd._contactdd` extension module: a thin pyo3 layer over `contactdd-core` and
//! `contactdd-ddm`. It converts numpy arrays and dicts into the Rust types and back and runs the
//! solves with the GIL released; all numerics live in the Rust crates.
//!
//! Solves run on a worker thread while the calling thread, detached from the interpreter, wakes
//! every 50 ms to check for signals: Ctrl-C sets the solver's cancel flag, the iteration stops at
//! the next iteration boundary and `KeyboardInterrupt` is raised.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use pyo3::exceptions::{PyRuntimeError, PyUserWarning};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use contactdd_core::Order;
use contactdd_ddm::contact::check as contact_check;
use contactdd_ddm::contact::Interface;
use contactdd_ddm::gamma_study::{SweepHooks, SweepRun};
use contactdd_ddm::{Gamma, Hooks, Method, Record, SetupError};
use contactdd_io::setup::MAX_RECTANGLE_CELLS;

mod benchmark;
mod convert;
mod error;
mod options;
mod problem;
mod results;
mod schema;
mod state;

use error::{
    convergence_error, convergence_error_type, io_error_type, panic_error, setup_error,
    ContactddError,
};
use options::{gamma, gamma_to_py, GammaArg, SolverOptions};
use problem::Problem;
use results::{Body, Contact, MonolithicResult, SolveResult};

/// How often the waiting thread checks for Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// The methods a sweep runs by default: the three of the paper's γ study.
const SWEEP_METHODS: [Method; 3] = [
    Method::ActiveSet,
    Method::NewtonChord,
    Method::NewtonKurchatov,
];

/// Runs `work` on a worker thread with the GIL released. The calling thread checks for signals
/// every [`SIGNAL_POLL`]; on the first one it sets the cancel flag passed to `work` and keeps
/// waiting for `work` to return. Returns `work`'s value and the signal's exception, if any. A
/// panic in `work` becomes a `RuntimeError`.
fn run_interruptible<T, F>(py: Python<'_>, work: F) -> PyResult<(T, Option<PyErr>)>
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
fn with_threads<T: Send>(
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

/// Solves a contact problem by the penalty Robin domain decomposition.
///
/// Settings left at ``None`` take the problem's (its ``[solver]`` table, or
/// :meth:`Problem.solver`). The solve releases the GIL and can be interrupted with Ctrl-C
/// (``KeyboardInterrupt``).
///
/// Args:
///     problem: the :class:`Problem`.
///     method: ``"neumann"``, ``"robin"``, ``"active-set"``, ``"newton-chord"`` or
///         ``"newton-kurchatov"``.
///     gamma: relaxation parameter γ > 0, or ``"auto"``.
///     tol: stopping tolerance ε_u.
///     max_iter: iteration cap.
///     u0, u_prev: initial normal displacements u⁰ₙ and u⁻¹ₙ.
///     threads: worker threads (default: the problem's, else all cores).
///     check: raise :class:`ConvergenceError` if the solve does not converge (default); with
///         ``False`` the result is returned regardless (see ``Result.converged``).
///     accelerator: ``"newton"`` (the default: the interface semismooth Newton
///         method, which uses neither method nor γ), ``"none"`` (Robin sweeps relaxed with
///         γ; the default when ``method`` or ``gamma`` is given) or ``"anderson"``.
///     coarse: the rigid-body coarse correction: ``"chains"`` (the sweeps' default: floating bodies that
///         touch each other), ``"all"`` or ``"off"``. A constant ``gamma`` alone selects the
///         paper's one-level iteration (accelerator ``"none"``, coarse ``"off"``).
///     enforcement: ``"penalty"`` or ``"augmented"`` for every contact pair (default: each
///         pair's own, see :meth:`Problem.add_contact`); ``"augmented"`` converges to the exact
///         unilateral contact for any penalty.
///     gap_tol: augmented pairs: the largest violation of the Signorini conditions of a
///         converged result, a length (default: 1e-6 times the largest normal displacement of
///         the contact points).
///     progress: a callable called after every iteration with a dict ``{"k", "gamma",
///         "rel_change", "active", "normal_force"}`` (the last three per body); an exception it
///         raises stops the solve and is raised by :func:`solve`.
///
/// Returns:
///     A :class:`Result`.
///
/// Raises:
///     ContactddError: bad settings, or a body that cannot be factorised.
///     ConvergenceError: the iteration did not converge (``check=True``); ``.result`` holds the
///         partial result.
///     KeyboardInterrupt: interrupted.
#[pyfunction]
#[pyo3(signature = (problem, method = None, gamma = None, tol = None, max_iter = None, u0 = None, u_prev = None, threads = None, check = true, accelerator = None, coarse = None, enforcement = None, gap_tol = None, progress = None))]
#[allow(clippy::too_many_arguments)]
fn solve(
    py: Python<'_>,
    problem: &Bound<'_, Problem>,
    method: Option<String>,
    gamma: Option<GammaArg>,
    tol: Option<f64>,
    max_iter: Option<usize>,
    u0: Option<f64>,
    u_prev: Option<f64>,
    threads: Option<usize>,
    check: bool,
    accelerator: Option<String>,
    coarse: Option<String>,
    enforcement: Option<String>,
    gap_tol: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<SolveResult>> {
    let options = SolverOptions {
        method,
        gamma,
        accelerator,
        coarse,
        tol,
        max_iter,
        u0,
        u_prev,
        threads,
        gap_tol,
        enforcement,
    };
    let (model, settings, threads) = problem.borrow().configured(&options)?;
    let model = Arc::new(model);
    let m = model.clone();
    // An exception of the progress callback: it stops the solve and is raised afterwards.
    let failed: Mutex<Option<PyErr>> = Mutex::new(None);
    let (out, interrupt) = run_interruptible(py, |cancel| {
        let report = |r: &Record| {
            if let Some(callback) = &progress {
                if let Err(e) = Python::attach(|py| call_progress(py, callback, r)) {
                    if let Ok(mut slot) = failed.lock() {
                        slot.get_or_insert(e);
                    }
                    cancel.store(true, Ordering::Relaxed);
                }
            }
        };
        with_threads(threads, || {
            let prepared = contactdd_ddm::prepare_with(&m, &settings)?;
            let findings = contact_check::check(&m, &prepared.interface);
            let hooks = Hooks {
                on_iteration: progress
                    .is_some()
                    .then_some(&report as &(dyn Fn(&Record) + Sync)),
                cancel: Some(cancel),
            };
            Ok((
                findings,
                contactdd_ddm::solve(&m, &prepared, &settings, hooks)?,
            ))
        })
    })?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    if let Some(e) = failed.into_inner().ok().flatten() {
        return Err(e);
    }
    let (findings, sol) = out.map_err(setup_error)?;
    warn_contact(py, &findings)?;
    let result = SolveResult::new(py, model, sol)?;
    let (converged, message) = (result.is_converged(), result.failure_message());
    let result = Py::new(py, result)?;
    if check && !converged {
        return Err(convergence_error(py, &message, result.into_any()));
    }
    Ok(result)
}

/// Calls the progress callback with one iteration's record as a dict.
fn call_progress(py: Python<'_>, callback: &Py<PyAny>, r: &Record) -> PyResult<()> {
    let record = PyDict::new(py);
    record.set_item("k", r.k)?;
    record.set_item("gamma", r.gamma)?;
    record.set_item("rel_change", r.rel_change.clone())?;
    record.set_item("active", r.active.clone())?;
    record.set_item("normal_force", r.contact_force.clone())?;
    callback.call1(py, (record,))?;
    Ok(())
}

/// Solves a problem at increasing loads: every load and prescribed displacement times each load
/// factor in turn, each step starting from the last, on one factorisation of the bodies.
/// Releases the GIL and can be interrupted with Ctrl-C.
///
/// Args:
///     problem: the :class:`Problem`.
///     load_steps: a number N of equal steps (load factors 1/N, …, 1), or the list of load
///         factors (each > 0).
///     tol, max_iter, threads, accelerator, enforcement, gap_tol: as for :func:`solve`.
///     check: raise :class:`ConvergenceError` if a step does not converge (default); the steps
///         stop at the first such step either way.
///
/// Returns:
///     One :class:`Result` per step solved, each with its ``load_factor``.
#[pyfunction]
#[pyo3(signature = (problem, load_steps, tol = None, max_iter = None, threads = None, check = true, accelerator = None, enforcement = None, gap_tol = None))]
#[allow(clippy::too_many_arguments)]
fn solve_steps<'py>(
    py: Python<'py>,
    problem: &Bound<'py, Problem>,
    load_steps: &Bound<'py, PyAny>,
    tol: Option<f64>,
    max_iter: Option<usize>,
    threads: Option<usize>,
    check: bool,
    accelerator: Option<String>,
    enforcement: Option<String>,
    gap_tol: Option<f64>,
) -> PyResult<Bound<'py, PyList>> {
    let factors: Vec<f64> = match load_steps.extract::<usize>() {
        Ok(n) => contactdd_ddm::steps::equal_steps(n),
        Err(_) => load_steps.extract::<Vec<f64>>().map_err(|_| {
            setup_error(SetupError::Solver(
                "load_steps: give a number of steps or a list of load factors".into(),
            ))
        })?,
    };
    contactdd_ddm::steps::check_factors(&factors)
        .map_err(|m| setup_error(SetupError::Solver(format!("load_steps: {m}"))))?;
    let options = SolverOptions {
        accelerator,
        tol,
        max_iter,
        threads,
        gap_tol,
        enforcement,
        ..SolverOptions::default()
    };
    let (model, settings, threads) = problem.borrow().configured(&options)?;
    let model = Arc::new(model);
    let m = model.clone();
    let (out, interrupt) = run_interruptible(py, move |cancel| {
        with_threads(threads, || {
            let mut prepared = contactdd_ddm::prepare_with(&m, &settings)?;
            let hooks = Hooks {
                on_iteration: None,
                cancel: Some(cancel),
            };
            contactdd_ddm::steps::solve_steps(
                &m,
                &mut prepared,
                &settings,
                &factors,
                hooks,
                &mut |_, _, _| (),
            )
        })
    })?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    let steps = out.map_err(setup_error)?;
    let mut results = Vec::with_capacity(steps.len());
    for (factor, sol) in steps {
        let result = SolveResult::new(py, model.clone(), sol)?.at_load_factor(factor);
        results.push(result);
    }
    let failed = results
        .last()
        .filter(|r| !r.is_converged())
        .map(|r| r.failure_message());
    let list = PyList::new(
        py,
        results
            .into_iter()
            .map(|r| Py::new(py, r))
            .collect::<PyResult<Vec<_>>>()?,
    )?;
    if let (true, Some(message)) = (check, failed) {
        let last = list.get_item(list.len() - 1)?;
        return Err(convergence_error(py, &message, last.unbind()));
    }
    Ok(list)
}

/// The warnings about the contact geometry as Python `UserWarning`s (the errors among the
/// findings were raised by `prepare`).
fn warn_contact(py: Python<'_>, findings: &[contact_check::Finding]) -> PyResult<()> {
    let category = py.get_type::<PyUserWarning>();
    for f in findings.iter().filter(|f| !f.is_error()) {
        let message = std::ffi::CString::new(f.to_string().replace('\0', " "))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        PyErr::warn(py, &category, &message, 1)?;
    }
    Ok(())
}

/// Runs a γ study: every method with every γ, on one preparation of the problem (assembly and
/// factorisation are done once; the runs execute in parallel). Releases the GIL and can be
/// interrupted with Ctrl-C (``KeyboardInterrupt``).
///
/// Args:
///     problem: the :class:`Problem`.
///     methods: method names (default: ``["active-set", "newton-chord", "newton-kurchatov"]``,
///         the paper's).
///     gammas: γ values (numbers, or ``"auto"``); default 0.02, 0.05, 0.1, 0.15, …, 0.85.
///     tol, max_iter, u0, u_prev, threads: as for :func:`solve` (default: the problem's).
///     progress: a callable called with each run's dict (as returned) as soon as the run ends;
///         the runs execute in parallel, so they end in any order. An exception it raises stops
///         the sweep (runs not yet started are skipped, running ones stop) and is raised by
///         :func:`sweep`.
///
/// Returns:
///     One dict per run, γ by γ and method by method: ``{"method": str, "gamma": float or
///     "auto", "iterations": int, "converged": bool, "reason": str}`` (``reason`` is empty when
///     converged).
#[pyfunction]
#[pyo3(signature = (problem, methods = None, gammas = None, tol = None, max_iter = None, u0 = None, u_prev = None, threads = None, progress = None))]
#[allow(clippy::too_many_arguments)]
fn sweep<'py>(
    py: Python<'py>,
    problem: &Bound<'py, Problem>,
    methods: Option<Vec<String>>,
    gammas: Option<Vec<GammaArg>>,
    tol: Option<f64>,
    max_iter: Option<usize>,
    u0: Option<f64>,
    u_prev: Option<f64>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyList>> {
    let methods: Vec<Method> = match methods {
        None => SWEEP_METHODS.to_vec(),
        Some(names) => names
            .iter()
            .map(|n| {
                n.parse::<Method>()
                    .map_err(|e| setup_error(SetupError::Solver(format!("methods: {e}"))))
            })
            .collect::<PyResult<_>>()?,
    };
    let gammas: Vec<Gamma> = match gammas {
        None => default_gammas(),
        Some(gs) => gs.iter().map(gamma).collect::<PyResult<_>>()?,
    };
    let options = SolverOptions {
        tol,
        max_iter,
        u0,
        u_prev,
        threads,
        ..SolverOptions::default()
    };
    let (model, base, threads) = problem.borrow().configured(&options)?;
    // An exception of the progress callback: it stops the sweep and is raised afterwards.
    let failed: Mutex<Option<PyErr>> = Mutex::new(None);
    let (out, interrupt) = run_interruptible(py, |cancel| {
        let report = |r: &SweepRun| {
            if let Some(callback) = &progress {
                let called = Python::attach(|py| callback.call1(py, (sweep_record(py, r)?,)));
                if let Err(e) = called {
                    if let Ok(mut slot) = failed.lock() {
                        slot.get_or_insert(e);
                    }
                    cancel.store(true, Ordering::Relaxed);
                }
            }
        };
        with_threads(threads, || {
            let how = contactdd_ddm::Preparation::for_sweeps(base.condensation);
            let prepared = contactdd_ddm::prepare_with(&model, how)?;
            let hooks = SweepHooks {
                cancel: Some(cancel),
                on_run: Some(&report),
            };
            Ok(contactdd_ddm::sweep_with(
                &model, &prepared, &methods, &gammas, &base, hooks,
            ))
        })
    })?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    if let Some(e) = failed.into_inner().ok().flatten() {
        return Err(e);
    }
    let runs = out.map_err(setup_error)?;
    let list = PyList::empty(py);
    for r in &runs {
        list.append(sweep_record(py, r)?)?;
    }
    Ok(list)
}

/// One run of a sweep as its dict: method, gamma, iterations, converged, reason.
fn sweep_record<'py>(py: Python<'py>, r: &SweepRun) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("method", r.method.name())?;
    let g = r.gamma.map_or(Gamma::Auto, Gamma::Constant);
    d.set_item("gamma", gamma_to_py(py, g)?)?;
    d.set_item("iterations", r.iterations)?;
    d.set_item("converged", r.converged)?;
    d.set_item("reason", r.reason.clone())?;
    Ok(d)
}

/// γ = 0.02, 0.05, 0.1, 0.15, …, 0.85: the grid of the paper's γ study.
fn default_gammas() -> Vec<Gamma> {
    [0.02, 0.05]
        .into_iter()
        .chain((2..=17).map(|i| f64::from(i) / 20.0))
        .map(Gamma::Constant)
        .collect()
}

/// Solves the same penalty problem monolithically (semismooth Newton on all bodies at once): the
/// reference the domain decomposition converges to. Releases the GIL.
///
/// Returns:
///     A :class:`MonolithicResult`.
#[pyfunction]
fn monolithic(py: Python<'_>, problem: &Bound<'_, Problem>) -> PyResult<Py<MonolithicResult>> {
    let model = Arc::new(problem.borrow().model()?);
    // The contact geometry checks of `solve`, before the Newton iteration.
    let interface = Interface::new(&model).map_err(setup_error)?;
    let findings = contact_check::check(&model, &interface);
    contact_check::refuse(&findings).map_err(setup_error)?;
    warn_contact(py, &findings)?;
    let (out, interrupt) = run_interruptible(py, |_| contactdd_ddm::solve_monolithic(&model))?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    let sol = out.map_err(setup_error)?;
    Py::new(py, MonolithicResult::new(py, model, sol)?)
}

/// The two-body notch benchmark of the paper (docs/method.md §5) as a :class:`Problem`.
///
/// Two 4 × 1 cm blocks (``lower``, ``upper``), pressed together by q = 0.01·E, with a notch of
/// depth 0.05 cm in the gap at the symmetry line x = 4; contact pair ``notch``. The default
/// settings are those of ``examples/notch.toml``: newton-kurchatov, γ = 0.5, ε_u = 1e-3,
/// u⁰ₙ = 1e-4, u⁻¹ₙ = 2e-4.
///
/// Args:
///     nx, ny: cells per body (32 × 16 in the paper).
///     order: ``"p1"`` or ``"p2"``.
#[pyfunction]
#[pyo3(signature = (nx = 32, ny = 16, order = "p1"))]
fn notch_benchmark(nx: usize, ny: usize, order: &str) -> PyResult<Problem> {
    let order: Order = convert::from_name(order).map_err(|e| {
        setup_error(SetupError::Invalid {
            key: "order".into(),
            message: e,
        })
    })?;
    // The problem file's limit, checked before the meshes are allocated.
    if nx
        .checked_mul(ny)
        .map_or(true, |cells| cells > MAX_RECTANGLE_CELLS)
    {
        return Err(setup_error(SetupError::Invalid {
            key: "nx, ny".into(),
            message: format!(
                "{nx} × {ny} cells per block is more than the limit of {MAX_RECTANGLE_CELLS}"
            ),
        }));
    }
    Problem::from_spec(benchmark::notch_spec(nx, ny, order), Path::new(""))
}

/// The contactdd extension module.
#[pymodule]
fn _contactdd(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<Problem>()?;
    m.add_class::<SolveResult>()?;
    m.add_class::<Body>()?;
    m.add_class::<Contact>()?;
    m.add_class::<MonolithicResult>()?;
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    m.add_function(wrap_pyfunction!(solve_steps, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(monolithic, m)?)?;
    m.add_function(wrap_pyfunction!(notch_benchmark, m)?)?;
    m.add("ContactddError", py.get_type::<ContactddError>())?;
    m.add("ConvergenceError", convergence_error_type(py)?)?;
    m.add("ContactddIOError", io_error_type(py)?)?;
    m.add(
        "METHODS",
        Method::ALL.iter().map(|m| m.name()).collect::<Vec<_>>(),
    )?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
