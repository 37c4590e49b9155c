//! The derived fields of a body written to its `.vtu` file: the stress as a 3×3 tensor, its
//! principal values, the contact point data (gap and status) and the element von Mises stress.

use contactdd_core::material::von_mises;
use contactdd_core::post::{stresses, Stress};
use contactdd_core::ElasticBody;
use contactdd_ddm::solution::PairResult;

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
    fn pure_shear_has_principal_values_plus_and_minus_tau() {
        let p = principal(&[0.0, 0.0, 5.0, 0.0]);
        assert_eq!(p, [5.0, 0.0, -5.0]);
    }
}
