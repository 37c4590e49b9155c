//! `contactdd.solve` and `contactdd.solve_steps`: the domain decomposition solve of a problem,
//! once at the full load or at each of its load steps, with the options of a `[solver]` table
//! and of `contactdd solve` as keyword arguments.

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use contactdd_ddm::contact::check as contact_check;
use contactdd_ddm::history::{Increment, LoadHistory};
use contactdd_ddm::{Hooks, Model, Record, SetupError};
use contactdd_io::setup::Monitor;
use contactdd_io::steps::{monitored_displacement, HistoryLabels};
use contactdd_io::vtu::VtuOptions;

use crate::error::{convergence_error, input_error, setup_error};
use crate::options::{friction_arg, GammaArg, SolverOptions};
use crate::problem::Problem;
use crate::results::SolveResult;
use crate::run::{run_interruptible, warn_contact, with_threads};
use crate::steps::{self, load_steps_spec, monitor_spec};

/// Solves a contact problem by the penalty Robin domain decomposition, once, at the full load.
///
/// Every keyword is a key of the problem file's ``[solver]`` table (in snake_case:
/// ``max-iter`` is ``max_iter``) or an option of ``contactdd solve`` (``--enforcement``,
/// ``--friction``, ``--out``); settings left at ``None`` take the problem's (its ``[solver]`` table, or
/// :meth:`Problem.solver`). The solve releases the GIL and can be interrupted with Ctrl-C
/// (``KeyboardInterrupt``).
///
/// A problem with load steps (``[solver] load-steps``, or :meth:`Problem.solver` with
/// ``load_steps``) is refused with a :class:`ContactddError` that says to call
/// :func:`solve_steps`, which runs them and returns one :class:`Result` per step (a single step
/// at factor 1 is a plain solve and is accepted).
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
///     friction: the friction of every contact pair (default: each pair's own, see
///         :meth:`Problem.add_contact`), as ``contactdd solve --friction``: ``"coulomb:0.3"``,
///         ``"tresca:5"`` or ``"none"``, or a dict ``{"law": "coulomb", "mu": 0.3}`` /
///         ``{"law": "tresca", "bound": 5.0}`` / ``{"law": "none"}``.
///     gap_tol: augmented pairs: the largest violation of the Signorini conditions of a
///         converged result, a length (default: 1e-6 times the largest normal displacement of
///         the contact points).
///     progress: a callable called after every iteration with a dict ``{"k", "gamma",
///         "rel_change", "active", "normal_force"}`` (the last three per body); an exception it
///         raises stops the solve and is raised by :func:`solve`.
///     equilibrium_tol, balance_tol, max_updates, condensation: as for :meth:`Problem.solver`.
///     monitor: the boundary whose mean displacement the result reports as
///         ``Result.monitor``: ``{"body": name, "boundary": name}`` or ``(body, boundary)``.
///     out: a folder to write the result files into (summary.json, contact.csv, history.csv,
///         one VTU file per body), as ``contactdd solve --out`` does; written also when the
///         solve does not converge.
///
/// Returns:
///     A :class:`Result`.
///
/// Raises:
///     ContactddError: bad settings, a problem with load steps, or a body that cannot be
///         factorised.
///     ConvergenceError: the iteration did not converge (``check=True``); ``.result`` holds the
///         partial result.
///     KeyboardInterrupt: interrupted.
#[pyfunction]
#[pyo3(signature = (problem, method = None, gamma = None, tol = None, max_iter = None, u0 = None, u_prev = None, threads = None, check = true, accelerator = None, coarse = None, enforcement = None, friction = None, gap_tol = None, progress = None, equilibrium_tol = None, balance_tol = None, max_updates = None, condensation = None, monitor = None, out = None))]
#[allow(clippy::too_many_arguments)]
pub fn solve(
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
    friction: Option<&Bound<'_, PyAny>>,
    gap_tol: Option<f64>,
    progress: Option<Py<PyAny>>,
    equilibrium_tol: Option<f64>,
    balance_tol: Option<f64>,
    max_updates: Option<usize>,
    condensation: Option<String>,
    monitor: Option<&Bound<'_, PyAny>>,
    out: Option<PathBuf>,
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
        equilibrium_tol,
        balance_tol,
        max_updates,
        condensation,
        enforcement,
        friction: friction_arg(friction)?,
    };
    let p = problem.borrow();
    refuse_load_steps(&p)?;
    let (model, settings, threads) = p.configured(&options)?;
    let monitor = monitored(&p, monitor, &model)?;
    let units = p.units().map(str::to_string);
    let vtu = p.spec.output.vtu_options();
    drop(p);
    let model = Arc::new(model);
    let m = model.clone();
    let (findings, sol) = run_reporting(py, threads, progress.as_ref(), move |hooks| {
        let prepared = contactdd_ddm::prepare_with(&m, &settings)?;
        let findings = contact_check::check(&m, &prepared.interface);
        Ok((
            findings,
            contactdd_ddm::solve(&m, &prepared, &settings, hooks)?,
        ))
    })?;
    warn_contact(py, &findings)?;
    if let Some(dir) = out {
        let units = units.as_deref();
        written(py, &dir, || {
            contactdd_io::output::write_results_noted(&dir, &model, &sol, units, vtu)
        })?;
    }
    let at = monitor
        .as_ref()
        .map(|m| monitored_displacement(&sol.bodies, m));
    let result = SolveResult::new(py, model, sol)?.with_monitor(at);
    let (converged, message) = (result.is_converged(), result.failure_message());
    let result = Py::new(py, result)?;
    if check && !converged {
        return Err(convergence_error(py, &message, result.into_any()));
    }
    Ok(result)
}

/// Refuses a problem whose load steps are more than the single factor 1: `solve` would skip
/// them.
fn refuse_load_steps(problem: &Problem) -> PyResult<()> {
    if !problem.spec.steps.is_empty() {
        return Err(setup_error(SetupError::Solver(format!(
            "steps: problem '{}' has a load history ([[steps]]), and contactdd.solve runs one              solve; run the history with contactdd.solve_steps(problem), which returns one              Result per increment",
            problem.name
        ))));
    }
    let Some(spec) = problem.load_steps() else {
        return Ok(());
    };
    let factors = steps::factors(spec)?;
    if factors == [1.0] {
        return Ok(());
    }
    Err(setup_error(SetupError::Solver(format!(
        "load-steps: problem '{}' has {} load steps, and contactdd.solve runs one solve at the \
         full load; run the steps with contactdd.solve_steps(problem), which returns one Result \
         per step, or set problem.solver(load_steps=1) for one solve at the full load",
        problem.name,
        factors.len()
    ))))
}

/// The monitored boundary: the argument's, else the problem's, checked against `model`.
fn monitored(
    problem: &Problem,
    arg: Option<&Bound<'_, PyAny>>,
    model: &Model,
) -> PyResult<Option<Monitor>> {
    let spec = match arg {
        Some(obj) => Some(monitor_spec(obj)?),
        None => problem.monitor().cloned(),
    };
    spec.map(|s| steps::monitor(&model.bodies, &s)).transpose()
}

/// Writes result files with the GIL released; an error names the folder.
fn written(
    py: Python<'_>,
    dir: &Path,
    write: impl FnOnce() -> std::io::Result<Vec<PathBuf>> + Send,
) -> PyResult<()> {
    py.detach(write).map_err(|e| {
        input_error(format!(
            "cannot write the results to '{}': {e}",
            dir.display()
        ))
    })?;
    Ok(())
}

/// Runs `work` with the GIL released in a pool of `threads` workers, Ctrl-C and `progress`
/// (called after every iteration) wired to its hooks. An exception of `progress` stops the
/// solve and is raised; so is Ctrl-C's `KeyboardInterrupt`.
fn run_reporting<T, F>(
    py: Python<'_>,
    threads: Option<usize>,
    progress: Option<&Py<PyAny>>,
    work: F,
) -> PyResult<T>
where
    T: Send + 'static,
    F: for<'h> FnOnce(Hooks<'h>) -> Result<T, SetupError> + Send + 'static,
{
    // An exception of the progress callback: it stops the solve and is raised afterwards.
    let failed: Arc<Mutex<Option<PyErr>>> = Arc::new(Mutex::new(None));
    let slot = failed.clone();
    let progress = progress.map(|p| p.clone_ref(py));
    let out = run_interruptible(py, move |cancel| {
        let report = |r: &Record| {
            // After Ctrl-C the caller has gone on: no more calls into Python.
            if cancel.load(Ordering::Relaxed) {
                return;
            }
            if let Some(callback) = &progress {
                if let Err(e) = Python::attach(|py| call_progress(py, callback, r)) {
                    if let Ok(mut slot) = slot.lock() {
                        slot.get_or_insert(e);
                    }
                    cancel.store(true, Ordering::Relaxed);
                }
            }
        };
        let hooks = Hooks {
            on_iteration: progress
                .is_some()
                .then_some(&report as &(dyn Fn(&Record) + Sync)),
            cancel: Some(cancel),
        };
        with_threads(threads, || work(hooks))
    })?;
    if let Some(e) = failed.lock().ok().and_then(|mut slot| slot.take()) {
        return Err(e);
    }
    out.map_err(setup_error)
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
/// factor in turn, each step starting from the last, on one factorisation of the bodies (the
/// ``load-steps`` of a ``[solver]`` table, as ``contactdd solve`` runs them). Releases the GIL
/// and can be interrupted with Ctrl-C.
///
/// Args:
///     problem: the :class:`Problem`.
///     load_steps: a number N of equal steps (load factors 1/N, …, 1), or the list of load
///         factors (each > 0); default: the problem's load history (``[[steps]]``: one solve
///         per increment, each result's ``load_factor`` the time of ``steps.csv``, the step's
///         number from 0 plus the fraction done), else its ``[solver] load-steps`` (or
///         :meth:`Problem.solver`); a :class:`ContactddError` if it has neither.
///     tol, max_iter, threads, accelerator, enforcement, friction, gap_tol, method, gamma,
///         coarse, u0, u_prev, equilibrium_tol, balance_tol, max_updates, condensation, progress: as for
///         :func:`solve`.
///     check: raise :class:`ConvergenceError` if a step does not converge (default); the steps
///         stop at the first such step either way.
///     monitor: the boundary whose mean displacement each step reports as ``Result.monitor``
///         (the displacement axis of a load–displacement curve): ``{"body": name, "boundary":
///         name}`` or ``(body, boundary)``; default: the problem's.
///     out: a folder to write the step results into (steps.csv, one VTU set per step,
///         results.pvd, summary.json), as ``contactdd solve --out`` does for a file with load
///         steps; written also when a step does not converge.
///
/// Returns:
///     One :class:`Result` per step solved, each with its ``load_factor``.
#[pyfunction]
#[pyo3(signature = (problem, load_steps = None, tol = None, max_iter = None, threads = None, check = true, accelerator = None, enforcement = None, friction = None, gap_tol = None, method = None, gamma = None, coarse = None, u0 = None, u_prev = None, equilibrium_tol = None, balance_tol = None, max_updates = None, condensation = None, monitor = None, out = None, progress = None))]
#[allow(clippy::too_many_arguments)]
pub fn solve_steps<'py>(
    py: Python<'py>,
    problem: &Bound<'py, Problem>,
    load_steps: Option<&Bound<'py, PyAny>>,
    tol: Option<f64>,
    max_iter: Option<usize>,
    threads: Option<usize>,
    check: bool,
    accelerator: Option<String>,
    enforcement: Option<String>,
    friction: Option<&Bound<'_, PyAny>>,
    gap_tol: Option<f64>,
    method: Option<String>,
    gamma: Option<GammaArg>,
    coarse: Option<String>,
    u0: Option<f64>,
    u_prev: Option<f64>,
    equilibrium_tol: Option<f64>,
    balance_tol: Option<f64>,
    max_updates: Option<usize>,
    condensation: Option<String>,
    monitor: Option<&Bound<'py, PyAny>>,
    out: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyList>> {
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
        equilibrium_tol,
        balance_tol,
        max_updates,
        condensation,
        enforcement,
        friction: friction_arg(friction)?,
    };
    let p = problem.borrow();
    let (model, settings, threads) = p.configured(&options)?;
    let (history, factors) = plan(&p, &model, load_steps)?;
    let monitor = monitored(&p, monitor, &model)?;
    let units = p.units().map(str::to_string);
    let vtu = p.spec.output.vtu_options();
    drop(p);
    if let Some(history) = history {
        let run = HistoryRun {
            model,
            settings,
            threads,
            monitor,
            units,
            vtu,
            out,
            check,
        };
        return solve_history(py, run, &history, progress.as_ref());
    }
    let model = Arc::new(model);
    let m = model.clone();
    let steps = run_reporting(py, threads, progress.as_ref(), move |hooks| {
        let mut prepared = contactdd_ddm::prepare_with(&m, &settings)?;
        let mut each = |_: usize, _: f64, _: &contactdd_ddm::Solution| ();
        contactdd_ddm::steps::solve_steps(&m, &mut prepared, &settings, &factors, hooks, &mut each)
    })?;
    if let Some(dir) = out {
        let (units, monitor) = (units.as_deref(), monitor.as_ref());
        written(py, &dir, || {
            contactdd_io::output::write_step_results(&dir, &model, &steps, (monitor, units), vtu)
        })?;
    }
    let models = vec![model; steps.len()];
    step_results(py, models, steps, monitor.as_ref(), check)
}

/// What `solve_steps` runs: the problem's load history (no `load_steps` argument), else the load
/// factors.
fn plan(
    problem: &Problem,
    model: &Model,
    load_steps: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Option<LoadHistory>, Vec<f64>)> {
    let history = match load_steps {
        Some(_) => None,
        None => history(problem, model)?,
    };
    let factors = match history {
        Some(_) => Vec::new(),
        None => step_factors(problem, load_steps)?,
    };
    Ok((history, factors))
}

/// The load factors: the argument's, else the problem's.
fn step_factors(problem: &Problem, arg: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<f64>> {
    match (arg, problem.load_steps()) {
        (Some(obj), _) => steps::factors(&load_steps_spec(obj)?),
        (None, Some(spec)) => steps::factors(spec),
        (None, None) => Err(setup_error(SetupError::Solver(format!(
            "load_steps: problem '{}' has no load steps ([solver] load-steps): give \
             load_steps=N or a list of load factors",
            problem.name
        )))),
    }
}

/// The steps as a list of results, each of the model it solved (`models`, one per step); a
/// `ConvergenceError` holding the last one if it did not converge and `check` is set.
fn step_results<'py>(
    py: Python<'py>,
    models: Vec<Arc<Model>>,
    steps: Vec<(f64, contactdd_ddm::Solution)>,
    monitor: Option<&Monitor>,
    check: bool,
) -> PyResult<Bound<'py, PyList>> {
    let mut results = Vec::with_capacity(steps.len());
    for (model, (factor, sol)) in models.into_iter().zip(steps) {
        let at = monitor.map(|m| monitored_displacement(&sol.bodies, m));
        let result = SolveResult::new(py, model, sol)?
            .at_load_factor(factor)
            .with_monitor(at);
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

/// The problem's load history (`[[steps]]` of its file, with the loads' groups), checked on
/// `model` as a file's is; `None` without one.
fn history(problem: &Problem, model: &contactdd_ddm::Model) -> PyResult<Option<LoadHistory>> {
    contactdd_io::history::history(&problem.spec, model).map_err(setup_error)
}

/// What a load history's run needs besides the history.
struct HistoryRun {
    /// The model.
    model: contactdd_ddm::Model,
    /// Iteration settings.
    settings: contactdd_ddm::Settings,
    /// Worker threads.
    threads: Option<usize>,
    /// The monitored boundary.
    monitor: Option<Monitor>,
    /// The problem's units note.
    units: Option<String>,
    /// The encoding and layout of the `.vtu` files.
    vtu: VtuOptions,
    /// The folder to write the results into.
    out: Option<std::path::PathBuf>,
    /// Raise if the last increment does not converge.
    check: bool,
}

/// Solves every increment of `history`: one result per increment (its `load_factor` the
/// increment's time, [`HistoryLabels::times`]), the folder written as `contactdd solve` writes it.
fn solve_history<'py>(
    py: Python<'py>,
    run: HistoryRun,
    history: &LoadHistory,
    progress: Option<&Py<PyAny>>,
) -> PyResult<Bound<'py, PyList>> {
    let HistoryRun {
        model,
        settings,
        threads,
        monitor,
        units,
        vtu,
        out,
        check,
    } = run;
    let model = Arc::new(model);
    let (m, h) = (model.clone(), history.clone());
    let done = run_reporting(py, threads, progress, move |hooks| {
        let mut prepared = contactdd_ddm::prepare_with(&m, &settings)?;
        let mut each = |_: &Increment, _: &contactdd_ddm::Solution| ();
        contactdd_ddm::history::solve_history(&m, &mut prepared, &settings, &h, hooks, &mut each)
    })?;
    let increments: Vec<Increment> = done.iter().map(|(i, _)| i.clone()).collect();
    let times = HistoryLabels::times(history, &increments);
    let mut steps: Vec<(f64, contactdd_ddm::Solution)> = times
        .into_iter()
        .zip(done.into_iter().map(|(_, s)| s))
        .collect();
    // Every result describes the model at its increment's combination (its applied loads and
    // reactions): that model at factor 1.
    let models: Vec<Arc<Model>> = increments
        .iter()
        .map(|i| Arc::new(history.model_at(&model, &i.factors)))
        .collect();
    for (_, sol) in &mut steps {
        sol.load_factor = 1.0;
    }
    if let (Some(dir), Some(last)) = (out, models.last()) {
        let labels = HistoryLabels::new(history, &increments);
        let (units, monitor) = (units.as_deref(), monitor.as_ref());
        written(py, &dir, || {
            let notes = (monitor, units);
            contactdd_io::output::write_history_results(&dir, last, &steps, notes, &labels, vtu)
        })?;
    }
    step_results(py, models, steps, monitor.as_ref(), check)
}
