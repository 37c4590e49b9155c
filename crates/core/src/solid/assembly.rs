//! Global assembly of a tetrahedral body: the sparsity pattern (built once), the stiffness values
//! and consistent load vectors (body forces, face tractions).
//!
//! DOF numbering: node `i` owns DOFs `3i + c` ([`super::dof`]). The stiffness is stored in full
//! (both triangles) compressed-column form. Values are assembled column by column in parallel:
//! each node owns its three columns and adds the blocks of the tetrahedra around it in increasing
//! element order, so no two threads write the same entry and the values are the same to the bit
//! on any number of threads.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use rayon::prelude::*;

use super::element::{stiffness_columns, tet_shape, TET_DEGREE_5};
use super::error::SolidError;
use super::mesh::{SolidMesh, TetOrder};
use super::{cross, dof, num_dofs, Point3, Vector3};
use crate::assembly::{node_chunks, node_pattern};
use crate::element::TRIANGLE_DEGREE_5;

/// Node-to-tetrahedron incidence and the sorted neighbours of every node (itself included).
struct Adjacency {
    tet_ptr: Vec<usize>,
    tets: Vec<usize>,
    nbr_ptr: Vec<usize>,
    nbrs: Vec<usize>,
}

impl Adjacency {
    fn new(mesh: &SolidMesh) -> Adjacency {
        let n = mesh.num_nodes();
        let npt = mesh.order().nodes_per_tet();
        let mut tet_ptr = vec![0usize; n + 1];
        for &v in mesh.tets() {
            tet_ptr[v + 1] += 1;
        }
        for i in 0..n {
            tet_ptr[i + 1] += tet_ptr[i];
        }
        let mut fill = tet_ptr.clone();
        let mut tets = vec![0; tet_ptr[n]];
        for (e, c) in mesh.tets().chunks(npt).enumerate() {
            for &v in c {
                tets[fill[v]] = e;
                fill[v] += 1;
            }
        }
        let lists: Vec<Vec<usize>> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut l: Vec<usize> = tets[tet_ptr[i]..tet_ptr[i + 1]]
                    .iter()
                    .flat_map(|&e| mesh.tet(e).iter().copied())
                    .collect();
                l.sort_unstable();
                l.dedup();
                l
            })
            .collect();
        let mut nbr_ptr = Vec::with_capacity(n + 1);
        nbr_ptr.push(0);
        for l in &lists {
            nbr_ptr.push(nbr_ptr[nbr_ptr.len() - 1] + l.len());
        }
        Adjacency {
            tet_ptr,
            tets,
            nbr_ptr,
            nbrs: lists.concat(),
        }
    }

    fn tets_of(&self, i: usize) -> &[usize] {
        &self.tets[self.tet_ptr[i]..self.tet_ptr[i + 1]]
    }

    fn neighbours(&self, i: usize) -> &[usize] {
        &self.nbrs[self.nbr_ptr[i]..self.nbr_ptr[i + 1]]
    }
}

/// The fixed sparsity pattern of a tetrahedral body's stiffness matrix.
pub struct SolidPattern {
    adjacency: Adjacency,
    symbolic: SymbolicSparseColMat<usize>,
}

impl SolidPattern {
    /// Builds the pattern of the `3n × 3n` stiffness matrix of `mesh`.
    pub fn new(mesh: &SolidMesh) -> SolidPattern {
        let adjacency = Adjacency::new(mesh);
        let symbolic = node_pattern(mesh.num_nodes(), 3, |i| adjacency.neighbours(i));
        SolidPattern {
            adjacency,
            symbolic,
        }
    }

    /// The symbolic structure.
    pub fn symbolic(&self) -> &SymbolicSparseColMat<usize> {
        &self.symbolic
    }

    /// Assembles the stiffness matrix with elasticity matrix `d` (6×6, Voigt) into this pattern.
    pub fn stiffness(&self, mesh: &SolidMesh, d: &[[f64; 6]; 6]) -> SparseColMat<usize, f64> {
        let n = mesh.num_nodes();
        let adj = &self.adjacency;
        let col_ptr = self.symbolic.col_ptr();
        let mut values = vec![0.0; self.symbolic.row_idx().len()];
        let chunks = node_chunks(&mut values, col_ptr, n, 3);
        chunks.into_par_iter().enumerate().for_each(|(i, cols)| {
            node_columns(mesh, d, (i, adj.tets_of(i), adj.neighbours(i)), cols);
        });
        SparseColMat::new(self.symbolic.clone(), values)
    }
}

/// Assembles the stiffness matrix of `mesh` with elasticity matrix `d` (pattern and values).
pub fn stiffness(mesh: &SolidMesh, d: &[[f64; 6]; 6]) -> SparseColMat<usize, f64> {
    SolidPattern::new(mesh).stiffness(mesh, d)
}

/// The three stiffness columns of node `i` (u_x, u_y, u_z; each over the rows of its sorted
/// neighbours `nbrs`, three per neighbour) added into `cols`, from the tetrahedra `tets` around it.
fn node_columns(
    mesh: &SolidMesh,
    d: &[[f64; 6]; 6],
    (i, tets, nbrs): (usize, &[usize], &[usize]),
    cols: &mut [f64],
) {
    let len = cols.len() / 3;
    for &e in tets {
        let c = mesh.tet(e);
        let Some(a) = c.iter().position(|&v| v == i) else {
            continue;
        };
        let blocks = stiffness_columns(&mesh.geometry(e), d, a);
        for (b, &j) in c.iter().enumerate() {
            let Ok(p) = nbrs.binary_search(&j) else {
                continue;
            };
            for ci in 0..3 {
                for cj in 0..3 {
                    // Column dof(i, ci), row dof(j, cj).
                    cols[ci * len + dof(p, cj)] += blocks[b][cj][ci];
                }
            }
        }
    }
}

/// Adds the consistent nodal forces `∫ f·N_k dV` of a body force `f(x)` (force per unit volume),
/// integrated by the degree-5 rule ([`TET_DEGREE_5`]) with the Jacobian of each point. Errors if
/// `rhs` has not one entry per DOF or a force is not finite.
pub fn add_body_force(
    mesh: &SolidMesh,
    f: impl Fn(Point3) -> Vector3,
    rhs: &mut [f64],
) -> Result<(), SolidError> {
    check_len(mesh, rhs)?;
    let p2 = mesh.order() == TetOrder::P2;
    for e in 0..mesh.num_tets() {
        let c = mesh.tet(e);
        let geo = mesh.geometry(e);
        for (l, w) in TET_DEGREE_5.points.iter().zip(TET_DEGREE_5.weights) {
            let n = tet_shape(p2, *l);
            let fx = f(geo.point(*l));
            if fx.iter().any(|v| !v.is_finite()) {
                return Err(SolidError::NonFinite {
                    what: format!("the body force at {:?}", geo.point(*l)),
                });
            }
            let dv = w * geo.grad(*l).1 / 6.0;
            for (k, &v) in c.iter().enumerate() {
                for comp in 0..3 {
                    rhs[dof(v, comp)] += dv * n[k] * fx[comp];
                }
            }
        }
    }
    Ok(())
}

/// Adds the consistent nodal forces `∫ t·N_k dS` of a traction on face `name`:
/// `traction(point, outward unit normal)` is the force per unit area. Each triangle is integrated
/// by the degree-5 triangle rule on its isoparametric surface (exact on flat P1 and P2 triangles
/// for tractions of degree up to 3). On a flat 6-node triangle a uniform traction loads the
/// vertices with zero and each mid-edge node with a third of the force.
pub fn add_face_traction(
    mesh: &SolidMesh,
    name: &str,
    traction: impl Fn(Point3, Vector3) -> Vector3,
    rhs: &mut [f64],
) -> Result<(), SolidError> {
    check_len(mesh, rhs)?;
    let npf = mesh.order().nodes_per_face();
    let p = mesh.nodes();
    for tri in mesh.face(name)?.chunks(npf) {
        for (l, w) in TRIANGLE_DEGREE_5
            .points
            .iter()
            .zip(TRIANGLE_DEGREE_5.weights)
        {
            let (n, ds, dt) = triangle_shape(npf == 6, *l);
            let mut x = [0.0; 3];
            let (mut xs, mut xt) = ([0.0; 3], [0.0; 3]);
            for (k, &v) in tri.iter().enumerate() {
                for c in 0..3 {
                    x[c] += n[k] * p[v][c];
                    xs[c] += ds[k] * p[v][c];
                    xt[c] += dt[k] * p[v][c];
                }
            }
            let normal = cross(xs, xt);
            let jac = normal.iter().map(|c| c * c).sum::<f64>().sqrt();
            let t = traction(x, normal.map(|c| c / jac));
            if t.iter().any(|v| !v.is_finite()) {
                return Err(SolidError::NonFinite {
                    what: format!("the traction on face '{name}' at {x:?}"),
                });
            }
            // Reference triangle area 1/2, weights summing to 1.
            let da = 0.5 * w * jac;
            for (k, &v) in tri.iter().enumerate() {
                for c in 0..3 {
                    rhs[dof(v, c)] += da * n[k] * t[c];
                }
            }
        }
    }
    Ok(())
}

/// Shape values and their derivatives with respect to s = l1 and t = l2 of a 3-node or (with
/// `p2`) 6-node triangle (vertices, then mid-edges 0-1, 1-2, 2-0) at barycentric point `l`.
fn triangle_shape(p2: bool, l: [f64; 3]) -> ([f64; 6], [f64; 6], [f64; 6]) {
    let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    let (mut n, mut ds, mut dt) = ([0.0; 6], [0.0; 6], [0.0; 6]);
    if !p2 {
        for i in 0..3 {
            (n[i], ds[i], dt[i]) = (l[i], dl[i][0], dl[i][1]);
        }
        return (n, ds, dt);
    }
    for i in 0..3 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        ds[i] = (4.0 * l[i] - 1.0) * dl[i][0];
        dt[i] = (4.0 * l[i] - 1.0) * dl[i][1];
    }
    for (k, (a, b)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
        n[3 + k] = 4.0 * l[a] * l[b];
        ds[3 + k] = 4.0 * (l[a] * dl[b][0] + l[b] * dl[a][0]);
        dt[3 + k] = 4.0 * (l[a] * dl[b][1] + l[b] * dl[a][1]);
    }
    (n, ds, dt)
}

/// A vector of one entry per DOF of `mesh`, or an error.
fn check_len(mesh: &SolidMesh, v: &[f64]) -> Result<(), SolidError> {
    if v.len() == num_dofs(mesh.num_nodes()) {
        Ok(())
    } else {
        Err(SolidError::Length {
            what: "the load vector",
            expected: num_dofs(mesh.num_nodes()),
            got: v.len(),
        })
    }
}
