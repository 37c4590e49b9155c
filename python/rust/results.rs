//! Result objects: `contactdd.Result` (a domain decomposition solve), `contactdd.Body`,
//! `contactdd.Contact` and `contactdd.MonolithicResult`. The arrays are copied into numpy once,
//! when the result is made; the Rust [`Solution`] is kept for output files and the summary. A
//! result that was unpickled or read from a result folder ([`Origin::Saved`]) holds its summary
//! instead, and writes no files.

use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple, PyType};

use contactdd_core::DIM;
use contactdd_ddm::solution::BodyResult;
use contactdd_ddm::{Condensation, Model, MonolithicSolution, Solution};
use contactdd_io::output::stop_name;

use crate::contact_result::contact_list;
use crate::convert::{array1, array2, name_of};
use crate::error::input_error;
use crate::options::gamma_to_py;
use crate::state::{attributes, get, reduce};

/// Where a result's summary and files come from.
enum Origin<S> {
    /// A solve of this process: the solver's data, from which the files are written.
    Solved { model: Arc<Model>, solution: Arc<S> },
    /// Unpickled or read from a result folder: the summary it had.
    Saved { summary: Py<PyAny> },
}

impl<S> Origin<S> {
    /// The solver data, or the error of a saved result asked to write files.
    fn solved(&self) -> PyResult<(Arc<Model>, Arc<S>)> {
        match self {
            Origin::Solved { model, solution } => Ok((model.clone(), solution.clone())),
            Origin::Saved { .. } => Err(input_error(
                "this result was unpickled or read from a result folder: it holds the fields and \
                 the summary but not the solver data that result files are written from (write \
                 them from the result of the solve itself)",
            )),
        }
    }

    /// The summary: made by `make` from the solver data, or a copy of the saved one.
    fn summary<'py>(
        &self,
        py: Python<'py>,
        make: impl FnOnce(&Model, &S) -> serde_json::Value,
    ) -> PyResult<Bound<'py, PyAny>> {
        match self {
            Origin::Solved { model, solution } => json_to_py(py, &make(model, solution)),
            Origin::Saved { summary } => py.import("copy")?.call_method1("deepcopy", (summary,)),
        }
    }
}

/// The attributes of a [`Body`], in its state dict.
const BODY_STATE: [&str; 9] = [
    "name",
    "order",
    "condensation",
    "nodes",
    "triangles",
    "displacement",
    "stress",
    "von_mises",
    "contact_pressure",
];

/// The attributes of a [`SolveResult`] in its state dict (with `summary`).
const RESULT_STATE: [&str; 17] = [
    "converged",
    "stop",
    "iterations",
    "message",
    "iteration",
    "solver",
    "method",
    "gamma",
    "theta",
    "history",
    "bodies",
    "contact",
    "timing",
    "updates",
    "gap_tol",
    "load_factor",
    "monitor",
];

/// The attributes of a [`MonolithicResult`] in its state dict (with `summary`).
const MONOLITHIC_STATE: [&str; 5] = [
    "newton_steps",
    "rigid_modes",
    "bodies",
    "contact",
    "seconds",
];

/// The fields of one body.
#[pyclass(module = "contactdd", name = "Body", frozen)]
pub struct Body {
    /// Body name.
    #[pyo3(get)]
    name: String,
    /// Element order, ``"p1"`` or ``"p2"``.
    #[pyo3(get)]
    order: String,
    /// How the solve condensed the body on its contact points, ``"dense"`` or ``"sparse"``
    /// (the cost model's choice under ``condensation = "auto"``); ``None`` for the monolithic
    /// reference, which does not condense.
    #[pyo3(get)]
    condensation: Option<String>,
    /// ``(n, 2)`` node coordinates (undeformed).
    #[pyo3(get)]
    nodes: Py<PyAny>,
    /// ``(m, 3)`` (P1) or ``(m, 6)`` (P2) node indices of the triangles.
    #[pyo3(get)]
    triangles: Py<PyAny>,
    /// ``(n, 2)`` displacement.
    #[pyo3(get)]
    displacement: Py<PyAny>,
    /// ``(n, 4)`` nodal (averaged) stress ``[σ_xx, σ_yy, σ_xy, σ_zz]``.
    #[pyo3(get)]
    stress: Py<PyAny>,
    /// ``(n,)`` nodal von Mises stress.
    #[pyo3(get)]
    von_mises: Py<PyAny>,
    /// ``(n,)`` normal contact stress σ_n (≤ 0, compressive) at contact nodes, 0 elsewhere (the
    /// VTU files' ``sigma_n``; :attr:`Contact.pressure` is the pressure p ≥ 0).
    #[pyo3(get)]
    contact_pressure: Py<PyAny>,
}

#[pymethods]
impl Body {
    /// Pickles the body as its attributes.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        reduce(slf.as_any(), attributes(slf.as_any(), &BODY_STATE)?)
    }

    /// A body from the dict of its attributes (pickle, :func:`contactdd.load_results`).
    #[classmethod]
    fn _from_state(_cls: &Bound<'_, PyType>, state: &Bound<'_, PyDict>) -> PyResult<Body> {
        Ok(Body {
            name: get(state, "name")?.extract()?,
            order: get(state, "order")?.extract()?,
            // Absent from results saved before it was reported.
            condensation: match state.get_item("condensation")? {
                Some(v) => v.extract()?,
                None => None,
            },
            nodes: get(state, "nodes")?.unbind(),
            triangles: get(state, "triangles")?.unbind(),
            displacement: get(state, "displacement")?.unbind(),
            stress: get(state, "stress")?.unbind(),
            von_mises: get(state, "von_mises")?.unbind(),
            contact_pressure: get(state, "contact_pressure")?.unbind(),
        })
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let n: usize = self.nodes.bind(py).len()?;
        let m: usize = self.triangles.bind(py).len()?;
        Ok(format!(
            "<contactdd.Body '{}': {} nodes, {} {} triangles>",
            self.name, n, m, self.order
        ))
    }
}

impl Body {
    fn new(py: Python<'_>, b: &BodyResult, condensation: Option<String>) -> PyResult<Body> {
        let mesh = &b.mesh;
        let npc = mesh.order().nodes_per_cell();
        let nodes: Vec<f64> = mesh.nodes().iter().flatten().copied().collect();
        let cells: Vec<i64> = mesh.cells().iter().map(|&v| v as i64).collect();
        let stress: Vec<f64> = b.stress.iter().flatten().copied().collect();
        Ok(Body {
            name: b.name.clone(),
            order: name_of(&mesh.order()),
            condensation,
            nodes: array2(py, nodes, DIM)?.unbind(),
            triangles: array2(py, cells, npc)?.unbind(),
            displacement: array2(py, b.displacement.clone(), DIM)?.unbind(),
            stress: array2(py, stress, 4)?.unbind(),
            von_mises: array1(py, b.von_mises.clone()).unbind(),
            contact_pressure: array1(py, b.contact_pressure.clone()).unbind(),
        })
    }
}

/// The bodies' results, each with its condensation path where the solve had one.
fn bodies_list(
    py: Python<'_>,
    bodies: &[BodyResult],
    paths: Option<&[Condensation]>,
) -> PyResult<Py<PyList>> {
    let items = (bodies.iter().enumerate())
        .map(|(b, body)| {
            let path = paths.and_then(|p| p.get(b)).map(ToString::to_string);
            Py::new(py, Body::new(py, body, path)?)
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok(PyList::new(py, items)?.unbind())
}

/// A JSON value as Python data (through Python's `json` module).
pub fn json_to_py<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| input_error(format!("cannot serialize the summary: {e}")))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// The result of a domain decomposition solve (also the partial result of a failed one, see
/// :class:`ConvergenceError`).
#[pyclass(module = "contactdd", name = "Result", frozen)]
pub struct SolveResult {
    /// True if every body met the tolerance.
    #[pyo3(get)]
    converged: bool,
    /// How the iteration ended: ``"converged"``, ``"max-iterations"``, ``"diverged"`` or
    /// ``"interrupted"``.
    #[pyo3(get)]
    stop: String,
    /// Iterations taken (m).
    #[pyo3(get)]
    iterations: usize,
    /// Why the solve did not converge (``None`` when it did).
    #[pyo3(get)]
    message: Option<String>,
    /// The iteration that ran: ``"interface-newton"`` or ``"robin-sweeps"``.
    #[pyo3(get)]
    iteration: String,
    /// The solver settings in words, as ``contactdd solve`` and ``contactdd check`` print them.
    #[pyo3(get)]
    solver: String,
    /// The Robin sweeps' method (unused by the interface Newton method).
    #[pyo3(get)]
    method: String,
    /// The γ used: a float, or ``"auto"``.
    #[pyo3(get)]
    gamma: Py<PyAny>,
    /// Penalty θ of each contact pair.
    #[pyo3(get)]
    theta: Vec<f64>,
    /// Per-iteration history: ``k`` (m,), ``gamma`` (m,: the sweeps' γ, the Newton method's step
    /// length), ``measure`` (m,: what the stopping test compares with the tolerance), and per
    /// body ``rel_change``,
    /// ``active`` (closed points) and ``normal_force`` (Σ w |σ_n|), each (m, number of bodies).
    #[pyo3(get)]
    history: Py<PyDict>,
    /// Per-body fields (:class:`Body`), in problem order.
    #[pyo3(get)]
    bodies: Py<PyList>,
    /// Per-pair contact results (:class:`Contact`), in problem order.
    #[pyo3(get)]
    contact: Py<PyList>,
    /// Wall time per phase in seconds.
    #[pyo3(get)]
    timing: Py<PyDict>,
    /// Augmented Lagrangian multiplier updates (inner solves) taken; 0 when every pair uses the
    /// penalty formulation.
    #[pyo3(get)]
    updates: usize,
    /// The gap tolerance of the augmented Lagrangian pairs (a length), or ``None``.
    #[pyo3(get)]
    gap_tol: Option<f64>,
    /// The load factor of this solve (1.0 unless it is a step of :func:`solve_steps`).
    #[pyo3(get)]
    load_factor: f64,
    /// The mean displacement ``(ux, uy)`` of the monitored boundary (the ``monitor`` setting),
    /// or ``None`` without one.
    #[pyo3(get)]
    monitor: Option<(f64, f64)>,
    origin: Origin<Solution>,
}

impl SolveResult {
    /// Converts a solution of `model`.
    pub fn new(py: Python<'_>, model: Arc<Model>, sol: Solution) -> PyResult<SolveResult> {
        let nb = model.bodies.len();
        let h = &sol.history;
        let history = PyDict::new(py);
        history.set_item("k", array1(py, h.iter().map(|r| r.k as i64).collect()))?;
        history.set_item("gamma", array1(py, h.iter().map(|r| r.gamma).collect()))?;
        history.set_item("measure", array1(py, h.iter().map(|r| r.measure).collect()))?;
        let per_body = |f: &dyn Fn(&contactdd_ddm::Record) -> Vec<f64>| -> Vec<f64> {
            h.iter().flat_map(f).collect()
        };
        history.set_item(
            "rel_change",
            array2(py, per_body(&|r| r.rel_change.clone()), nb)?,
        )?;
        let active: Vec<i64> = h
            .iter()
            .flat_map(|r| r.active.iter().map(|&a| a as i64))
            .collect();
        history.set_item("active", array2(py, active, nb)?)?;
        history.set_item(
            "normal_force",
            array2(py, per_body(&|r| r.contact_force.clone()), nb)?,
        )?;
        let timing = PyDict::new(py);
        for (k, v) in &sol.timing {
            timing.set_item(k, v)?;
        }
        Ok(SolveResult {
            converged: sol.converged,
            stop: stop_name(&sol.stop).to_string(),
            iterations: sol.iterations,
            message: sol.message.clone(),
            iteration: sol.settings.iteration().to_string(),
            solver: sol.settings.to_string(),
            method: sol.method.name().to_string(),
            gamma: gamma_to_py(py, sol.gamma)?,
            theta: sol.theta.clone(),
            history: history.unbind(),
            bodies: bodies_list(py, &sol.bodies, Some(&sol.condensation))?,
            contact: contact_list(py, &sol.contact, &sol.bodies)?,
            timing: timing.unbind(),
            updates: sol.updates,
            gap_tol: sol.gap_tol,
            load_factor: 1.0,
            monitor: None,
            origin: Origin::Solved {
                model,
                solution: Arc::new(sol),
            },
        })
    }

    /// The result as the step of load factor `factor`.
    pub fn at_load_factor(self, factor: f64) -> SolveResult {
        SolveResult {
            load_factor: factor,
            ..self
        }
    }

    /// The result with the mean displacement of the monitored boundary.
    pub fn with_monitor(self, monitor: Option<[f64; 2]>) -> SolveResult {
        SolveResult {
            monitor: monitor.map(|[ux, uy]| (ux, uy)),
            ..self
        }
    }

    /// The message of a non-converged solve.
    pub fn failure_message(&self) -> String {
        self.message
            .clone()
            .unwrap_or_else(|| "the solve did not converge".into())
    }

    /// True if converged.
    pub fn is_converged(&self) -> bool {
        self.converged
    }
}

#[pymethods]
impl SolveResult {
    /// Writes the VTU files of every body and the summary JSON into ``directory`` (created if
    /// needed), exactly as ``contactdd solve --output`` does.
    ///
    /// Args:
    ///     directory: the folder to write.
    ///     format: the encoding of the VTU files: ``"zlib"`` (appended binary in zlib blocks,
    ///         the smallest), ``"binary"`` (appended raw binary) or ``"ascii"`` (text).
    ///     layout: ``"per-body"`` (one VTU file per body) or ``"collection"`` (one file,
    ///         ``bodies.vtu``, holding every body as its own piece).
    ///
    /// Returns:
    ///     The paths of the files written.
    ///
    /// Raises:
    ///     ContactddError: the result was unpickled or read by :func:`load_results` (it holds no
    ///         solver data to write from), ``format`` is not ``"zlib"``, ``"binary"`` or ``"ascii"``,
    ///         ``layout`` is not ``"per-body"`` or ``"collection"``, or a file cannot be written.
    #[pyo3(signature = (directory, format = "zlib", layout = "per-body"))]
    fn write_vtu(
        &self,
        py: Python<'_>,
        directory: std::path::PathBuf,
        format: &str,
        layout: &str,
    ) -> PyResult<Vec<String>> {
        let vtu = vtu_options(format, layout)?;
        let (model, sol) = self.origin.solved()?;
        let paths = py
            .detach(move || {
                contactdd_io::output::write_results_noted(&directory, &model, &sol, None, vtu)
            })
            .map_err(|e| input_error(format!("cannot write results: {e}")))?;
        Ok(paths.iter().map(|p| p.display().to_string()).collect())
    }

    /// The summary of the solve as a dict: the content of the ``summary.json`` file the command
    /// line writes.
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.origin.summary(py, contactdd_io::output::summary_json)
    }

    /// Pickles the result as its attributes and its summary; the unpickled result has the same
    /// attributes and :meth:`summary` but cannot :meth:`write_vtu`.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let state = attributes(slf.as_any(), &RESULT_STATE)?;
        state.set_item("summary", slf.borrow().summary(slf.py())?)?;
        reduce(slf.as_any(), state)
    }

    /// A result from the dict of its attributes and ``summary`` (pickle,
    /// :func:`contactdd.load_results`).
    #[classmethod]
    fn _from_state(_cls: &Bound<'_, PyType>, state: &Bound<'_, PyDict>) -> PyResult<SolveResult> {
        Ok(SolveResult {
            converged: get(state, "converged")?.extract()?,
            stop: get(state, "stop")?.extract()?,
            iterations: get(state, "iterations")?.extract()?,
            message: get(state, "message")?.extract()?,
            iteration: get(state, "iteration")?.extract()?,
            solver: get(state, "solver")?.extract()?,
            method: get(state, "method")?.extract()?,
            gamma: get(state, "gamma")?.unbind(),
            theta: get(state, "theta")?.extract()?,
            history: get(state, "history")?.cast_into::<PyDict>()?.unbind(),
            bodies: get(state, "bodies")?.cast_into::<PyList>()?.unbind(),
            contact: get(state, "contact")?.cast_into::<PyList>()?.unbind(),
            timing: get(state, "timing")?.cast_into::<PyDict>()?.unbind(),
            updates: get(state, "updates")?.extract()?,
            gap_tol: get(state, "gap_tol")?.extract()?,
            load_factor: get(state, "load_factor")?.extract()?,
            // A result folder read back names no monitored value.
            monitor: match state.get_item("monitor")? {
                Some(m) => m.extract()?,
                None => None,
            },
            origin: Origin::Saved {
                summary: get(state, "summary")?.unbind(),
            },
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "<contactdd.Result: {} after {} iterations ({})>",
            self.stop, self.iterations, self.solver
        )
    }
}

/// The monolithic reference solution (semismooth Newton on all bodies at once).
#[pyclass(module = "contactdd", name = "MonolithicResult", frozen)]
pub struct MonolithicResult {
    /// Newton steps taken.
    #[pyo3(get)]
    newton_steps: usize,
    /// Rigid modes of the assembled problem that were fixed by a zero-mean constraint.
    #[pyo3(get)]
    rigid_modes: Vec<String>,
    /// Per-body fields (:class:`Body`).
    #[pyo3(get)]
    bodies: Py<PyList>,
    /// Per-pair contact results (:class:`Contact`).
    #[pyo3(get)]
    contact: Py<PyList>,
    /// Wall time in seconds.
    #[pyo3(get)]
    seconds: f64,
    origin: Origin<MonolithicSolution>,
}

impl MonolithicResult {
    /// Converts a monolithic solution.
    pub fn new(
        py: Python<'_>,
        model: Arc<Model>,
        sol: MonolithicSolution,
    ) -> PyResult<MonolithicResult> {
        Ok(MonolithicResult {
            newton_steps: sol.newton_steps,
            rigid_modes: sol.rigid_modes.clone(),
            bodies: bodies_list(py, &sol.bodies, None)?,
            contact: contact_list(py, &sol.contact, &sol.bodies)?,
            seconds: sol.seconds,
            origin: Origin::Solved {
                model,
                solution: Arc::new(sol),
            },
        })
    }
}

#[pymethods]
impl MonolithicResult {
    /// Writes ``summary.json``, ``contact.csv`` and one VTU file per body into ``directory``, as
    /// ``contactdd monolithic --output`` does.
    ///
    /// Args:
    ///     directory: the folder to write.
    ///     format: the encoding of the VTU files: ``"zlib"`` (appended binary in zlib blocks,
    ///         the smallest), ``"binary"`` (appended raw binary) or ``"ascii"`` (text).
    ///     layout: ``"per-body"`` (one VTU file per body) or ``"collection"`` (one file,
    ///         ``bodies.vtu``, holding every body as its own piece).
    ///
    /// Returns:
    ///     The paths of the files written.
    ///
    /// Raises:
    ///     ContactddError: the result was unpickled or read by :func:`load_results`, ``format`` is
    ///         not ``"zlib"``, ``"binary"`` or ``"ascii"``, ``layout`` is not ``"per-body"`` or
    ///         ``"collection"``, or a file cannot be written.
    #[pyo3(signature = (directory, format = "zlib", layout = "per-body"))]
    fn write_vtu(
        &self,
        py: Python<'_>,
        directory: std::path::PathBuf,
        format: &str,
        layout: &str,
    ) -> PyResult<Vec<String>> {
        let vtu = vtu_options(format, layout)?;
        let (model, sol) = self.origin.solved()?;
        let paths = py
            .detach(move || {
                contactdd_io::output::write_monolithic_results(&directory, &model, &sol, vtu)
            })
            .map_err(|e| input_error(format!("cannot write results: {e}")))?;
        Ok(paths.iter().map(|p| p.display().to_string()).collect())
    }

    /// The summary as a dict (the ``summary.json`` of a monolithic solve).
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.origin.summary(py, |m, s| {
            contactdd_io::output::monolithic_summary_json(m, s)
        })
    }

    /// Pickles the result as its attributes and its summary (see :meth:`Result.__reduce__`).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let state = attributes(slf.as_any(), &MONOLITHIC_STATE)?;
        state.set_item("summary", slf.borrow().summary(slf.py())?)?;
        reduce(slf.as_any(), state)
    }

    /// A result from the dict of its attributes and ``summary`` (pickle,
    /// :func:`contactdd.load_results`).
    #[classmethod]
    fn _from_state(
        _cls: &Bound<'_, PyType>,
        state: &Bound<'_, PyDict>,
    ) -> PyResult<MonolithicResult> {
        Ok(MonolithicResult {
            newton_steps: get(state, "newton_steps")?.extract()?,
            rigid_modes: get(state, "rigid_modes")?.extract()?,
            bodies: get(state, "bodies")?.cast_into::<PyList>()?.unbind(),
            contact: get(state, "contact")?.cast_into::<PyList>()?.unbind(),
            seconds: get(state, "seconds")?.extract()?,
            origin: Origin::Saved {
                summary: get(state, "summary")?.unbind(),
            },
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "<contactdd.MonolithicResult: {} Newton steps, rigid modes fixed: [{}]>",
            self.newton_steps,
            self.rigid_modes.join(", ")
        )
    }
}

/// The VTU encoding named `format` and the layout named `layout` (`write_vtu(format=...,
/// layout=...)`); another name is a `ContactddError` naming the valid ones.
fn vtu_options(format: &str, layout: &str) -> PyResult<contactdd_io::vtu::VtuOptions> {
    let error = |e: &dyn std::fmt::Display| input_error(format!("write_vtu: {e}"));
    Ok(contactdd_io::vtu::VtuOptions {
        format: format.parse().map_err(|e| error(&e))?,
        layout: layout.parse().map_err(|e| error(&e))?,
    })
}
