//! A triangulated contact surface: its nodes, its linear (3-node) triangles, the unit normal and
//! area of every triangle, and per node the lumped weight ∫ φ_j dA and the nodal normal.

use super::{cross, length, sub, Point3};

/// Why a set of points and triangles is not a contact surface.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SurfaceError {
    /// A triangle names a node that does not exist.
    #[error("triangle {triangle} names node {node}, but the surface has {nodes} nodes")]
    NodeOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The node it names.
        node: usize,
        /// The number of nodes.
        nodes: usize,
    },
    /// A node's coordinate is NaN or infinite.
    #[error("node {node} has a non-finite coordinate {coordinates:?}")]
    NotFinite {
        /// The node.
        node: usize,
        /// Its coordinates.
        coordinates: Point3,
    },
    /// A triangle has no area (repeated or collinear nodes).
    #[error("triangle {triangle} (nodes {nodes:?}) is degenerate: its area is {area:e}")]
    Degenerate {
        /// The triangle.
        triangle: usize,
        /// Its nodes.
        nodes: [usize; 3],
        /// Its area.
        area: f64,
    },
    /// The surface has no triangle.
    #[error("the surface has no triangle")]
    Empty,
}

/// A triangulated surface whose triangles are numbered counterclockwise seen from outside the
/// body, so that every triangle's normal (b − a) × (c − a) points out of it.
#[derive(Clone, Debug)]
pub struct Surface {
    points: Vec<Point3>,
    triangles: Vec<[usize; 3]>,
    /// Per triangle, the outward unit normal and the area.
    faces: Vec<(Point3, f64)>,
    /// Per node, ∫ φ_j dA (a third of its triangles' areas).
    weights: Vec<f64>,
    /// Per node, the area-weighted mean of its triangles' normals, of unit length.
    normals: Vec<Point3>,
    /// The 6-node triangles a quadratic surface was split from (triangle t is the part
    /// t mod 4 of parent t / 4, [`SUB`]); `None` for a linear surface.
    parents: Option<Vec<[usize; 6]>>,
}

/// The corners of the four parts of a 6-node triangle in its barycentric coordinates: the
/// corners' triangles, then the middle one (the order of [`Surface::from_quadratic`]).
const SUB: [[[f64; 3]; 3]; 4] = [
    [[1.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.5, 0.0, 0.5]],
    [[0.5, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.5, 0.5]],
    [[0.5, 0.0, 0.5], [0.0, 0.5, 0.5], [0.0, 0.0, 1.0]],
    [[0.5, 0.5, 0.0], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5]],
];

impl Surface {
    /// The surface of `triangles` over `points`, checked: every index in range, every coordinate
    /// finite, and every triangle of positive area (above 1e-14 of the surface's extent squared).
    pub fn new(points: Vec<Point3>, triangles: Vec<[usize; 3]>) -> Result<Surface, SurfaceError> {
        if triangles.is_empty() {
            return Err(SurfaceError::Empty);
        }
        if let Some((node, &coordinates)) =
            (points.iter().enumerate()).find(|(_, p)| p.iter().any(|x| !x.is_finite()))
        {
            return Err(SurfaceError::NotFinite { node, coordinates });
        }
        for (triangle, t) in triangles.iter().enumerate() {
            if let Some(&node) = t.iter().find(|&&v| v >= points.len()) {
                return Err(SurfaceError::NodeOutOfRange {
                    triangle,
                    node,
                    nodes: points.len(),
                });
            }
        }
        let extent = extent(&points);
        let mut faces = Vec::with_capacity(triangles.len());
        for (triangle, &t) in triangles.iter().enumerate() {
            let [a, b, c] = t.map(|v| points[v]);
            let n = cross(sub(b, a), sub(c, a));
            let area = 0.5 * length(n);
            if area.is_nan() || area <= 1e-14 * extent * extent {
                return Err(SurfaceError::Degenerate {
                    triangle,
                    nodes: t,
                    area,
                });
            }
            faces.push((n.map(|x| 0.5 * x / area), area));
        }
        let (weights, normals) = nodal(&points, &triangles, &faces);
        Ok(Surface {
            points,
            triangles,
            faces,
            weights,
            normals,
            parents: None,
        })
    }

    /// The surface of quadratic 6-node triangles (Gmsh's order: the corners, then the nodes of
    /// the sides 0–1, 1–2 and 2–0) as four linear triangles each: the corners' triangles and
    /// the middle one. Every node is a vertex of the result, with a positive weight (a corner
    /// A/12 of each triangle, a side node A/4), which the quadratic shape functions would not
    /// give (their corners integrate to zero): the contact points of a P2 body carry
    /// piecewise-linear multipliers on the finer surface.
    pub fn from_quadratic(
        points: Vec<Point3>,
        triangles: &[[usize; 6]],
    ) -> Result<Surface, SurfaceError> {
        let split = triangles
            .iter()
            .flat_map(|&[a, b, c, ab, bc, ca]| {
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect();
        let mut surface = Surface::new(points, split)?;
        surface.parents = Some(triangles.to_vec());
        Ok(surface)
    }

    /// True for a surface split from 6-node triangles.
    pub fn is_quadratic(&self) -> bool {
        self.parents.is_some()
    }

    /// The surface's shape functions at the point of triangle t with barycentric coordinates
    /// `bary` (in t): (node, value) of the three linear ones, or of the six quadratic ones of t's
    /// parent on a quadratic surface (whose displacement they interpolate).
    pub fn shape(&self, t: usize, bary: [f64; 3]) -> Vec<(usize, f64)> {
        let Some(parents) = &self.parents else {
            return (0..3).map(|i| (self.triangles[t][i], bary[i])).collect();
        };
        let mut l = [0.0; 3];
        for (corner, b) in SUB[t % 4].iter().zip(bary) {
            for c in 0..3 {
                l[c] += b * corner[c];
            }
        }
        let [a, b, c, ab, bc, ca] = parents[t / 4];
        vec![
            (a, l[0] * (2.0 * l[0] - 1.0)),
            (b, l[1] * (2.0 * l[1] - 1.0)),
            (c, l[2] * (2.0 * l[2] - 1.0)),
            (ab, 4.0 * l[0] * l[1]),
            (bc, 4.0 * l[1] * l[2]),
            (ca, 4.0 * l[2] * l[0]),
        ]
    }

    /// The nodes' coordinates.
    pub fn points(&self) -> &[Point3] {
        &self.points
    }

    /// The triangles (node indices, counterclockwise seen from outside).
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// Triangle t's outward unit normal and area.
    pub fn face(&self, t: usize) -> (Point3, f64) {
        self.faces[t]
    }

    /// Per node, ∫ φ_j dA: the weight of its contact force.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Per node, the unit normal: the area-weighted mean of its triangles' normals (a node that
    /// no triangle names has the zero vector).
    pub fn normals(&self) -> &[Point3] {
        &self.normals
    }

    /// The corners of the box around triangle t.
    pub fn bounds(&self, t: usize) -> (Point3, Point3) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in self.triangles[t] {
            for c in 0..3 {
                lo[c] = lo[c].min(self.points[v][c]);
                hi[c] = hi[c].max(self.points[v][c]);
            }
        }
        (lo, hi)
    }
}

/// The largest side of the box around `points`.
fn extent(points: &[Point3]) -> f64 {
    (0..3)
        .map(|c| {
            let (lo, hi) = points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                    (l.min(p[c]), h.max(p[c]))
                });
            hi - lo
        })
        .fold(0.0, f64::max)
}

/// Per node, the lumped weight and the area-weighted normal of the triangles around it.
fn nodal(
    points: &[Point3],
    triangles: &[[usize; 3]],
    faces: &[(Point3, f64)],
) -> (Vec<f64>, Vec<Point3>) {
    let mut weights = vec![0.0; points.len()];
    let mut sums = vec![[0.0; 3]; points.len()];
    for (t, &(n, area)) in triangles.iter().zip(faces) {
        for v in *t {
            weights[v] += area / 3.0;
            for c in 0..3 {
                sums[v][c] += area * n[c];
            }
        }
    }
    let normals = sums
        .into_iter()
        .map(|s| {
            let l = length(s);
            if l > 0.0 {
                s.map(|x| x / l)
            } else {
                [0.0; 3]
            }
        })
        .collect();
    (weights, normals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_unit_square_has_unit_area_and_upward_normals() {
        let points = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let s = Surface::new(points, vec![[0, 1, 2], [0, 2, 3]]).unwrap();
        let total: f64 = s.weights().iter().sum();
        assert!((total - 1.0).abs() < 1e-15);
        for n in s.normals() {
            assert_eq!(*n, [0.0, 0.0, 1.0]);
        }
    }

    #[test]
    fn bad_surfaces_are_refused_with_the_reason() {
        let p = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let err = Surface::new(p.clone(), vec![[0, 1, 3]]).unwrap_err();
        assert!(matches!(err, SurfaceError::NodeOutOfRange { node: 3, .. }));
        let err = Surface::new(p.clone(), vec![[0, 1, 1]]).unwrap_err();
        assert!(matches!(err, SurfaceError::Degenerate { triangle: 0, .. }));
        let mut q = p.clone();
        q[1][2] = f64::NAN;
        let err = Surface::new(q, vec![[0, 1, 2]]).unwrap_err();
        assert!(matches!(err, SurfaceError::NotFinite { node: 1, .. }));
        assert_eq!(Surface::new(p, vec![]).unwrap_err(), SurfaceError::Empty);
    }
}
