//! `contactdd.Contact`: the contact quantities of one pair, per contact point of either side.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple, PyType};

use contactdd_core::DIM;
use contactdd_ddm::solution::{BodyResult, PairResult};
use contactdd_io::fields::{contact_pressures, friction_point};
use contactdd_io::output::point_status;

use crate::convert::{array1, array2};
use crate::state::{attributes, get, reduce};

/// The attributes of a [`Contact`], in its state dict.
const CONTACT_STATE: [&str; 24] = [
    "name",
    "bodies",
    "side",
    "node",
    "x",
    "y",
    "gap",
    "pressure",
    "nodal_traction",
    "closed",
    "status",
    "weight",
    "normal",
    "nodal_force",
    "forces",
    "max_penetration",
    "complementarity",
    "tangential",
    "slip",
    "total_slip",
    "friction_status",
    "tangential_force",
    "stick_length",
    "slip_length",
];

/// The contact quantities of one contact pair: one entry per contact point of either side
/// (a contact point is a node of a contact boundary).
#[pyclass(module = "contactdd", name = "Contact", frozen)]
pub struct Contact {
    /// Pair name.
    #[pyo3(get)]
    name: String,
    /// The two body names.
    #[pyo3(get)]
    bodies: (String, String),
    /// Side (0 or 1) of each point: which of the two bodies it belongs to.
    #[pyo3(get)]
    side: Py<PyAny>,
    /// Node index of each point in its body.
    #[pyo3(get)]
    node: Py<PyAny>,
    /// Undeformed x coordinate.
    #[pyo3(get)]
    x: Py<PyAny>,
    /// Undeformed y coordinate.
    #[pyo3(get)]
    y: Py<PyAny>,
    /// Gap after deformation d − s (negative: penetration of the penalty solution; ``inf`` where
    /// the normal misses the other body).
    #[pyo3(get)]
    gap: Py<PyAny>,
    /// Contact pressure p ≥ 0: −σ_n where the point's own pressure acts (an own-side pair, the
    /// reference side of a balanced pair), the reference side's pressure read at the point on a
    /// balanced pair's following side; 0 where open (``contact.csv``'s ``pressure``).
    #[pyo3(get)]
    pressure: Py<PyAny>,
    /// The point's own value: σ_n = (d − s)⁻/θ (≤ 0) where its pressure acts, on a balanced
    /// pair's following side the nodal traction F/w (``contact.csv``'s ``nodal_traction``).
    #[pyo3(get)]
    nodal_traction: Py<PyAny>,
    /// True where the point is closed (d − s < 0).
    #[pyo3(get)]
    closed: Py<PyAny>,
    /// Status of each point as in ``summary.json``: ``"closed"``, ``"open"`` or
    /// ``"no-partner"`` (the normal misses the other body).
    #[pyo3(get)]
    status: Vec<String>,
    /// Nodal quadrature weight (length) of each point.
    #[pyo3(get)]
    weight: Py<PyAny>,
    /// ``(k, 2)`` outward unit normal of each point.
    #[pyo3(get)]
    normal: Py<PyAny>,
    /// ``(k, 2)`` contact force on each point's node: w σ_n n for an own-side pair; for a
    /// balanced pair the node's share of the reference side's pressures.
    #[pyo3(get)]
    nodal_force: Py<PyAny>,
    /// Total contact force on each side, ``((fx, fy), (fx, fy))``: the sum of the side's nodal
    /// contact forces (the force the other body exerts; Σ w σ_n n for an own-side pair).
    #[pyo3(get)]
    forces: ((f64, f64), (f64, f64)),
    /// The largest penetration max (s − d)⁺ (a length; 0 for exact contact).
    #[pyo3(get)]
    max_penetration: f64,
    /// The largest gap |d − s| where the contact presses: the complementarity residual of the
    /// Signorini conditions (a length; 0 for exact contact).
    #[pyo3(get)]
    complementarity: f64,
    /// Tangential traction σ_t of each point along t = n turned by +90° (the reference side's
    /// points of a pair with friction; 0 elsewhere and without friction; ``contact.csv``'s
    /// ``tangential_traction``).
    #[pyo3(get)]
    tangential: Py<PyAny>,
    /// Slip of this solve (load step): g − g₀, the change of the tangential relative
    /// displacement g = (u_own − u_partner)·t since the last step (0 without friction).
    #[pyo3(get)]
    slip: Py<PyAny>,
    /// The accumulated tangential relative displacement g since the unloaded state.
    #[pyo3(get)]
    total_slip: Py<PyAny>,
    /// Where each point is on its friction disc: ``"open"``, ``"stick"`` or ``"slip"``
    /// (``"open"`` without friction).
    #[pyo3(get)]
    friction_status: Vec<String>,
    /// The resultant tangential force Σ w σ_t (a force per unit thickness; 0 without friction).
    #[pyo3(get)]
    tangential_force: f64,
    /// The length Σ w of the points that stick.
    #[pyo3(get)]
    stick_length: f64,
    /// The length Σ w of the points that slip.
    #[pyo3(get)]
    slip_length: f64,
}

#[pymethods]
impl Contact {
    /// Pickles the contact table as its attributes.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        reduce(slf.as_any(), attributes(slf.as_any(), &CONTACT_STATE)?)
    }

    /// A contact table from the dict of its attributes (pickle, :func:`contactdd.load_results`).
    #[classmethod]
    fn _from_state(_cls: &Bound<'_, PyType>, state: &Bound<'_, PyDict>) -> PyResult<Contact> {
        Ok(Contact {
            name: get(state, "name")?.extract()?,
            bodies: get(state, "bodies")?.extract()?,
            side: get(state, "side")?.unbind(),
            node: get(state, "node")?.unbind(),
            x: get(state, "x")?.unbind(),
            y: get(state, "y")?.unbind(),
            gap: get(state, "gap")?.unbind(),
            pressure: get(state, "pressure")?.unbind(),
            nodal_traction: get(state, "nodal_traction")?.unbind(),
            closed: get(state, "closed")?.unbind(),
            status: get(state, "status")?.extract()?,
            weight: get(state, "weight")?.unbind(),
            normal: get(state, "normal")?.unbind(),
            nodal_force: get(state, "nodal_force")?.unbind(),
            forces: get(state, "forces")?.extract()?,
            max_penetration: get(state, "max_penetration")?.extract()?,
            complementarity: get(state, "complementarity")?.extract()?,
            tangential: get(state, "tangential")?.unbind(),
            slip: get(state, "slip")?.unbind(),
            total_slip: get(state, "total_slip")?.unbind(),
            friction_status: get(state, "friction_status")?.extract()?,
            tangential_force: get(state, "tangential_force")?.extract()?,
            stick_length: get(state, "stick_length")?.extract()?,
            slip_length: get(state, "slip_length")?.extract()?,
        })
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!(
            "<contactdd.Contact '{}' ({} / {}): {} points>",
            self.name,
            self.bodies.0,
            self.bodies.1,
            self.x.bind(py).len()?
        ))
    }
}

impl Contact {
    fn new(py: Python<'_>, p: &PairResult, pressure: &[f64]) -> PyResult<Contact> {
        let [b0, b1] = p.bodies.clone();
        let normal: Vec<f64> = p.nx.iter().zip(&p.ny).flat_map(|(&a, &b)| [a, b]).collect();
        let nodal_force: Vec<f64> = p.fx.iter().zip(&p.fy).flat_map(|(&a, &b)| [a, b]).collect();
        let force = |s| {
            let f = p.force_on(s);
            (f[0], f[1])
        };
        let friction: Vec<_> = (0..p.x.len()).map(|i| friction_point(p, i)).collect();
        let column = |f: fn(&contactdd_io::fields::FrictionPoint) -> f64| {
            array1(py, friction.iter().map(f).collect()).unbind()
        };
        let (stick, slip) = p.stick_slip_lengths();
        Ok(Contact {
            name: p.name.clone(),
            bodies: (b0, b1),
            side: array1(py, p.side.iter().map(|&v| v as i64).collect()).unbind(),
            node: array1(py, p.node.iter().map(|&v| v as i64).collect()).unbind(),
            x: array1(py, p.x.clone()).unbind(),
            y: array1(py, p.y.clone()).unbind(),
            gap: array1(py, p.gap.clone()).unbind(),
            pressure: array1(py, pressure.to_vec()).unbind(),
            nodal_traction: array1(py, p.pressure.clone()).unbind(),
            closed: array1(py, p.closed.clone()).unbind(),
            status: (0..p.x.len())
                .map(|i| point_status(p, i).to_string())
                .collect(),
            weight: array1(py, p.weight.clone()).unbind(),
            normal: array2(py, normal, DIM)?.unbind(),
            nodal_force: array2(py, nodal_force, DIM)?.unbind(),
            forces: (force(0), force(1)),
            max_penetration: p.max_penetration(),
            complementarity: p.complementarity(),
            tangential: column(|f| f.tangential),
            slip: column(|f| f.slip),
            total_slip: column(|f| f.total_slip),
            friction_status: friction
                .iter()
                .map(|f| f.status.name().to_string())
                .collect(),
            tangential_force: p.tangential_force(),
            stick_length: stick,
            slip_length: slip,
        })
    }
}

/// The contact tables of `pairs`, with the pressures p ≥ 0 read on the bodies' meshes.
pub fn contact_list(
    py: Python<'_>,
    pairs: &[PairResult],
    bodies: &[BodyResult],
) -> PyResult<Py<PyList>> {
    let pressures = contact_pressures(pairs, bodies);
    let items = pairs
        .iter()
        .zip(&pressures)
        .map(|(p, pressure)| Py::new(py, Contact::new(py, p, pressure)?))
        .collect::<PyResult<Vec<_>>>()?;
    Ok(PyList::new(py, items)?.unbind())
}
