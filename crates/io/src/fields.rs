//! The derived fields of the result files: the stress as a 3×3 tensor, its principal values, the
//! contact pressure p ≥ 0 of every contact point ([`contact_pressures`]) and node
//! ([`nodal_contact_pressure`]), the contact point data (gap and status) and the element von Mises
//! stress.

use std::collections::HashMap;

use contactdd_core::material::von_mises;
use contactdd_core::post::{stresses, Stress};
use contactdd_core::ElasticBody;
use contactdd_ddm::solution::{BodyResult, PairResult};
use contactdd_ddm::{FrictionStatus, Model};

use crate::nearest_segment::{Segment, Segments};

/// The 3×3 stress tensor of `[σ_xx, σ_yy, σ_xy, σ_zz]`, row-major (9 values, the VTK tensor
/// layout; the plane problem has σ_xz = σ_yz = 0).
pub fn tensor(s: &Stress) -> [f64; 9] {
    let [xx, yy, xy, zz] = *s;
    [xx, xy, 0.0, xy, yy, 0.0, 0.0, 0.0, zz]
}

/// The principal stresses σ1 ≥ σ2 ≥ σ3 of `[σ_xx, σ_yy, σ_xy, σ_zz]`: the two in-plane ones and
/// σ_zz, sorted.
pub fn principal(s: &Stress) -> [f64; 3] {
    let [xx, yy, xy, zz] = *s;
    let centre = 0.5 * (xx + yy);
    let radius = (0.5 * (xx - yy)).hypot(xy);
    let mut p = [centre + radius, centre - radius, zz];
    p.sort_by(|a, b| b.total_cmp(a));
    p
}

/// Per node of a body, the gap and the contact status of its contact points, NaN at nodes that are
/// no contact point. Status: 1 closed, 0 open, −1 no partner (infinite gap). A node in several
/// pairs gets the point with the smallest gap (the most closed one).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPointData {
    /// Gap d − s after deformation (negative: penetration of the penalty solution).
    pub gap: Vec<f64>,
    /// Contact status code.
    pub status: Vec<f64>,
}

/// The [`ContactPointData`] of body `name` with `num_nodes` nodes, from the pairs' results.
pub fn contact_point_data(name: &str, num_nodes: usize, pairs: &[PairResult]) -> ContactPointData {
    let mut data = ContactPointData {
        gap: vec![f64::NAN; num_nodes],
        status: vec![f64::NAN; num_nodes],
    };
    // Only the pairs of this body: a model of thousands of bodies has thousands of pairs.
    for p in pairs.iter().filter(|p| p.bodies.iter().any(|b| b == name)) {
        for i in (0..p.side.len()).filter(|&i| p.bodies[p.side[i]] == name) {
            let (v, gap) = (p.node[i], p.gap[i]);
            let old = data.gap.get(v).copied();
            if old.is_some_and(|old| old.is_nan() || gap < old) {
                data.gap[v] = gap;
                data.status[v] = if !gap.is_finite() {
                    -1.0
                } else if p.closed[i] {
                    1.0
                } else {
                    0.0
                };
            }
        }
    }
    data
}

/// True when some pair of `model` has friction: the outputs then hold the friction columns,
/// fields and keys (and a frictionless problem's outputs none of them).
pub fn has_friction(model: &Model) -> bool {
    model.pairs.iter().any(|p| p.friction.is_active())
}

/// The friction results of one contact point (0 and open where a result holds none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionPoint {
    /// Tangential traction σ_t along t = n turned by +90°.
    pub tangential: f64,
    /// Slip g − g₀ of this solve.
    pub slip: f64,
    /// Accumulated tangential relative displacement g.
    pub total_slip: f64,
    /// Open, stick or slip.
    pub status: FrictionStatus,
}

/// The friction results of point `i` of `pair`.
pub fn friction_point(pair: &PairResult, i: usize) -> FrictionPoint {
    let at = |v: &[f64]| v.get(i).copied().unwrap_or(0.0);
    FrictionPoint {
        tangential: at(&pair.tangential),
        slip: at(&pair.slip),
        total_slip: at(&pair.total_slip),
        status: pair.status.get(i).copied().unwrap_or(FrictionStatus::Open),
    }
}

/// Per node of body `name` with `num_nodes` nodes, the tangential traction σ_t and the friction
/// status code (0 open, 1 stick, 2 slip) of its contact points, 0 at the other nodes. A node in
/// several pairs gets the point with the largest |σ_t|.
pub fn friction_point_data(
    name: &str,
    num_nodes: usize,
    pairs: &[PairResult],
) -> (Vec<f64>, Vec<f64>) {
    let (mut tangential, mut status) = (vec![0.0f64; num_nodes], vec![0.0f64; num_nodes]);
    for p in pairs.iter().filter(|p| p.bodies.iter().any(|b| b == name)) {
        for i in (0..p.side.len()).filter(|&i| p.bodies[p.side[i]] == name) {
            let (v, f) = (p.node[i], friction_point(p, i));
            let code = match f.status {
                FrictionStatus::Open => 0.0,
                FrictionStatus::Stick => 1.0,
                FrictionStatus::Slip => 2.0,
            };
            if let Some(t) = tangential.get_mut(v) {
                if f.tangential.abs() > t.abs() || (status[v] == 0.0 && code > 0.0) {
                    *t = f.tangential;
                    status[v] = code;
                }
            }
        }
    }
    (tangential, status)
}

/// The contact pressure p ≥ 0 of every point of every pair (one `Vec` per pair, in the points'
/// order), from the pairs' results and the bodies' meshes (`bodies` holds the body each pair
/// names; a body whose fields another process holds still has its mesh).
///
/// Where a point's own pressure acts (every point of an `own-side` pair; the reference side of a
/// `balanced` pair, whose `enforced` is true) p = −σ_n = (s − d)⁺/θ. A point of a balanced
/// pair's following side carries no pressure of its own: its p is the reference side's pressure
/// read at the point, the linear interpolation of the reference points' p along the reference
/// body's boundary edges between them, at the point of those edges nearest to it; 0 without a
/// partner. The nodal traction of the following side (the reference side's forces on its node
/// over its weight, [`PairResult::pressure`] there) is another quantity: it is no pressure field
/// and can change sign near the edge of the contact zone.
pub fn contact_pressures(pairs: &[PairResult], bodies: &[BodyResult]) -> Vec<Vec<f64>> {
    let meshes: HashMap<&str, &BodyResult> = bodies.iter().map(|b| (b.name.as_str(), b)).collect();
    pairs
        .iter()
        .map(|pair| pair_pressures(pair, &meshes))
        .collect()
}

/// The p ≥ 0 of a point whose own pressure acts: −σ_n (never −0).
fn own_pressure(sigma_n: f64) -> f64 {
    if sigma_n < 0.0 {
        -sigma_n
    } else {
        0.0
    }
}

/// [`contact_pressures`] of one pair.
fn pair_pressures(pair: &PairResult, meshes: &HashMap<&str, &BodyResult>) -> Vec<f64> {
    let enforced = |i: usize| pair.enforced.get(i).copied().unwrap_or(true);
    let mut p: Vec<f64> = (0..pair.gap.len())
        .map(|i| {
            if enforced(i) {
                own_pressure(pair.pressure[i])
            } else {
                0.0
            }
        })
        .collect();
    for side in 0..2 {
        let followers: Vec<usize> = (0..pair.gap.len())
            .filter(|&i| pair.side[i] == side && !enforced(i) && pair.gap[i].is_finite())
            .collect();
        if followers.is_empty() {
            continue;
        }
        let reference = &pair.bodies[1 - side];
        let carried: HashMap<usize, f64> = (0..pair.gap.len())
            .filter(|&i| pair.side[i] != side && enforced(i))
            .map(|i| (pair.node[i], p[i]))
            .collect();
        let Some(body) = meshes.get(reference.as_str()) else {
            continue;
        };
        let segments = reference_segments(body, &carried);
        let index = Segments::new(&segments);
        for i in followers {
            p[i] = index.read([pair.x[i], pair.y[i]]);
        }
    }
    p
}

/// The boundary edges (each half of a P2 edge) of the body's mesh (its skin on a process that does
/// not mesh it) whose two nodes are reference points, with their pressures `carried` (the body's
/// own node number → p).
fn reference_segments(body: &BodyResult, carried: &HashMap<usize, f64>) -> Vec<Segment> {
    let (mesh, id) = (&body.mesh, |n: usize| body.body_node(n));
    let nodes = mesh.nodes();
    let mut segments = Vec::new();
    for edge in mesh.boundaries().values().flatten() {
        let pieces = match edge.mid {
            Some(m) => vec![(edge.a, m), (m, edge.b)],
            None => vec![(edge.a, edge.b)],
        };
        for (a, b) in pieces {
            if let (Some(&pa), Some(&pb), Some(&xa), Some(&xb)) = (
                carried.get(&id(a)),
                carried.get(&id(b)),
                nodes.get(a),
                nodes.get(b),
            ) {
                segments.push(([xa, xb], [pa, pb]));
            }
        }
    }
    segments
}

/// The contact pressure p ≥ 0 of every node of body `name` with `num_nodes` nodes: the largest p
/// ([`contact_pressures`], given as `pressures`) of its contact points over the pairs `pairs`, 0
/// at the other nodes.
pub fn nodal_contact_pressure(
    name: &str,
    num_nodes: usize,
    pairs: &[PairResult],
    pressures: &[Vec<f64>],
) -> Vec<f64> {
    let mut nodal = vec![0.0; num_nodes];
    for (pair, p) in pairs.iter().zip(pressures) {
        if !pair.bodies.iter().any(|b| b == name) {
            continue;
        }
        for i in (0..pair.side.len()).filter(|&i| pair.bodies[pair.side[i]] == name) {
            if let (Some(v), Some(&pi)) = (nodal.get_mut(pair.node[i]), p.get(i)) {
                *v = f64::max(*v, pi);
            }
        }
    }
    nodal
}

/// The von Mises stress of each element of `body`, at its centroid, from the displacement `u`.
pub fn element_von_mises(body: &ElasticBody, u: &[f64]) -> Vec<f64> {
    stresses(&body.mesh, &body.material, body.plane, u)
        .element
        .iter()
        .map(|s| von_mises(s[0], s[1], s[2], s[3]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn principal_values_of_a_diagonal_stress_are_its_sorted_entries() {
        assert_eq!(principal(&[1.0, 3.0, 0.0, 2.0]), [3.0, 2.0, 1.0]);
    }

    #[test]
    fn a_following_point_reads_the_nearest_reference_segment() {
        let segments = [
            ([[0.0, 0.0], [1.0, 0.0]], [0.0, 10.0]),
            ([[1.0, 0.0], [2.0, 0.0]], [10.0, 4.0]),
        ];
        let read = |x| Segments::new(&segments).read(x);
        // Above the first segment at a quarter of its length, slightly off the line.
        assert!((read([0.25, 0.01]) - 2.5).abs() < 1e-12);
        assert!((read([1.5, -0.02]) - 7.0).abs() < 1e-12);
        // Beyond the reference side's end: its end value.
        assert_eq!(read([3.0, 0.0]), 4.0);
        assert_eq!(Segments::new(&[]).read([0.0, 0.0]), 0.0);
    }

    #[test]
    fn own_pressure_is_never_negative_zero() {
        assert_eq!(own_pressure(-3.0), 3.0);
        assert!(own_pressure(0.0).is_sign_positive() && own_pressure(-0.0).is_sign_positive());
    }

    #[test]
    fn pure_shear_has_principal_values_plus_and_minus_tau() {
        let p = principal(&[0.0, 0.0, 5.0, 0.0]);
        assert_eq!(p, [5.0, 0.0, -5.0]);
    }
}
