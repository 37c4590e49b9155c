//! Reference P1/P2 Lagrange triangles, their geometry (straight-sided or curved), and quadrature
//! rules.
//!
//! Shape functions are written in barycentric coordinates λ = (λ0, λ1, λ2). P2 node order:
//! vertices 0, 1, 2, then mid-sides of (0,1), (1,2), (2,0). A straight-sided triangle ([`Affine`])
//! maps affinely, so the gradients of the barycentric coordinates are constant on it. A curved P2
//! triangle (a mid-side node off its edge's midpoint, e.g. from Gmsh `SetOrder(2)` on a curved
//! boundary) is isoparametric ([`Isoparametric`]): the point `x(λ) = Σ N_i(λ) x_i` follows the
//! same quadratic shape functions as the displacement, and gradients are `J⁻ᵀ ∇_ξ N` with the
//! Jacobian of that map. [`Geometry`] picks one of the two per cell.

use crate::geometry::{dof, Point, Vector, DIM};
use crate::mesh::{Mesh, Order};

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

/// Geometry of one curved (isoparametric) P2 triangle: the quadratic map
/// `x(λ) = Σ N_i(λ) x_i` of its six nodes, with reference coordinates `ξ = λ1`, `η = λ2` on the
/// triangle (0,0), (1,0), (0,1) of area ½.
#[derive(Clone, Copy, Debug)]
pub struct Isoparametric {
    /// The six nodes, in the P2 order (vertices, then mid-sides of (0,1), (1,2), (2,0)).
    pub nodes: [Point; MAX_NODES],
}

impl Isoparametric {
    /// Geometry of the P2 triangle with nodes `x`.
    pub fn new(x: [Point; MAX_NODES]) -> Isoparametric {
        Isoparametric { nodes: x }
    }

    /// Gradients `(∂N_i/∂ξ, ∂N_i/∂η)` of the six P2 shape functions at barycentric point `l`.
    pub fn reference_grad(l: [f64; 3]) -> [Vector; MAX_NODES] {
        let a = 4.0 * l[0] - 1.0;
        [
            [-a, -a],
            [4.0 * l[1] - 1.0, 0.0],
            [0.0, 4.0 * l[2] - 1.0],
            [4.0 * (l[0] - l[1]), -4.0 * l[1]],
            [4.0 * l[2], 4.0 * l[1]],
            [-4.0 * l[2], 4.0 * (l[0] - l[2])],
        ]
    }

    /// The Jacobian `J[c][k] = ∂x_c/∂ξ_k` of the map at barycentric point `l`.
    pub fn jacobian(&self, l: [f64; 3]) -> [[f64; DIM]; DIM] {
        let dn = Isoparametric::reference_grad(l);
        let mut j = [[0.0; DIM]; DIM];
        for (x, g) in self.nodes.iter().zip(&dn) {
            for c in 0..DIM {
                for k in 0..DIM {
                    j[c][k] += x[c] * g[k];
                }
            }
        }
        j
    }

    /// `det J` at barycentric point `l` (twice the local area ratio to the reference triangle;
    /// positive everywhere on a valid mesh, [`crate::mesh::Mesh::new`] checks it).
    pub fn det(&self, l: [f64; 3]) -> f64 {
        let j = self.jacobian(l);
        j[0][0] * j[1][1] - j[0][1] * j[1][0]
    }

    /// Physical point of barycentric coordinates `l`.
    pub fn point(&self, l: [f64; 3]) -> Point {
        let n = shape(Order::P2, l);
        let mut x = [0.0; DIM];
        for (ni, xi) in n.iter().zip(&self.nodes) {
            for c in 0..DIM {
                x[c] += ni * xi[c];
            }
        }
        x
    }

    /// Physical gradients `J⁻ᵀ ∇_ξ N_i` of the six shape functions at barycentric point `l`.
    pub fn grad(&self, l: [f64; 3]) -> [Vector; MAX_NODES] {
        let j = self.jacobian(l);
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        Isoparametric::reference_grad(l).map(|[dxi, deta]| {
            [
                (j[1][1] * dxi - j[1][0] * deta) / det,
                (j[0][0] * deta - j[0][1] * dxi) / det,
            ]
        })
    }

    /// Area `∫ det J dξ dη`: `det J` is quadratic, so the degree-2 rule is exact.
    pub fn area(&self) -> f64 {
        TRIANGLE_DEGREE_2
            .points
            .iter()
            .zip(TRIANGLE_DEGREE_2.weights)
            .map(|(l, w)| w * 0.5 * self.det(*l))
            .sum()
    }

    /// Element stiffness matrix `∫ Bᵀ D B dA` (all six nodes), by the 7-point degree-5 rule
    /// ([`TRIANGLE_DEGREE_5`]). The integrand `(adj J ∇_ξN)ᵀ D (adj J ∇_ξN) / det J` is rational:
    /// its numerator has degree 4, the usual rule for P2 isoparametric triangles is therefore of
    /// degree 4; the degree-5 rule has one point more, all inside, and also integrates the
    /// `1 / det J` variation of a curved triangle more closely. Straight triangles keep their
    /// exact 3-point rule ([`stiffness`]).
    pub fn stiffness(&self, d: &[[f64; 3]; 3]) -> ElementMatrix {
        let mut k = [[0.0; DIM * MAX_NODES]; DIM * MAX_NODES];
        for (l, w) in TRIANGLE_DEGREE_5
            .points
            .iter()
            .zip(TRIANGLE_DEGREE_5.weights)
        {
            add_btdb(&mut k, &self.grad(*l), w * 0.5 * self.det(*l), d, MAX_NODES);
        }
        k
    }
}

/// Geometry of one triangle of a mesh: straight-sided (affine, constant Jacobian) or curved
/// (isoparametric P2), chosen per cell by [`Mesh::is_curved_cell`]. Straight triangles use
/// [`Affine`] and its arithmetic unchanged.
#[derive(Clone, Copy, Debug)]
pub enum Geometry {
    /// A straight-sided triangle (P1, or P2 with its mid-side nodes on the edge midpoints).
    Straight(Affine),
    /// A curved P2 triangle.
    Curved(Isoparametric),
}

impl Geometry {
    /// The geometry of triangle `e` of `mesh`.
    pub fn of_cell(mesh: &Mesh, e: usize) -> Geometry {
        let c = mesh.cell(e);
        let p = mesh.nodes();
        if mesh.is_curved_cell(e) {
            Geometry::Curved(Isoparametric::new(std::array::from_fn(|i| p[c[i]])))
        } else {
            Geometry::Straight(Affine::new([p[c[0]], p[c[1]], p[c[2]]]))
        }
    }

    /// Area of the triangle.
    pub fn area(&self) -> f64 {
        match self {
            Geometry::Straight(a) => a.area,
            Geometry::Curved(c) => c.area(),
        }
    }

    /// Physical point of barycentric coordinates `l`.
    pub fn point(&self, l: [f64; 3]) -> Point {
        match self {
            Geometry::Straight(a) => a.point(l),
            Geometry::Curved(c) => c.point(l),
        }
    }

    /// The area element of a quadrature point `l` of weight `w` (weights summing to 1): `w` times
    /// the area on a straight triangle, `w · det J(l) / 2` on a curved one.
    pub fn weight(&self, w: f64, l: [f64; 3]) -> f64 {
        match self {
            Geometry::Straight(a) => w * a.area,
            Geometry::Curved(c) => w * 0.5 * c.det(l),
        }
    }

    /// Physical gradients of the shape functions at barycentric point `l` (a curved triangle is
    /// always P2).
    pub fn grad(&self, order: Order, l: [f64; 3]) -> [Vector; MAX_NODES] {
        match self {
            Geometry::Straight(a) => a.grad(order, l),
            Geometry::Curved(c) => c.grad(l),
        }
    }

    /// Element stiffness matrix ([`stiffness`] or [`Isoparametric::stiffness`]).
    pub fn stiffness(&self, order: Order, d: &[[f64; 3]; 3]) -> ElementMatrix {
        match self {
            Geometry::Straight(a) => stiffness(order, a, d),
            Geometry::Curved(c) => c.stiffness(d),
        }
    }

    /// Strain `(ε_xx, ε_yy, γ_xy)` at barycentric point `l` from the element's nodal
    /// displacements `u` (2 per node).
    pub fn strain(&self, order: Order, l: [f64; 3], u: &[Vector]) -> [f64; 3] {
        strain_of(&self.grad(order, l), u)
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

/// Radon's 7-point rule, exact for polynomials of degree 5 (loads, error norms, the stiffness of a
/// curved triangle).
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

/// An element stiffness matrix, DOFs ordered `(u_x, u_y)` node by node; only the leading
/// `2 × nodes_per_cell` block is used.
pub type ElementMatrix = [[f64; DIM * MAX_NODES]; DIM * MAX_NODES];

/// Element stiffness matrix `∫ Bᵀ D B dA` of a straight triangle, DOFs ordered
/// `(u_x, u_y)` node by node; only the leading `2 × nodes_per_cell` block is used.
pub fn stiffness(order: Order, geo: &Affine, d: &[[f64; 3]; 3]) -> ElementMatrix {
    let n = order.nodes_per_cell();
    let mut k = [[0.0; DIM * MAX_NODES]; DIM * MAX_NODES];
    let rule: (&[[f64; 3]], &[f64]) = match order {
        // Constant gradients: one point is exact.
        Order::P1 => (&[[1.0 / 3.0; 3]], &[1.0]),
        Order::P2 => (TRIANGLE_DEGREE_2.points, TRIANGLE_DEGREE_2.weights),
    };
    for (l, w) in rule.0.iter().zip(rule.1) {
        add_btdb(&mut k, &geo.grad(order, *l), w * geo.area, d, n);
    }
    k
}

/// Adds `scale · Bᵀ D B` at one quadrature point of physical shape function gradients `g` (the
/// first `n`) to `k`.
fn add_btdb(
    k: &mut ElementMatrix,
    g: &[Vector; MAX_NODES],
    scale: f64,
    d: &[[f64; 3]; 3],
    n: usize,
) {
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

/// Strain `(ε_xx, ε_yy, γ_xy)` at barycentric point `l` from the element's nodal displacements
/// `u` (2 per node).
pub fn strain(order: Order, geo: &Affine, l: [f64; 3], u: &[Vector]) -> [f64; 3] {
    strain_of(&geo.grad(order, l), u)
}

/// Strain from physical shape function gradients `g` and nodal displacements `u`.
fn strain_of(g: &[Vector; MAX_NODES], u: &[Vector]) -> [f64; 3] {
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
