//! # contactdd
//!
//! A facade over the workspace crates: [`fem`] (meshes, P1/P2 elasticity, sparse Cholesky per
//! body), [`ddm`] (contact, the penalty Robin domain decomposition, the monolithic reference) and
//! [`io`] (problem files and result files).
//! [`cases`], [`frictional`] and [`press_fit`] hold hard test problems built in code.
//! This package also hosts the workspace-level tests and benches.

pub use contactdd_core as fem;
pub use contactdd_ddm as ddm;
pub use contactdd_io as io;

pub mod cases;
pub mod frictional;
pub mod hertz;
pub mod press_fit;
