//! What a contact point of a pair in space measures: its normal approach and its two tangential
//! slips, as rows over the Cartesian displacements of the nodes of both sides.
//!
//! Point j is a node of the reference surface with its mortar row c_jk over the partner's nodes
//! ([`super::dual_mortar`]). Its relative displacement Δu_j = u_j − Σ_k c_jk u_k is read in one
//! frame, from the reference side: the nodal normal ν_j and two unit tangents t₁, t₂ with
//! (t₁, t₂, ν) right-handed. Then s_j = ν·Δu_j (positive: the sides approach) and
//! g_j = (t₁·Δu_j, t₂·Δu_j), the slip on which the Coulomb disc acts. Both sides see the same
//! frame, so a force along it acts on them equal and opposite; since Σ_k c_jk = 1, a joint
//! translation changes neither s nor g.

use super::mortar::MortarRow;
use super::{cross, dot3, length, Point3};

/// The two unit tangents of the plane normal to the unit vector `n`: t₁ is the normalised cross
/// product of the coordinate axis least aligned with n and n, t₂ = n × t₁.
pub fn tangents(n: Point3) -> [Point3; 2] {
    let a = n.map(f64::abs);
    let axis = if a[0] <= a[1] && a[0] <= a[2] {
        [1.0, 0.0, 0.0]
    } else if a[1] <= a[2] {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let t = cross(axis, n);
    let t1 = t.map(|x| x / length(t));
    [t1, cross(n, t1)]
}

/// Which body a term of a row reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The reference surface's body.
    Reference,
    /// The partner surface's body.
    Partner,
}

/// The rows of one contact point: per (side, node) the vectors that the node's displacement is
/// dotted with to give s (the normal approach) and the two slips.
#[derive(Clone, Debug, PartialEq)]
pub struct PointRows {
    /// The reference node.
    pub node: usize,
    /// ν, t₁, t₂.
    pub frame: [Point3; 3],
    /// (side, node, coefficient): the point reads coefficient × (ν, t₁, t₂)·u of that node.
    pub terms: Vec<(Side, usize, f64)>,
}

impl PointRows {
    /// The rows of reference node `node` with normal `normal` and mortar row `row` (its own side
    /// read through `row.own`).
    pub fn new(node: usize, normal: Point3, row: &MortarRow) -> PointRows {
        let [t1, t2] = tangents(normal);
        let mut terms: Vec<(Side, usize, f64)> = (row.own.iter())
            .map(|&(k, e)| (Side::Reference, k, e))
            .collect();
        terms.extend(
            row.coefficients
                .iter()
                .map(|&(k, c)| (Side::Partner, k, -c)),
        );
        PointRows {
            node,
            frame: [normal, t1, t2],
            terms,
        }
    }

    /// (s, g₁, g₂) for the displacements `reference` and `partner` of the two sides' nodes.
    pub fn read(&self, reference: &[Point3], partner: &[Point3]) -> [f64; 3] {
        let mut jump = [0.0; 3];
        for &(side, k, c) in &self.terms {
            let u = match side {
                Side::Reference => reference[k],
                Side::Partner => partner[k],
            };
            for (x, v) in jump.iter_mut().zip(u) {
                *x += c * v;
            }
        }
        self.frame.map(|e| dot3(e, jump))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tangents_complete_a_right_handed_orthonormal_frame() {
        for n in [
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [1.0, 0.0, 0.0],
            [0.6, -0.8, 0.0],
            [0.48, 0.6, 0.64],
        ] {
            let [t1, t2] = tangents(n);
            for (a, b) in [(t1, t1), (t2, t2), (n, n)] {
                assert!((dot3(a, b) - 1.0).abs() < 1e-15);
            }
            for (a, b) in [(t1, t2), (t1, n), (t2, n)] {
                assert!(dot3(a, b).abs() < 1e-15);
            }
            // (t₁, t₂, ν) right-handed: t₁ × t₂ = ν.
            let c = cross(t1, t2);
            assert!((0..3).all(|i| (c[i] - n[i]).abs() < 1e-15));
        }
    }
}
