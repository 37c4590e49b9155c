//! Python values read into entries of the problem-file schema (`contactdd_io::problem`): dicts
//! deserialized with the schema's keys and defaults, arrays of node indices, and meshes as inline
//! tables.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use numpy::{AllowTypeChange, PyArray2, PyArrayLike2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::de::DeserializeOwned;

use contactdd_core::Mesh;
use contactdd_ddm::SetupError;
use contactdd_io::problem::{MeshSpec, Problem as ProblemSpec};

use crate::convert::{shown, to_json, Bad};
use crate::error::{input_error, setup_error};

/// A built mesh as an inline mesh table, which resolves to the same mesh.
pub fn inline_spec(mesh: &Mesh) -> MeshSpec {
    let npc = mesh.order().nodes_per_cell();
    MeshSpec::Inline {
        nodes: mesh.nodes().to_vec(),
        triangles: mesh.cells().chunks(npc).map(<[usize]>::to_vec).collect(),
        boundaries: mesh
            .boundaries()
            .iter()
            .map(|(k, edges)| (k.clone(), edges.iter().map(|e| [e.a, e.b]).collect()))
            .collect(),
        node_sets: mesh.node_sets().clone(),
    }
}

/// Makes every relative Gmsh path of `spec` absolute (against `base_dir`, itself against the
/// current folder), so that the problem written out reads the same meshes from any folder.
pub fn absolute_mesh_paths(spec: &mut ProblemSpec, base_dir: &Path) -> PyResult<()> {
    for body in &mut spec.bodies {
        if let MeshSpec::Gmsh { file, .. } = &mut body.mesh {
            if file.is_relative() {
                *file = std::path::absolute(base_dir.join(&*file)).map_err(|e| {
                    input_error(format!("cannot resolve the path '{}': {e}", file.display()))
                })?;
            }
        }
    }
    Ok(())
}

pub fn body_error(body: &str, key: &str, message: impl std::fmt::Display) -> SetupError {
    SetupError::Body {
        body: body.to_string(),
        message: format!("{key}: {message}"),
    }
}

/// Parses one schema value at path `key`; a bad value or schema error is returned as a message
/// (starting with the path) for the caller to attribute to a body or pair.
pub fn parse<T: DeserializeOwned>(
    obj: &Bound<'_, PyAny>,
    key: &str,
) -> PyResult<Result<T, String>> {
    match to_json(obj, key) {
        Ok(value) => Ok(serde_json::from_value(value).map_err(|e| format!("{key}: {e}"))),
        Err(Bad::Value(message)) => Ok(Err(message)),
        Err(Bad::Py(e)) => Err(e),
    }
}

/// An optional value `key` of contact pair `pair` (`None` and Python's `None` alike), its errors
/// naming the pair.
pub fn pair_option<T: DeserializeOwned>(
    obj: Option<&Bound<'_, PyAny>>,
    key: &str,
    pair: &str,
) -> PyResult<Option<T>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    let value = parse(obj, key)?.map_err(|message| {
        setup_error(SetupError::Pair {
            pair: pair.to_string(),
            message,
        })
    })?;
    Ok(Some(value))
}

/// A list of support or load dicts of body `body`.
pub fn specs<T: DeserializeOwned>(
    body: &str,
    key: &str,
    list: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<T>> {
    let Some(list) = list else {
        return Ok(Vec::new());
    };
    let body_err = |message: String| {
        setup_error(SetupError::Body {
            body: body.to_string(),
            message,
        })
    };
    if list.is_instance_of::<PyDict>() {
        return Err(body_err(format!(
            "{key}: expected a list of dicts, got a single dict (wrap it in a list)"
        )));
    }
    let items = list.try_iter().map_err(|_| {
        body_err(format!(
            "{key}: expected a list of dicts, got a value of type {}",
            type_name(list)
        ))
    })?;
    let mut out = Vec::new();
    for (i, item) in items.enumerate() {
        let k = format!("{key}[{i}]");
        out.push(parse(&item?, &k)?.map_err(|message| {
            setup_error(SetupError::Body {
                body: body.to_string(),
                message,
            })
        })?);
    }
    Ok(out)
}

/// The type name of a Python value, for messages.
pub fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map_or_else(|_| "?".into(), |n| n.to_string())
}

/// A string argument `key` (a `ContactddError` naming it if `obj` is not a string).
pub fn text(obj: &Bound<'_, PyAny>, key: &str) -> PyResult<String> {
    obj.extract().map_err(|_| {
        input_error(format!(
            "{key}: expected a string, got a value of type {}",
            type_name(obj)
        ))
    })
}

/// A 2-D array of numbers (`what` names it in the message if `obj` is not one).
pub fn float_array<'py>(
    obj: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<PyArrayLike2<'py, f64, AllowTypeChange>> {
    obj.extract().map_err(|_| {
        input_error(format!(
            "{what}: expected a 2-D array of numbers, got a value of type {}",
            type_name(obj)
        ))
    })
}

/// Converts a 2-D array of node indices, row-major, with its number of columns. Integer arrays
/// are read exactly; floats with an integer value (`2.0`, as `numpy.loadtxt` gives) are
/// accepted; a fraction, NaN or infinity is refused rather than truncated.
pub fn indices(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<(Vec<usize>, usize)> {
    // A list becomes an array of its own type first: integers stay exact, fractions are seen.
    let array = obj.py().import("numpy")?.call_method1("asarray", (obj,));
    if let Some(ints) = array
        .as_ref()
        .ok()
        .and_then(|a| a.cast::<PyArray2<i64>>().ok())
    {
        let ints = ints.readonly();
        let cols = ints.shape()[1];
        let out = ints
            .as_array()
            .iter()
            .map(|&v| {
                usize::try_from(v)
                    .map_err(|_| input_error(format!("{what}: node index {v} is negative")))
            })
            .collect::<PyResult<_>>()?;
        return Ok((out, cols));
    }
    let a = float_array(obj, what)?;
    // Exactly representable integers only: beyond 2⁵³ a float no longer names one index.
    const EXACT: f64 = 9_007_199_254_740_992.0;
    let out = a
        .as_array()
        .iter()
        .map(|&v| {
            if v.fract() != 0.0 || !v.is_finite() {
                Err(input_error(format!(
                    "{what}: node index {} is not an integer",
                    shown(v)
                )))
            } else if v < 0.0 {
                Err(input_error(format!(
                    "{what}: node index {} is negative",
                    shown(v)
                )))
            } else if v > EXACT {
                Err(input_error(format!(
                    "{what}: node index {} is too large",
                    shown(v)
                )))
            } else {
                Ok(v as usize)
            }
        })
        .collect::<PyResult<_>>()?;
    Ok((out, a.shape()[1]))
}

/// The named boundary edge sets of body `name`'s mesh arrays: `(k, 2)` node pairs, or for a P2
/// mesh (`nodes_per_cell` 6) also `(k, 3)` with the mid-side node of each edge, which must be
/// the mid-side node `cells` gives the edge.
pub fn boundary_edges(
    name: &str,
    boundaries: &Bound<'_, PyAny>,
    cells: &[usize],
    nodes_per_cell: usize,
) -> PyResult<BTreeMap<String, Vec<[usize; 2]>>> {
    let mesh_error = |message: String| setup_error(body_error(name, "mesh", message));
    let boundaries = boundaries.cast::<PyDict>().map_err(|_| {
        mesh_error(format!(
            "boundaries: expected a dict {{name: (k, 2) array of node pairs}}, got a value of \
             type {}",
            type_name(boundaries)
        ))
    })?;
    let mids = mid_side_nodes(cells, nodes_per_cell);
    let mut edge_sets = BTreeMap::new();
    for (key, value) in boundaries.iter() {
        let bname: String = key
            .extract()
            .map_err(|_| mesh_error("boundaries: the names must be strings".into()))?;
        let what = format!("body '{name}': mesh: boundaries['{bname}']");
        let (flat, cols) = indices(&value, &what)?;
        match (cols, nodes_per_cell) {
            (2, _) | (3, 6) => {}
            (3, _) => {
                return Err(mesh_error(format!(
                    "boundaries['{bname}'] has 3 nodes per edge, but the triangles are P1 \
                     (3 nodes): give (k, 2) node pairs"
                )))
            }
            _ => {
                return Err(mesh_error(format!(
                    "boundaries['{bname}'] must have 2 columns (node pairs){}, got {cols}",
                    if nodes_per_cell == 6 {
                        " or 3 (with the P2 mid-side node)"
                    } else {
                        ""
                    }
                )))
            }
        }
        let mut edges = Vec::with_capacity(flat.len() / cols.max(1));
        for (i, e) in flat.chunks(cols).enumerate() {
            if cols == 3 {
                let key = (e[0].min(e[1]), e[0].max(e[1]));
                if let Some(&mid) = mids.get(&key).filter(|&&m| m != e[2]) {
                    return Err(mesh_error(format!(
                        "boundaries['{bname}'][{i}]: the mid-side node of edge ({}, {}) is {mid} \
                         in the triangles, not {}",
                        e[0], e[1], e[2]
                    )));
                }
            }
            edges.push([e[0], e[1]]);
        }
        edge_sets.insert(bname, edges);
    }
    Ok(edge_sets)
}

/// The mid-side node of every edge of P2 `cells` (6 nodes per cell: vertices, then the mid-side
/// nodes of edges (0,1), (1,2), (2,0)), by the edge's vertices in increasing order; empty for P1.
fn mid_side_nodes(cells: &[usize], nodes_per_cell: usize) -> HashMap<(usize, usize), usize> {
    let mut mids = HashMap::new();
    if nodes_per_cell != 6 {
        return mids;
    }
    for c in cells.chunks(6) {
        for (k, (a, b)) in [(c[0], c[1]), (c[1], c[2]), (c[2], c[0])]
            .into_iter()
            .enumerate()
        {
            mids.insert((a.min(b), a.max(b)), c[3 + k]);
        }
    }
    mids
}

/// The named node sets of body `name`'s mesh arrays (none if not given).
pub fn node_set_indices(
    name: &str,
    node_sets: Option<&Bound<'_, PyAny>>,
) -> PyResult<BTreeMap<String, Vec<usize>>> {
    let mesh_error = |message: String| setup_error(body_error(name, "mesh", message));
    let mut sets = BTreeMap::new();
    let Some(node_sets) = node_sets.filter(|o| !o.is_none()) else {
        return Ok(sets);
    };
    let node_sets = node_sets.cast::<PyDict>().map_err(|_| {
        mesh_error(format!(
            "node_sets: expected a dict {{name: array of node indices}}, got a value of type {}",
            type_name(node_sets)
        ))
    })?;
    for (key, value) in node_sets.iter() {
        let sname: String = key
            .extract()
            .map_err(|_| mesh_error("node_sets: the names must be strings".into()))?;
        let what = format!("body '{name}': mesh: node_sets['{sname}']");
        // A 1-D array as one row.
        let row = value
            .py()
            .import("numpy")?
            .call_method1("atleast_2d", (&value,))
            .map_err(|_| {
                input_error(format!(
                    "{what}: expected an array of node indices, got a value of type {}",
                    type_name(&value)
                ))
            })?;
        sets.insert(sname, indices(&row, &what)?.0);
    }
    Ok(sets)
}
