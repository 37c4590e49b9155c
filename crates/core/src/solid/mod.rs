//! Three-dimensional linear elasticity on tetrahedra: the finite element layer of 3D bodies.
//!
//! The layer is self-contained and follows the same data flow as the planar core:
//! [`mesh`] (and the structured [`box_mesh`]) → [`element`] → [`assembly`] → [`supports`] →
//! [`crate::factor::FactoredBody`] → [`body`] (solve, stress recovery). [`rigid`] gives the six
//! rigid-body modes of a body.
//!
//! Degrees of freedom are interleaved by node: node `v` owns DOFs `3v`, `3v + 1`, `3v + 2`
//! (u_x, u_y, u_z), see [`dof`]. The weak form is `∫ ε(v) : C : ε(u) dV = ∫ f·v dV + ∫_Γ t·v dS`
//! with prescribed components of `u` eliminated by the factorised operator.
//!
//! The contact layer in space (`contactdd_ddm::contact3d`, `solid_dd`, `solid_monolithic`) and
//! the problem files with `dimension = 3` build on this module (docs/three-d.md).

pub mod assembly;
pub mod body;
pub mod box_mesh;
pub mod element;
pub mod error;
pub mod mesh;
pub mod post;
pub mod rigid;
pub mod supports;

pub use body::SolidBody;
pub use box_mesh::BoxMesh;
pub use error::SolidError;
pub use mesh::{SolidMesh, TetOrder};
pub use supports::Axis;

/// The space dimension of this module: coordinates of a point, displacement components per node.
pub const DIM3: usize = 3;

/// A point of space (x, y, z).
pub type Point3 = [f64; DIM3];

/// A vector of space: a displacement, a force, a normal.
pub type Vector3 = [f64; DIM3];

/// Global index of displacement component `component` (0, 1, 2 for x, y, z) of node `node`.
#[inline]
pub const fn dof(node: usize, component: usize) -> usize {
    DIM3 * node + component
}

/// Number of degrees of freedom of `num_nodes` nodes.
#[inline]
pub const fn num_dofs(num_nodes: usize) -> usize {
    DIM3 * num_nodes
}

/// `a × b`.
#[inline]
pub(crate) fn cross(a: Vector3, b: Vector3) -> Vector3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a · b`.
#[inline]
pub(crate) fn dot3(a: Vector3, b: Vector3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `b − a`.
#[inline]
pub(crate) fn sub(b: Point3, a: Point3) -> Vector3 {
    [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
}
