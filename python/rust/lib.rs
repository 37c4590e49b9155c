//! # contactdd-python
//!
//! The `contactdd._contactdd` extension module: a thin pyo3 layer over `contactdd-core` and
//! `contactdd-ddm`. It converts numpy arrays and dicts into the Rust types and back and runs the
//! solves with the GIL released; all numerics live in the Rust crates.
//!
//! Solves run on a worker thread while the calling thread, detached from the interpreter, wakes
//! every 50 ms to check for signals: Ctrl-C raises `KeyboardInterrupt` at once, also during the
//! assembly and factorisation, and sets the solver's cancel flag, so that the abandoned worker
//! stops at its next iteration boundary (a setup under way runs to its end in the background).

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use contactdd_core::Order;
use contactdd_ddm::contact::check as contact_check;
use contactdd_ddm::contact::Interface;
use contactdd_ddm::gamma_study::{SweepHooks, SweepRun};
use contactdd_ddm::monolithic::MonolithicSettings;
use contactdd_ddm::{Gamma, Method, SetupError};
use contactdd_io::setup::MAX_RECTANGLE_CELLS;

mod benchmark;
mod contact_result;
mod convert;
mod error;
mod files;
mod options;
mod problem;
mod results;
mod run;
mod schema;
mod solve;
mod space;
mod space_problem;
mod space_result;
mod space_schema;
mod space_system;
mod state;
mod steps;

use contact_result::Contact;
use error::{convergence_error_type, input_error, io_error_type, setup_error, ContactddError};
use options::{gamma, gamma_to_py, GammaArg, SolverOptions};
use problem::Problem;
use results::{Body, MonolithicResult, SolveResult};
use run::{run_interruptible, warn_contact, with_threads};

/// The methods a sweep runs by default: the three of the paper's γ study.
const SWEEP_METHODS: [Method; 3] = [
    Method::ActiveSet,
    Method::NewtonChord,
    Method::NewtonKurchatov,
];

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
    let failed: Arc<Mutex<Option<PyErr>>> = Arc::new(Mutex::new(None));
    let slot = failed.clone();
    let out = run_interruptible(py, move |cancel| {
        let report = |r: &SweepRun| {
            // After Ctrl-C the caller has gone on: no more calls into Python.
            if cancel.load(Ordering::Relaxed) {
                return;
            }
            if let Some(callback) = &progress {
                let called = Python::attach(|py| callback.call1(py, (sweep_record(py, r)?,)));
                if let Err(e) = called {
                    if let Ok(mut slot) = slot.lock() {
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
    if let Some(e) = failed.lock().ok().and_then(|mut slot| slot.take()) {
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
/// The keywords are the options of ``contactdd monolithic``; ``threads`` and ``gap_tol`` default
/// to the problem's (``[solver]`` table or :meth:`Problem.solver`). The problem's load steps and
/// iteration settings do not apply: the reference is solved at the full load.
///
/// Args:
///     problem: the :class:`Problem`.
///     threads: worker threads (default: the problem's, else all cores).
///     max_steps: Newton steps at most (default 50).
///     enforcement: ``"penalty"`` or ``"augmented"`` for every contact pair (default: each
///         pair's own); ``"augmented"`` runs Uzawa updates of the multipliers around the Newton
///         solves.
///     friction: the friction of every pair (default: each pair's own), as for :func:`solve`
///         and ``contactdd monolithic --friction``.
///     gap_tol: augmented pairs: the largest violation of the Signorini conditions, a length.
///     out: a folder to write the result files into (summary.json, contact.csv, one VTU file
///         per body), as ``contactdd monolithic --out`` does.
///
/// Returns:
///     A :class:`MonolithicResult`.
#[pyfunction]
#[pyo3(signature = (problem, threads = None, max_steps = None, enforcement = None, friction = None, gap_tol = None, out = None))]
#[allow(clippy::too_many_arguments)]
fn monolithic(
    py: Python<'_>,
    problem: &Bound<'_, Problem>,
    threads: Option<usize>,
    max_steps: Option<usize>,
    enforcement: Option<String>,
    friction: Option<&Bound<'_, PyAny>>,
    gap_tol: Option<f64>,
    out: Option<PathBuf>,
) -> PyResult<Py<MonolithicResult>> {
    let options = SolverOptions {
        threads,
        gap_tol,
        enforcement,
        friction: options::friction_arg(friction)?,
        ..SolverOptions::default()
    };
    // The checks of a `[solver]` table for threads and gap_tol.
    let (model, base, threads) = problem.borrow().configured(&options)?;
    let vtu = problem.borrow().spec.output.vtu_options();
    let mut settings = MonolithicSettings {
        gap_tol: base.gap_tol,
        ..MonolithicSettings::default()
    };
    if let Some(b) = base.balance_tol {
        settings.balance_tol = b;
    }
    if let Some(k) = max_steps {
        settings.max_steps = k;
    }
    let model = Arc::new(model);
    // The contact geometry checks of `solve`, before the Newton iteration.
    let interface = Interface::new(&model).map_err(setup_error)?;
    let findings = contact_check::check(&model, &interface);
    contact_check::refuse(&findings).map_err(setup_error)?;
    warn_contact(py, &findings)?;
    let m = model.clone();
    let out_sol = run_interruptible(py, move |_| {
        with_threads(threads, || {
            contactdd_ddm::monolithic::solve_monolithic_with(&m, &settings, None)
        })
    })?;
    let sol = out_sol.map_err(setup_error)?;
    if let Some(dir) = out {
        py.detach(|| contactdd_io::output::write_monolithic_results(&dir, &model, &sol, vtu))
            .map_err(|e| {
                input_error(format!(
                    "cannot write the results to '{}': {e}",
                    dir.display()
                ))
            })?;
    }
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
    m.add_function(wrap_pyfunction!(solve::solve, m)?)?;
    m.add_function(wrap_pyfunction!(solve::solve_steps, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(monolithic, m)?)?;
    m.add_function(wrap_pyfunction!(notch_benchmark, m)?)?;
    m.add_function(wrap_pyfunction!(files::_read_result_file, m)?)?;
    m.add("SpaceProblem", py.get_type::<space_problem::SpaceProblem>())?;
    m.add("SpaceResult", py.get_type::<space_result::SpaceResult>())?;
    m.add("SpaceBody", py.get_type::<space_result::SpaceBody>())?;
    m.add_function(wrap_pyfunction!(space::space_solve, m)?)?;
    m.add_function(wrap_pyfunction!(space::space_monolithic, m)?)?;
    m.add_function(wrap_pyfunction!(space_system::space_system, m)?)?;
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
