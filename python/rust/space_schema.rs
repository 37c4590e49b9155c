//! Python values read into entries of the schema of a problem file in space
//! (`contactdd_io::solid_problem`): numpy arrays into an inline tetrahedral mesh, a built mesh
//! into the inline table that resolves to it, and the Gmsh paths of a problem made absolute.
//!
//! Only the arrays' shapes are checked here (what numpy can get wrong and a problem file
//! cannot); the mesh itself (indices in range, orientation, boundary faces) is checked by
//! `contactdd_io::solid_setup::resolve_solid`, as an inline mesh of a problem file is.

use std::collections::BTreeMap;
use std::path::Path;

use numpy::PyUntypedArrayMethods;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use contactdd_core::names::shown;
use contactdd_core::solid::SolidMesh;
use contactdd_io::solid_problem::{SolidMeshSpec, SolidProblem};

use crate::error::input_error;
use crate::schema::{float_array, indices, type_name};

/// A `ContactddError` about the mesh of body `body`, worded as a problem file's.
pub fn mesh_error(body: &str, message: impl std::fmt::Display) -> PyErr {
    input_error(format!("body '{}': mesh: {message}", shown(body)))
}

/// The inline mesh of body `body` from its arrays: `(n, 3)` node coordinates, `(m, 4)` or
/// `(m, 10)` tetrahedra and the faces `{name: (k, 3) or (k, 6) triangles}`.
pub fn inline_arrays(
    body: &str,
    nodes: &Bound<'_, PyAny>,
    tetrahedra: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
) -> PyResult<SolidMeshSpec> {
    let prefix = format!("body '{}': mesh", shown(body));
    let coords = float_array(nodes, &format!("{prefix}: nodes"))?;
    let [n, dim] = [coords.shape()[0], coords.shape()[1]];
    if dim != 3 {
        return Err(mesh_error(
            body,
            format!("nodes must have shape (n, 3), got ({n}, {dim})"),
        ));
    }
    let points: Vec<[f64; 3]> = (coords.as_array().rows().into_iter())
        .map(|r| [r[0], r[1], r[2]])
        .collect();
    let (cells, width) = indices(tetrahedra, &format!("{prefix}: tetrahedra"))?;
    let per_face = match width {
        4 => 3,
        10 => 6,
        _ => {
            return Err(mesh_error(
                body,
                format!("tetrahedra must have 4 (P1) or 10 (P2) columns, got {width}"),
            ))
        }
    };
    Ok(SolidMeshSpec::Inline {
        nodes: points,
        tetrahedra: cells.chunks(width).map(<[usize]>::to_vec).collect(),
        faces: face_arrays(body, faces, per_face)?,
    })
}

/// The named faces of body `body`: `{name: (k, per_face) array of node indices}`.
fn face_arrays(
    body: &str,
    faces: &Bound<'_, PyAny>,
    per_face: usize,
) -> PyResult<BTreeMap<String, Vec<Vec<usize>>>> {
    let faces = faces.cast::<PyDict>().map_err(|_| {
        mesh_error(
            body,
            format!(
                "faces: expected a dict {{name: (k, {per_face}) array of node indices}}, got a \
                 value of type {}",
                type_name(faces)
            ),
        )
    })?;
    let mut out = BTreeMap::new();
    for (key, value) in faces.iter() {
        let name: String = key
            .extract()
            .map_err(|_| mesh_error(body, "faces: the names must be strings"))?;
        let what = format!("body '{}': mesh: faces['{}']", shown(body), shown(&name));
        let (flat, cols) = indices(&value, &what)?;
        if cols != per_face {
            let order = if per_face == 3 { "P1" } else { "P2" };
            return Err(mesh_error(
                body,
                format!(
                    "faces['{}'] must have {per_face} columns (the tetrahedra are {order}), got \
                     {cols}",
                    shown(&name)
                ),
            ));
        }
        out.insert(name, flat.chunks(cols).map(<[usize]>::to_vec).collect());
    }
    Ok(out)
}

/// A built tetrahedral mesh as an inline mesh table, which resolves to the same mesh.
pub fn inline_solid(mesh: &SolidMesh) -> SolidMeshSpec {
    let npt = mesh.order().nodes_per_tet();
    let npf = mesh.order().nodes_per_face();
    let faces = (mesh.face_names())
        .map(|name| {
            let triangles = mesh.face(name).unwrap_or_default();
            let rows = triangles.chunks(npf).map(<[usize]>::to_vec).collect();
            (name.to_string(), rows)
        })
        .collect();
    SolidMeshSpec::Inline {
        nodes: mesh.nodes().to_vec(),
        tetrahedra: mesh.tets().chunks(npt).map(<[usize]>::to_vec).collect(),
        faces,
    }
}

/// Makes every relative Gmsh path of `spec` absolute (against `base_dir`, itself against the
/// current folder), so that the problem written out reads the same meshes from any folder.
pub fn absolute_solid_paths(spec: &mut SolidProblem, base_dir: &Path) -> PyResult<()> {
    for body in &mut spec.bodies {
        if let SolidMeshSpec::Gmsh { file, .. } = &mut body.mesh {
            if file.is_relative() {
                *file = std::path::absolute(base_dir.join(&*file)).map_err(|e| {
                    input_error(format!("cannot resolve the path '{}': {e}", file.display()))
                })?;
            }
        }
    }
    Ok(())
}
