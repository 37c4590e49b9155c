//! `contactdd.space.system`: the discrete problem of a problem in space, for another solver to
//! solve (a peer's monolithic Newton method, as scripts/peers_space.py does): every body's
//! stiffness (unconstrained, CSC), loads and prescribed DOFs, and the contact points' rows.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use contactdd_core::solid::assembly::stiffness;
use contactdd_ddm::solid_contact::solid_contact_rows;

use crate::convert::array1;
use crate::error::input_error;
use crate::space_problem::SpaceProblem;

/// The discrete problem of ``problem``, as the solvers of contactdd take it.
///
/// Returns:
///     A dict: ``offsets`` (where each body's DOFs start in the coupled numbering, 3 per node),
///     ``dofs`` (their total), ``bodies`` (per body ``name``, ``stiffness`` as the CSC arrays
///     ``(data, indices, indptr)`` of its unconstrained stiffness matrix, ``load``,
///     ``prescribed_dofs`` and ``prescribed_values`` in its own numbering) and ``rows`` (the
///     contact points' approaches a·u as CSR arrays ``data``, ``indices``, ``indptr`` over the
///     coupled DOFs, with ``gap``, ``weight``, ``theta`` and ``exact``: a point carries the
///     pressure max(0, a·u − gap)/theta, or where ``exact`` (an augmented pair) the pressure p
///     of the Signorini conditions p = max(0, p + (a·u − gap)/theta), and the force
///     weight·pressure along −a), in the order of the result's contact points.
///
/// Raises:
///     ContactddError: a pair that cannot be built.
#[pyfunction]
pub fn space_system<'py>(
    py: Python<'py>,
    problem: &Bound<'py, SpaceProblem>,
) -> PyResult<Bound<'py, PyDict>> {
    let model = problem.borrow().model()?;
    let specs = model.body_specs();
    let (offsets, n, rows) =
        solid_contact_rows(&specs, &model.pair_specs()).map_err(|e| input_error(e.to_string()))?;
    let out = PyDict::new(py);
    out.set_item("offsets", offsets)?;
    out.set_item("dofs", n)?;
    let bodies = pyo3::types::PyList::empty(py);
    for (b, spec) in model.bodies.iter().zip(&specs) {
        let k = stiffness(spec.mesh, &spec.elasticity);
        let body = PyDict::new(py);
        body.set_item("name", &b.name)?;
        let csc = (
            array1(py, k.val().to_vec()),
            array1(py, k.symbolic().row_idx().to_vec()),
            array1(py, k.symbolic().col_ptr().to_vec()),
        );
        body.set_item("stiffness", csc)?;
        body.set_item("load", array1(py, spec.load.clone()))?;
        let (dofs, values): (Vec<usize>, Vec<f64>) = spec.prescribed.iter().copied().unzip();
        body.set_item("prescribed_dofs", array1(py, dofs))?;
        body.set_item("prescribed_values", array1(py, values))?;
        bodies.append(body)?;
    }
    out.set_item("bodies", bodies)?;
    let mut indptr = vec![0usize];
    let (mut indices, mut data) = (Vec::new(), Vec::new());
    for r in &rows {
        indices.extend(r.approach.iter().map(|e| e.0));
        data.extend(r.approach.iter().map(|e| e.1));
        indptr.push(indices.len());
    }
    let table = PyDict::new(py);
    table.set_item("data", array1(py, data))?;
    table.set_item("indices", array1(py, indices))?;
    table.set_item("indptr", array1(py, indptr))?;
    table.set_item(
        "gap",
        array1(py, rows.iter().map(|r| r.point.gap).collect()),
    )?;
    table.set_item(
        "weight",
        array1(py, rows.iter().map(|r| r.point.weight).collect()),
    )?;
    table.set_item("theta", array1(py, rows.iter().map(|r| r.theta).collect()))?;
    let exact: Vec<bool> = rows.iter().map(|r| r.exact).collect();
    table.set_item("exact", numpy::PyArray1::from_vec(py, exact))?;
    out.set_item("rows", table)?;
    Ok(out)
}
