//! One body's stiffness reduced exactly onto the DOFs its contact terms touch.
//!
//! The contact terms of the assembled system only couple the DOFs of contact nodes along their
//! normals (the *contact DOFs*). Ordering them last in a sparse Cholesky factorisation of
//! K + A (A = k_ref on the contact DOFs' diagonal, which holds a body that only contact holds)
//! makes the trailing factor block L₂₂ the Schur complement: the block elimination of the interior
//! DOFs gives S = L₂₂L₂₂ᵀ − A and the condensed load g, exactly. The Newton iteration then only
//! changes the contact block, so the interior is factorised once.

use faer::Mat;

use contactdd_core::rigid::{RigidBasis, NUM_MODES};
use contactdd_core::{component_of, dof, node_of, ElasticBody, FactoredBody, Vector, DIM};

use crate::contact::ContactPoint;
use crate::error::SetupError;

/// A body reduced onto its free contact DOFs.
pub(super) struct ReducedBody {
    op: FactoredBody,
    /// Free contact DOFs (full numbering), in the order of `s`.
    pub dofs: Vec<usize>,
    /// The Schur complement of K on `dofs`.
    pub s: Mat<f64>,
    /// The condensed load: S x − g is the interior-eliminated K u − f.
    pub g: Vec<f64>,
    /// The regularising spring on every contact DOF.
    k_ref: f64,
}

impl ReducedBody {
    /// Factorises and reduces one body; errors (as `solve` does) if its supports and contact
    /// zones leave it free to move rigidly.
    pub fn new(
        body: &ElasticBody,
        points: &[ContactPoint],
        par: faer::Par,
    ) -> Result<ReducedBody, SetupError> {
        let springs: Vec<(usize, Vector)> = points.iter().map(|p| (p.node, p.normal)).collect();
        body.check_held(&springs)?;
        let mut contact: Vec<usize> = points
            .iter()
            .flat_map(|p| {
                (0..DIM)
                    .filter(|&c| p.normal[c] != 0.0)
                    .map(|c| dof(p.node, c))
            })
            .collect();
        contact.sort_unstable();
        contact.dedup();
        let k = body.stiffness();
        let k_ref = diagonal_scale(&k, &contact);
        let mut op = FactoredBody::new(&body.name, k, &body.constraints, &contact)?;
        op.set_parallelism(par);
        let additions: Vec<(usize, usize, f64)> = contact.iter().map(|&d| (d, d, k_ref)).collect();
        op.factorize(&additions)?;
        let index = op.interface_index(&contact);
        let mut dofs = vec![0; index.iter().flatten().count()];
        for (&d, i) in contact.iter().zip(&index) {
            // Coefficient 1: no contact node lies on an inclined support (checked before).
            if let Some((i, _)) = i {
                dofs[*i] = d;
            }
        }
        let l22 = op.schur_factor()?;
        let mut s = &l22 * l22.transpose();
        for i in 0..dofs.len() {
            s[(i, i)] -= k_ref;
        }
        // g = (S + A) u₀ on the contact DOFs for u₀ = (K + A)⁻¹ f: the interior-eliminated load.
        let u0 = op.solve(&body.load)?;
        let g = (0..dofs.len())
            .map(|i| {
                (0..dofs.len())
                    .map(|j| (s[(i, j)] + if i == j { k_ref } else { 0.0 }) * u0[dofs[j]])
                    .sum()
            })
            .collect();
        Ok(ReducedBody {
            op,
            dofs,
            s,
            g,
            k_ref,
        })
    }

    /// The full displacement for contact DOF values `x` and nodal contact forces `contact`
    /// (full numbering): the interior follows from K u = f + contact, since the spring A x added
    /// to both sides cancels on the contact DOFs. The rigid part of x (coefficients `rigid` in the
    /// body's rigid basis, removed from `x`) is added back afterwards, so the solve sees only the
    /// deformation (K annihilates the rigid part: (K + A)(u − R c) = f + contact + A (x − R c)).
    pub fn recover(
        &self,
        body: &ElasticBody,
        contact: &[f64],
        x: &[f64],
        rigid: &[f64; NUM_MODES],
    ) -> Result<Vec<f64>, SetupError> {
        let mut f: Vec<f64> = body.load.iter().zip(contact).map(|(a, b)| a + b).collect();
        for (&d, &v) in self.dofs.iter().zip(x) {
            f[d] += self.k_ref * v;
        }
        let mut u = self.op.solve(&f)?;
        let basis = RigidBasis::new(&body.mesh);
        for (d, ud) in u.iter_mut().enumerate() {
            if body.constraints.get(d).is_none() {
                *ud += basis.motion(body.mesh.nodes()[node_of(d)], rigid)[component_of(d)];
            }
        }
        Ok(u)
    }

    /// The assembled stiffness (supports not eliminated).
    pub fn stiffness(&self) -> &faer::sparse::SparseColMat<usize, f64> {
        self.op.stiffness()
    }
}

/// The mean diagonal entry of `k` on `dofs` (1 if there are none): a spring of the body's own
/// stiffness scale, so that subtracting it again loses no digits.
fn diagonal_scale(k: &faer::sparse::SparseColMat<usize, f64>, dofs: &[usize]) -> f64 {
    let (cp, ri, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    let sum: f64 = dofs
        .iter()
        .map(|&d| {
            (cp[d]..cp[d + 1])
                .find(|&p| ri[p] == d)
                .map_or(0.0, |p| val[p].abs())
        })
        .sum();
    if dofs.is_empty() || sum == 0.0 {
        1.0
    } else {
        sum / dofs.len() as f64
    }
}
