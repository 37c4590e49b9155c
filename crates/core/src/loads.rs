//! Loads of one body: normal pressure and traction on named boundaries, and a body force.

use crate::assembly::{add_body_force, add_edge_traction, add_pressure};
use crate::error::MeshError;
use crate::geometry::{num_dofs, Vector, DIM};
use crate::mesh::Mesh;

/// One load. A problem file's `loads` entries are this type, selected by `kind` (`pressure`,
/// `traction`, `body-force`), e.g. `{ kind = "pressure", boundary = "top", value = 10.0 }`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", deny_unknown_fields, rename_all = "kebab-case")]
pub enum Load {
    /// Uniform normal pressure on a boundary, positive into the body (traction `−p n`).
    Pressure {
        /// Boundary name.
        boundary: String,
        /// Pressure (force per unit length in 2D).
        value: f64,
    },
    /// Uniform traction vector `[tx, ty]` on a boundary.
    Traction {
        /// Boundary name.
        boundary: String,
        /// Force per unit length.
        value: Vector,
    },
    /// Uniform body force `[fx, fy]` per unit area (e.g. `ρ g`).
    BodyForce {
        /// Force per unit area.
        value: Vector,
    },
}

/// The consistent load vector (2 entries per node) of a set of loads.
pub fn load_vector(mesh: &Mesh, loads: &[Load]) -> Result<Vec<f64>, MeshError> {
    let mut f = vec![0.0; num_dofs(mesh.num_nodes())];
    for load in loads {
        match load {
            Load::Pressure { boundary, value } => {
                add_pressure(mesh, mesh.boundary(boundary)?, *value, &mut f)
            }
            Load::Traction { boundary, value } => {
                add_edge_traction(mesh, mesh.boundary(boundary)?, |_, _| *value, &mut f)
            }
            Load::BodyForce { value } => add_body_force(mesh, |_| *value, &mut f),
        }
    }
    Ok(f)
}

/// Total applied force `[fx, fy]` of a body (the sum of its nodal load vector).
pub fn applied_load(load: &[f64]) -> Vector {
    load.chunks(DIM).fold([0.0; DIM], |s, f| {
        std::array::from_fn(|c| s[c] + f.get(c).copied().unwrap_or(0.0))
    })
}
