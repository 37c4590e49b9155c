//! A 3D elastic body: mesh, material and supports assembled and factorised once, then solved for
//! any number of load vectors.

use std::time::{Duration, Instant};

use super::assembly::SolidPattern;
use super::element::elasticity;
use super::error::SolidError;
use super::mesh::SolidMesh;
use super::num_dofs;
use super::post::{centroid_stresses, nodal_stresses};
use crate::factor::FactoredBody;
use crate::material::Material;
use crate::supports::Constraints;

/// Wall-clock times of the phases of [`SolidBody::new`].
#[derive(Clone, Copy, Debug, Default)]
pub struct SolidTimings {
    /// Sparsity pattern.
    pub pattern: Duration,
    /// Stiffness values.
    pub assembly: Duration,
    /// Elimination of the supports and symbolic analysis (ordering included).
    pub symbolic: Duration,
    /// Numeric Cholesky factorisation.
    pub numeric: Duration,
}

/// A factorised 3D body.
pub struct SolidBody {
    mesh: SolidMesh,
    d: [[f64; 6]; 6],
    factored: FactoredBody,
    timings: SolidTimings,
}

impl SolidBody {
    /// Assembles the stiffness of `mesh` with `material`, eliminates the supports `constraints`
    /// (three DOFs per node, [`super::supports`]) and factorises. Errors if the constraints do not
    /// match the mesh, or the factorisation fails (a body whose supports leave a rigid mode is
    /// not positive definite).
    pub fn new(
        name: &str,
        mesh: SolidMesh,
        material: Material,
        constraints: &Constraints,
    ) -> Result<SolidBody, SolidError> {
        let ndof = num_dofs(mesh.num_nodes());
        if constraints.len() != ndof {
            return Err(SolidError::Length {
                what: "the constraints",
                expected: ndof,
                got: constraints.len(),
            });
        }
        let d = elasticity(&material);
        let mut timings = SolidTimings::default();
        let t = Instant::now();
        let pattern = SolidPattern::new(&mesh);
        timings.pattern = t.elapsed();
        let t = Instant::now();
        let k = pattern.stiffness(&mesh, &d);
        timings.assembly = t.elapsed();
        drop(pattern);
        let t = Instant::now();
        let mut factored = FactoredBody::new(name, k, constraints, &[])?;
        timings.symbolic = t.elapsed();
        let t = Instant::now();
        factored.factorize(&[])?;
        timings.numeric = t.elapsed();
        Ok(SolidBody {
            mesh,
            d,
            factored,
            timings,
        })
    }

    /// Solves `K u = f` with the prescribed values on the supports; `f` has one entry per DOF.
    pub fn solve(&self, f: &[f64]) -> Result<Vec<f64>, SolidError> {
        if f.len() != self.factored.num_dofs() {
            return Err(SolidError::Length {
                what: "the load vector",
                expected: self.factored.num_dofs(),
                got: f.len(),
            });
        }
        Ok(self.factored.solve(f)?)
    }

    /// The mesh.
    pub fn mesh(&self) -> &SolidMesh {
        &self.mesh
    }

    /// The elasticity matrix (6×6, Voigt).
    pub fn elasticity(&self) -> &[[f64; 6]; 6] {
        &self.d
    }

    /// The factorised operator (stiffness, factor size, memory estimate).
    pub fn factored(&self) -> &FactoredBody {
        &self.factored
    }

    /// The phase times of [`SolidBody::new`].
    pub fn timings(&self) -> SolidTimings {
        self.timings
    }

    /// The stress at every tetrahedron's centroid for the displacement `u`.
    pub fn centroid_stresses(&self, u: &[f64]) -> Result<Vec<[f64; 6]>, SolidError> {
        centroid_stresses(&self.mesh, &self.d, u)
    }

    /// The stress at every node (averaged over the tetrahedra around it) for the displacement `u`.
    pub fn nodal_stresses(&self, u: &[f64]) -> Result<Vec<[f64; 6]>, SolidError> {
        nodal_stresses(&self.mesh, &self.d, u)
    }
}
