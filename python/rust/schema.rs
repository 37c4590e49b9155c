//! Python values read into entries of the problem-file schema (`contactdd_io::problem`): dicts
//! deserialized with the schema's keys and defaults, arrays of node indices, and meshes as inline
//! tables.

use std::collections::BTreeMap;
use std::path::Path;

use numpy::{AllowTypeChange, PyArrayLike2, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::de::DeserializeOwned;

use contactdd_core::Mesh;
use contactdd_ddm::SetupError;
use contactdd_io::problem::{MeshSpec, Problem as ProblemSpec};

use crate::convert::{to_json, Bad};
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
    if list.is_instance_of::<PyDict>() {
        return Err(PyTypeError::new_err(format!(
            "{key}: expected a list of dicts, got a single dict (wrap it in a list)"
        )));
    }
    let mut out = Vec::new();
    for (i, item) in list.try_iter()?.enumerate() {
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

/// Converts an array of node indices. Integer arrays and floats with an integer value (`2.0`, as
/// `numpy.loadtxt` gives) are accepted; a fraction, NaN or infinity is refused rather than
/// truncated.
pub fn indices(a: &PyArrayLike2<'_, f64, AllowTypeChange>, what: &str) -> PyResult<Vec<usize>> {
    // Exactly representable integers only: beyond 2⁵³ a float no longer names one index.
    const EXACT: f64 = 9_007_199_254_740_992.0;
    a.as_array()
        .iter()
        .map(|&v| {
            if !(v.fract() == 0.0 && v.abs() <= EXACT) {
                Err(input_error(format!(
                    "{what}: node index {v} is not an integer"
                )))
            } else if v < 0.0 {
                Err(input_error(format!("{what}: node index {v} is negative")))
            } else {
                Ok(v as usize)
            }
        })
        .collect()
}

/// The named boundary edge sets of body `name`'s mesh arrays: `(k, 2)` node pairs (a third
/// column of P2 mid-side nodes is ignored).
pub fn boundary_edges(
    name: &str,
    boundaries: &Bound<'_, PyDict>,
) -> PyResult<BTreeMap<String, Vec<[usize; 2]>>> {
    let mesh_error = |message: String| setup_error(body_error(name, "mesh", message));
    let mut edge_sets = BTreeMap::new();
    for (key, value) in boundaries.iter() {
        let bname: String = key.extract()?;
        let what = format!("body '{name}': mesh: boundaries['{bname}']");
        let arr: PyArrayLike2<'_, f64, AllowTypeChange> = value.extract()?;
        let cols = arr.shape()[1];
        if cols != 2 && cols != 3 {
            return Err(mesh_error(format!(
                "boundaries['{bname}'] must have shape (k, 2) or (k, 3), got {:?}",
                arr.shape()
            )));
        }
        let flat = indices(&arr, &what)?;
        let edges: Vec<[usize; 2]> = flat.chunks(cols).map(|e| [e[0], e[1]]).collect();
        edge_sets.insert(bname, edges);
    }
    Ok(edge_sets)
}

/// The named node sets of body `name`'s mesh arrays (none if not given).
pub fn node_set_indices(
    name: &str,
    node_sets: Option<&Bound<'_, PyDict>>,
) -> PyResult<BTreeMap<String, Vec<usize>>> {
    let mesh_error = |message: String| setup_error(body_error(name, "mesh", message));
    let mut sets = BTreeMap::new();
    if let Some(node_sets) = node_sets {
        for (key, value) in node_sets.iter() {
            let sname: String = key.extract()?;
            let ids: Vec<i64> = value.extract()?;
            let ids = ids
                .into_iter()
                .map(|v| {
                    usize::try_from(v).map_err(|_| {
                        mesh_error(format!("node_sets['{sname}']: node index {v} is negative"))
                    })
                })
                .collect::<PyResult<Vec<usize>>>()?;
            sets.insert(sname, ids);
        }
    }
    Ok(sets)
}
