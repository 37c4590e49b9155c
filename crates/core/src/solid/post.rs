//! Stress recovery of a 3D body: stresses at element centroids, at nodes (averaged over the
//! tetrahedra around each node), and the von Mises stress.

use super::element::{strain, tet_node_barycentric, TetGeometry};
use super::error::SolidError;
use super::mesh::{SolidMesh, TetOrder};
use super::{dof, num_dofs, Vector3};

/// The stress `σ = D ε` (Voigt `(σ_xx, σ_yy, σ_zz, σ_yz, σ_xz, σ_xy)`) of the Voigt strain `eps`.
pub fn stress_of(d: &[[f64; 6]; 6], eps: [f64; 6]) -> [f64; 6] {
    std::array::from_fn(|i| (0..6).map(|j| d[i][j] * eps[j]).sum())
}

/// The von Mises equivalent stress of a Voigt stress:
/// `√(½((σxx−σyy)² + (σyy−σzz)² + (σzz−σxx)²) + 3(σyz² + σxz² + σxy²))`.
pub fn von_mises(s: [f64; 6]) -> f64 {
    let normal = (s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2);
    let shear = s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
    (0.5 * normal + 3.0 * shear).sqrt()
}

/// The nodal displacements of tetrahedron `e` from the DOF vector `u`.
fn element_displacements(mesh: &SolidMesh, e: usize, u: &[f64]) -> Vec<Vector3> {
    mesh.tet(e)
        .iter()
        .map(|&v| std::array::from_fn(|c| u[dof(v, c)]))
        .collect()
}

/// Checks that `u` has one entry per DOF of `mesh`.
fn check(mesh: &SolidMesh, u: &[f64]) -> Result<(), SolidError> {
    let expected = num_dofs(mesh.num_nodes());
    if u.len() == expected {
        Ok(())
    } else {
        Err(SolidError::Length {
            what: "the displacement",
            expected,
            got: u.len(),
        })
    }
}

/// The stress at the centroid of every tetrahedron for the displacement `u` (one per DOF).
pub fn centroid_stresses(
    mesh: &SolidMesh,
    d: &[[f64; 6]; 6],
    u: &[f64],
) -> Result<Vec<[f64; 6]>, SolidError> {
    check(mesh, u)?;
    Ok((0..mesh.num_tets())
        .map(|e| {
            let ue = element_displacements(mesh, e, u);
            stress_of(d, strain(&mesh.geometry(e), [0.25; 4], &ue))
        })
        .collect())
}

/// The stress at every node: the mean over the tetrahedra around the node of each one's stress
/// at that node (the plain average, not weighted by volume).
pub fn nodal_stresses(
    mesh: &SolidMesh,
    d: &[[f64; 6]; 6],
    u: &[f64],
) -> Result<Vec<[f64; 6]>, SolidError> {
    check(mesh, u)?;
    let at = tet_node_barycentric(mesh.order() == TetOrder::P2);
    let mut sum = vec![[0.0; 6]; mesh.num_nodes()];
    let mut count = vec![0usize; mesh.num_nodes()];
    for e in 0..mesh.num_tets() {
        let geo: TetGeometry = mesh.geometry(e);
        let ue = element_displacements(mesh, e, u);
        for (k, &v) in mesh.tet(e).iter().enumerate() {
            let s = stress_of(d, strain(&geo, at[k], &ue));
            for i in 0..6 {
                sum[v][i] += s[i];
            }
            count[v] += 1;
        }
    }
    Ok(sum
        .into_iter()
        .zip(count)
        .map(|(s, n)| s.map(|x| x / n.max(1) as f64))
        .collect())
}
