//! Typed errors of the 3D layer.

use thiserror::Error;

use crate::error::{BodyError, MaterialError};

/// A tetrahedral mesh, box, support, load or body of the 3D layer that cannot be used.
#[derive(Debug, Error)]
pub enum SolidError {
    /// No nodes or no tetrahedra.
    #[error("the 3D mesh is empty (no nodes or no tetrahedra)")]
    Empty,
    /// Connectivity length is not a multiple of the nodes per tetrahedron.
    #[error(
        "connectivity has {len} entries, not a multiple of {nodes_per_tet} nodes per tetrahedron"
    )]
    BadConnectivity {
        /// Length of the flat connectivity.
        len: usize,
        /// Nodes per tetrahedron of the declared order.
        nodes_per_tet: usize,
    },
    /// A node coordinate is NaN or infinite.
    #[error("node {node} has a non-finite coordinate")]
    NonFiniteNode {
        /// Node index.
        node: usize,
    },
    /// A tetrahedron refers to a node that does not exist.
    #[error("tetrahedron {element} refers to node {node}, but the mesh has {count} nodes")]
    NodeOutOfRange {
        /// Tetrahedron index.
        element: usize,
        /// Offending node index.
        node: usize,
        /// Number of nodes.
        count: usize,
    },
    /// A node that no tetrahedron uses (it would make the stiffness matrix singular).
    #[error("node {node} is not used by any tetrahedron")]
    UnreferencedNode {
        /// Node index.
        node: usize,
    },
    /// Zero (or nearly zero) volume.
    #[error("tetrahedron {element} is degenerate (zero volume)")]
    DegenerateElement {
        /// Tetrahedron index.
        element: usize,
    },
    /// Negative volume: vertices 1, 2, 3 seen from vertex 0 turn clockwise.
    #[error("tetrahedron {element} is inverted (negative volume: (p1-p0)·((p2-p0)×(p3-p0)) < 0)")]
    InvertedElement {
        /// Tetrahedron index.
        element: usize,
    },
    /// A curved P2 tetrahedron whose Jacobian is not positive at every checked point.
    #[error("curved P2 tetrahedron {element} is folded: a mid-edge node lies so far off its edge that the Jacobian is not positive everywhere")]
    CurvedInverted {
        /// Tetrahedron index.
        element: usize,
    },
    /// A face connectivity whose length is not a multiple of the nodes per face triangle.
    #[error("face '{face}' has {len} node entries, not a multiple of {nodes_per_face} nodes per triangle")]
    FaceConnectivity {
        /// Face name.
        face: String,
        /// Length of its flat connectivity.
        len: usize,
        /// Nodes per face triangle of the mesh's order.
        nodes_per_face: usize,
    },
    /// A face triangle refers to a node that does not exist.
    #[error("face '{face}' refers to node {node}, but the mesh has {count} nodes")]
    FaceNodeOutOfRange {
        /// Face name.
        face: String,
        /// Offending node.
        node: usize,
        /// Number of nodes.
        count: usize,
    },
    /// A face triangle that is not a boundary face of exactly one tetrahedron (with the same
    /// mid-edge nodes, for P2).
    #[error("face '{face}': triangle {triangle} is not a boundary face of the mesh")]
    NotABoundaryFace {
        /// Face name.
        face: String,
        /// Index of the triangle within the face.
        triangle: usize,
    },
    /// A face name that does not exist.
    #[error("no face named '{name}' (known: {})", known.join(", "))]
    NoSuchFace {
        /// Requested name.
        name: String,
        /// Names that exist.
        known: Vec<String>,
    },
    /// Bad parameters of the structured box mesher.
    #[error("box mesh: {0}")]
    BadBox(String),
    /// Invalid material (E ≤ 0, ν ∉ (−1, 0.5)).
    #[error(transparent)]
    Material(#[from] MaterialError),
    /// A prescribed value or a load that is NaN or infinite.
    #[error("{what} is not finite")]
    NonFinite {
        /// What carries the value.
        what: String,
    },
    /// A vector whose length does not match the body's DOFs.
    #[error("{what} has {got} entries, the body has {expected} DOFs")]
    Length {
        /// Which vector.
        what: &'static str,
        /// The body's number of DOFs.
        expected: usize,
        /// The vector's length.
        got: usize,
    },
    /// Factorisation or solve of the body failed.
    #[error(transparent)]
    Body(#[from] BodyError),
}
