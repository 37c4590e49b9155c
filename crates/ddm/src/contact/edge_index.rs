//! The search for the partner edge that a contact point's normal ray hits: the edges of one
//! contact boundary in an R-tree of their bounding boxes.

use contactdd_core::element::edge_shape;
use contactdd_core::geometry::dot;
use contactdd_core::mesh::dist;
use contactdd_core::{Edge, Mesh, Point, Vector, DIM};

use super::curved_edge;

use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};

fn cross(a: Vector, b: Vector) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The edges of one contact boundary in an R-tree of their bounding boxes, for the ray
/// projections of the partner's points: each query looks only at the edges near the ray, so
/// projecting all m points of a zone costs O(m log m) instead of O(m²).
pub struct EdgeIndex<'m> {
    mesh: &'m Mesh,
    edges: &'m [Edge],
    tree: RTree<GeomWithData<Rectangle<Point>, usize>>,
    /// Centre and half-diagonal of the bounding box of all the edges.
    centre: Point,
    radius: f64,
    /// First search half-length: the mean edge length.
    start: f64,
}

impl<'m> EdgeIndex<'m> {
    /// Indexes `edges` of `mesh`.
    pub fn new(mesh: &'m Mesh, edges: &'m [Edge]) -> EdgeIndex<'m> {
        let p = mesh.nodes();
        let boxes: Vec<GeomWithData<Rectangle<Point>, usize>> = edges
            .iter()
            .enumerate()
            .map(|(k, e)| {
                let (a, b) = (p[e.a], p[e.b]);
                // Inflated by the projection's tolerance on the edge parameter (1e−9).
                let pad = 1e-8 * dist(a, b) + f64::MIN_POSITIVE;
                let (lo, hi) = hull(mesh, e);
                let lo = [lo[0] - pad, lo[1] - pad];
                let hi = [hi[0] + pad, hi[1] + pad];
                GeomWithData::new(Rectangle::from_corners(lo, hi), k)
            })
            .collect();
        let (mut lo, mut hi) = ([f64::INFINITY; DIM], [f64::NEG_INFINITY; DIM]);
        for e in edges {
            let (elo, ehi) = hull(mesh, e);
            for c in 0..DIM {
                lo[c] = lo[c].min(elo[c]);
                hi[c] = hi[c].max(ehi[c]);
            }
        }
        let total: f64 = edges.iter().map(|e| dist(p[e.a], p[e.b])).sum();
        EdgeIndex {
            mesh,
            edges,
            tree: RTree::bulk_load(boxes),
            centre: std::array::from_fn(|c| 0.5 * (lo[c] + hi[c])),
            radius: 0.5 * dist(lo, hi),
            start: (total / edges.len().max(1) as f64).max(f64::MIN_POSITIVE),
        }
    }

    /// The nearest hit of the ray x + t n (see `project`): edges are searched in growing boxes
    /// around the segment [x − R n, x + R n] until a hit with |t| ≤ R is found (no nearer hit can
    /// lie outside the box) or the box holds every edge.
    pub fn project(&self, x: Point, n: Vector) -> Option<(f64, Vec<(usize, f64)>)> {
        if self.edges.is_empty() {
            return None;
        }
        let reach = dist(x, self.centre) + self.radius;
        let mut r = self.start;
        loop {
            let (a, b) = (
                [x[0] - r * n[0], x[1] - r * n[1]],
                [x[0] + r * n[0], x[1] + r * n[1]],
            );
            let envelope = AABB::from_corners(
                [a[0].min(b[0]), a[1].min(b[1])],
                [a[0].max(b[0]), a[1].max(b[1])],
            );
            let mut near: Vec<usize> = self
                .tree
                .locate_in_envelope_intersecting(&envelope)
                .map(|g| g.data)
                .collect();
            // The edge order of a full scan, so that ties go to the same edge.
            near.sort_unstable();
            let hit = project(x, n, self.mesh, near.iter().map(|&k| &self.edges[k]));
            match hit {
                Some((t, _)) if t.abs() <= r => return hit,
                _ if r > reach => return hit,
                _ => r *= 2.0,
            }
        }
    }
}

impl EdgeIndex<'_> {
    /// Where the vertices of the partner edges facing the edge `e` of `own` project onto it
    /// along its normals, as parameters t of the edge (for a straight edge from a to b, of
    /// a + t (b − a), on its whole line): the breakpoints of the partner's shape functions
    /// along the edge. Searched in the band the edge sweeps along its chord's normal out to its
    /// rays' hits, widened by its length; empty if no ray from it hits.
    pub(super) fn vertices_facing(&self, own: &Mesh, e: &Edge) -> Vec<f64> {
        let curved = own.is_curved_edge(e);
        let (n, _) = own.edge_normal(e);
        let (a, b) = (own.nodes()[e.a], own.nodes()[e.b]);
        let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let reach: Vec<f64> = [(a, 0.0), (mid, 0.5), (b, 1.0)]
            .iter()
            .filter_map(|&(x, t)| match curved {
                true => self.project(own.edge_point(e, t), own.edge_normal_at(e, t).0),
                false => self.project(x, n),
            })
            .map(|h| h.0)
            .collect();
        if reach.is_empty() {
            return Vec::new();
        }
        let len = dist(a, b);
        let lo = reach.iter().fold(f64::INFINITY, |m, &t| m.min(t)) - len;
        let hi = reach.iter().fold(f64::NEG_INFINITY, |m, &t| m.max(t)) + len;
        let corners = [a, b].map(|x| [lo, hi].map(|s| [x[0] + s * n[0], x[1] + s * n[1]]));
        let all = corners.iter().flatten();
        let (mut min, mut max) = ([f64::INFINITY; DIM], [f64::NEG_INFINITY; DIM]);
        for x in all {
            for c in 0..DIM {
                min[c] = min[c].min(x[c]);
                max[c] = max[c].max(x[c]);
            }
        }
        let dir: Vector = [b[0] - a[0], b[1] - a[1]];
        let dd = dot(dir, dir);
        let p = self.mesh.nodes();
        let mut out = Vec::new();
        for g in self
            .tree
            .locate_in_envelope_intersecting(&AABB::from_corners(min, max))
        {
            let partner = &self.edges[g.data];
            if dot(self.mesh.edge_normal(partner).0, n) >= -1e-3 {
                continue;
            }
            for v in [partner.a, partner.b] {
                match curved {
                    true => out.extend(curved_edge::normal_feet(own, e, p[v])),
                    false => out.push(dot([p[v][0] - a[0], p[v][1] - a[1]], dir) / dd),
                }
            }
        }
        out
    }
}

/// The bounding box of an edge: of its vertices, and for a curved edge also of the control
/// point 2 mid − (a + b)/2 of its parabola, whose convex hull with the vertices holds the arc.
fn hull(mesh: &Mesh, e: &Edge) -> (Point, Point) {
    let p = mesh.nodes();
    let (a, b) = (p[e.a], p[e.b]);
    let (mut lo, mut hi) = (
        [a[0].min(b[0]), a[1].min(b[1])],
        [a[0].max(b[0]), a[1].max(b[1])],
    );
    if let Some(m) = e.mid.filter(|_| mesh.is_curved_edge(e)) {
        let control: Point = std::array::from_fn(|c| 2.0 * p[m][c] - 0.5 * (a[c] + b[c]));
        for c in 0..DIM {
            lo[c] = lo[c].min(control[c]);
            hi[c] = hi[c].max(control[c]);
        }
    }
    (lo, hi)
}

/// The hit of the ray x + t n on edge `e` (facing the ray): its signed distance t and the
/// edge's parameter s there.
fn hit(x: Point, n: Vector, mesh: &Mesh, e: &Edge) -> Option<(f64, f64)> {
    let tol = 1e-9;
    if mesh.is_curved_edge(e) {
        // The nearest hit where the arc faces the ray.
        return curved_edge::ray_hits(mesh, e, x, n, tol)
            .into_iter()
            .filter(|&(s, _)| dot(mesh.edge_normal_at(e, s).0, n) < -1e-3)
            .map(|(s, t)| (t, s))
            .min_by(|p, q| p.0.abs().total_cmp(&q.0.abs()));
    }
    let p = mesh.nodes();
    let (ne, len) = mesh.edge_normal(e);
    // Only edges facing the point: their outward normal opposes n.
    if dot(ne, n) >= -1e-3 {
        return None;
    }
    let (a, b) = (p[e.a], p[e.b]);
    let dir: Vector = std::array::from_fn(|c| b[c] - a[c]);
    let den = cross(n, dir);
    if den.abs() < 1e-14 * len {
        return None;
    }
    let ax: Vector = std::array::from_fn(|c| a[c] - x[c]);
    let t = cross(ax, dir) / den;
    let s = cross(ax, n) / den;
    if !(-tol..=1.0 + tol).contains(&s) {
        return None;
    }
    Some((t, s.clamp(0.0, 1.0)))
}

/// Intersects the ray x + t n with the edges (facing the ray) and returns the signed distance t
/// of the nearest hit and the partner node coefficients there.
fn project<'e>(
    x: Point,
    n: Vector,
    mesh: &Mesh,
    edges: impl IntoIterator<Item = &'e Edge>,
) -> Option<(f64, Vec<(usize, f64)>)> {
    let mut best: Option<(f64, Vec<(usize, f64)>)> = None;
    for e in edges {
        let Some((t, s)) = hit(x, n, mesh, e) else {
            continue;
        };
        if best.as_ref().is_some_and(|(bt, _)| bt.abs() <= t.abs()) {
            continue;
        }
        let shape = edge_shape(mesh.order(), s);
        let coeffs = e.nodes().zip(shape).filter(|(_, c)| *c != 0.0).collect();
        best = Some((t, coeffs));
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use contactdd_core::{Diagonal, Order, Rectangle};

    /// The R-tree search finds exactly the hit of a scan over all edges (same t, same edge and
    /// coefficients), for rays from many points in many directions, hitting or missing.
    #[test]
    fn the_edge_index_finds_the_same_hit_as_a_full_scan() {
        let mesh = Rectangle {
            origin: [0.0, 0.0],
            corner: [3.0, 1.0],
            nx: 37,
            ny: 3,
            diagonal: Diagonal::Right,
            mirror: false,
            order: Order::P1,
        }
        .mesh()
        .unwrap()
        .map_nodes(|p| [p[0], p[1] + 0.1 * (2.0 * p[0]).sin() * p[1]])
        .unwrap();
        let edges = mesh.boundary("top").unwrap();
        let index = EdgeIndex::new(&mesh, edges);
        let mut checked = 0;
        for i in 0..200 {
            let x = [
                -0.5 + 4.0 * (i as f64 * 0.618).fract(),
                1.05 + 0.3 * (i as f64 * 0.37).fract(),
            ];
            let angle = -std::f64::consts::FRAC_PI_2 + 1.4 * ((i as f64 * 0.29).fract() - 0.5);
            let n = [angle.cos(), angle.sin()];
            let (fast, slow) = (index.project(x, n), project(x, n, &mesh, edges));
            assert_eq!(fast, slow, "ray {i} from {x:?} along {n:?}");
            checked += usize::from(slow.is_some());
        }
        assert!(checked > 100, "only {checked} rays hit");
    }
}
