//! A structured mesh of a box: `cells[0] × cells[1] × cells[2]` cubes (boxes), each split into six
//! tetrahedra along its main diagonal (the Kuhn, or Freudenthal, split).
//!
//! The six tetrahedra of a cube are the paths from its corner (0,0,0) to (1,1,1) taking one unit
//! step along each axis, in the six orders of the axes. The split is the same in every cube, so
//! each cube face is cut by the same diagonal from both sides and the mesh is conforming. P2 adds
//! the mid-edge nodes, shared by all tetrahedra of an edge: they are exactly the points of the
//! grid of half the spacing (cube edges' midpoints, face centres, cube centres).
//!
//! The named faces are `x-`, `x+`, `y-`, `y+`, `z-`, `z+`: the box's faces at the low and high end
//! of each axis, two triangles per cube face, outward oriented by [`SolidMesh::new`].

use super::element::TET_EDGES;
use super::error::SolidError;
use super::mesh::{SolidMesh, TetOrder};
use super::Point3;

/// Parameters of a structured tetrahedral box mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxMesh {
    /// The corner of lowest coordinates.
    pub origin: Point3,
    /// Edge lengths along x, y, z.
    pub size: [f64; 3],
    /// Cubes along x, y, z.
    pub cells: [usize; 3],
    /// Element order.
    pub order: TetOrder,
}

/// The face names, by axis and end (low, high).
pub const BOX_FACES: [[&str; 2]; 3] = [["x-", "x+"], ["y-", "y+"], ["z-", "z+"]];

impl BoxMesh {
    /// Builds the mesh. Errors on a zero cell count, a non-positive or non-finite size or a
    /// non-finite origin, or more nodes than fit in memory indices.
    pub fn mesh(&self) -> Result<SolidMesh, SolidError> {
        self.check()?;
        let s = if self.order == TetOrder::P2 { 2 } else { 1 };
        // Grid of the nodes: every vertex (P1) or every half-step point (P2).
        let g = self.cells.map(|n| s * n + 1);
        let index = |i: [usize; 3]| i[0] + g[0] * (i[1] + g[1] * i[2]);
        let nodes: Vec<Point3> = (0..g[2])
            .flat_map(|k| (0..g[1]).flat_map(move |j| (0..g[0]).map(move |i| [i, j, k])))
            .map(|i| {
                std::array::from_fn(|c| {
                    self.origin[c] + self.size[c] * i[c] as f64 / (s * self.cells[c]) as f64
                })
            })
            .collect();
        let mut tets =
            Vec::with_capacity(6 * self.cells.iter().product::<usize>() * (4 + 6 * (s - 1)));
        let mut faces: Vec<(String, Vec<usize>)> = (0..6)
            .map(|f| (BOX_FACES[f / 2][f % 2].to_string(), Vec::new()))
            .collect();
        for k in 0..self.cells[2] {
            for j in 0..self.cells[1] {
                for i in 0..self.cells[0] {
                    for verts in cube_tets([i, j, k]) {
                        // Grid points of the vertices (and of the mid-edge nodes, halfway).
                        let gp: Vec<[usize; 3]> = verts.iter().map(|v| v.map(|x| s * x)).collect();
                        let mut all = gp.clone();
                        if s == 2 {
                            all.extend(TET_EDGES.iter().map(|[a, b]| {
                                std::array::from_fn(|c| (gp[*a][c] + gp[*b][c]) / 2)
                            }));
                        }
                        tets.extend(all.iter().map(|&p| index(p)));
                        self.boundary_faces(&all, &index, &mut faces);
                    }
                }
            }
        }
        let order = self.order;
        SolidMesh::new(nodes, order, tets, faces)
    }

    /// Adds the faces of the tetrahedron with grid points `all` that lie on the box's boundary.
    fn boundary_faces(
        &self,
        all: &[[usize; 3]],
        index: &impl Fn([usize; 3]) -> usize,
        faces: &mut [(String, Vec<usize>)],
    ) {
        let s = if self.order == TetOrder::P2 { 2 } else { 1 };
        for opposite in 0..4 {
            let tri: Vec<usize> = (0..4).filter(|&v| v != opposite).collect();
            for axis in 0..3 {
                for (end, value) in [0, s * self.cells[axis]].into_iter().enumerate() {
                    if tri.iter().all(|&v| all[v][axis] == value) {
                        let mut f: Vec<usize> = tri.iter().map(|&v| index(all[v])).collect();
                        if s == 2 {
                            let mid = |a: usize, b: usize| {
                                index(std::array::from_fn(|c| (all[a][c] + all[b][c]) / 2))
                            };
                            f.extend([
                                mid(tri[0], tri[1]),
                                mid(tri[1], tri[2]),
                                mid(tri[2], tri[0]),
                            ]);
                        }
                        faces[2 * axis + end].1.extend(f);
                    }
                }
            }
        }
    }

    /// Parameter checks.
    fn check(&self) -> Result<(), SolidError> {
        if self.cells.contains(&0) {
            return Err(SolidError::BadBox(format!(
                "every cell count must be at least 1, got {:?}",
                self.cells
            )));
        }
        if !self.size.iter().all(|s| s.is_finite() && *s > 0.0) {
            return Err(SolidError::BadBox(format!(
                "every size must be positive and finite, got {:?}",
                self.size
            )));
        }
        if !self.origin.iter().all(|o| o.is_finite()) {
            return Err(SolidError::BadBox(format!(
                "the origin must be finite, got {:?}",
                self.origin
            )));
        }
        let s = if self.order == TetOrder::P2 { 2 } else { 1 };
        let nodes = self
            .cells
            .iter()
            .try_fold(1usize, |acc, &n| acc.checked_mul(s * n + 1));
        if nodes.and_then(|n| n.checked_mul(30)).is_none() {
            return Err(SolidError::BadBox(format!(
                "too many nodes for {:?} cells",
                self.cells
            )));
        }
        Ok(())
    }
}

/// The six positively oriented tetrahedra (vertex grid points) of cube `c`: the paths from its
/// corner (0,0,0) to (1,1,1) along the axes in each order; for an odd order of the axes the
/// second and third vertices are swapped so that the volume is positive.
fn cube_tets(c: [usize; 3]) -> [[[usize; 3]; 4]; 6] {
    const ORDERS: [([usize; 3], bool); 6] = [
        ([0, 1, 2], false),
        ([1, 2, 0], false),
        ([2, 0, 1], false),
        ([0, 2, 1], true),
        ([2, 1, 0], true),
        ([1, 0, 2], true),
    ];
    ORDERS.map(|(axes, odd)| {
        let mut v = [c; 4];
        for step in 0..3 {
            v[step + 1] = v[step];
            v[step + 1][axes[step]] += 1;
        }
        if odd {
            v.swap(1, 2);
        }
        v
    })
}
