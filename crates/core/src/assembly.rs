//! Global assembly: the sparsity pattern of a body (built once) and the stiffness values
//! (assembled into it), plus consistent load vectors.
//!
//! DOF numbering: node `i` owns DOFs `2i` (u_x) and `2i + 1` (u_y). The stiffness matrix is stored
//! in full (both triangles) compressed-column form. Values are assembled column by column in
//! parallel: each node owns its two columns and gathers the contributions of the triangles around
//! it, so no two threads ever write the same entry and the result does not depend on the number of
//! threads.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use rayon::prelude::*;

use crate::element::{self, Affine, Geometry, EDGE_GAUSS_3, TRIANGLE_DEGREE_5};
use crate::geometry::{dof, Point, Vector, DIM};
use crate::mesh::{Edge, Mesh};

/// Node-to-triangle incidence of a mesh: for node i, the triangles
/// `cells[cell_ptr[i]..cell_ptr[i + 1]]`, in increasing order.
struct Incidence {
    cell_ptr: Vec<usize>,
    cells: Vec<usize>,
}

impl Incidence {
    fn new(mesh: &Mesh) -> Incidence {
        let n = mesh.num_nodes();
        let npc = mesh.order().nodes_per_cell();
        let mut count = vec![0usize; n + 1];
        for &v in mesh.cells() {
            count[v + 1] += 1;
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let cell_ptr = count.clone();
        let mut cells = vec![0; cell_ptr[n]];
        let mut fill = count;
        for (e, c) in mesh.cells().chunks(npc).enumerate() {
            for &v in c {
                cells[fill[v]] = e;
                fill[v] += 1;
            }
        }
        Incidence { cell_ptr, cells }
    }

    /// The triangles around node `i`.
    fn cells_of(&self, i: usize) -> &[usize] {
        &self.cells[self.cell_ptr[i]..self.cell_ptr[i + 1]]
    }

    /// The sorted neighbour nodes of node `i` (including i itself).
    fn neighbours_of(&self, mesh: &Mesh, i: usize) -> Vec<usize> {
        let mut l: Vec<usize> = (self.cells_of(i).iter())
            .flat_map(|&e| mesh.cell(e).iter().copied())
            .collect();
        l.sort_unstable();
        l.dedup();
        l
    }
}

/// Node-to-triangle incidence and node adjacency of a mesh.
struct Adjacency {
    incidence: Incidence,
    /// Sorted neighbour nodes (including i itself), CSR.
    nbr_ptr: Vec<usize>,
    nbrs: Vec<usize>,
}

impl Adjacency {
    fn new(mesh: &Mesh) -> Adjacency {
        let incidence = Incidence::new(mesh);
        let lists: Vec<Vec<usize>> = (0..mesh.num_nodes())
            .into_par_iter()
            .map(|i| incidence.neighbours_of(mesh, i))
            .collect();
        let mut nbr_ptr = Vec::with_capacity(lists.len() + 1);
        nbr_ptr.push(0);
        for l in &lists {
            nbr_ptr.push(nbr_ptr.last().copied().unwrap_or(0) + l.len());
        }
        let nbrs = lists.concat();
        Adjacency {
            incidence,
            nbr_ptr,
            nbrs,
        }
    }

    fn neighbours(&self, i: usize) -> &[usize] {
        &self.nbrs[self.nbr_ptr[i]..self.nbr_ptr[i + 1]]
    }
}

/// The two stiffness columns of node `i` (u_x, then u_y; each over the rows of its sorted
/// neighbours `nbrs`, two per neighbour) added into `cols`, from the triangles `cells` around it.
fn node_columns(
    mesh: &Mesh,
    d: &[[f64; 3]; 3],
    (i, cells, nbrs): (usize, &[usize], &[usize]),
    cols: &mut [f64],
) {
    let len = cols.len() / DIM;
    for &e in cells {
        let c = mesh.cell(e);
        let ke = Geometry::of_cell(mesh, e).stiffness(mesh.order(), d);
        let Some(a) = c.iter().position(|&v| v == i) else {
            continue;
        };
        for (b, &j) in c.iter().enumerate() {
            let Ok(p) = nbrs.binary_search(&j) else {
                continue;
            };
            for ci in 0..DIM {
                for cj in 0..DIM {
                    // Column dof(i, ci), row dof(j, cj).
                    cols[ci * len + dof(p, cj)] += ke[dof(b, cj)][dof(a, ci)];
                }
            }
        }
    }
}

/// The residual K u − f of the stiffness with elasticity matrix `d` in the rows of the nodes
/// `rows` only (zero in every other row), without assembling K: only the columns of the rows'
/// neighbours are built. Each row adds the same terms in the same order as the product with the
/// assembled matrix (`crate::post::residual`), so the values are the same to the bit. What a
/// body's support reactions need, at a cost that grows with the supported nodes.
pub fn residual_rows(
    mesh: &Mesh,
    d: &[[f64; 3]; 3],
    (u, f): (&[f64], &[f64]),
    rows: &[usize],
) -> Vec<f64> {
    let incidence = Incidence::new(mesh);
    let mut wanted = vec![false; mesh.num_nodes()];
    rows.iter().for_each(|&v| wanted[v] = true);
    let mut columns: Vec<usize> = (rows.iter())
        .flat_map(|&v| incidence.neighbours_of(mesh, v))
        .collect();
    columns.sort_unstable();
    columns.dedup();
    let built: Vec<(Vec<usize>, Vec<f64>)> = columns
        .par_iter()
        .map(|&j| {
            let nbrs = incidence.neighbours_of(mesh, j);
            let mut cols = vec![0.0; DIM * DIM * nbrs.len()];
            node_columns(mesh, d, (j, incidence.cells_of(j), &nbrs), &mut cols);
            (nbrs, cols)
        })
        .collect();
    let mut r = vec![0.0; f.len()];
    rows.iter()
        .for_each(|&v| (0..DIM).for_each(|c| r[dof(v, c)] = -f[dof(v, c)]));
    for (&j, (nbrs, cols)) in columns.iter().zip(&built) {
        let len = DIM * nbrs.len();
        for ci in 0..DIM {
            let uj = u[dof(j, ci)];
            for (p, &k) in nbrs.iter().enumerate().filter(|(_, &k)| wanted[k]) {
                for cj in 0..DIM {
                    r[dof(k, cj)] += cols[ci * len + dof(p, cj)] * uj;
                }
            }
        }
    }
    r
}

/// The fixed sparsity pattern of a body's stiffness matrix and the data needed to refill it.
pub struct Pattern {
    adjacency: Adjacency,
    symbolic: SymbolicSparseColMat<usize>,
}

impl Pattern {
    /// Builds the pattern of the `2n × 2n` stiffness matrix of `mesh`.
    pub fn new(mesh: &Mesh) -> Pattern {
        let adjacency = Adjacency::new(mesh);
        let symbolic = node_pattern(mesh.num_nodes(), DIM, |i| adjacency.neighbours(i));
        Pattern {
            adjacency,
            symbolic,
        }
    }

    /// The symbolic structure.
    pub fn symbolic(&self) -> &SymbolicSparseColMat<usize> {
        &self.symbolic
    }

    /// Assembles the stiffness matrix with elasticity matrix `d` into this pattern.
    pub fn stiffness(&self, mesh: &Mesh, d: &[[f64; 3]; 3]) -> SparseColMat<usize, f64> {
        let n = mesh.num_nodes();
        let adj = &self.adjacency;
        let col_ptr = self.symbolic.col_ptr();
        let mut values = vec![0.0; self.symbolic.row_idx().len()];
        let chunks = node_chunks(&mut values, col_ptr, n, DIM);
        chunks.into_par_iter().enumerate().for_each(|(i, cols)| {
            let cells = adj.incidence.cells_of(i);
            node_columns(mesh, d, (i, cells, adj.neighbours(i)), cols);
        });
        SparseColMat::new(self.symbolic.clone(), values)
    }
}

/// The symbolic pattern of the stiffness matrix of `n` nodes with `dofs` DOFs each (DOF
/// `dofs · node + component`), node i's columns holding the DOFs of `neighbours(i)` (sorted, i
/// included): each node's columns are contiguous, so its values are filled on their own
/// ([`node_chunks`]).
pub fn node_pattern<'a>(
    n: usize,
    dofs: usize,
    neighbours: impl Fn(usize) -> &'a [usize],
) -> SymbolicSparseColMat<usize> {
    let mut col_ptr = Vec::with_capacity(dofs * n + 1);
    col_ptr.push(0usize);
    let entries: usize = (0..n).map(|i| neighbours(i).len()).sum();
    let mut row_idx = Vec::with_capacity(dofs * dofs * entries);
    for i in 0..n {
        for _ in 0..dofs {
            for &j in neighbours(i) {
                row_idx.extend((0..dofs).map(|c| dofs * j + c));
            }
            col_ptr.push(row_idx.len());
        }
    }
    // Safe by construction: rows sorted and unique within each column, all < dofs · n.
    SymbolicSparseColMat::new_checked(dofs * n, dofs * n, col_ptr, None, row_idx)
}

/// The values of a [`node_pattern`] matrix split into each node's columns, for the nodes to fill
/// in parallel.
pub fn node_chunks<'a>(
    values: &'a mut [f64],
    col_ptr: &[usize],
    n: usize,
    dofs: usize,
) -> Vec<&'a mut [f64]> {
    let mut chunks: Vec<&mut [f64]> = Vec::with_capacity(n);
    let mut rest = values;
    for i in 0..n {
        let (head, tail) = rest.split_at_mut(col_ptr[dofs * (i + 1)] - col_ptr[dofs * i]);
        chunks.push(head);
        rest = tail;
    }
    chunks
}

/// Straight-sided geometry of triangle `c` (its first three nodes are the vertices); a curved
/// triangle's geometry is [`Geometry::of_cell`].
pub fn affine(mesh: &Mesh, c: &[usize]) -> Affine {
    let p = mesh.nodes();
    Affine::new([p[c[0]], p[c[1]], p[c[2]]])
}

/// Adds the consistent nodal forces of a body force `f(x)` (force per unit area), integrated by a
/// degree-5 rule (on a curved triangle, with the area element `det J / 2` of each point).
pub fn add_body_force(mesh: &Mesh, f: impl Fn(Point) -> Vector, rhs: &mut [f64]) {
    let order = mesh.order();
    for e in 0..mesh.num_cells() {
        let c = mesh.cell(e);
        let geo = Geometry::of_cell(mesh, e);
        for (l, w) in TRIANGLE_DEGREE_5
            .points
            .iter()
            .zip(TRIANGLE_DEGREE_5.weights)
        {
            let n = element::shape(order, *l);
            let fx = f(geo.point(*l));
            let da = geo.weight(*w, *l);
            for (k, &v) in c.iter().enumerate() {
                for c in 0..DIM {
                    rhs[dof(v, c)] += da * n[k] * fx[c];
                }
            }
        }
    }
}

/// Adds the consistent nodal forces of a traction on boundary edges. `traction(point, normal)`
/// returns the force per unit length at a point of an edge with outward unit normal `normal`.
///
/// Both straight and curved edges use the 3-point Gauss rule. A straight edge is integrated along
/// its chord; a curved edge along its parabola ([`Mesh::edge_point`], [`Mesh::edge_normal_at`]).
/// For a pressure, `n |dx/dt|` is linear in `t` and the rule is exact on curved edges too. For a
/// uniform traction vector the length element `|dx/dt|` is the square root of a quadratic: the
/// rule's relative error is of order θ⁶ on an edge turning by θ (4e-7 at θ = 30°), far below the
/// θ⁴ by which the parabola's length differs from the arc it replaces (8e-5 at 30°).
pub fn add_edge_traction(
    mesh: &Mesh,
    edges: &[Edge],
    traction: impl Fn(Point, Vector) -> Vector,
    rhs: &mut [f64],
) {
    let order = mesh.order();
    let p = mesh.nodes();
    for edge in edges {
        let ids: Vec<usize> = edge.nodes().collect();
        let mut add = |t: f64, w: f64, x: Point, normal: Vector, len: f64| {
            let tr = traction(x, normal);
            let n = element::edge_shape(order, t);
            for (k, &v) in ids.iter().enumerate() {
                for c in 0..DIM {
                    rhs[dof(v, c)] += w * len * n[k] * tr[c];
                }
            }
        };
        if mesh.is_curved_edge(edge) {
            for (t, w) in EDGE_GAUSS_3.0.iter().zip(EDGE_GAUSS_3.1) {
                let (normal, speed) = mesh.edge_normal_at(edge, *t);
                add(*t, w, mesh.edge_point(edge, *t), normal, speed);
            }
            continue;
        }
        let (normal, len) = mesh.edge_normal(edge);
        let (a, b) = (p[edge.a], p[edge.b]);
        for (t, w) in EDGE_GAUSS_3.0.iter().zip(EDGE_GAUSS_3.1) {
            let x: Point = std::array::from_fn(|c| a[c] + t * (b[c] - a[c]));
            add(*t, w, x, normal, len);
        }
    }
}

/// Adds a uniform normal pressure `p` on boundary edges (positive pushes into the body, i.e. the
/// traction is `−p n`).
pub fn add_pressure(mesh: &Mesh, edges: &[Edge], p: f64, rhs: &mut [f64]) {
    add_edge_traction(mesh, edges, |_, n| [-p * n[0], -p * n[1]], rhs);
}
