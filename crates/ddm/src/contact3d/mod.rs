//! The contact geometry of bodies in space: triangulated contact surfaces, their nodal normals and
//! weights, a spatial index of their triangles, and the dual mortar coefficients of a pair of
//! non-matching surfaces by segment-to-segment integration (docs/three-d.md).
//!
//! This is the three-dimensional counterpart of the planar `contact::mortar`: a point j of the
//! reference surface reads its partner through
//!
//!   c_jk = ∫ ψ_j φ_k(x′(x)) dA / ∫ ψ_j dA,     d_j = ∫ ψ_j h(x) dA / ∫ ψ_j dA,
//!
//! with ψ_j the dual basis of the reference surface's shape functions, x′(x) the partner point
//! that projects onto x along the reference triangle's normal, φ_k the partner's shape functions
//! and h the distance along that normal. The integrals are exact on flat triangles: every
//! partner triangle is projected onto the plane of each reference triangle it faces, clipped
//! against it ([`clipping`]), and the clipped polygon is integrated piece by piece
//! ([`mortar`]). Each reference node then reads its normal approach and its two tangential slips
//! in one frame ([`frames`]), and friction bounds the tangential traction by a disc ([`disc`]).
//! Data flows one way: [`Surface`] → [`TriangleIndex`] → [`dual_mortar`] → [`PointRows`].

pub mod clipping;
pub mod disc;
pub mod frames;
pub mod mortar;
pub mod surface;
pub mod triangle_index;

pub use disc::DiscStatus;
pub use frames::{tangents, PointRows, Side};
pub use mortar::{dual_mortar, MortarRow};
pub use surface::{Surface, SurfaceError};
pub use triangle_index::TriangleIndex;

/// A point or vector in space.
pub type Point3 = [f64; 3];

/// a − b.
pub(crate) fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a · b.
pub(crate) fn dot3(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b.
pub(crate) fn cross(a: Point3, b: Point3) -> Point3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// |a|.
pub(crate) fn length(a: Point3) -> f64 {
    dot3(a, a).sqrt()
}
