//! The nodal quadrature of a contact boundary: its nodes with their nodal normals (length-weighted
//! averages of the adjacent edge normals, which makes curved boundaries work; on a curved P2 edge,
//! the arc's normal at the node) and quadrature weights (trapezoid for P1, Simpson for P2, the
//! integrals ∫ φ_k ds along a curved edge, over the part of each edge that faces the partner).

use std::collections::HashMap;

use contactdd_core::element::edge_nodal_weights;
use contactdd_core::{Edge, Mesh, Order, Vector, DIM};

use super::curved_edge;
use super::edge_index::EdgeIndex;

/// Nodes of a boundary with their nodal normals and quadrature weights.
///
/// The weights are the integrals of the edge shape functions over the part of each edge that faces
/// the partner boundary: trapezoid (P1) and Simpson (P2) weights for edges facing it entirely (the
/// usual case), and a share of the covered part for an edge that sticks out past the end of the
/// partner, so that a short body on a long one is loaded over its own length only.
pub(super) fn nodal_quadrature(
    mesh: &Mesh,
    edges: &[Edge],
    partner: &EdgeIndex,
) -> (Vec<usize>, Vec<Vector>, Vec<f64>) {
    let mut index: HashMap<usize, usize> = HashMap::new();
    let (mut nodes, mut normals, mut weights) = (Vec::new(), Vec::new(), Vec::new());
    for e in edges {
        let (n, len) = mesh.edge_normal(e);
        let (t0, t1) = covered_part(mesh, e, n, partner);
        let curved = mesh.is_curved_edge(e);
        let (w, len) = match curved {
            true => (
                curved_weights(mesh, e, t0, t1),
                curved_edge::length(mesh, e, 0.0, 1.0),
            ),
            false => (partial_edge_weights(mesh.order(), len, t0, t1), len),
        };
        for (k, v) in e.nodes().enumerate() {
            // A curved edge's normal at the node itself (t = 0, 1, ½ in the order a, b, mid).
            let n = match curved {
                true => mesh.edge_normal_at(e, [0.0, 1.0, 0.5][k]).0,
                false => n,
            };
            let i = *index.entry(v).or_insert_with(|| {
                nodes.push(v);
                normals.push([0.0; DIM]);
                weights.push(0.0);
                nodes.len() - 1
            });
            weights[i] += w[k];
            for c in 0..DIM {
                normals[i][c] += len * n[c];
            }
        }
    }
    for n in &mut normals {
        let l = n[0].hypot(n[1]);
        if l > 0.0 {
            *n = [n[0] / l, n[1] / l];
        }
    }
    (nodes, normals, weights)
}

/// The parameter interval [t0, t1] ⊂ [0, 1] of edge `e` whose normal rays hit the partner
/// boundary (empty as t0 = t1 = 0). Found by sampling and bisection.
fn covered_part(mesh: &Mesh, e: &Edge, n: Vector, partner: &EdgeIndex) -> (f64, f64) {
    const SAMPLES: usize = 8;
    let (a, b) = (mesh.nodes()[e.a], mesh.nodes()[e.b]);
    let curved = mesh.is_curved_edge(e);
    let hits = |t: f64| match curved {
        true => {
            let (x, n, _) = curved_edge::frame(mesh, e, t);
            partner.project(x, n).is_some()
        }
        false => {
            let x = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            partner.project(x, n).is_some()
        }
    };
    let covered: Vec<bool> = (0..=SAMPLES)
        .map(|i| hits(i as f64 / SAMPLES as f64))
        .collect();
    if covered.iter().all(|&c| c) {
        return (0.0, 1.0);
    }
    let (Some(first), Some(last)) = (
        covered.iter().position(|&c| c),
        covered.iter().rposition(|&c| c),
    ) else {
        return (0.0, 0.0);
    };
    // Bisect between the last uncovered and first covered sample (and vice versa at the end).
    let refine = |mut lo: f64, mut hi: f64, covered_hi: bool| {
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if hits(mid) == covered_hi {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    };
    let step = 1.0 / SAMPLES as f64;
    let t0 = if first == 0 {
        0.0
    } else {
        refine((first - 1) as f64 * step, first as f64 * step, true)
    };
    let t1 = if last == SAMPLES {
        1.0
    } else {
        refine((last + 1) as f64 * step, last as f64 * step, true)
    };
    (t0, t1.max(t0))
}

/// The weights of a curved edge: ∫ φ_k ds over [t0, t1], with the same treatment of a partial
/// edge's negative vertex shares as [`partial_edge_weights`].
fn curved_weights(mesh: &Mesh, e: &Edge, t0: f64, t1: f64) -> [f64; 3] {
    let w = curved_edge::shape_integrals(mesh, e, t0, t1);
    if t0 == 0.0 && t1 == 1.0 {
        return w;
    }
    let positive = w.map(|x| x.max(0.0));
    let sum: f64 = positive.iter().sum();
    let covered: f64 = w.iter().sum();
    if sum > 0.0 {
        positive.map(|x| x * covered / sum)
    } else {
        [0.0; 3]
    }
}

/// Integrals of the edge shape functions (order `a, b, [mid]`) over [t0, t1] of an edge of length
/// `len`: trapezoid / Simpson weights for [0, 1]. Negative P2 vertex shares of a partial edge are
/// dropped and the rest rescaled to the covered length.
fn partial_edge_weights(order: Order, len: f64, t0: f64, t1: f64) -> [f64; 3] {
    if t0 == 0.0 && t1 == 1.0 {
        return edge_nodal_weights(order, len);
    }
    let integral = |f: &dyn Fn(f64) -> f64| len * (f(t1) - f(t0));
    let w = match order {
        Order::P1 => [
            integral(&|t| t - 0.5 * t * t),
            integral(&|t| 0.5 * t * t),
            0.0,
        ],
        Order::P2 => [
            integral(&|t| t - 1.5 * t * t + 2.0 / 3.0 * t.powi(3)),
            integral(&|t| 2.0 / 3.0 * t.powi(3) - 0.5 * t * t),
            integral(&|t| 2.0 * t * t - 4.0 / 3.0 * t.powi(3)),
        ],
    };
    let positive = w.map(|x| x.max(0.0));
    let sum: f64 = positive.iter().sum();
    let covered = len * (t1 - t0);
    if sum > 0.0 {
        positive.map(|x| x * covered / sum)
    } else {
        [0.0; 3]
    }
}
