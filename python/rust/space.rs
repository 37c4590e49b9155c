//! `contactdd.space`: problems in space (`dimension = 3`, tetrahedral bodies) read from a problem
//! file ([`SpaceProblem`]) and solved by the decomposition ([`space_solve`]) or the monolithic
//! reference ([`space_monolithic`]), each checked by the independent force balance of
//! `contactdd_io::solid_run::run_solid`, as `contactdd solve` and `contactdd monolithic` do.
//!
//! Errors map as in the plane: a file that cannot be read is a `ContactddIOError`, a bad file,
//! a bad argument or a body the decomposition cannot hold a `ContactddError` (the message the
//! command line prints), a result that does not converge a `ConvergenceError` holding it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyTuple;

use contactdd_io::solid_problem::{is_solid_text, SolidProblem};
use contactdd_io::solid_run::{run_solid, SolidOutcome, SolidSolver};
use contactdd_io::solid_setup::{resolve_solid, SolidLoadError, SolidModel};

use crate::convert::shown;
use crate::error::{convergence_error, input_error, os_error};
use crate::run::run_interruptible;
use crate::space_result::{write_folder, SpaceResult};

/// A contact problem in space: tetrahedral bodies, their supports and loads, the contact pairs
/// and the solver settings of a problem file with ``dimension = 3`` (``docs/three-d.md``,
/// "Problem files and results"), every value checked and every body meshed.
///
/// Made by :meth:`from_toml` or :meth:`from_toml_str`; solved by :func:`contactdd.space.solve`
/// (the decomposition) or :func:`contactdd.space.monolithic` (the reference).
#[pyclass(module = "contactdd.space", name = "Problem", frozen)]
pub struct SpaceProblem {
    pub(crate) model: Arc<SolidModel>,
}

impl SpaceProblem {
    /// Parses and resolves `text`, a problem file in space named `source` in messages, whose
    /// relative Gmsh paths resolve against `base`; `stem` is the default name.
    fn parse(
        py: Python<'_>,
        text: &str,
        source: &str,
        base: &Path,
        stem: &str,
    ) -> PyResult<SpaceProblem> {
        if !is_solid_text(text) {
            return Err(input_error(format!(
                "{source}: not a problem in space: it has no top-level `dimension = 3` \
                 (contactdd.Problem.from_toml reads a planar problem)"
            )));
        }
        let problem: SolidProblem = toml::from_str(text).map_err(|e| {
            input_error(SolidLoadError::Toml {
                file: source.to_string(),
                source: e,
            })
        })?;
        let invalid = |message: String| {
            input_error(SolidLoadError::Invalid {
                file: source.to_string(),
                message,
            })
        };
        let model = py
            .detach(|| resolve_solid(problem, base, stem))
            .map_err(invalid)?;
        Ok(SpaceProblem {
            model: Arc::new(model),
        })
    }
}

#[pymethods]
impl SpaceProblem {
    /// Reads a problem file in space (``dimension = 3``).
    ///
    /// Relative Gmsh mesh paths resolve against the file's folder; the problem's name defaults
    /// to the file's stem.
    ///
    /// Args:
    ///     path: the problem file.
    ///
    /// Raises:
    ///     ContactddIOError: the file cannot be read (an ``OSError``).
    ///     ContactddError: the file is not a valid problem in space; the message names the
    ///         body, pair or key.
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<SpaceProblem> {
        let text = py.detach(|| std::fs::read_to_string(&path)).map_err(|e| {
            let errno = e.raw_os_error();
            let message = SolidLoadError::Io {
                path: path.display().to_string(),
                source: e,
            };
            os_error(py, message.to_string(), errno)
        })?;
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("problem");
        let base = path.parent().unwrap_or(Path::new(""));
        let source = path.display().to_string();
        SpaceProblem::parse(py, &text, &source, base, stem)
    }

    /// Parses the text of a problem file in space (``dimension = 3``).
    ///
    /// Args:
    ///     text: the file's content.
    ///     base_dir: folder against which relative mesh paths resolve (default: the current
    ///         folder).
    ///     source: name of the text in error messages.
    ///
    /// Raises:
    ///     ContactddError: the text is not a valid problem in space.
    #[staticmethod]
    #[pyo3(signature = (text, base_dir = None, source = "<string>"))]
    fn from_toml_str(
        py: Python<'_>,
        text: &str,
        base_dir: Option<PathBuf>,
        source: &str,
    ) -> PyResult<SpaceProblem> {
        let base = base_dir.unwrap_or_else(|| PathBuf::from("."));
        SpaceProblem::parse(py, text, source, &base, "problem")
    }

    /// The problem's name.
    #[getter]
    fn name(&self) -> String {
        self.model.name.clone()
    }

    /// The bodies' names, in problem order.
    #[getter]
    fn bodies(&self) -> Vec<String> {
        self.model.bodies.iter().map(|b| b.name.clone()).collect()
    }

    /// The contact pairs' names, in problem order.
    #[getter]
    fn contacts(&self) -> Vec<String> {
        self.model.pairs.iter().map(|p| p.name.clone()).collect()
    }

    /// The force balance's tolerance of a converged result (``[solver] balance-tol``, default
    /// 1e-6).
    #[getter]
    fn balance_tol(&self) -> f64 {
        self.model.balance_tol
    }

    /// The worker threads of ``[solver] threads``, or ``None`` (all cores).
    #[getter]
    fn threads(&self) -> Option<usize> {
        self.model.threads
    }

    fn __repr__(&self) -> String {
        format!(
            "<contactdd.space.Problem '{}': {} bodies, {} contact pairs>",
            self.model.name,
            self.model.bodies.len(),
            self.model.pairs.len()
        )
    }

    /// Not picklable: a problem in space holds its meshes, not its file.
    fn __reduce__<'py>(&self) -> PyResult<Bound<'py, PyTuple>> {
        Err(input_error(
            "a contactdd.space.Problem cannot be pickled: pickle the problem file's text and \
             read it with Problem.from_toml_str",
        ))
    }
}

/// How a solve in space runs: the keywords of [`space_solve`] and [`space_monolithic`].
struct SpaceRun {
    threads: Option<usize>,
    balance_tol: Option<f64>,
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
#[pyo3(signature = (problem, threads = None, balance_tol = None, out = None, check = true))]
pub fn space_solve(
    py: Python<'_>,
    problem: &Bound<'_, SpaceProblem>,
    threads: Option<usize>,
    balance_tol: Option<f64>,
    out: Option<PathBuf>,
    check: bool,
) -> PyResult<Py<SpaceResult>> {
    let run = SpaceRun {
        threads,
        balance_tol,
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
///     problem, threads, balance_tol, out, check: as for :func:`solve`.
///
/// Returns:
///     A :class:`Result`.
///
/// Raises:
///     ContactddError: a bad argument, or a solve without a result.
///     ConvergenceError: the result is not converged (``check=True``); ``.result`` holds it.
#[pyfunction]
#[pyo3(signature = (problem, threads = None, balance_tol = None, out = None, check = true))]
pub fn space_monolithic(
    py: Python<'_>,
    problem: &Bound<'_, SpaceProblem>,
    threads: Option<usize>,
    balance_tol: Option<f64>,
    out: Option<PathBuf>,
    check: bool,
) -> PyResult<Py<SpaceResult>> {
    let run = SpaceRun {
        threads,
        balance_tol,
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
    let mut model = problem.get().model.clone();
    if let Some(b) = run.balance_tol {
        if !(b.is_finite() && b > 0.0) {
            return Err(input_error(format!(
                "balance_tol: must be positive, got {}",
                shown(b)
            )));
        }
        Arc::make_mut(&mut model).balance_tol = b;
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
