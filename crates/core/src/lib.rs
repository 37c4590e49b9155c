//! # contactdd-core
//!
//! The finite element core of contactdd: 2D linear elasticity on P1/P2 triangles (straight-sided,
//! or curved isoparametric P2 as Gmsh `SetOrder(2)` writes them, [`element::Geometry`]) in plane
//! strain or plane stress, assembled into a fixed sparsity pattern and solved by a sparse
//! Cholesky factorisation (faer) per body.
//!
//! Modules follow the data flow: [`mesh`] (and [`rectangle`], [`gmsh`]) → [`element`] →
//! [`material`] → [`assembly`] / [`loads`] → [`supports`] → [`factor`] → [`post`]. Result files
//! (VTU, JSON, CSV) are written by `contactdd-io`; [`gmsh`] is the one reader of a file format
//! here, kept because it only builds a [`Mesh`] (see its module docs).
//! [`body::ElasticBody::solve`] runs all stages in one call.
//!
//! The weak form per body is `a(u, v) = ∫ ε(v) : C : ε(u) dA = ∫ f·v dA + ∫_Γσ t·v ds`, with
//! prescribed components of `u` eliminated from the system.

pub mod assembly;
pub mod body;
pub mod element;
pub mod error;
pub mod factor;
mod fast_hash;
pub mod geometry;
pub mod gmsh;
pub mod incremental_cholesky;
pub mod loads;
pub mod material;
pub mod memory;
pub mod mesh;
pub mod mesh_memory;
pub mod names;
pub mod ordering;
pub mod post;
pub mod rectangle;
pub mod rigid;
pub mod solid;
mod subtrees;
pub mod supports;

pub use body::{ElasticBody, LinearSolution};
pub use error::{BodyError, GmshError, MaterialError, MeshError, SupportError};
pub use factor::{FactorValues, FactoredBody};
pub use geometry::{component_of, dof, node_of, node_vector, num_dofs, Point, Vector, DIM};
pub use loads::Load;
pub use material::{Material, Plane};
pub use mesh::{Edge, Mesh, Order};
pub use rectangle::{Diagonal, Layout, Rectangle};
pub use rigid::RigidBasis;
pub use supports::{Component, Constraints};
