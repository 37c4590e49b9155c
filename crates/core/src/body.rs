//! One elastic body and the easy one-call linear solve (the explicit stages are
//! [`Pattern`] → [`FactoredBody`] → solve).

use crate::assembly::Pattern;
use crate::error::BodyError;
use crate::factor::FactoredBody;
use crate::geometry::Vector;
use crate::material::{Material, Plane};
use crate::mesh::Mesh;
use crate::post::{residual, stresses, Stresses};
use crate::rigid::free_rigid_modes;
use crate::supports::Constraints;

/// A body: mesh, material, supports and applied loads.
#[derive(Clone, Debug)]
pub struct ElasticBody {
    /// Name used in messages.
    pub name: String,
    /// The mesh.
    pub mesh: Mesh,
    /// Material.
    pub material: Material,
    /// Plane strain or plane stress.
    pub plane: Plane,
    /// Supports.
    pub constraints: Constraints,
    /// Applied nodal forces (2 per node).
    pub load: Vec<f64>,
}

/// A linear elastic solution of one body.
#[derive(Clone, Debug)]
pub struct LinearSolution {
    /// Displacement, 2 per node.
    pub displacement: Vec<f64>,
    /// `K u − f` per DOF: the support reactions on supported DOFs.
    pub residual: Vec<f64>,
    /// Stresses.
    pub stresses: Stresses,
}

impl ElasticBody {
    /// Assembles the stiffness matrix.
    pub fn stiffness(&self) -> faer::sparse::SparseColMat<usize, f64> {
        Pattern::new(&self.mesh).stiffness(&self.mesh, &self.material.elasticity(self.plane))
    }

    /// Errors if supports plus springs at `springs` (node, direction) leave rigid-body modes.
    pub fn check_held(&self, springs: &[(usize, Vector)]) -> Result<(), BodyError> {
        let modes = free_rigid_modes(&self.mesh, &self.constraints, springs);
        if modes.is_empty() {
            return Ok(());
        }
        Err(BodyError::Floating {
            body: self.name.clone(),
            modes: modes.len(),
            description: modes.join("; "),
            contact: if springs.is_empty() {
                ""
            } else {
                " or contact zones"
            },
        })
    }

    /// Solves the linear elasticity problem of this body alone.
    pub fn solve(&self) -> Result<LinearSolution, BodyError> {
        self.check_held(&[])?;
        if self.load.iter().any(|v| !v.is_finite()) {
            return Err(BodyError::NonFinite {
                body: self.name.clone(),
                what: "the load vector".into(),
            });
        }
        let k = self.stiffness();
        let mut op = FactoredBody::new(&self.name, k, &self.constraints, &[])?;
        op.set_parallelism(faer::get_global_parallelism());
        op.factorize(&[])?;
        let displacement = op.solve(&self.load)?;
        let residual = residual(op.stiffness(), &displacement, &self.load);
        let stresses = stresses(&self.mesh, &self.material, self.plane, &displacement);
        Ok(LinearSolution {
            displacement,
            residual,
            stresses,
        })
    }
}
