//! Dual mortar coefficients between two triangulated surfaces by segment-to-segment integration
//! (the module docs of [`crate::contact3d`] give the integrals).
//!
//! For every reference triangle T, each partner triangle that faces it (opposite normals) and
//! lies within the search distance is projected along T's normal onto T's plane, and the
//! projection is clipped against T. On the clipped polygon, split into triangles from its
//! centroid, the integrands — the dual basis ψ_j = 4λ_j − 1 of T's linear shape functions λ_j,
//! times the partner's shape functions or times the distance h along the normal — are
//! polynomials of degree 2 (the projection of a flat partner triangle is affine), so a
//! three-point rule of degree 2 integrates them exactly. Biorthogonality, ∫_T ψ_i λ_l = δ_il
//! ∫_T λ_i, then makes Σ_k c_jk x_k = x_j for every field linear over a partner that covers the
//! point's triangles: a matching mesh gives the identity, and a uniform pressure the consistent
//! nodal loads.

use std::collections::HashMap;

use contactdd_core::element::TRIANGLE_DEGREE_5;

use super::clipping::{area, clip_convex, orient, Point2};
use super::surface::Surface;
use super::triangle_index::TriangleIndex;
use super::{cross, dot3, length, sub, Point3};

/// The symmetric three-point rule of degree 2 on a triangle: barycentric points, weight 1/3 each.
const RULE: [[f64; 3]; 3] = [
    [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0],
    [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
];

/// A reference node's view of the partner surface.
#[derive(Clone, Debug, PartialEq)]
pub struct MortarRow {
    /// (reference node, e_jk) by node: how point j reads its own side, Σ_k e_jk u_k. The node
    /// alone (e_jj = 1) on a linear surface, where biorthogonality makes the others vanish; on a
    /// quadratic one ∫ ψ_j N_k / ∫ ψ_j with N_k the quadratic shape functions, which ψ_j is not
    /// biorthogonal to. They sum to 1.
    pub own: Vec<(usize, f64)>,
    /// (partner node, c_jk), by partner node; they sum to 1.
    pub coefficients: Vec<(usize, f64)>,
    /// The weighted distance to the partner along the reference normals (negative: overlap).
    pub gap: f64,
    /// ∫ ψ_j over the part the partner covers, over ∫ φ_j: 1 for a node the partner covers all
    /// around.
    pub coverage: f64,
}

/// The integrals of one reference node: ∫ ψ φ_k per partner node k, and ∫ ψ h.
#[derive(Clone, Debug, Default)]
struct Integrals {
    coupling: HashMap<usize, f64>,
    own: HashMap<usize, f64>,
    gap: f64,
}

/// Per node of `reference`, its dual mortar row against `partner` (found through `index`, the
/// partner's [`TriangleIndex`]), counting partner triangles within `search` of the reference
/// triangle along its normal; `None` for a node the partner does not cover (∫ ψ over the covered
/// part not a positive share of the node).
pub fn dual_mortar(
    reference: &Surface,
    partner: &Surface,
    index: &TriangleIndex,
    search: f64,
) -> Vec<Option<MortarRow>> {
    let mut integrals = vec![Integrals::default(); reference.points().len()];
    for t in 0..reference.triangles().len() {
        let frame = Frame::of(reference, t);
        // The box of the prism the triangle sweeps along its normal over ±search: a partner
        // triangle that overlaps the triangle's projection within that distance meets it.
        let (mut lo, mut hi) = reference.bounds(t);
        for c in 0..3 {
            let reach = search * frame.normal[c].abs();
            lo[c] -= reach;
            hi[c] += reach;
        }
        for p in index.near(lo, hi) {
            if let Some(overlap) = frame.overlap(partner, p, search) {
                let sides = (reference, t, partner, p);
                frame.integrate(&overlap, sides, &mut integrals);
            }
        }
    }
    let quadratic = reference.is_quadratic();
    (integrals.iter().enumerate())
        .map(|(j, node)| normalised(node, (j, reference.weights()[j]), quadratic))
        .collect()
}

/// A reference triangle's plane: its first corner, two unit axes and the normal, and its
/// corners in plane coordinates (counterclockwise).
struct Frame {
    origin: Point3,
    axes: [Point3; 2],
    normal: Point3,
    corners: [Point2; 3],
}

/// A partner triangle clipped against a reference triangle: the polygon, and the partner's
/// corners' projected positions and heights.
struct Overlap {
    polygon: Vec<Point2>,
    projected: [Point2; 3],
    heights: [f64; 3],
}

impl Frame {
    fn of(surface: &Surface, t: usize) -> Frame {
        let [a, b, c] = surface.triangles()[t].map(|v| surface.points()[v]);
        let (normal, _) = surface.face(t);
        let ab = sub(b, a);
        let e1 = ab.map(|x| x / length(ab));
        let e2 = cross(normal, e1);
        let at = |p: Point3| [dot3(sub(p, a), e1), dot3(sub(p, a), e2)];
        Frame {
            origin: a,
            axes: [e1, e2],
            normal,
            corners: [at(a), at(b), at(c)],
        }
    }

    /// Partner triangle p projected onto the plane and clipped, if it faces this triangle, lies
    /// within `search` along the normal and overlaps it.
    fn overlap(&self, partner: &Surface, p: usize, search: f64) -> Option<Overlap> {
        let (n_p, _) = partner.face(p);
        if dot3(n_p, self.normal) >= 0.0 {
            return None;
        }
        let nodes = partner.triangles()[p];
        let mut projected = [[0.0; 2]; 3];
        let mut heights = [0.0; 3];
        for (i, &v) in nodes.iter().enumerate() {
            let d = sub(partner.points()[v], self.origin);
            projected[i] = [dot3(d, self.axes[0]), dot3(d, self.axes[1])];
            heights[i] = dot3(d, self.normal);
        }
        let (lowest, highest) = (heights.iter())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                (l.min(x), h.max(x))
            });
        if lowest > search || highest < -search {
            return None;
        }
        // A partner facing this triangle runs clockwise in its plane; one seen edge-on has no
        // area there.
        let own = orient(self.corners[0], self.corners[1], self.corners[2]);
        let [q0, q1, q2] = projected;
        if -orient(q0, q1, q2) <= 1e-12 * own {
            return None;
        }
        let polygon = clip_convex(&[q0, q2, q1], &self.corners);
        (polygon.len() >= 3 && area(&polygon) > 1e-14 * own).then_some(Overlap {
            polygon,
            projected,
            heights,
        })
    }

    /// Adds the overlap's integrals to the nodes of reference triangle t: `sides` is
    /// (reference, t, partner, p). The rule is exact for the integrands: degree 2 between linear
    /// surfaces, degree 5 where a side is quadratic (ψ times a quadratic shape function).
    fn integrate(
        &self,
        overlap: &Overlap,
        (reference, t, partner, p): (&Surface, usize, &Surface, usize),
        integrals: &mut [Integrals],
    ) {
        let quadratic = reference.is_quadratic() || partner.is_quadratic();
        let (points, weights) = match quadratic {
            true => (TRIANGLE_DEGREE_5.points, TRIANGLE_DEGREE_5.weights),
            false => (&RULE[..], &[1.0 / 3.0; 3][..]),
        };
        let nodes = reference.triangles()[t];
        let poly = &overlap.polygon;
        let m = poly.len() as f64;
        let centre = poly
            .iter()
            .fold([0.0; 2], |s, p| [s[0] + p[0] / m, s[1] + p[1] / m]);
        for i in 0..poly.len() {
            let piece = [centre, poly[i], poly[(i + 1) % poly.len()]];
            let size = orient(piece[0], piece[1], piece[2]) / 2.0;
            for (&bary, &wq) in points.iter().zip(weights) {
                let y = combine(&piece, bary);
                let lambda = barycentric(&self.corners, y);
                let mu = barycentric(&overlap.projected, y);
                let h: f64 = (0..3).map(|l| mu[l] * overlap.heights[l]).sum();
                let theirs = partner.shape(p, mu);
                let ours = reference.is_quadratic().then(|| reference.shape(t, lambda));
                let w = size * wq;
                for (i, &v) in nodes.iter().enumerate() {
                    let psi = 4.0 * lambda[i] - 1.0;
                    let node = &mut integrals[v];
                    for &(k, phi) in &theirs {
                        *node.coupling.entry(k).or_insert(0.0) += w * psi * phi;
                    }
                    for &(k, phi) in ours.iter().flatten() {
                        *node.own.entry(k).or_insert(0.0) += w * psi * phi;
                    }
                    node.gap += w * psi * h;
                }
            }
        }
    }
}

/// The point with barycentric coordinates `bary` in `triangle`.
fn combine(triangle: &[Point2; 3], bary: [f64; 3]) -> Point2 {
    let mut y = [0.0; 2];
    for (p, b) in triangle.iter().zip(bary) {
        y[0] += b * p[0];
        y[1] += b * p[1];
    }
    y
}

/// The barycentric coordinates of `y` in `triangle` (either orientation).
fn barycentric(triangle: &[Point2; 3], y: Point2) -> [f64; 3] {
    let [a, b, c] = *triangle;
    let whole = orient(a, b, c);
    [
        orient(y, b, c) / whole,
        orient(a, y, c) / whole,
        orient(a, b, y) / whole,
    ]
}

/// A node's integrals normalised by ∫ ψ over the covered part (`None` where that is not a
/// positive share of the integrals' size, or not finite): `node` is (j, its ∫ φ), and the own
/// row is the node alone unless the surface is `quadratic`.
fn normalised(
    integrals: &Integrals,
    (j, weight): (usize, f64),
    quadratic: bool,
) -> Option<MortarRow> {
    let sorted = |map: &HashMap<usize, f64>| {
        let mut row: Vec<(usize, f64)> = map.iter().map(|(&k, &c)| (k, c)).collect();
        row.sort_by_key(|e| e.0);
        row
    };
    let mut coefficients = sorted(&integrals.coupling);
    let total: f64 = coefficients.iter().map(|e| e.1).sum();
    let size: f64 = coefficients.iter().map(|e| e.1.abs()).sum();
    if !total.is_finite() || total <= 1e-9 * size {
        return None;
    }
    coefficients.iter_mut().for_each(|e| e.1 /= total);
    let own = match quadratic {
        true => sorted(&integrals.own)
            .into_iter()
            .map(|(k, c)| (k, c / total))
            .collect(),
        false => vec![(j, 1.0)],
    };
    Some(MortarRow {
        own,
        coefficients,
        gap: integrals.gap / total,
        coverage: total / weight,
    })
}
