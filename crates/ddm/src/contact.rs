//! Contact geometry and the pairs' formulations: contact points with nodal normals and quadrature
//! weights, initial gaps, and the projection of every contact point onto the opposite body's
//! contact boundary.
//!
//! The files, each depending only on those listed before it:
//! - `formulation`: a pair's formulation in one value (penalty law, enforcement, forces, inner
//!   penalty);
//! - `friction`: the tangential laws (Coulomb, Tresca) and a frictional point's return mapping;
//! - `gap_profile`: the prescribed gap profiles of the pairs;
//! - `points`: the contact points, their roles, and the [`Interface`] they form;
//! - `curved_edge`: integrals, normals and ray hits along a curved (isoparametric) P2 edge;
//! - `edge_index`: the R-tree search for the partner edge a normal ray hits;
//! - `nodal_quadrature`: the nodes, nodal normals and quadrature weights of a contact boundary;
//! - `mortar`: the dual mortar coefficients of the balanced pairs;
//! - `balanced_pair`: the balanced pairs' rewrite of the points;
//! - `builder`: [`Interface::new`], the stages that build the interface of a model;
//! - `check`: the plausibility checks of the built contact geometry.

pub mod balanced_pair;
mod builder;
pub mod check;
mod curved_edge;
mod edge_index;
pub mod formulation;
pub mod friction;
pub mod gap_profile;
mod mortar;
mod nodal_quadrature;
mod points;

pub use edge_index::EdgeIndex;
pub use formulation::{Formulation, AUGMENTED_C};
pub use friction::{Friction, FrictionPoint, Status};
pub use points::{ContactPoint, Interface, Role};
