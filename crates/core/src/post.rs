//! Post-processing: stresses per element and averaged at nodes, von Mises, reaction forces.

use faer::sparse::SparseColMat;

use crate::element::{node_barycentric, Geometry};
use crate::geometry::{dof, node_vector, Vector, DIM};
use crate::material::{von_mises, Material, Plane};
use crate::mesh::Mesh;

/// Stress components `[σ_xx, σ_yy, σ_xy, σ_zz]`.
pub type Stress = [f64; 4];

/// Stress fields of one body.
#[derive(Clone, Debug, PartialEq)]
pub struct Stresses {
    /// Stress at each triangle's centroid.
    pub element: Vec<Stress>,
    /// Area-weighted average at each node of the element stresses evaluated at that node (a
    /// curved triangle weighs by its curved area).
    pub nodal: Vec<Stress>,
    /// von Mises stress of `nodal`.
    pub von_mises: Vec<f64>,
}

/// The stress at barycentric point `l` of a triangle of geometry `geo` and nodal displacements
/// `ue`.
fn stress_at(
    mesh: &Mesh,
    material: &Material,
    plane: Plane,
    d: &[[f64; 3]; 3],
    geo: &Geometry,
    l: [f64; 3],
    ue: &[Vector],
) -> Stress {
    let eps = geo.strain(mesh.order(), l, ue);
    let s: [f64; 3] = [0, 1, 2].map(|i| d[i][0] * eps[0] + d[i][1] * eps[1] + d[i][2] * eps[2]);
    [s[0], s[1], s[2], material.sigma_zz(plane, s[0], s[1])]
}

/// Stresses from the displacement `u` (2 per node).
pub fn stresses(mesh: &Mesh, material: &Material, plane: Plane, u: &[f64]) -> Stresses {
    let d = material.elasticity(plane);
    let n = mesh.num_nodes();
    let mut nodal = vec![[0.0; 4]; n];
    let mut weight = vec![0.0; n];
    let mut element = Vec::with_capacity(mesh.num_cells());
    for e in 0..mesh.num_cells() {
        let c = mesh.cell(e);
        let geo = Geometry::of_cell(mesh, e);
        let ue: Vec<Vector> = c.iter().map(|&v| node_vector(u, v)).collect();
        element.push(stress_at(
            mesh,
            material,
            plane,
            &d,
            &geo,
            [1.0 / 3.0; 3],
            &ue,
        ));
        let area = geo.area();
        for (&v, l) in c.iter().zip(node_barycentric(mesh.order())) {
            let s = stress_at(mesh, material, plane, &d, &geo, *l, &ue);
            for k in 0..4 {
                nodal[v][k] += area * s[k];
            }
            weight[v] += area;
        }
    }
    for (s, w) in nodal.iter_mut().zip(&weight) {
        if *w > 0.0 {
            s.iter_mut().for_each(|x| *x /= w);
        }
    }
    let von_mises = nodal
        .iter()
        .map(|s| von_mises(s[0], s[1], s[2], s[3]))
        .collect();
    Stresses {
        element,
        nodal,
        von_mises,
    }
}

/// The residual `K u − f` per DOF. On supported DOFs it is the reaction: the force the supports
/// exert on the body (it vanishes elsewhere for an equilibrium solution).
pub fn residual(k: &SparseColMat<usize, f64>, u: &[f64], f: &[f64]) -> Vec<f64> {
    let mut r: Vec<f64> = f.iter().map(|v| -v).collect();
    let (col_ptr, row_idx, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    for (j, &uj) in u.iter().enumerate() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            r[row_idx[p]] += val[p] * uj;
        }
    }
    r
}

/// Total reaction force `[R_x, R_y]` on the nodes of a boundary, from the residual `K u − f`.
pub fn reaction_on(mesh: &Mesh, boundary: &str, residual: &[f64]) -> Option<Vector> {
    let nodes = mesh.boundary_nodes(boundary).ok()?;
    Some(nodes.iter().fold([0.0; DIM], |s, &v| {
        std::array::from_fn(|c| s[c] + residual[dof(v, c)])
    }))
}
