//! Tetrahedral elements: P1 and P2 shape functions on the reference tetrahedron, quadrature rules,
//! the isotropic elasticity matrix and element stiffness blocks `∫ B_bᵀ D B_a dV`.
//!
//! The reference tetrahedron has the vertices (0,0,0), (1,0,0), (0,1,0), (0,0,1); a point is given
//! by its barycentric coordinates `λ = (λ0, λ1, λ2, λ3)` with (ξ, η, ζ) = (λ1, λ2, λ3). The P2
//! tetrahedron has Gmsh's node order ("Tetrahedron10" in Gmsh's node ordering): vertices 0-3, then
//! the mid-edge nodes of the edges 0-1, 1-2, 0-2, 0-3, 2-3, 1-3 ([`TET_EDGES`]).
//!
//! Strains and stresses are Voigt 6-vectors `(ε_xx, ε_yy, ε_zz, γ_yz, γ_xz, γ_xy)` (engineering
//! shears γ = 2ε) and `(σ_xx, σ_yy, σ_zz, σ_yz, σ_xz, σ_xy)`; Hooke's law is `σ = D ε`.
//!
//! The geometry is isoparametric: `x(λ) = Σ N_k(λ) x_k` over the element's nodes. A straight-sided
//! P2 tetrahedron (mid-edge nodes at the edges' midpoints) has the constant Jacobian of its
//! vertices, and its stiffness uses the degree-2 rule, exact for it; a curved one uses the
//! degree-5 rule.

use super::{Point3, Vector3};
use crate::error::MaterialError;
use crate::material::Material;

/// Most nodes of a tetrahedron (P2).
pub const MAX_TET_NODES: usize = 10;

/// The local vertices of the six edges of a tetrahedron, in the order of the P2 mid-edge nodes
/// 4..9 (Gmsh's order).
pub const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [0, 2], [0, 3], [2, 3], [1, 3]];

/// A quadrature rule on the tetrahedron: barycentric points and weights summing to 1 (multiply
/// by the volume, or by `det J / 6` at each point of an isoparametric element).
pub struct TetRule {
    /// Barycentric coordinates of the points.
    pub points: &'static [[f64; 4]],
    /// Weights, summing to 1.
    pub weights: &'static [f64],
}

/// The centroid rule, exact for polynomials of degree 1.
pub const TET_DEGREE_1: TetRule = TetRule {
    points: &[[0.25; 4]],
    weights: &[1.0],
};

const Q2_A: f64 = 0.585_410_196_624_968_5; // (5 + 3√5) / 20
const Q2_B: f64 = 0.138_196_601_125_010_5; // (5 − √5) / 20

/// The 4-point rule of Hammer, Marlowe and Stroud, exact for polynomials of degree 2: points
/// `((5 + 3√5)/20, (5 − √5)/20, …)` and their permutations, equal weights.
pub const TET_DEGREE_2: TetRule = TetRule {
    points: &[
        [Q2_A, Q2_B, Q2_B, Q2_B],
        [Q2_B, Q2_A, Q2_B, Q2_B],
        [Q2_B, Q2_B, Q2_A, Q2_B],
        [Q2_B, Q2_B, Q2_B, Q2_A],
    ],
    weights: &[0.25; 4],
};

const Q5_A1: f64 = 0.092_735_250_310_891_29;
const Q5_B1: f64 = 0.721_794_249_067_326_1;
const Q5_W1: f64 = 0.073_493_043_116_362_07;
const Q5_A2: f64 = 0.310_885_919_263_300_67;
const Q5_B2: f64 = 0.067_342_242_210_097_98;
const Q5_W2: f64 = 0.112_687_925_718_016_06;
const Q5_C: f64 = 0.045_503_704_125_649_5;
const Q5_D: f64 = 0.454_496_295_874_350_53;
const Q5_W3: f64 = 0.042_546_020_777_081_25;

/// The 14-point rule of Walkington ("Quadrature on simplices of arbitrary dimension", 2000),
/// exact for polynomials of degree 5, all weights positive: two orbits of 4 points
/// `(a, a, a, 1 − 3a)` and one of 6 points `(c, c, ½ − c, ½ − c)`. The digits are the roots of
/// the rule's moment equations, solved to 30 digits and rounded to `f64`.
pub const TET_DEGREE_5: TetRule = TetRule {
    points: &[
        [Q5_B1, Q5_A1, Q5_A1, Q5_A1],
        [Q5_A1, Q5_B1, Q5_A1, Q5_A1],
        [Q5_A1, Q5_A1, Q5_B1, Q5_A1],
        [Q5_A1, Q5_A1, Q5_A1, Q5_B1],
        [Q5_B2, Q5_A2, Q5_A2, Q5_A2],
        [Q5_A2, Q5_B2, Q5_A2, Q5_A2],
        [Q5_A2, Q5_A2, Q5_B2, Q5_A2],
        [Q5_A2, Q5_A2, Q5_A2, Q5_B2],
        [Q5_C, Q5_C, Q5_D, Q5_D],
        [Q5_C, Q5_D, Q5_C, Q5_D],
        [Q5_C, Q5_D, Q5_D, Q5_C],
        [Q5_D, Q5_C, Q5_C, Q5_D],
        [Q5_D, Q5_C, Q5_D, Q5_C],
        [Q5_D, Q5_D, Q5_C, Q5_C],
    ],
    weights: &[
        Q5_W1, Q5_W1, Q5_W1, Q5_W1, Q5_W2, Q5_W2, Q5_W2, Q5_W2, Q5_W3, Q5_W3, Q5_W3, Q5_W3, Q5_W3,
        Q5_W3,
    ],
};

/// Gradients of the barycentric coordinates with respect to (ξ, η, ζ).
const DLAMBDA: [[f64; 3]; 4] = [
    [-1.0, -1.0, -1.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];

/// Shape function values at barycentric point `l` for `p2` (10 nodes) or P1 (4 nodes, the rest
/// zero).
pub fn tet_shape(p2: bool, l: [f64; 4]) -> [f64; MAX_TET_NODES] {
    let mut n = [0.0; MAX_TET_NODES];
    if !p2 {
        n[..4].copy_from_slice(&l);
        return n;
    }
    for i in 0..4 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
    }
    for (k, [a, b]) in TET_EDGES.iter().enumerate() {
        n[4 + k] = 4.0 * l[*a] * l[*b];
    }
    n
}

/// Shape function gradients with respect to (ξ, η, ζ) at barycentric point `l` (P1: 4 nodes,
/// P2: 10 nodes).
pub fn tet_reference_grad(p2: bool, l: [f64; 4]) -> [Vector3; MAX_TET_NODES] {
    let mut g = [[0.0; 3]; MAX_TET_NODES];
    if !p2 {
        g[..4].copy_from_slice(&DLAMBDA);
        return g;
    }
    for i in 0..4 {
        g[i] = DLAMBDA[i].map(|d| (4.0 * l[i] - 1.0) * d);
    }
    for (k, [a, b]) in TET_EDGES.iter().enumerate() {
        g[4 + k] = std::array::from_fn(|c| 4.0 * (l[*a] * DLAMBDA[*b][c] + l[*b] * DLAMBDA[*a][c]));
    }
    g
}

/// The barycentric coordinates of the nodes of a P1 (4) or P2 (10) tetrahedron.
pub fn tet_node_barycentric(p2: bool) -> Vec<[f64; 4]> {
    let mut l: Vec<[f64; 4]> = (0..4)
        .map(|i| std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }))
        .collect();
    if p2 {
        for [a, b] in TET_EDGES {
            l.push(std::array::from_fn(|j| {
                if j == a || j == b {
                    0.5
                } else {
                    0.0
                }
            }));
        }
    }
    l
}

/// The isotropic elasticity matrix (6×6, Voigt order as in the module docs) of Young's modulus
/// `young` and Poisson's ratio `poisson`: `D = λ 𝟙𝟙ᵀ + 2μ I` on the normal strains and `μ` on the
/// engineering shears. Errors if E ≤ 0, E or ν not finite, or ν ∉ (−1, 0.5).
pub fn elasticity_matrix(young: f64, poisson: f64) -> Result<[[f64; 6]; 6], MaterialError> {
    Ok(elasticity(&Material::new(young, poisson)?))
}

/// The isotropic elasticity matrix of a validated material (see [`elasticity_matrix`]).
pub fn elasticity(material: &Material) -> [[f64; 6]; 6] {
    let (e, nu) = (material.young(), material.poisson());
    let mu = e / (2.0 * (1.0 + nu));
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mut d = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            d[i][j] = lambda;
        }
        d[i][i] = lambda + 2.0 * mu;
        d[3 + i][3 + i] = mu;
    }
    d
}

/// The geometry of one tetrahedron: its node coordinates and whether it is P2 and curved.
#[derive(Clone, Copy, Debug)]
pub struct TetGeometry {
    x: [Point3; MAX_TET_NODES],
    p2: bool,
    curved: bool,
}

impl TetGeometry {
    /// The tetrahedron with nodes `x` (4 for P1, 10 for P2 in Gmsh's order). A P2 tetrahedron is
    /// curved when a mid-edge node lies off its edge's midpoint by more than 1e-12 × the edge.
    pub fn new(x: &[Point3]) -> TetGeometry {
        let mut nodes = [[0.0; 3]; MAX_TET_NODES];
        nodes[..x.len()].copy_from_slice(x);
        let p2 = x.len() == MAX_TET_NODES;
        let curved = p2
            && TET_EDGES.iter().enumerate().any(|(k, [a, b])| {
                let (pa, pb, m) = (nodes[*a], nodes[*b], nodes[4 + k]);
                let off: f64 = (0..3).map(|c| (m[c] - 0.5 * (pa[c] + pb[c])).powi(2)).sum();
                let len2: f64 = (0..3).map(|c| (pb[c] - pa[c]).powi(2)).sum();
                off > 1e-24 * len2
            });
        TetGeometry {
            x: nodes,
            p2,
            curved,
        }
    }

    /// Number of nodes (4 or 10).
    pub fn num_nodes(&self) -> usize {
        if self.p2 {
            MAX_TET_NODES
        } else {
            4
        }
    }

    /// True for a P2 tetrahedron with a mid-edge node off its edge.
    pub fn is_curved(&self) -> bool {
        self.curved
    }

    /// The stiffness rule: the centroid for P1, degree 2 for straight P2, degree 5 for curved P2.
    pub fn stiffness_rule(&self) -> &'static TetRule {
        match (self.p2, self.curved) {
            (false, _) => &TET_DEGREE_1,
            (true, false) => &TET_DEGREE_2,
            (true, true) => &TET_DEGREE_5,
        }
    }

    /// The Jacobian `J[i][j] = ∂x_i/∂ξ_j` at barycentric point `l`.
    pub fn jacobian(&self, l: [f64; 4]) -> [[f64; 3]; 3] {
        let g = tet_reference_grad(self.p2, l);
        let mut j = [[0.0; 3]; 3];
        for k in 0..self.num_nodes() {
            for r in 0..3 {
                for c in 0..3 {
                    j[r][c] += self.x[k][r] * g[k][c];
                }
            }
        }
        j
    }

    /// The point of barycentric coordinates `l`.
    pub fn point(&self, l: [f64; 4]) -> Point3 {
        let n = tet_shape(self.p2, l);
        let mut p = [0.0; 3];
        for k in 0..self.num_nodes() {
            for c in 0..3 {
                p[c] += n[k] * self.x[k][c];
            }
        }
        p
    }

    /// Physical shape gradients `∇N_k = J⁻ᵀ ∇_ξ N_k` and `det J` at barycentric point `l`.
    pub fn grad(&self, l: [f64; 4]) -> ([Vector3; MAX_TET_NODES], f64) {
        let j = self.jacobian(l);
        // Cofactor matrix: J⁻ᵀ = cof(J) / det J.
        let cof: [[f64; 3]; 3] = std::array::from_fn(|r| {
            std::array::from_fn(|c| {
                let (r1, r2, c1, c2) = ((r + 1) % 3, (r + 2) % 3, (c + 1) % 3, (c + 2) % 3);
                j[r1][c1] * j[r2][c2] - j[r1][c2] * j[r2][c1]
            })
        });
        let det = j[0][0] * cof[0][0] + j[0][1] * cof[0][1] + j[0][2] * cof[0][2];
        let gr = tet_reference_grad(self.p2, l);
        let mut g = [[0.0; 3]; MAX_TET_NODES];
        for k in 0..self.num_nodes() {
            for r in 0..3 {
                g[k][r] = (0..3).map(|c| cof[r][c] * gr[k][c]).sum::<f64>() / det;
            }
        }
        (g, det)
    }

    /// The volume `∫ dV`, by the degree-5 rule (exact for straight sides).
    pub fn volume(&self) -> f64 {
        TET_DEGREE_5
            .points
            .iter()
            .zip(TET_DEGREE_5.weights)
            .map(|(l, w)| w * self.grad(*l).1 / 6.0)
            .sum()
    }
}

/// The 3×3 block `∫ B_bᵀ D B_a dV` of the element stiffness for every node b, given node a: row
/// component i of node b, column component j of node a, in `out[b][i][j]`.
pub fn stiffness_columns(
    geo: &TetGeometry,
    d: &[[f64; 6]; 6],
    a: usize,
) -> [[[f64; 3]; 3]; MAX_TET_NODES] {
    let rule = geo.stiffness_rule();
    let mut out = [[[0.0; 3]; 3]; MAX_TET_NODES];
    for (l, w) in rule.points.iter().zip(rule.weights) {
        let (g, det) = geo.grad(*l);
        let dv = w * det / 6.0;
        let m = d_times_b(d, g[a]);
        for (b, gb) in g.iter().take(geo.num_nodes()).enumerate() {
            let [x, y, z] = *gb;
            for j in 0..3 {
                out[b][0][j] += dv * (x * m[0][j] + z * m[4][j] + y * m[5][j]);
                out[b][1][j] += dv * (y * m[1][j] + z * m[3][j] + x * m[5][j]);
                out[b][2][j] += dv * (z * m[2][j] + y * m[3][j] + x * m[4][j]);
            }
        }
    }
    out
}

/// `D B_a` (6×3) for the node with physical gradient `h`.
fn d_times_b(d: &[[f64; 6]; 6], h: Vector3) -> [[f64; 3]; 6] {
    let [x, y, z] = h;
    let cols = [
        [x, 0.0, 0.0, 0.0, z, y],
        [0.0, y, 0.0, z, 0.0, x],
        [0.0, 0.0, z, y, x, 0.0],
    ];
    std::array::from_fn(|k| std::array::from_fn(|j| (0..6).map(|l| d[k][l] * cols[j][l]).sum()))
}

/// The full element stiffness `∫ Bᵀ D B dV` (3n × 3n, DOF 3k + c for node k, component c).
pub fn element_stiffness(geo: &TetGeometry, d: &[[f64; 6]; 6]) -> Vec<Vec<f64>> {
    let n = geo.num_nodes();
    let mut k = vec![vec![0.0; 3 * n]; 3 * n];
    for a in 0..n {
        let cols = stiffness_columns(geo, d, a);
        for b in 0..n {
            for i in 0..3 {
                for j in 0..3 {
                    k[3 * b + i][3 * a + j] = cols[b][i][j];
                }
            }
        }
    }
    k
}

/// The Voigt strain `(ε_xx, ε_yy, ε_zz, γ_yz, γ_xz, γ_xy)` at barycentric point `l` of the
/// element whose nodal displacements are `u` (one per node).
pub fn strain(geo: &TetGeometry, l: [f64; 4], u: &[Vector3]) -> [f64; 6] {
    let (g, _) = geo.grad(l);
    let mut grad_u = [[0.0; 3]; 3]; // ∂u_i/∂x_j
    for (k, uk) in u.iter().enumerate().take(geo.num_nodes()) {
        for i in 0..3 {
            for j in 0..3 {
                grad_u[i][j] += uk[i] * g[k][j];
            }
        }
    }
    [
        grad_u[0][0],
        grad_u[1][1],
        grad_u[2][2],
        grad_u[1][2] + grad_u[2][1],
        grad_u[0][2] + grad_u[2][0],
        grad_u[0][1] + grad_u[1][0],
    ]
}
