//! A tetrahedral mesh: nodes in space, P1 (4-node) or P2 (10-node, Gmsh's order, see
//! [`super::element`]) tetrahedra, and named boundary faces made of triangles.
//!
//! A face triangle has 3 nodes (P1) or 6 (P2: vertices a, b, c, then the mid-edge nodes of a-b,
//! b-c, c-a, Gmsh's 6-node triangle order). [`SolidMesh::new`] checks everything and stores each
//! face triangle oriented so that `(b − a) × (c − a)` points out of the body.

use std::collections::{BTreeMap, HashMap};

use super::element::{TetGeometry, TET_DEGREE_5, TET_EDGES};
use super::error::SolidError;
use super::{cross, dot3, sub, Point3};

/// Polynomial order of the tetrahedra.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TetOrder {
    /// Linear, 4 nodes.
    P1,
    /// Quadratic, 10 nodes.
    P2,
}

impl TetOrder {
    /// Nodes per tetrahedron.
    pub fn nodes_per_tet(self) -> usize {
        match self {
            TetOrder::P1 => 4,
            TetOrder::P2 => 10,
        }
    }

    /// Nodes per face triangle.
    pub fn nodes_per_face(self) -> usize {
        match self {
            TetOrder::P1 => 3,
            TetOrder::P2 => 6,
        }
    }
}

/// A validated tetrahedral mesh with named boundary faces.
#[derive(Clone, Debug)]
pub struct SolidMesh {
    nodes: Vec<Point3>,
    order: TetOrder,
    tets: Vec<usize>,
    faces: BTreeMap<String, Vec<usize>>,
}

/// Triangle key → (number of tetrahedra with this face, the last one, its local vertex opposite).
type Owners = HashMap<[usize; 3], (usize, usize, usize)>;

/// The local vertices of the face opposite vertex k, k = 0..4.
const OPPOSITE: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];

impl SolidMesh {
    /// Checks and builds a mesh: `tets` is the flat connectivity (4 or 10 nodes per tetrahedron
    /// by `order`), `faces` the named face triangles (flat, 3 or 6 nodes each).
    ///
    /// Errors: an empty mesh, a connectivity of the wrong length, a non-finite coordinate, a node
    /// index out of range, a node no tetrahedron uses, a degenerate (volume ≤ 1e-12 × the cube of
    /// its longest edge) or inverted tetrahedron, a curved P2 tetrahedron whose Jacobian is not
    /// positive at its nodes and at the 14 points of the degree-5 rule, a face triangle that is
    /// not the boundary face of exactly one tetrahedron (for P2 with the same mid-edge nodes).
    pub fn new(
        nodes: Vec<Point3>,
        order: TetOrder,
        tets: Vec<usize>,
        faces: Vec<(String, Vec<usize>)>,
    ) -> Result<SolidMesh, SolidError> {
        let npt = order.nodes_per_tet();
        if nodes.is_empty() || tets.is_empty() {
            return Err(SolidError::Empty);
        }
        if tets.len() % npt != 0 {
            return Err(SolidError::BadConnectivity {
                len: tets.len(),
                nodes_per_tet: npt,
            });
        }
        if let Some(node) = nodes.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(SolidError::NonFiniteNode { node });
        }
        check_connectivity(&nodes, &tets, npt)?;
        for (element, c) in tets.chunks(npt).enumerate() {
            check_tet(&nodes, c, element)?;
        }
        let mut mesh = SolidMesh {
            nodes,
            order,
            tets,
            faces: BTreeMap::new(),
        };
        let npf = order.nodes_per_face();
        for (name, f) in &faces {
            mesh.check_face_nodes(name, f)?;
        }
        let owners = mesh.face_owners(faces.iter().flat_map(|(_, f)| f.chunks(npf)));
        for (name, f) in faces {
            let oriented = mesh.orient_face(&name, &f, &owners)?;
            mesh.faces.entry(name).or_default().extend(oriented);
        }
        Ok(mesh)
    }

    /// The same connectivity and faces with the nodes moved to `nodes` (checked again).
    pub fn with_nodes(&self, nodes: Vec<Point3>) -> Result<SolidMesh, SolidError> {
        let faces = self
            .faces
            .iter()
            .map(|(n, f)| (n.clone(), f.clone()))
            .collect();
        SolidMesh::new(nodes, self.order, self.tets.clone(), faces)
    }

    /// Node coordinates.
    pub fn nodes(&self) -> &[Point3] {
        &self.nodes
    }

    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Element order.
    pub fn order(&self) -> TetOrder {
        self.order
    }

    /// Flat connectivity.
    pub fn tets(&self) -> &[usize] {
        &self.tets
    }

    /// Number of tetrahedra.
    pub fn num_tets(&self) -> usize {
        self.tets.len() / self.order.nodes_per_tet()
    }

    /// The nodes of tetrahedron `e`.
    pub fn tet(&self, e: usize) -> &[usize] {
        let npt = self.order.nodes_per_tet();
        &self.tets[e * npt..(e + 1) * npt]
    }

    /// The geometry of tetrahedron `e`.
    pub fn geometry(&self, e: usize) -> TetGeometry {
        let x: Vec<Point3> = self.tet(e).iter().map(|&v| self.nodes[v]).collect();
        TetGeometry::new(&x)
    }

    /// The face names, sorted.
    pub fn face_names(&self) -> impl Iterator<Item = &str> {
        self.faces.keys().map(String::as_str)
    }

    /// The triangles (flat, outward oriented) of face `name`.
    pub fn face(&self, name: &str) -> Result<&[usize], SolidError> {
        self.faces
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| SolidError::NoSuchFace {
                name: name.to_string(),
                known: self.faces.keys().cloned().collect(),
            })
    }

    /// The sorted distinct nodes of face `name`.
    pub fn face_nodes(&self, name: &str) -> Result<Vec<usize>, SolidError> {
        let mut v = self.face(name)?.to_vec();
        v.sort_unstable();
        v.dedup();
        Ok(v)
    }

    /// Diameter of the nodes' bounding box.
    pub fn bounding_box_diameter(&self) -> f64 {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.nodes {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        (0..3).map(|c| (hi[c] - lo[c]).powi(2)).sum::<f64>().sqrt()
    }

    /// Checks the length and the node indices of the connectivity `f` of face `name`.
    fn check_face_nodes(&self, name: &str, f: &[usize]) -> Result<(), SolidError> {
        let npf = self.order.nodes_per_face();
        if f.len() % npf != 0 {
            return Err(SolidError::FaceConnectivity {
                face: name.to_string(),
                len: f.len(),
                nodes_per_face: npf,
            });
        }
        if let Some(&node) = f.iter().find(|&&v| v >= self.nodes.len()) {
            return Err(SolidError::FaceNodeOutOfRange {
                face: name.to_string(),
                node,
                count: self.nodes.len(),
            });
        }
        Ok(())
    }

    /// Checks the triangles of face `name` against their `owners` ([`SolidMesh::face_owners`])
    /// and returns them outward oriented.
    fn orient_face(
        &self,
        name: &str,
        f: &[usize],
        owners: &Owners,
    ) -> Result<Vec<usize>, SolidError> {
        let npf = self.order.nodes_per_face();
        let mut out = Vec::with_capacity(f.len());
        for (t, tri) in f.chunks(npf).enumerate() {
            let bad = || SolidError::NotABoundaryFace {
                face: name.to_string(),
                triangle: t,
            };
            let Some(&(count, e, k)) = owners.get(&key(tri)) else {
                return Err(bad());
            };
            if count != 1 || !self.same_mid_nodes(tri, e) {
                return Err(bad());
            }
            let opposite = self.nodes[self.tet(e)[k]];
            let p = |i: usize| self.nodes[tri[i]];
            let n = cross(sub(p(1), p(0)), sub(p(2), p(0)));
            if dot3(n, sub(p(0), opposite)) >= 0.0 {
                out.extend_from_slice(tri);
            } else if npf == 3 {
                out.extend_from_slice(&[tri[0], tri[2], tri[1]]);
            } else {
                out.extend_from_slice(&[tri[0], tri[2], tri[1], tri[5], tri[4], tri[3]]);
            }
        }
        Ok(out)
    }

    /// For each of the triangles `tris`: how many tetrahedra have it as a face, and the last
    /// one's index and local vertex opposite the face.
    fn face_owners<'a>(&self, tris: impl Iterator<Item = &'a [usize]>) -> Owners {
        let mut owners: Owners = tris.map(|t| (key(t), (0, 0, 0))).collect();
        for e in 0..self.num_tets() {
            let c = self.tet(e);
            for (k, loc) in OPPOSITE.iter().enumerate() {
                if let Some(o) = owners.get_mut(&key(&[c[loc[0]], c[loc[1]], c[loc[2]]])) {
                    *o = (o.0 + 1, e, k);
                }
            }
        }
        owners
    }

    /// True if the P2 triangle `tri` has the mid-edge nodes of tetrahedron `e` on its edges
    /// (always true for P1).
    fn same_mid_nodes(&self, tri: &[usize], e: usize) -> bool {
        if tri.len() == 3 {
            return true;
        }
        let c = self.tet(e);
        let mid = |a: usize, b: usize| {
            TET_EDGES.iter().enumerate().find_map(|(k, [i, j])| {
                let (vi, vj) = (c[*i], c[*j]);
                ((vi == a && vj == b) || (vi == b && vj == a)).then_some(c[4 + k])
            })
        };
        [(0, 1, 3), (1, 2, 4), (2, 0, 5)]
            .iter()
            .all(|&(i, j, m)| mid(tri[i], tri[j]) == Some(tri[m]))
    }
}

/// The sorted vertices of a face triangle.
fn key(tri: &[usize]) -> [usize; 3] {
    let mut k = [tri[0], tri[1], tri[2]];
    k.sort_unstable();
    k
}

/// Node indices in range, every node used.
fn check_connectivity(nodes: &[Point3], tets: &[usize], npt: usize) -> Result<(), SolidError> {
    let mut used = vec![false; nodes.len()];
    for (element, c) in tets.chunks(npt).enumerate() {
        for &node in c {
            if node >= nodes.len() {
                return Err(SolidError::NodeOutOfRange {
                    element,
                    node,
                    count: nodes.len(),
                });
            }
            used[node] = true;
        }
    }
    match used.iter().position(|u| !u) {
        Some(node) => Err(SolidError::UnreferencedNode { node }),
        None => Ok(()),
    }
}

/// Volume sign and size of tetrahedron `c`; for a curved P2 one, the Jacobian at its nodes and
/// at the points of the degree-5 rule.
fn check_tet(nodes: &[Point3], c: &[usize], element: usize) -> Result<(), SolidError> {
    let p = |i: usize| nodes[c[i]];
    let det = dot3(sub(p(1), p(0)), cross(sub(p(2), p(0)), sub(p(3), p(0))));
    let longest = (0..4)
        .flat_map(|i| (i + 1..4).map(move |j| (i, j)))
        .map(|(i, j)| dot3(sub(p(j), p(i)), sub(p(j), p(i))).sqrt())
        .fold(0.0, f64::max);
    if det.abs() <= 1e-12 * longest.powi(3) {
        return Err(SolidError::DegenerateElement { element });
    }
    if det < 0.0 {
        return Err(SolidError::InvertedElement { element });
    }
    let x: Vec<Point3> = c.iter().map(|&v| nodes[v]).collect();
    let geo = TetGeometry::new(&x);
    if geo.is_curved() {
        let at_nodes = super::element::tet_node_barycentric(true);
        let folded = (at_nodes.iter().chain(TET_DEGREE_5.points))
            .any(|l| geo.grad(*l).1 <= 1e-12 * det.abs());
        if folded {
            return Err(SolidError::CurvedInverted { element });
        }
    }
    Ok(())
}
