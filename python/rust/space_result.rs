//! The result of a solve in space: `contactdd.space.Result` and `contactdd.space.Body`. The arrays
//! are copied into numpy once, when the result is made; the Rust model and outcome are kept for
//! the result folder and the summary. A result unpickled or read from a result folder holds its
//! summary instead, and writes no files.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple, PyType};

use contactdd_core::solid::element::elasticity;
use contactdd_core::solid::post::{nodal_stresses, von_mises};
use contactdd_core::solid::TetOrder;
use contactdd_ddm::contact3d::DiscStatus;
use contactdd_ddm::solid_contact::SolidContactPoint;
use contactdd_io::solid_results::{solid_summary, write_solid_results};
use contactdd_io::solid_run::SolidOutcome;
use contactdd_io::solid_setup::{SolidBodyModel, SolidModel};

use crate::convert::{array1, array2};
use crate::error::input_error;
use crate::results::json_to_py;
use crate::state::{attributes, get, reduce};

/// The attributes of a [`SpaceBody`] in its state dict.
const BODY_STATE: [&str; 8] = [
    "name",
    "order",
    "nodes",
    "tetrahedra",
    "displacement",
    "stress",
    "von_mises",
    "imbalance",
];

/// The attributes of a [`SpaceResult`] in its state dict (with `summary`).
const RESULT_STATE: [&str; 8] = [
    "converged",
    "reason",
    "solver",
    "newton_steps",
    "bodies",
    "contact",
    "balance",
    "timing",
];

/// Where a result's summary and files come from.
enum Origin {
    /// A solve of this process.
    Solved {
        model: Arc<SolidModel>,
        outcome: Arc<SolidOutcome>,
    },
    /// Unpickled or read from a result folder: the summary it had.
    Saved { summary: Py<PyAny> },
}

/// The fields of one tetrahedral body.
#[pyclass(module = "contactdd.space", name = "Body", frozen)]
pub struct SpaceBody {
    /// Body name.
    #[pyo3(get)]
    name: String,
    /// Element order, ``"p1"`` (4-node tetrahedra) or ``"p2"`` (10-node).
    #[pyo3(get)]
    order: String,
    /// ``(n, 3)`` node coordinates (undeformed).
    #[pyo3(get)]
    nodes: Py<PyAny>,
    /// ``(m, 4)`` (P1) or ``(m, 10)`` (P2) node indices of the tetrahedra, in Gmsh's order (the
    /// vertices, then the mid-edge nodes of the edges 0-1, 1-2, 0-2, 0-3, 2-3, 1-3).
    #[pyo3(get)]
    tetrahedra: Py<PyAny>,
    /// ``(n, 3)`` displacement.
    #[pyo3(get)]
    displacement: Py<PyAny>,
    /// ``(n, 6)`` nodal (averaged) stress ``[σ_xx, σ_yy, σ_zz, σ_yz, σ_xz, σ_xy]``.
    #[pyo3(get)]
    stress: Py<PyAny>,
    /// ``(n,)`` nodal von Mises stress.
    #[pyo3(get)]
    von_mises: Py<PyAny>,
    /// The force balance's imbalance of the body: the largest net force or moment its loads,
    /// contact forces and reactions leave, relative to the largest force total of a body.
    #[pyo3(get)]
    imbalance: f64,
}

impl SpaceBody {
    fn new(
        py: Python<'_>,
        body: &SolidBodyModel,
        u: &[f64],
        imbalance: f64,
    ) -> PyResult<SpaceBody> {
        let mesh = &body.mesh;
        let stress = nodal_stresses(mesh, &elasticity(&body.material), u)
            .map_err(|e| input_error(format!("body '{}': {e}", body.name)))?;
        let mises: Vec<f64> = stress.iter().map(|s| von_mises(*s)).collect();
        let nodes: Vec<f64> = mesh.nodes().iter().flatten().copied().collect();
        let tets: Vec<i64> = mesh.tets().iter().map(|&v| v as i64).collect();
        let stress: Vec<f64> = stress.iter().flatten().copied().collect();
        Ok(SpaceBody {
            name: body.name.clone(),
            order: if mesh.order() == TetOrder::P2 {
                "p2"
            } else {
                "p1"
            }
            .into(),
            nodes: array2(py, nodes, 3)?.unbind(),
            tetrahedra: array2(py, tets, mesh.order().nodes_per_tet())?.unbind(),
            displacement: array2(py, u.to_vec(), 3)?.unbind(),
            stress: array2(py, stress, 6)?.unbind(),
            von_mises: array1(py, mises).unbind(),
            imbalance,
        })
    }
}

#[pymethods]
impl SpaceBody {
    /// Pickles the body as its attributes.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        reduce(slf.as_any(), attributes(slf.as_any(), &BODY_STATE)?)
    }

    /// A body from the dict of its attributes (pickle, :func:`contactdd.load_results`).
    #[classmethod]
    fn _from_state(_cls: &Bound<'_, PyType>, state: &Bound<'_, PyDict>) -> PyResult<SpaceBody> {
        Ok(SpaceBody {
            name: get(state, "name")?.extract()?,
            order: get(state, "order")?.extract()?,
            nodes: get(state, "nodes")?.unbind(),
            tetrahedra: get(state, "tetrahedra")?.unbind(),
            displacement: get(state, "displacement")?.unbind(),
            stress: get(state, "stress")?.unbind(),
            von_mises: get(state, "von_mises")?.unbind(),
            imbalance: get(state, "imbalance")?.extract()?,
        })
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let n: usize = self.nodes.bind(py).len()?;
        let m: usize = self.tetrahedra.bind(py).len()?;
        Ok(format!(
            "<contactdd.space.Body '{}': {} nodes, {} {} tetrahedra>",
            self.name, n, m, self.order
        ))
    }
}

/// The result of a solve in space (also the result of one that did not converge, see
/// :class:`contactdd.ConvergenceError`).
#[pyclass(module = "contactdd.space", name = "Result", frozen)]
pub struct SpaceResult {
    /// True if the result is a solution: the closed set settled and the independent force
    /// balance holds.
    #[pyo3(get)]
    converged: bool,
    /// Why the result did not converge (``None`` when it did).
    #[pyo3(get)]
    reason: Option<String>,
    /// The solver that ran, as the command line prints it: ``"interface newton (decomposition
    /// in space)"`` or ``"monolithic reference (semismooth newton)"``.
    #[pyo3(get)]
    solver: String,
    /// Newton steps taken (the last one confirms the closed set).
    #[pyo3(get)]
    newton_steps: usize,
    /// Per-body fields (:class:`Body`), in problem order.
    #[pyo3(get)]
    bodies: Py<PyList>,
    /// The contact points with a partner, the rows of ``contact.csv``, as a dict of ``(k,)``
    /// numpy arrays: ``pair`` and ``body`` (the pair's name and its reference body's, strings),
    /// ``node`` (the reference body's node), ``x``, ``y``, ``z`` (its position), ``weight`` (its
    /// nodal area), ``gap`` (the initial gap) and ``pressure`` (≥ 0); with a frictional pair
    /// also ``traction_x``, ``traction_y``, ``traction_z`` (the tangential traction on the
    /// reference side), ``slip_x``, ``slip_y``, ``slip_z`` (its slip relative to the partner;
    /// NaN at a frictionless pair's points) and ``status`` (``"stick"``, ``"slip"``, ``"open"``,
    /// or ``""`` at a frictionless pair's points).
    #[pyo3(get)]
    contact: Py<PyDict>,
    /// The independent check: ``{"worst": the largest imbalance of a body, "tol": the
    /// balance-tol, "contact_law": the pressures' largest deviation from the contact law of the
    /// displacements, relative to the largest}``, and with a frictional pair ``"friction_law"``:
    /// the tractions' largest deviation from the friction law, on the same scale.
    #[pyo3(get)]
    balance: Py<PyDict>,
    /// Wall time per phase in seconds.
    #[pyo3(get)]
    timing: Py<PyDict>,
    origin: Origin,
}

impl SpaceResult {
    /// Converts the outcome of a solve of `model`.
    pub fn new(
        py: Python<'_>,
        model: Arc<SolidModel>,
        outcome: SolidOutcome,
    ) -> PyResult<SpaceResult> {
        let bodies = (model.bodies.iter().enumerate())
            .map(|(b, body)| {
                let u = &outcome.solution.displacements[b];
                let imbalance = outcome.balance.bodies[b].imbalance;
                Py::new(py, SpaceBody::new(py, body, u, imbalance)?)
            })
            .collect::<PyResult<Vec<_>>>()?;
        let balance = PyDict::new(py);
        balance.set_item("worst", outcome.balance.worst())?;
        balance.set_item("tol", model.balance_tol)?;
        balance.set_item("contact_law", outcome.balance.contact_law)?;
        if model.pairs.iter().any(|p| p.friction.is_active()) {
            balance.set_item("friction_law", outcome.balance.friction_law)?;
        }
        let timing = PyDict::new(py);
        for (phase, s) in &outcome.solution.timings {
            timing.set_item(phase, s)?;
        }
        Ok(SpaceResult {
            converged: outcome.converged,
            reason: outcome.reason.clone(),
            solver: outcome.solver.label().to_string(),
            newton_steps: outcome.solution.newton_steps,
            bodies: PyList::new(py, bodies)?.unbind(),
            contact: contact_table(py, &model, &outcome)?.unbind(),
            balance: balance.unbind(),
            timing: timing.unbind(),
            origin: Origin::Solved {
                model,
                outcome: Arc::new(outcome),
            },
        })
    }
}

/// The contact points of `outcome` as the dict of numpy arrays of [`CONTACT_COLUMNS`].
fn contact_table<'py>(
    py: Python<'py>,
    model: &SolidModel,
    outcome: &SolidOutcome,
) -> PyResult<Bound<'py, PyDict>> {
    let points = &outcome.solution.points;
    let pair: Vec<&str> = points
        .iter()
        .map(|p| model.pairs[p.pair].name.as_str())
        .collect();
    let body: Vec<&str> = (points.iter())
        .map(|p| model.bodies[model.pairs[p.pair].sides[0].0].name.as_str())
        .collect();
    let numpy = py.import("numpy")?;
    let strings = |names: Vec<&str>| -> PyResult<Bound<'py, PyAny>> {
        let kwargs = PyDict::new(py);
        kwargs.set_item("dtype", "str")?;
        numpy.call_method("array", (PyList::new(py, names)?,), Some(&kwargs))
    };
    let table = PyDict::new(py);
    table.set_item("pair", strings(pair)?)?;
    table.set_item("body", strings(body)?)?;
    let node: Vec<i64> = points.iter().map(|p| p.node as i64).collect();
    table.set_item("node", array1(py, node))?;
    for (c, name) in ["x", "y", "z"].into_iter().enumerate() {
        table.set_item(
            name,
            array1(py, points.iter().map(|p| p.position[c]).collect()),
        )?;
    }
    table.set_item(
        "weight",
        array1(py, points.iter().map(|p| p.weight).collect()),
    )?;
    table.set_item("gap", array1(py, points.iter().map(|p| p.gap).collect()))?;
    table.set_item(
        "pressure",
        array1(py, points.iter().map(|p| p.pressure).collect()),
    )?;
    if model.pairs.iter().any(|p| p.friction.is_active()) {
        friction_columns(py, points, &table)?;
        let status: Vec<&str> = (points.iter())
            .map(|p| match p.friction.as_ref().map(|f| f.status) {
                None => "",
                Some(None) => "open",
                Some(Some(DiscStatus::Stick)) => "stick",
                Some(Some(DiscStatus::Slip)) => "slip",
            })
            .collect();
        table.set_item("status", strings(status)?)?;
    }
    Ok(table)
}

/// The traction and slip columns of the contact table (NaN at a frictionless pair's points).
fn friction_columns(
    py: Python<'_>,
    points: &[SolidContactPoint],
    table: &Bound<'_, PyDict>,
) -> PyResult<()> {
    let vector = |p: &SolidContactPoint, slip: bool| match &p.friction {
        Some(f) if slip => f.slip_vector(),
        Some(f) => f.traction_vector(),
        None => [f64::NAN; 3],
    };
    for (slip, stem) in [(false, "traction"), (true, "slip")] {
        for (c, axis) in ["x", "y", "z"].into_iter().enumerate() {
            let values = points.iter().map(|p| vector(p, slip)[c]).collect();
            table.set_item(format!("{stem}_{axis}"), array1(py, values))?;
        }
    }
    Ok(())
}

#[pymethods]
impl SpaceResult {
    /// The summary of the solve as a dict: the content of the ``summary.json`` file the command
    /// line writes, without its list of files.
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match &self.origin {
            Origin::Solved { model, outcome } => json_to_py(py, &solid_summary(model, outcome)),
            Origin::Saved { summary } => py.import("copy")?.call_method1("deepcopy", (summary,)),
        }
    }

    /// Writes the result folder into ``directory`` (created if needed), exactly as ``contactdd
    /// solve --out`` does: ``summary.json``, ``contact.csv`` and one ``.vtu`` file per body (or
    /// ``bodies.vtu``), encoded as the problem's ``[output]`` table says.
    ///
    /// Args:
    ///     directory: the folder to write.
    ///
    /// Returns:
    ///     The paths of the files written.
    ///
    /// Raises:
    ///     ContactddError: the result was unpickled or read by :func:`contactdd.load_results`
    ///         (it holds no solver data to write from), or a file cannot be written.
    fn write(&self, py: Python<'_>, directory: PathBuf) -> PyResult<Vec<String>> {
        let (model, outcome) = match &self.origin {
            Origin::Solved { model, outcome } => (model.clone(), outcome.clone()),
            Origin::Saved { .. } => {
                return Err(input_error(
                    "this result was unpickled or read from a result folder: it holds the \
                     fields and the summary but not the solver data that result files are \
                     written from (write them from the result of the solve itself)",
                ))
            }
        };
        let paths = write_folder(py, &directory, model, &outcome)?;
        Ok(paths.iter().map(|p| p.display().to_string()).collect())
    }

    /// Pickles the result as its attributes and its summary; the unpickled result has the same
    /// attributes and :meth:`summary` but cannot :meth:`write`.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let state = attributes(slf.as_any(), &RESULT_STATE)?;
        state.set_item("summary", slf.borrow().summary(slf.py())?)?;
        reduce(slf.as_any(), state)
    }

    /// A result from the dict of its attributes and ``summary`` (pickle,
    /// :func:`contactdd.load_results`).
    #[classmethod]
    fn _from_state(_cls: &Bound<'_, PyType>, state: &Bound<'_, PyDict>) -> PyResult<SpaceResult> {
        Ok(SpaceResult {
            converged: get(state, "converged")?.extract()?,
            reason: get(state, "reason")?.extract()?,
            solver: get(state, "solver")?.extract()?,
            newton_steps: get(state, "newton_steps")?.extract()?,
            bodies: get(state, "bodies")?.cast_into::<PyList>()?.unbind(),
            contact: get(state, "contact")?.cast_into::<PyDict>()?.unbind(),
            balance: get(state, "balance")?.cast_into::<PyDict>()?.unbind(),
            timing: get(state, "timing")?.cast_into::<PyDict>()?.unbind(),
            origin: Origin::Saved {
                summary: get(state, "summary")?.unbind(),
            },
        })
    }

    fn __repr__(&self) -> String {
        let verdict = if self.converged {
            "converged"
        } else {
            "not converged"
        };
        format!(
            "<contactdd.space.Result: {verdict} after {} Newton steps ({})>",
            self.newton_steps, self.solver
        )
    }
}

/// Writes the result folder of `outcome` into `dir` with the GIL released; an error names it.
pub fn write_folder(
    py: Python<'_>,
    dir: &Path,
    model: Arc<SolidModel>,
    outcome: &SolidOutcome,
) -> PyResult<Vec<PathBuf>> {
    py.detach(|| write_solid_results(dir, &model, outcome))
        .map_err(|e| {
            input_error(format!(
                "cannot write the results to '{}': {e}",
                dir.display()
            ))
        })
}
