//! Dual mortar coefficients of a balanced pair: how the partner's displacement at a contact point
//! is averaged over the point's share of its boundary (docs/method.md §4).
//!
//! The ray interpolation of a point (the partner's shape functions at one projected point) does
//! not integrate a constant pressure exactly on non-matching meshes: the nodal forces of the
//! balanced formulation, which distribute every point's force to the partner's nodes with the
//! gap's coefficients, would then differ from the consistent loads of a uniform pressure. The
//! mortar coefficients integrate instead:
//!
//!   c_jk = ∫ ψ_j(x) φ_k(x′(x)) ds / ∫ ψ_j ds,
//!
//! over the edges of point j's boundary, with x′(x) the projection of x along its edge's normal
//! onto the partner and φ_k the partner's shape functions; the gap d_j is weighted the same way,
//! d_j = ∫ ψ_j d(x) ds / ∫ ψ_j ds. ψ_j is the dual basis of the point's
//! own shape functions on each edge (∫ ψ_i φ_l = δ_il ∫ φ_i, Wohlmuth's biorthogonal basis):
//! then Σ_k c_jk x_k = x_j for any field linear (P2: quadratic) along a partner that matches
//! the point's boundary, so on meshes that match node for node c_jk is the identity, and on any
//! mesh a constant pressure yields the consistent nodal loads. The integrals are exact: each
//! edge is split where the partner's vertices project onto it, and every piece gets a Gauss rule
//! exact for the product of two quadratics.

use std::collections::HashMap;

use contactdd_core::element::edge_shape;
use contactdd_core::{Edge, Mesh, Order, Vector};

use super::curved_edge;
use super::edge_index::EdgeIndex;

/// Three-point Gauss–Legendre rule on [0, 1]: exact to degree 5.
const GAUSS: [(f64, f64); 3] = [
    (0.112_701_665_379_258_31, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

/// The dual basis on an edge as combinations of its shape functions (order `a, b, mid`):
/// ψ_i = Σ_l A_il φ_l with A = D M⁻¹ (M the edge's mass matrix, D its row sums).
fn dual(order: Order) -> [[f64; 3]; 3] {
    match order {
        Order::P1 => [[2.0, -1.0, 0.0], [-1.0, 2.0, 0.0], [0.0; 3]],
        Order::P2 => [[1.5, 0.5, -0.25], [0.5, 1.5, -0.25], [-1.0, -1.0, 1.5]],
    }
}

/// The dual mortar integrals of one node over the part of its edges whose normal rays hit the
/// partner (the caller normalises by Σ_k `coupling[k]`, which is ∫ ψ there).
#[derive(Clone, Debug, Default)]
pub(super) struct Integrals {
    /// ∫ ψ φ_k per partner node k.
    pub coupling: HashMap<usize, f64>,
    /// ∫ ψ t n_e: the rays' lengths t along their edge's normal n_e, as a vector, so that the
    /// caller can read the distance along its point's normal.
    pub ray: Vector,
    /// ∫ ψ d_profile: the pair's prescribed gap profile.
    pub profile: f64,
}

/// Per node of `edges`, its [`Integrals`] against the partner boundary, with the pair's gap
/// `profile`.
pub(super) fn dual_integrals(
    mesh: &Mesh,
    edges: &[Edge],
    partner: &EdgeIndex,
    profile: &dyn Fn(Vector) -> f64,
) -> HashMap<usize, Integrals> {
    let a_dual = dual(mesh.order());
    let mut out: HashMap<usize, Integrals> = HashMap::new();
    let p = mesh.nodes();
    for e in edges {
        let (n, len) = mesh.edge_normal(e);
        let (a, b) = (p[e.a], p[e.b]);
        let dir: Vector = [b[0] - a[0], b[1] - a[1]];
        // A curved edge: its own dual basis, the arc's points and normals, a finer rule.
        let curved = mesh.is_curved_edge(e);
        let (a_edge, rule) = match curved {
            true => (
                curved_edge::dual(mesh, e).unwrap_or(a_dual),
                &curved_edge::GAUSS_5[..],
            ),
            false => (a_dual, &GAUSS[..]),
        };
        let frame = |t: f64| match curved {
            true => curved_edge::frame(mesh, e, t),
            false => ([a[0] + t * dir[0], a[1] + t * dir[1]], n, len),
        };
        let mut cuts = partner.vertices_facing(mesh, e);
        cuts.retain(|&t| t > 0.0 && t < 1.0);
        cuts.extend([0.0, 1.0]);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let nodes: Vec<usize> = e.nodes().collect();
        for piece in cuts.windows(2) {
            let (t0, t1) = (piece[0], piece[1]);
            for &(g, wg) in rule {
                let t = t0 + g * (t1 - t0);
                let (x, n, speed) = frame(t);
                let Some((ray, coeffs)) = partner.project(x, n) else {
                    continue;
                };
                let phi = edge_shape(mesh.order(), t);
                let w = speed * (t1 - t0) * wg;
                let d = profile(x);
                for (i, &v) in nodes.iter().enumerate() {
                    let psi: f64 = (0..3).map(|l| a_edge[i][l] * phi[l]).sum();
                    let node = out.entry(v).or_default();
                    for &(k, c) in &coeffs {
                        *node.coupling.entry(k).or_insert(0.0) += w * psi * c;
                    }
                    node.ray[0] += w * psi * ray * n[0];
                    node.ray[1] += w * psi * ray * n[1];
                    node.profile += w * psi * d;
                }
            }
        }
    }
    out
}

/// A point's dual mortar coefficients and weighted gap ([`Integrals`] normalised by ∫ ψ).
#[derive(Clone, Debug)]
pub(super) struct Mortar {
    /// Coefficients over the partner's (normal) points.
    pub coefficients: Vec<(usize, f64)>,
    /// The weighted ray vector ∫ ψ t n_e / ∫ ψ: its component along ν is the distance.
    pub ray: Vector,
    /// The weighted gap profile.
    pub profile: f64,
}

/// The mortar integrals of one point normalised by ∫ ψ: the coefficients over the partner's
/// points (they sum to 1, which makes the gap invariant under a joint translation), in point
/// order, with the weighted ray vector and profile; `None` where ∫ ψ is not a positive share of
/// the point.
pub(super) fn normalised(
    node: &Integrals,
    partner_index: &HashMap<usize, usize>,
) -> Option<Mortar> {
    let mut out: Vec<(usize, f64)> = node
        .coupling
        .iter()
        .filter_map(|(node, &c)| partner_index.get(node).map(|&g| (g, c)))
        .collect();
    out.sort_by_key(|e| e.0);
    let total: f64 = out.iter().map(|e| e.1).sum();
    let size: f64 = out.iter().map(|e| e.1.abs()).sum();
    // Also refuses NaN.
    if total.is_nan() || total <= 1e-9 * size {
        return None;
    }
    Some(Mortar {
        coefficients: out.into_iter().map(|(g, c)| (g, c / total)).collect(),
        ray: [node.ray[0] / total, node.ray[1] / total],
        profile: node.profile / total,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use contactdd_core::{Diagonal, Rectangle};

    fn strip(y0: f64, y1: f64, nx: usize, order: Order) -> Mesh {
        let mesh = Rectangle {
            origin: [0.0, y0],
            corner: [1.0, y1],
            nx,
            ny: 1,
            diagonal: Diagonal::Right,
            mirror: false,
            order: Order::P1,
        }
        .mesh()
        .unwrap()
        .map_nodes(|[x, y]| [x + 0.05 * (3.0 * x).sin(), y])
        .unwrap();
        match order {
            Order::P1 => mesh,
            Order::P2 => mesh.to_p2(),
        }
    }

    /// On two non-matching straight boundaries that touch, the normalised coefficients of every
    /// fully covered node reproduce the partner's x coordinates (a linear field): Σ_k c_k x_k = x_j
    /// (P1 and P2, whose dual basis reproduces quadratics too).
    #[test]
    fn dual_coefficients_reproduce_linear_fields() {
        for order in [Order::P1, Order::P2] {
            let (lower, upper) = (strip(-1.0, 0.0, 7, order), strip(0.0, 1.0, 11, order));
            let partner = lower.boundary("top").unwrap();
            let index = EdgeIndex::new(&lower, partner);
            let slave = upper.boundary("bottom").unwrap();
            let rows = dual_integrals(&upper, slave, &index, &|_| 0.0);
            let mut checked = 0;
            for (&v, node) in &rows {
                let row = &node.coupling;
                let x = upper.nodes()[v][0];
                if !(0.15..=0.85).contains(&x) {
                    continue;
                }
                let total: f64 = row.values().sum();
                let mean: f64 = row
                    .iter()
                    .map(|(&k, &c)| c * lower.nodes()[k][0])
                    .sum::<f64>()
                    / total;
                let square: f64 = row
                    .iter()
                    .map(|(&k, &c)| c * lower.nodes()[k][0].powi(2))
                    .sum::<f64>()
                    / total;
                assert!(
                    (mean - x).abs() < 1e-12,
                    "{order:?} node {v}: {mean} against {x}"
                );
                if order == Order::P2 {
                    assert!(
                        (square - x * x).abs() < 1e-12,
                        "{order:?} node {v}: {square} against {}",
                        x * x
                    );
                }
                checked += 1;
            }
            assert!(checked > 5, "{checked}");
        }
    }
}
