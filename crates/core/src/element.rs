//! Reference P1/P2 Lagrange triangles on straight-sided (affine) geometry, and quadrature rules.
//!
//! Shape functions are written in barycentric coordinates λ = (λ0, λ1, λ2). P2 node order:
//! vertices 0, 1, 2, then mid-sides of (0,1), (1,2), (2,0). Because the map is affine, the
//! gradients of the barycentric coordinates are constant on a triangle.

use crate::geometry::{dof, Point, Vector, DIM};
use crate::mesh::Order;

/// Largest number of nodes of a triangle (P2).
pub const MAX_NODES: usize = 6;

/// Values of the shape functions at barycentric point `l`.
pub fn shape(order: Order, l: [f64; 3]) -> [f64; MAX_NODES] {
    match order {
        Order::P1 => [l[0], l[1], l[2], 0.0, 0.0, 0.0],
        Order::P2 => [
            l[0] * (2.0 * l[0] - 1.0),
            l[1] * (2.0 * l[1] - 1.0),
            l[2] * (2.0 * l[2] - 1.0),
            4.0 * l[0] * l[1],
            4.0 * l[1] * l[2],
            4.0 * l[2] * l[0],
        ],
    }
}

/// Geometry of one straight-sided triangle: area and barycentric gradients.
#[derive(Clone, Copy, Debug)]
pub struct Affine {
    /// Area (positive for a counter-clockwise triangle).
    pub area: f64,
    /// ∇λ_i, constant on the triangle.
    pub grad_l: [Vector; 3],
    /// The three vertices.
    pub vertices: [Point; 3],
}

impl Affine {
    /// Geometry of the triangle with vertices `p`.
    pub fn new(p: [Point; 3]) -> Affine {
        let area2 =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        let g = |i: usize, j: usize| [(p[i][1] - p[j][1]) / area2, (p[j][0] - p[i][0]) / area2];
        Affine {
            area: 0.5 * area2,
            grad_l: [g(1, 2), g(2, 0), g(0, 1)],
            vertices: p,
        }
    }

    /// Physical point of barycentric coordinates `l`.
    pub fn point(&self, l: [f64; 3]) -> Point {
        let v = &self.vertices;
        [
            l[0] * v[0][0] + l[1] * v[1][0] + l[2] * v[2][0],
            l[0] * v[0][1] + l[1] * v[1][1] + l[2] * v[2][1],
        ]
    }

    /// Physical gradients of the shape functions at barycentric point `l`.
    pub fn grad(&self, order: Order, l: [f64; 3]) -> [Vector; MAX_NODES] {
        let g = &self.grad_l;
        let mut out = [[0.0; DIM]; MAX_NODES];
        match order {
            Order::P1 => out[..3].copy_from_slice(g),
            Order::P2 => {
                for d in 0..DIM {
                    for i in 0..3 {
                        out[i][d] = (4.0 * l[i] - 1.0) * g[i][d];
                    }
                    for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                        out[3 + k][d] = 4.0 * (l[i] * g[j][d] + l[j] * g[i][d]);
                    }
                }
            }
        }
        out
    }
}

/// A quadrature rule on the reference triangle: barycentric points and weights summing to 1
/// (multiply by the area).
pub struct TriangleRule {
    /// Barycentric points.
    pub points: &'static [[f64; 3]],
    /// Weights, summing to 1.
    pub weights: &'static [f64],
}

/// Exact for polynomials of degree 2 (P2 stiffness on straight triangles).
pub const TRIANGLE_DEGREE_2: TriangleRule = TriangleRule {
    points: &[
        [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0],
        [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
        [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
    ],
    weights: &[1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
};

const R7_A: f64 = 0.059_715_871_789_769_82;
const R7_B: f64 = 0.470_142_064_105_115_1;
const R7_C: f64 = 0.797_426_985_353_087_3;
const R7_D: f64 = 0.101_286_507_323_456_34;
const R7_WB: f64 = 0.132_394_152_788_506_2;
const R7_WD: f64 = 0.125_939_180_544_827_15;

/// Radon's 7-point rule, exact for polynomials of degree 5 (loads, error norms).
pub const TRIANGLE_DEGREE_5: TriangleRule = TriangleRule {
    points: &[
        [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
        [R7_A, R7_B, R7_B],
        [R7_B, R7_A, R7_B],
        [R7_B, R7_B, R7_A],
        [R7_C, R7_D, R7_D],
        [R7_D, R7_C, R7_D],
        [R7_D, R7_D, R7_C],
    ],
    weights: &[0.225, R7_WB, R7_WB, R7_WB, R7_WD, R7_WD, R7_WD],
};

/// 3-point Gauss–Legendre rule on [0, 1] (exact to degree 5): (points, weights summing to 1).
pub const EDGE_GAUSS_3: ([f64; 3], [f64; 3]) = (
    [0.112_701_665_379_258_31, 0.5, 0.887_298_334_620_741_7],
    [5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0],
);

/// Shape functions of a boundary edge at parameter `t ∈ [0, 1]` from `a` to `b`, in the edge node
/// order `a, b, [mid]`.
pub fn edge_shape(order: Order, t: f64) -> [f64; 3] {
    match order {
        Order::P1 => [1.0 - t, t, 0.0],
        Order::P2 => [
            (1.0 - t) * (1.0 - 2.0 * t),
            t * (2.0 * t - 1.0),
            4.0 * t * (1.0 - t),
        ],
    }
}

/// Nodal quadrature weights of an edge of length `len` (trapezoid for P1, Simpson for P2), in the
/// edge node order `a, b, [mid]`. These are the contact integration weights of docs/method.md §4.
pub fn edge_nodal_weights(order: Order, len: f64) -> [f64; 3] {
    match order {
        Order::P1 => [0.5 * len, 0.5 * len, 0.0],
        Order::P2 => [len / 6.0, len / 6.0, 4.0 * len / 6.0],
    }
}

/// Element stiffness matrix `∫ Bᵀ D B dA` of a straight triangle, DOFs ordered
/// `(u_x, u_y)` node by node; only the leading `2 × nodes_per_cell` block is used.
pub fn stiffness(
    order: Order,
    geo: &Affine,
    d: &[[f64; 3]; 3],
) -> [[f64; DIM * MAX_NODES]; DIM * MAX_NODES] {
    let n = order.nodes_per_cell();
    let mut k = [[0.0; DIM * MAX_NODES]; DIM * MAX_NODES];
    let rule: (&[[f64; 3]], &[f64]) = match order {
        // Constant gradients: one point is exact.
        Order::P1 => (&[[1.0 / 3.0; 3]], &[1.0]),
        Order::P2 => (TRIANGLE_DEGREE_2.points, TRIANGLE_DEGREE_2.weights),
    };
    for (l, w) in rule.0.iter().zip(rule.1) {
        let g = geo.grad(order, *l);
        let scale = w * geo.area;
        for a in 0..n {
            let (ax, ay) = (g[a][0], g[a][1]);
            // D·B_a, columns for u_x and u_y of node a (B_a = [[ax,0],[0,ay],[ay,ax]]).
            let dbx = [
                d[0][0] * ax + d[0][2] * ay,
                d[1][0] * ax + d[1][2] * ay,
                d[2][0] * ax + d[2][2] * ay,
            ];
            let dby = [
                d[0][1] * ay + d[0][2] * ax,
                d[1][1] * ay + d[1][2] * ax,
                d[2][1] * ay + d[2][2] * ax,
            ];
            for b in 0..n {
                let (bx, by) = (g[b][0], g[b][1]);
                // B_bᵀ (D B_a)
                k[dof(b, 0)][dof(a, 0)] += scale * (bx * dbx[0] + by * dbx[2]);
                k[dof(b, 1)][dof(a, 0)] += scale * (by * dbx[1] + bx * dbx[2]);
                k[dof(b, 0)][dof(a, 1)] += scale * (bx * dby[0] + by * dby[2]);
                k[dof(b, 1)][dof(a, 1)] += scale * (by * dby[1] + bx * dby[2]);
            }
        }
    }
    k
}

/// Strain `(ε_xx, ε_yy, γ_xy)` at barycentric point `l` from the element's nodal displacements
/// `u` (2 per node).
pub fn strain(order: Order, geo: &Affine, l: [f64; 3], u: &[Vector]) -> [f64; 3] {
    let g = geo.grad(order, l);
    let mut e = [0.0; 3];
    for (gi, ui) in g.iter().zip(u) {
        e[0] += gi[0] * ui[0];
        e[1] += gi[1] * ui[1];
        e[2] += gi[1] * ui[0] + gi[0] * ui[1];
    }
    e
}

/// Barycentric coordinates of the nodes of the reference triangle (3 or 6 nodes).
pub fn node_barycentric(order: Order) -> &'static [[f64; 3]] {
    const NODES: [[f64; 3]; 6] = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.5],
        [0.5, 0.0, 0.5],
    ];
    &NODES[..order.nodes_per_cell()]
}
