//! Integrals along a curved (isoparametric) P2 edge of a contact boundary: the parabola x(t)
//! through its vertices and mid-side node, with the length element |x′(t)| dt. A straight edge
//! never comes here; its integrals keep their closed forms (trapezoid, Simpson, the reference
//! dual basis).

use contactdd_core::element::edge_shape;
use contactdd_core::{Edge, Mesh, Order, Point, Vector};

/// Five-point Gauss–Legendre rule on [0, 1]: exact to degree 9, which leaves the error of the
/// non-polynomial length element |x′(t)| of a mildly curved edge at rounding.
pub(super) const GAUSS_5: [(f64, f64); 5] = [
    (0.046_910_077_030_668_004, 0.118_463_442_528_094_54),
    (0.230_765_344_947_158_45, 0.239_314_335_249_683_23),
    (0.5, 0.284_444_444_444_444_45),
    (0.769_234_655_052_841_5, 0.239_314_335_249_683_23),
    (0.953_089_922_969_332, 0.118_463_442_528_094_54),
];

/// The point, outward unit normal and speed |x′(t)| of a curved edge at parameter `t`.
pub(super) fn frame(mesh: &Mesh, edge: &Edge, t: f64) -> (Point, Vector, f64) {
    let (n, speed) = mesh.edge_normal_at(edge, t);
    (mesh.edge_point(edge, t), n, speed)
}

/// ∫ φ_k |x′| dt over [t0, t1] for the edge's three shape functions (order `a, b, mid`).
pub(super) fn shape_integrals(mesh: &Mesh, edge: &Edge, t0: f64, t1: f64) -> [f64; 3] {
    let mut w = [0.0; 3];
    for &(g, wg) in &GAUSS_5 {
        let t = t0 + g * (t1 - t0);
        let speed = mesh.edge_normal_at(edge, t).1;
        let phi = edge_shape(Order::P2, t);
        for k in 0..3 {
            w[k] += wg * (t1 - t0) * speed * phi[k];
        }
    }
    w
}

/// The arc length of a curved edge over [t0, t1].
pub(super) fn length(mesh: &Mesh, edge: &Edge, t0: f64, t1: f64) -> f64 {
    shape_integrals(mesh, edge, t0, t1).iter().sum()
}

/// The dual basis of a curved edge as combinations of its shape functions, A = D M⁻¹ with M its
/// mass matrix ∫ φ_i φ_l |x′| dt and D the row sums of M: biorthogonal in the edge's own length
/// element, ∫ ψ_i φ_l ds = δ_il ∫ φ_i ds. `None` if M is singular (a folded edge).
pub(super) fn dual(mesh: &Mesh, edge: &Edge) -> Option<[[f64; 3]; 3]> {
    let mut m = [[0.0; 3]; 3];
    for &(t, wg) in &GAUSS_5 {
        let speed = mesh.edge_normal_at(edge, t).1;
        let phi = edge_shape(Order::P2, t);
        for i in 0..3 {
            for l in 0..3 {
                m[i][l] += wg * speed * phi[i] * phi[l];
            }
        }
    }
    let inverse = inverse3(&m)?;
    let d: [f64; 3] = m.map(|row| row.iter().sum());
    Some(std::array::from_fn(|i| {
        std::array::from_fn(|l| d[i] * inverse[i][l])
    }))
}

/// The inverse of a 3 × 3 matrix by cofactors, `None` if it is singular.
fn inverse3(m: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let c = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]
    };
    let det: f64 = (0..3).map(|j| m[0][j] * c(0, j)).sum();
    let scale: f64 = m.iter().flatten().fold(0.0, |s, x| s.max(x.abs()));
    // Also refuses NaN.
    if det.is_nan() || det.abs() <= 1e-14 * scale.powi(3) {
        return None;
    }
    // (M⁻¹)_ij = C_ji / det.
    Some(std::array::from_fn(|i| {
        std::array::from_fn(|j| c(j, i) / det)
    }))
}

/// The parameters t ∈ (0, 1) where the normal line of a curved edge passes through `v`: the
/// roots of the cubic f(t) = (v − x(t))·x′(t), found by sampling and bisection. The breakpoints
/// that a partner vertex `v` puts on the edge.
pub(super) fn normal_feet(mesh: &Mesh, edge: &Edge, v: Point) -> Vec<f64> {
    const SAMPLES: usize = 16;
    let f = |t: f64| {
        let (x, n, _) = frame(mesh, edge, t);
        // x′ is n turned by +90°, up to the speed.
        (v[0] - x[0]) * -n[1] + (v[1] - x[1]) * n[0]
    };
    let mut out = Vec::new();
    let mut lo = (0.0, f(0.0));
    for i in 1..=SAMPLES {
        let t = i as f64 / SAMPLES as f64;
        let hi = (t, f(t));
        if lo.1 == 0.0 {
            out.push(lo.0);
        } else if lo.1 * hi.1 < 0.0 {
            let (mut a, mut b) = (lo, hi);
            for _ in 0..60 {
                let mid = 0.5 * (a.0 + b.0);
                let fm = f(mid);
                if fm * a.1 > 0.0 {
                    a = (mid, fm);
                } else {
                    b = (mid, fm);
                }
            }
            out.push(0.5 * (a.0 + b.0));
        }
        lo = hi;
    }
    out
}

/// The hits of the ray x + s n on a curved edge: the parameters t ∈ [0, 1] (within `tol`,
/// then clamped) where cross(x(t) − x, n) = 0, with the signed distance s along the ray. The
/// parabola is x(t) = a + t d₁ + t² d₂, so the condition is a quadratic in t.
pub(super) fn ray_hits(mesh: &Mesh, edge: &Edge, x: Point, n: Vector, tol: f64) -> Vec<(f64, f64)> {
    let Some(m) = edge.mid else {
        return Vec::new();
    };
    let p = mesh.nodes();
    let (a, b, m) = (p[edge.a], p[edge.b], p[m]);
    let cross = |u: Vector, w: Vector| u[0] * w[1] - u[1] * w[0];
    let d1: Vector = std::array::from_fn(|c| -3.0 * a[c] - b[c] + 4.0 * m[c]);
    let d2: Vector = std::array::from_fn(|c| 2.0 * a[c] + 2.0 * b[c] - 4.0 * m[c]);
    let d0: Vector = std::array::from_fn(|c| a[c] - x[c]);
    let (qa, qb, qc) = (cross(d2, n), cross(d1, n), cross(d0, n));
    let roots: Vec<f64> = if qa.abs() <= 1e-12 * qb.abs() {
        if qb == 0.0 {
            Vec::new()
        } else {
            vec![-qc / qb]
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            Vec::new()
        } else {
            // The stable pair of roots.
            let q = -0.5 * (qb + qb.signum() * disc.sqrt());
            let mut r = vec![q / qa];
            if q != 0.0 {
                r.push(qc / q);
            }
            r
        }
    };
    roots
        .into_iter()
        .filter(|t| (-tol..=1.0 + tol).contains(t))
        .map(|t| {
            let t = t.clamp(0.0, 1.0);
            let y = mesh.edge_point(edge, t);
            (t, (y[0] - x[0]) * n[0] + (y[1] - x[1]) * n[1])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use contactdd_core::{Diagonal, Rectangle};
    use std::f64::consts::FRAC_PI_2;

    /// A quarter annulus r ∈ [1, 1.5] of curved P2 triangles: a P2 rectangle mapped to polar
    /// coordinates, so the mid-side nodes of its arcs lie on the circles.
    fn annulus(arcs: usize) -> Mesh {
        Rectangle {
            origin: [0.0, 0.0],
            corner: [1.0, 0.5],
            nx: arcs,
            ny: 2,
            diagonal: Diagonal::Right,
            mirror: false,
            order: Order::P2,
        }
        .mesh()
        .unwrap()
        .map_nodes(|[x, y]| {
            let (r, phi) = (1.0 + y, FRAC_PI_2 * (1.0 - x));
            [r * phi.cos(), r * phi.sin()]
        })
        .unwrap()
    }

    /// A ray sent back along the normal from a point off the arc hits the arc where the normal
    /// was taken, at the distance it was sent from.
    #[test]
    fn a_ray_along_the_normal_hits_where_the_normal_was_taken() {
        let mesh = annulus(6);
        let edges = mesh.boundary("bottom").unwrap();
        assert!(edges.iter().all(|e| mesh.is_curved_edge(e)));
        for e in edges {
            for t in [0.0, 0.13, 0.5, 0.77, 1.0] {
                let (y, n, _) = frame(&mesh, e, t);
                let x = [y[0] + 0.3 * n[0], y[1] + 0.3 * n[1]];
                let hits = ray_hits(&mesh, e, x, [-n[0], -n[1]], 1e-9);
                assert!(
                    hits.iter()
                        .any(|&(s, d)| (s - t).abs() < 1e-12 && (d - 0.3).abs() < 1e-12),
                    "t {t}: {hits:?}"
                );
                let feet = normal_feet(&mesh, e, x);
                if t > 0.0 && t < 1.0 {
                    assert!(feet.iter().any(|&s| (s - t).abs() < 1e-12), "{t}: {feet:?}");
                }
            }
        }
    }

    /// The dual basis of a curved edge is biorthogonal in its length element, checked with a
    /// composite Simpson rule independent of the Gauss rule that built it.
    #[test]
    fn the_curved_dual_basis_is_biorthogonal_along_the_arc() {
        // Edges of 11.25°: the five-point rule leaves an error of the non-polynomial length
        // element below 1e-10 (at 30°, about 1e-8).
        let mesh = annulus(8);
        let e = &mesh.boundary("bottom").unwrap()[1];
        let a = dual(&mesh, e).unwrap();
        let panels = 2000;
        let mut m = [[0.0; 3]; 3];
        for k in 0..=2 * panels {
            let t = k as f64 / (2 * panels) as f64;
            let simpson = match k {
                0 => 1.0,
                k if k == 2 * panels => 1.0,
                k if k % 2 == 1 => 4.0,
                _ => 2.0,
            } / (6 * panels) as f64;
            let speed = mesh.edge_normal_at(e, t).1;
            let phi = edge_shape(Order::P2, t);
            for i in 0..3 {
                let psi: f64 = (0..3).map(|l| a[i][l] * phi[l]).sum();
                for l in 0..3 {
                    m[i][l] += simpson * speed * psi * phi[l];
                }
            }
        }
        let w = shape_integrals(&mesh, e, 0.0, 1.0);
        for i in 0..3 {
            for l in 0..3 {
                let want = if i == l { w[i] } else { 0.0 };
                assert!(
                    (m[i][l] - want).abs() < 1e-10,
                    "{i} {l}: {} vs {want}",
                    m[i][l]
                );
            }
        }
    }

    /// The arc lengths of the curved edges of a quarter circle converge to π/2 at fourth order
    /// (the parabolas' error), the chords only at second.
    #[test]
    fn curved_edges_measure_the_circle_at_fourth_order() {
        let errors: Vec<(f64, f64)> = [4, 8, 16]
            .iter()
            .map(|&arcs| {
                let mesh = annulus(arcs);
                let edges = mesh.boundary("bottom").unwrap();
                let arc: f64 = edges.iter().map(|e| length(&mesh, e, 0.0, 1.0)).sum();
                let chords: f64 = edges.iter().map(|e| mesh.edge_normal(e).1).sum();
                ((arc - FRAC_PI_2).abs(), (chords - FRAC_PI_2).abs())
            })
            .collect();
        for w in errors.windows(2) {
            let (curved, straight) = ((w[0].0 / w[1].0).log2(), (w[0].1 / w[1].1).log2());
            assert!(curved > 3.8, "curved rate {curved}: {errors:?}");
            assert!(
                (1.9..2.1).contains(&straight),
                "chord rate {straight}: {errors:?}"
            );
        }
    }
}
