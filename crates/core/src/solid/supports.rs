//! Supports of a 3D body: prescribed displacement components on named faces, as [`Constraints`]
//! with three DOFs per node ([`super::dof`]).

use super::error::SolidError;
use super::mesh::SolidMesh;
use super::{dof, num_dofs, Point3, Vector3};
use crate::supports::Constraints;

/// A displacement component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// u_x.
    X,
    /// u_y.
    Y,
    /// u_z.
    Z,
}

impl Axis {
    /// The component index (0, 1, 2).
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    /// All three components.
    pub const ALL: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];
}

/// No DOF constrained, three DOFs per node of `mesh`.
pub fn constraints(mesh: &SolidMesh) -> Constraints {
    Constraints::for_dofs(num_dofs(mesh.num_nodes()))
}

/// Prescribes `value` for each of the components `axes` on every node of face `name`; a later
/// prescription of the same DOF replaces an earlier one. Errors on an unknown face or a
/// non-finite value.
pub fn fix(
    constraints: &mut Constraints,
    mesh: &SolidMesh,
    name: &str,
    axes: &[Axis],
    value: f64,
) -> Result<(), SolidError> {
    prescribe(constraints, mesh, name, |_| [value; 3], axes)
}

/// Prescribes the displacement `g(x)` (all three components) on every node of face `name`.
pub fn fix_field(
    constraints: &mut Constraints,
    mesh: &SolidMesh,
    name: &str,
    g: impl Fn(Point3) -> Vector3,
) -> Result<(), SolidError> {
    prescribe(constraints, mesh, name, g, &Axis::ALL)
}

/// Prescribes the components `axes` of `g(x)` on the nodes of face `name`.
fn prescribe(
    constraints: &mut Constraints,
    mesh: &SolidMesh,
    name: &str,
    g: impl Fn(Point3) -> Vector3,
    axes: &[Axis],
) -> Result<(), SolidError> {
    if constraints.len() != num_dofs(mesh.num_nodes()) {
        return Err(SolidError::Length {
            what: "the constraints",
            expected: num_dofs(mesh.num_nodes()),
            got: constraints.len(),
        });
    }
    for v in mesh.face_nodes(name)? {
        let u = g(mesh.nodes()[v]);
        for a in axes {
            let value = u[a.index()];
            if !value.is_finite() {
                return Err(SolidError::NonFinite {
                    what: format!("the displacement prescribed on face '{name}' at node {v}"),
                });
            }
            constraints.prescribe(dof(v, a.index()), value);
        }
    }
    Ok(())
}
