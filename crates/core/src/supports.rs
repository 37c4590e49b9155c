//! Prescribed displacements (supports) and the check that a body has no rigid-body modes left.

use crate::error::SupportError;
use crate::geometry::{dof, num_dofs, Vector};
use crate::mesh::Mesh;
use crate::rigid::{describe, free_modes};

/// Which displacement component a support prescribes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Component {
    /// u_x only.
    X,
    /// u_y only.
    Y,
    /// Both components.
    Both,
    /// The normal component of a straight axis-aligned boundary (a symmetry line: u·n fixed,
    /// zero shear).
    Normal,
}

/// Prescribed values per DOF of one body (`None` = free).
#[derive(Clone, Debug, PartialEq)]
pub struct Constraints {
    values: Vec<Option<f64>>,
}

impl Constraints {
    /// No DOF constrained, for a mesh with `num_nodes` nodes.
    pub fn new(num_nodes: usize) -> Constraints {
        Constraints {
            values: vec![None; num_dofs(num_nodes)],
        }
    }

    /// Prescribes `value` for `component` on every node of boundary (or node set) `name`.
    /// A DOF fixed twice keeps the last value.
    pub fn fix(
        &mut self,
        mesh: &Mesh,
        name: &str,
        component: Component,
        value: f64,
    ) -> Result<(), SupportError> {
        if !value.is_finite() {
            return Err(SupportError::NonFinite {
                boundary: name.to_string(),
                value,
            });
        }
        let nodes = mesh.boundary_nodes(name)?;
        let comps: &[usize] = match component {
            Component::X => &[0],
            Component::Y => &[1],
            Component::Both => &[0, 1],
            Component::Normal => match axis_normal(mesh, name) {
                Some(0) => &[0],
                Some(_) => &[1],
                None => {
                    return Err(SupportError::NotAxisAligned {
                        boundary: name.to_string(),
                    })
                }
            },
        };
        for v in nodes {
            for &c in comps {
                self.values[dof(v, c)] = Some(value);
            }
        }
        Ok(())
    }

    /// Prescribes (or frees, with `None`) one DOF directly.
    pub fn set(&mut self, dof: usize, value: Option<f64>) {
        self.values[dof] = value;
    }

    /// Prescribed value of DOF `dof`, if any.
    pub fn get(&self, dof: usize) -> Option<f64> {
        self.values[dof]
    }

    /// Number of DOFs (2 per node).
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// True if there are no DOFs at all.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Constrained DOFs and their values.
    pub fn fixed(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.values
            .iter()
            .enumerate()
            .filter_map(|(i, v)| v.map(|v| (i, v)))
    }
}

/// 0 if boundary `name` is a straight line x = const, 1 if y = const, None otherwise.
fn axis_normal(mesh: &Mesh, name: &str) -> Option<usize> {
    let edges = mesh.boundary(name).ok()?;
    let p = mesh.nodes();
    let first = edges.first()?;
    let axis = if (p[first.a][0] - p[first.b][0]).abs() < (p[first.a][1] - p[first.b][1]).abs() {
        0
    } else {
        1
    };
    let tol = 1e-9 * mesh.bounding_box_diameter();
    let c = p[first.a][axis];
    edges
        .iter()
        .flat_map(|e| e.nodes())
        .all(|v| (p[v][axis] - c).abs() <= tol)
        .then_some(axis)
}

/// Rigid-body modes of a body that neither its supports nor the given normal springs remove.
/// `springs` are (node, unit direction) pairs of springs of any positive stiffness. Returns a
/// human readable description of each free mode (empty if the body is held).
pub fn free_rigid_modes(
    mesh: &Mesh,
    constraints: &Constraints,
    springs: &[(usize, Vector)],
) -> Vec<String> {
    free_modes(mesh, constraints, springs)
        .iter()
        .map(describe)
        .collect()
}
