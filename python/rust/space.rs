//! `contactdd.space`: problems in space (`dimension = 3`, tetrahedral bodies), read from a
//! problem file or built in code ([`SpaceProblem`]), solved by the decomposition
//! ([`space_solve`]) or the monolithic reference ([`space_monolithic`]), each checked by the independent force balance of
//! `contactdd_io::solid_run::run_solid`, as `contactdd solve` and `contactdd monolithic` do.
//!
//! Errors map as in the plane: a file that cannot be read is a `ContactddIOError`, a bad file,
//! a bad argument or a body the decomposition cannot hold a `ContactddError` (the message the
//! command line prints), a result that does not converge a `ConvergenceError` holding it.

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::prelude::*;

use contactdd_io::solid_run::{run_solid, SolidOutcome, SolidSolver};

use contactdd_io::problem::EnforcementSpec;

use contactdd_ddm::Friction;

use crate::convert::{from_name, shown};
use crate::error::{convergence_error, input_error};
use crate::options::friction_arg;
use crate::run::run_interruptible;
use crate::space_problem::SpaceProblem;
use crate::space_result::{write_folder, SpaceResult};

/// How a solve in space runs: the keywords of [`space_solve`] and [`space_monolithic`].
struct SpaceRun {
    threads: Option<usize>,
    balance_tol: Option<f64>,
    enforcement: Option<String>,
    friction: Option<Friction>,
    out: Option<PathBuf>,
    check: bool,
}

/// Solves a problem in space by the decomposition: every body factorised once, Newton on the
/// contact points (``contactdd solve`` on a file with ``dimension = 3``). The result counts as
/// converged only after the independent force balance. Releases the GIL; Ctrl-C raises
/// ``KeyboardInterrupt``.
///
/// Args:
///     problem: the :class:`Problem`.
///     threads: worker threads (default: the problem's ``[solver] threads``, else all cores).
///     balance_tol: the force balance's tolerance of a converged result (default: the
///         problem's ``[solver] balance-tol``, else 1e-6).
///     enforcement: ``"penalty"`` or ``"augmented"`` for every contact pair (default: each
///         pair's own), as ``contactdd solve --enforcement``.
///     friction: the friction of every pair (default: each pair's own): ``"coulomb:0.3"``,
///         ``"tresca:5"``, ``"none"`` or a dict as in :meth:`Problem.add_contact`, as
///         ``contactdd solve --friction``.
///     out: a folder to write the result files into (``summary.json``, ``contact.csv``, one
///         ``.vtu`` file per body or ``bodies.vtu``), as ``contactdd solve --out`` does;
///         written also when the result does not converge.
///     check: raise :class:`contactdd.ConvergenceError` if the result does not converge
///         (default); with ``False`` the result is returned regardless (see
///         ``Result.converged``).
///
/// Returns:
///     A :class:`Result`.
///
/// Raises:
///     ContactddError: a bad argument, or a body whose supports leave one of its six rigid
///         motions free (the message names the body), or a solve without a result (a closed
///         set that does not settle, a singular system).
///     ConvergenceError: the result is not converged (``check=True``); ``.result`` holds it.
#[pyfunction]
#[pyo3(signature = (problem, threads = None, balance_tol = None, enforcement = None, friction = None, out = None, check = true))]
#[allow(clippy::too_many_arguments)]
pub fn space_solve(
    py: Python<'_>,
    problem: &Bound<'_, SpaceProblem>,
    threads: Option<usize>,
    balance_tol: Option<f64>,
    enforcement: Option<String>,
    friction: Option<&Bound<'_, PyAny>>,
    out: Option<PathBuf>,
    check: bool,
) -> PyResult<Py<SpaceResult>> {
    let run = SpaceRun {
        threads,
        balance_tol,
        enforcement,
        friction: friction_arg(friction)?,
        out,
        check,
    };
    solve_with(py, problem, SolidSolver::Decomposition, run)
}

/// Solves a problem in space by the monolithic reference: semismooth Newton on the coupled
/// system of every body (``contactdd monolithic`` on a file with ``dimension = 3``); it also
/// takes a body that only closed contact holds. Checked, released and interrupted as
/// :func:`solve`.
///
/// Args:
///     problem, threads, balance_tol, enforcement, friction, out, check: as for :func:`solve`.
///
/// Returns:
///     A :class:`Result`.
///
/// Raises:
///     ContactddError: a bad argument, or a solve without a result.
///     ConvergenceError: the result is not converged (``check=True``); ``.result`` holds it.
#[pyfunction]
#[pyo3(signature = (problem, threads = None, balance_tol = None, enforcement = None, friction = None, out = None, check = true))]
#[allow(clippy::too_many_arguments)]
pub fn space_monolithic(
    py: Python<'_>,
    problem: &Bound<'_, SpaceProblem>,
    threads: Option<usize>,
    balance_tol: Option<f64>,
    enforcement: Option<String>,
    friction: Option<&Bound<'_, PyAny>>,
    out: Option<PathBuf>,
    check: bool,
) -> PyResult<Py<SpaceResult>> {
    let run = SpaceRun {
        threads,
        balance_tol,
        enforcement,
        friction: friction_arg(friction)?,
        out,
        check,
    };
    solve_with(py, problem, SolidSolver::Monolithic, run)
}

/// Runs `solver` on `problem` with the settings of `run`, writes the folder and makes the result.
fn solve_with(
    py: Python<'_>,
    problem: &Bound<'_, SpaceProblem>,
    solver: SolidSolver,
    run: SpaceRun,
) -> PyResult<Py<SpaceResult>> {
    let mut model = problem.borrow().model()?;
    if let Some(b) = run.balance_tol {
        if !(b.is_finite() && b > 0.0) {
            return Err(input_error(format!(
                "balance_tol: must be positive, got {}",
                shown(b)
            )));
        }
        Arc::make_mut(&mut model).balance_tol = b;
    }
    if let Some(name) = &run.enforcement {
        let e: EnforcementSpec =
            from_name(name).map_err(|m| input_error(format!("enforcement: {m}")))?;
        let pairs = &mut Arc::make_mut(&mut model).pairs;
        pairs.iter_mut().for_each(|p| p.enforcement = e.into());
    }
    if let Some(f) = run.friction {
        let pairs = &mut Arc::make_mut(&mut model).pairs;
        pairs.iter_mut().for_each(|p| p.friction = f);
    }
    if run.threads == Some(0) {
        return Err(input_error("threads: must be at least 1, got 0"));
    }
    let threads = run.threads.or(model.threads);
    let m = model.clone();
    let outcome = run_interruptible(py, move |_| {
        pooled(threads, || run_solid(&m, solver).map_err(|e| e.to_string()))
    })?;
    let outcome = outcome.and_then(|o| o).map_err(input_error)?;
    if let Some(dir) = run.out {
        write_folder(py, &dir, model.clone(), &outcome)?;
    }
    let (converged, message) = (outcome.converged, failure_message(&outcome));
    let result = Py::new(py, SpaceResult::new(py, model, outcome)?)?;
    if run.check && !converged {
        return Err(convergence_error(py, &message, result.into_any()));
    }
    Ok(result)
}

/// The message of a result that did not converge, as the command line's verdict says it.
fn failure_message(o: &SolidOutcome) -> String {
    let n = o.solution.newton_steps;
    format!(
        "not converged after {n} Newton step{} ({}): {}",
        if n == 1 { "" } else { "s" },
        o.solver.label(),
        o.reason.as_deref().unwrap_or("the check failed")
    )
}

/// Runs `f` in a rayon pool of `threads` workers (`None`: the global pool).
fn pooled<T: Send>(threads: Option<usize>, f: impl FnOnce() -> T + Send) -> Result<T, String> {
    match threads {
        None => Ok(f()),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map(|pool| pool.install(f))
            .map_err(|e| format!("threads: cannot start {n} worker threads: {e}")),
    }
}
