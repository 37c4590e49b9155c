//! Triangular meshes: nodes, P1/P2 triangles, named boundary edge sets and node sets.
//!
//! A [`Mesh`] is always validated on construction: every triangle is counter-clockwise with a
//! positive area, every curved P2 triangle (a mid-side node off its edge's midpoint: an
//! isoparametric triangle) has a positive Jacobian everywhere, every node is used by some triangle, and every boundary edge is an edge of exactly one triangle. Boundary
//! edges are stored oriented so that the body lies on their left; the outward normal of an edge
//! from `a` to `b` is therefore `(b - a)` rotated clockwise.

use std::collections::BTreeMap;

use crate::error::MeshError;
use crate::fast_hash::FastMap;
use crate::geometry::{Point, Vector, DIM};
use crate::names::{listed, shown};

/// Polynomial order of the Lagrange triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Order {
    /// Linear triangle, 3 vertex nodes.
    P1,
    /// Quadratic triangle, 3 vertex nodes then the mid-side nodes of edges (0,1), (1,2), (2,0).
    P2,
}

impl Order {
    /// Number of nodes of one triangle.
    pub fn nodes_per_cell(self) -> usize {
        match self {
            Order::P1 => 3,
            Order::P2 => 6,
        }
    }
}

/// A boundary edge. For P2 meshes `mid` is the mid-side node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// First vertex (the body lies to the left of `a → b` once the mesh is validated).
    pub a: usize,
    /// Second vertex.
    pub b: usize,
    /// Mid-side node (P2 only).
    pub mid: Option<usize>,
}

impl Edge {
    /// A P1 edge.
    pub fn new(a: usize, b: usize) -> Self {
        Edge { a, b, mid: None }
    }

    /// The edge's nodes in the order `a, b, [mid]`.
    pub fn nodes(&self) -> impl Iterator<Item = usize> + '_ {
        [self.a, self.b].into_iter().chain(self.mid)
    }
}

/// A validated triangular mesh of one body.
#[derive(Clone, Debug)]
pub struct Mesh {
    nodes: Vec<Point>,
    order: Order,
    cells: Vec<usize>,
    boundaries: BTreeMap<String, Vec<Edge>>,
    node_sets: BTreeMap<String, Vec<usize>>,
}

/// Local vertex pairs of a triangle's edges, and the local index of their mid-side node.
pub const TRIANGLE_EDGES: [(usize, usize, usize); 3] = [(0, 1, 3), (1, 2, 4), (2, 0, 5)];

impl Mesh {
    /// Validates and builds a mesh. `cells` is flat, `order.nodes_per_cell()` node indices per
    /// triangle. Boundary edges may be given in either direction; they are re-oriented so that the
    /// body lies on their left, and for P2 the missing mid-side node is filled in.
    pub fn new(
        nodes: Vec<Point>,
        order: Order,
        cells: Vec<usize>,
        boundaries: BTreeMap<String, Vec<Edge>>,
        node_sets: BTreeMap<String, Vec<usize>>,
    ) -> Result<Mesh, MeshError> {
        let npc = order.nodes_per_cell();
        if nodes.is_empty() || cells.is_empty() {
            return Err(MeshError::Empty);
        }
        if cells.len() % npc != 0 {
            return Err(MeshError::BadConnectivity {
                len: cells.len(),
                nodes_per_cell: npc,
            });
        }
        for (i, p) in nodes.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(MeshError::NonFiniteNode { node: i });
            }
        }
        let n = nodes.len();
        let mut used = vec![false; n];
        for (e, cell) in cells.chunks(npc).enumerate() {
            for &v in cell {
                if v >= n {
                    return Err(MeshError::NodeOutOfRange {
                        element: e,
                        node: v,
                        count: n,
                    });
                }
                used[v] = true;
            }
        }
        if let Some(node) = used.iter().position(|u| !u) {
            return Err(MeshError::UnreferencedNode { node });
        }
        let mut mesh = Mesh {
            nodes,
            order,
            cells,
            boundaries: BTreeMap::new(),
            node_sets,
        };
        mesh.check_cells()?;
        for (name, set) in &mesh.node_sets {
            if let Some(&node) = set.iter().find(|&&v| v >= n) {
                return Err(MeshError::NodeSetOutOfRange {
                    set: shown(name),
                    node,
                });
            }
        }
        mesh.boundaries = mesh.orient_boundaries(boundaries)?;
        Ok(mesh)
    }

    fn check_cells(&self) -> Result<(), MeshError> {
        let h = self.bounding_box_diameter();
        for e in 0..self.num_cells() {
            let c = self.cell(e);
            let [p0, p1, p2] = [self.nodes[c[0]], self.nodes[c[1]], self.nodes[c[2]]];
            let area2 = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]);
            let longest = [dist(p0, p1), dist(p1, p2), dist(p2, p0)]
                .into_iter()
                .fold(0.0, f64::max);
            // A triangle whose area is tiny relative to its longest edge squared is degenerate.
            if area2.abs() <= 1e-12 * longest * longest || longest <= 1e-14 * h {
                return Err(MeshError::DegenerateElement { element: e });
            }
            if area2 < 0.0 {
                return Err(MeshError::InvertedElement { element: e });
            }
            if self.is_curved_cell(e) && !self.positive_jacobian(e) {
                return Err(MeshError::CurvedInverted { element: e });
            }
        }
        Ok(())
    }

    /// The owners of every given boundary edge, by its sorted vertex pair: how many triangles
    /// have it (saturating at 255) and the first one's (element, local edge). One pass over the
    /// triangles fills the owners of these edges only; an edge with a node out of range has none.
    fn boundary_owners(
        &self,
        boundaries: &BTreeMap<String, Vec<Edge>>,
    ) -> FastMap<(usize, usize), (u8, (usize, usize))> {
        let mut owners: FastMap<(usize, usize), (u8, (usize, usize))> = FastMap::default();
        let mut on_boundary = vec![false; self.nodes.len()];
        for edge in boundaries.values().flatten() {
            owners.insert((edge.a.min(edge.b), edge.a.max(edge.b)), (0, (0, 0)));
            for v in [edge.a, edge.b] {
                if let Some(flag) = on_boundary.get_mut(v) {
                    *flag = true;
                }
            }
        }
        for e in 0..self.num_cells() {
            let c = self.cell(e);
            for (k, &(i, j, _)) in TRIANGLE_EDGES.iter().enumerate() {
                // Cells hold nodes in range (checked by `Mesh::new` before).
                if !(on_boundary[c[i]] && on_boundary[c[j]]) {
                    continue;
                }
                if let Some((count, owner)) = owners.get_mut(&(c[i].min(c[j]), c[i].max(c[j]))) {
                    if *count == 0 {
                        *owner = (e, k);
                    }
                    *count = count.saturating_add(1);
                }
            }
        }
        owners
    }

    fn orient_boundaries(
        &self,
        boundaries: BTreeMap<String, Vec<Edge>>,
    ) -> Result<BTreeMap<String, Vec<Edge>>, MeshError> {
        let owners = self.boundary_owners(&boundaries);
        let mut out = BTreeMap::new();
        for (name, edges) in boundaries {
            let mut oriented = Vec::with_capacity(edges.len());
            for edge in edges {
                let key = (edge.a.min(edge.b), edge.a.max(edge.b));
                let Some(&(1, (e, k))) = owners.get(&key) else {
                    return Err(MeshError::NotABoundaryEdge {
                        boundary: shown(&name),
                        a: edge.a,
                        b: edge.b,
                    });
                };
                let (i, j, m) = TRIANGLE_EDGES[k];
                let c = self.cell(e);
                let mid = match self.order {
                    Order::P1 => None,
                    Order::P2 => Some(c[m]),
                };
                oriented.push(Edge {
                    a: c[i],
                    b: c[j],
                    mid,
                });
            }
            out.insert(name, oriented);
        }
        Ok(out)
    }

    /// Node coordinates.
    pub fn nodes(&self) -> &[Point] {
        &self.nodes
    }

    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Element order.
    pub fn order(&self) -> Order {
        self.order
    }

    /// Number of triangles.
    pub fn num_cells(&self) -> usize {
        self.cells.len() / self.order.nodes_per_cell()
    }

    /// Node indices of triangle `e` (3 or 6).
    pub fn cell(&self, e: usize) -> &[usize] {
        let npc = self.order.nodes_per_cell();
        &self.cells[e * npc..(e + 1) * npc]
    }

    /// Flat connectivity, `nodes_per_cell` indices per triangle.
    pub fn cells(&self) -> &[usize] {
        &self.cells
    }

    /// Named boundary edge sets.
    pub fn boundaries(&self) -> &BTreeMap<String, Vec<Edge>> {
        &self.boundaries
    }

    /// Named node sets (e.g. Gmsh physical points).
    pub fn node_sets(&self) -> &BTreeMap<String, Vec<usize>> {
        &self.node_sets
    }

    /// The edges of boundary `name`, or an error listing the names that exist.
    pub fn boundary(&self, name: &str) -> Result<&[Edge], MeshError> {
        self.boundaries
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| MeshError::NoSuchBoundary {
                name: shown(name),
                known: listed(self.boundaries.keys().map(String::as_str)),
            })
    }

    /// Sorted, deduplicated nodes of boundary `name` (or of node set `name`).
    pub fn boundary_nodes(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        let mut nodes: Vec<usize> = match (self.boundaries.get(name), self.node_sets.get(name)) {
            (Some(edges), _) => edges.iter().flat_map(|e| e.nodes()).collect(),
            (None, Some(set)) => set.clone(),
            (None, None) => {
                return Err(MeshError::NoSuchBoundary {
                    name: shown(name),
                    known: listed(
                        (self.boundaries.keys())
                            .chain(self.node_sets.keys())
                            .map(String::as_str),
                    ),
                })
            }
        };
        nodes.sort_unstable();
        nodes.dedup();
        Ok(nodes)
    }

    /// Length of the bounding box diagonal (a length scale for tolerances).
    pub fn bounding_box_diameter(&self) -> f64 {
        let (lo, hi) = self.bounding_box();
        dist(lo, hi)
    }

    /// The lower and upper corners of the bounding box of the nodes.
    pub fn bounding_box(&self) -> (Point, Point) {
        let (mut lo, mut hi) = ([f64::INFINITY; DIM], [f64::NEG_INFINITY; DIM]);
        for p in &self.nodes {
            for d in 0..DIM {
                lo[d] = lo[d].min(p[d]);
                hi[d] = hi[d].max(p[d]);
            }
        }
        (lo, hi)
    }

    /// Turns a P1 mesh into the P2 mesh on the same triangles by adding one node per edge
    /// (a P2 mesh is returned unchanged). The new nodes follow the old ones, numbered in the
    /// order their edges are first met, triangle by triangle.
    pub fn to_p2(&self) -> Mesh {
        if self.order == Order::P2 {
            return self.clone();
        }
        let n = self.nodes.len();
        let mut mid_of = EdgeTable::new(n, &self.cells);
        let mut cells = Vec::with_capacity(self.num_cells() * 6);
        let mut next = n;
        for c in self.cells.chunks_exact(3) {
            cells.extend_from_slice(c);
            for &(i, j, _) in &TRIANGLE_EDGES {
                cells.push(mid_of.number(c[i], c[j], &mut next));
            }
        }
        // The mid-side nodes in their numbering: each is met first where its number is next.
        let mut nodes = Vec::with_capacity(next);
        nodes.extend_from_slice(&self.nodes);
        for cell in cells.chunks_exact(6) {
            for &(i, j, m) in &TRIANGLE_EDGES {
                if cell[m] == nodes.len() {
                    let (a, b) = (self.nodes[cell[i]], self.nodes[cell[j]]);
                    nodes.push([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
                }
            }
        }
        let boundaries = self
            .boundaries
            .iter()
            .map(|(name, edges)| {
                let edges = edges
                    .iter()
                    .map(|e| Edge {
                        a: e.a,
                        b: e.b,
                        mid: mid_of.get(e.a, e.b),
                    })
                    .collect();
                (name.clone(), edges)
            })
            .collect();
        Mesh {
            nodes,
            order: Order::P2,
            cells,
            boundaries,
            node_sets: self.node_sets.clone(),
        }
    }

    /// The part of the mesh on the boundaries `names`: their nodes, renumbered in increasing
    /// order of their numbers here (returned beside: the new node k is node `ids[k]` here), and
    /// their edges. Every other boundary and node set keeps its name with no edges or nodes, and
    /// there are no elements. What another process needs of a body to pair with it; names that
    /// are not boundaries of the mesh are left out.
    pub fn skin(&self, names: &[&str]) -> (Mesh, Vec<usize>) {
        let chosen = |name: &String| names.contains(&name.as_str());
        let mut ids: Vec<usize> = (self.boundaries.iter())
            .filter(|(name, _)| chosen(name))
            .flat_map(|(_, edges)| edges.iter().flat_map(|e| e.nodes()))
            .collect();
        ids.sort_unstable();
        ids.dedup();
        // Every node of a chosen edge is in `ids`, so the search finds it.
        let at = |v: usize| ids.binary_search(&v).unwrap_or_else(|k| k);
        let boundaries = (self.boundaries.iter())
            .map(|(name, edges)| {
                let kept = match chosen(name) {
                    true => (edges.iter())
                        .map(|e| Edge {
                            a: at(e.a),
                            b: at(e.b),
                            mid: e.mid.map(at),
                        })
                        .collect(),
                    false => Vec::new(),
                };
                (name.clone(), kept)
            })
            .collect();
        let skin = Mesh {
            nodes: ids.iter().map(|&v| self.nodes[v]).collect(),
            order: self.order,
            cells: Vec::new(),
            boundaries,
            node_sets: self
                .node_sets
                .keys()
                .map(|k| (k.clone(), Vec::new()))
                .collect(),
        };
        (skin, ids)
    }

    /// A skin ([`Mesh::skin`]) from its parts, as it travels between processes: its nodes, order
    /// and boundaries (checked to name existing nodes), and the names of the body's node sets.
    pub fn skin_from_parts(
        nodes: Vec<Point>,
        order: Order,
        boundaries: BTreeMap<String, Vec<Edge>>,
        node_sets: Vec<String>,
    ) -> Result<Mesh, MeshError> {
        for (name, edges) in &boundaries {
            if let Some(e) = edges.iter().find(|e| e.nodes().any(|v| v >= nodes.len())) {
                return Err(MeshError::NotABoundaryEdge {
                    boundary: shown(name),
                    a: e.a,
                    b: e.b,
                });
            }
        }
        Ok(Mesh {
            nodes,
            order,
            cells: Vec::new(),
            boundaries,
            node_sets: node_sets.into_iter().map(|k| (k, Vec::new())).collect(),
        })
    }

    /// Whether the mid-side node `mid` of the edge from `a` to `b` lies off the edge's midpoint
    /// (by more than 1e-8 of its length, the rounding of a mesh written in text): the edge is
    /// then a parabolic arc, and every quantity along it uses the quadratic map.
    fn curved(&self, a: usize, b: usize, mid: Option<usize>) -> bool {
        let Some(m) = mid else { return false };
        let (a, b, m) = (self.nodes[a], self.nodes[b], self.nodes[m]);
        // Squared lengths: asked once per triangle and column in the assembly.
        let square = |u: Point, v: Point| (u[0] - v[0]).powi(2) + (u[1] - v[1]).powi(2);
        square([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])], m) > 1e-16 * square(a, b)
    }

    /// Whether a boundary edge is curved (a P2 edge whose mid-side node is off its midpoint).
    pub fn is_curved_edge(&self, edge: &Edge) -> bool {
        self.curved(edge.a, edge.b, edge.mid)
    }

    /// Whether triangle `e` is curved (isoparametric): one of its edges is.
    pub fn is_curved_cell(&self, e: usize) -> bool {
        self.order == Order::P2
            && TRIANGLE_EDGES.iter().any(|&(i, j, m)| {
                let c = self.cell(e);
                self.curved(c[i], c[j], Some(c[m]))
            })
    }

    /// Whether any triangle of the mesh is curved.
    pub fn is_curved(&self) -> bool {
        (0..self.num_cells()).any(|e| self.is_curved_cell(e))
    }

    /// Whether the Jacobian determinant of the quadratic map of triangle `e` is positive
    /// everywhere. It is a quadratic polynomial, so its six nodal values give its Bernstein
    /// coefficients (the vertex values, and 2 f(mid) − (f_a + f_b)/2 per edge), and positive
    /// coefficients make it positive on the whole triangle.
    fn positive_jacobian(&self, e: usize) -> bool {
        let c = self.cell(e);
        let x: [Point; 6] = std::array::from_fn(|i| self.nodes[c[i]]);
        let det = |l: [f64; 3]| {
            // ∂x/∂λ_k of the P2 map, then J = [∂x/∂λ1 − ∂x/∂λ0, ∂x/∂λ2 − ∂x/∂λ0].
            let d: [[f64; 6]; 3] = [
                [4.0 * l[0] - 1.0, 0.0, 0.0, 4.0 * l[1], 0.0, 4.0 * l[2]],
                [0.0, 4.0 * l[1] - 1.0, 0.0, 4.0 * l[0], 4.0 * l[2], 0.0],
                [0.0, 0.0, 4.0 * l[2] - 1.0, 0.0, 4.0 * l[1], 4.0 * l[0]],
            ];
            let dx = |k: usize, c: usize| (0..6).map(|i| d[k][i] * x[i][c]).sum::<f64>();
            let j = |k: usize, c: usize| dx(k, c) - dx(0, c);
            j(1, 0) * j(2, 1) - j(2, 0) * j(1, 1)
        };
        let v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(det);
        let m = [[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]].map(det);
        let bernstein = [
            2.0 * m[0] - 0.5 * (v[0] + v[1]),
            2.0 * m[1] - 0.5 * (v[1] + v[2]),
            2.0 * m[2] - 0.5 * (v[2] + v[0]),
        ];
        v.iter().chain(&bernstein).all(|&b| b > 0.0)
    }

    /// The point of a boundary edge at parameter `t ∈ [0, 1]` (from `a` to `b`): on the chord
    /// for a straight edge, on the parabola through `a`, `mid`, `b` for a curved one.
    pub fn edge_point(&self, edge: &Edge, t: f64) -> Point {
        let (a, b) = (self.nodes[edge.a], self.nodes[edge.b]);
        match edge.mid.filter(|_| self.is_curved_edge(edge)) {
            None => std::array::from_fn(|c| a[c] + t * (b[c] - a[c])),
            Some(m) => {
                let m = self.nodes[m];
                let n = [
                    (1.0 - t) * (1.0 - 2.0 * t),
                    t * (2.0 * t - 1.0),
                    4.0 * t * (1.0 - t),
                ];
                std::array::from_fn(|c| n[0] * a[c] + n[1] * b[c] + n[2] * m[c])
            }
        }
    }

    /// The outward unit normal of a boundary edge at parameter `t`, and the speed |dx/dt| there
    /// (the edge's length for a straight edge, whose normal is the same everywhere).
    pub fn edge_normal_at(&self, edge: &Edge, t: f64) -> (Vector, f64) {
        let Some(m) = edge.mid.filter(|_| self.is_curved_edge(edge)) else {
            return self.edge_normal(edge);
        };
        let (a, b, m) = (self.nodes[edge.a], self.nodes[edge.b], self.nodes[m]);
        let d: Vector = std::array::from_fn(|c| {
            (4.0 * t - 3.0) * a[c] + (4.0 * t - 1.0) * b[c] + (4.0 - 8.0 * t) * m[c]
        });
        let speed = d[0].hypot(d[1]);
        ([d[1] / speed, -d[0] / speed], speed)
    }

    /// Outward unit normal and length of a boundary edge's chord (for a curved edge, the
    /// chord from `a` to `b`; [`Mesh::edge_normal_at`] gives the normal along the arc).
    pub fn edge_normal(&self, edge: &Edge) -> (Vector, f64) {
        let (a, b) = (self.nodes[edge.a], self.nodes[edge.b]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        ([dy / len, -dx / len], len)
    }

    /// Returns a copy with every node moved by `f` (e.g. to map a reference mesh onto a body).
    /// The result is validated again.
    pub fn map_nodes(&self, f: impl Fn(Point) -> Point) -> Result<Mesh, MeshError> {
        self.with_nodes(self.nodes.iter().map(|&p| f(p)).collect())
    }

    /// Returns a copy whose nodes are `nodes` (one per node, e.g. mid-side nodes moved onto a
    /// curve), with the same cells, boundaries and node sets. The result is validated again.
    pub fn with_nodes(&self, nodes: Vec<Point>) -> Result<Mesh, MeshError> {
        Mesh::new(
            nodes,
            self.order,
            self.cells.clone(),
            self.boundaries.clone(),
            self.node_sets.clone(),
        )
    }
}

/// The edges of a P1 connectivity, each with a number: per smaller vertex, a slot for each time
/// a triangle edge starts there (found by a scan of the few slots of one vertex, in a table laid
/// out like the nodes, so that neighbouring triangles use neighbouring memory). A hash map of the
/// edges would do the same with a random access per edge.
struct EdgeTable {
    /// Slots of vertex `v`: `start[v]..start[v + 1]`.
    start: Vec<usize>,
    /// How many slots of each vertex are used.
    used: Vec<u32>,
    /// (larger vertex, number) per slot.
    slots: Vec<(usize, usize)>,
}

impl EdgeTable {
    /// An empty table for the edges of the triangles `cells` (3 vertices each, in `0..n`).
    fn new(n: usize, cells: &[usize]) -> EdgeTable {
        let mut start = vec![0usize; n + 1];
        for c in cells.chunks_exact(3) {
            for &(i, j, _) in &TRIANGLE_EDGES {
                start[c[i].min(c[j]) + 1] += 1;
            }
        }
        for v in 0..n {
            start[v + 1] += start[v];
        }
        EdgeTable {
            used: vec![0; n],
            slots: vec![(0, 0); start[n]],
            start,
        }
    }

    /// The used slots of vertex `v`.
    fn slots(&self, v: usize) -> &[(usize, usize)] {
        let s = self.start[v];
        &self.slots[s..s + self.used[v] as usize]
    }

    /// The number of the edge from `a` to `b`: the one it has, or `next` (then incremented).
    fn number(&mut self, a: usize, b: usize, next: &mut usize) -> usize {
        let (lo, hi) = (a.min(b), a.max(b));
        if let Some(&(_, k)) = self.slots(lo).iter().find(|s| s.0 == hi) {
            return k;
        }
        // Every edge of the cells has a slot of its own: the count never passes the capacity.
        self.slots[self.start[lo] + self.used[lo] as usize] = (hi, *next);
        self.used[lo] += 1;
        *next += 1;
        *next - 1
    }

    /// The number of the edge from `a` to `b`, if it is an edge of the cells.
    fn get(&self, a: usize, b: usize) -> Option<usize> {
        let (lo, hi) = (a.min(b), a.max(b));
        (lo < self.used.len())
            .then(|| self.slots(lo).iter().find(|s| s.0 == hi).map(|s| s.1))
            .flatten()
    }
}

/// Reorders every clockwise triangle of the flat connectivity `cells` (3 vertices, then for P2
/// the mid-side nodes of edges (0,1), (1,2), (2,0)) into counter-clockwise order: vertices
/// (0, 2, 1), mid-side nodes of (0,2), (2,1), (1,0). Degenerate triangles and indices out of
/// range are left for [`Mesh::new`] to report.
pub fn counter_clockwise(nodes: &[Point], order: Order, cells: &mut [usize]) {
    for cell in cells.chunks_exact_mut(order.nodes_per_cell()) {
        let corner = |k: usize| nodes.get(cell[k]).copied();
        let (Some(p0), Some(p1), Some(p2)) = (corner(0), corner(1), corner(2)) else {
            continue;
        };
        let area2 = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]);
        if area2 < 0.0 {
            cell.swap(1, 2);
            if cell.len() == 6 {
                cell.swap(3, 5);
            }
        }
    }
}

/// Euclidean distance of two points.
pub fn dist(a: Point, b: Point) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}
