//! Typed errors of the finite element core.

use thiserror::Error;

/// A mesh that cannot be used.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeshError {
    /// No nodes or no triangles.
    #[error("the mesh is empty (no nodes or no triangles)")]
    Empty,
    /// Connectivity length is not a multiple of the nodes per triangle.
    #[error(
        "connectivity has {len} entries, not a multiple of {nodes_per_cell} nodes per triangle"
    )]
    BadConnectivity {
        /// Length of the flat connectivity.
        len: usize,
        /// Nodes per triangle of the declared order.
        nodes_per_cell: usize,
    },
    /// A node coordinate is NaN or infinite.
    #[error("node {node} has a non-finite coordinate")]
    NonFiniteNode {
        /// Node index.
        node: usize,
    },
    /// A triangle refers to a node that does not exist.
    #[error("triangle {element} refers to node {node}, but the mesh has {count} nodes")]
    NodeOutOfRange {
        /// Triangle index.
        element: usize,
        /// Offending node index.
        node: usize,
        /// Number of nodes.
        count: usize,
    },
    /// A node that no triangle uses (it would make the stiffness matrix singular).
    #[error("node {node} is not used by any triangle")]
    UnreferencedNode {
        /// Node index.
        node: usize,
    },
    /// Zero (or nearly zero) area.
    #[error("triangle {element} is degenerate (zero area)")]
    DegenerateElement {
        /// Triangle index.
        element: usize,
    },
    /// Clockwise vertex order.
    #[error("triangle {element} is inverted (clockwise vertex order, negative area)")]
    InvertedElement {
        /// Triangle index.
        element: usize,
    },
    /// A curved P2 triangle whose Jacobian is not positive everywhere.
    #[error("curved P2 triangle {element} is folded: a mid-side node lies so far off its edge that the element's Jacobian is not positive everywhere (move it closer to the edge's midpoint, or refine the mesh near the curve)")]
    CurvedInverted {
        /// Triangle index.
        element: usize,
    },
    /// A named boundary edge that is not on the boundary of the mesh.
    #[error("boundary '{boundary}': edge {a}-{b} is not a boundary edge of the mesh")]
    NotABoundaryEdge {
        /// Boundary name.
        boundary: String,
        /// First node.
        a: usize,
        /// Second node.
        b: usize,
    },
    /// A boundary or node set name that does not exist.
    #[error("no boundary named '{name}' ({})", known_names(known))]
    NoSuchBoundary {
        /// Requested name.
        name: String,
        /// Names that exist.
        known: Vec<String>,
    },
    /// A node set refers to a node that does not exist.
    #[error("node set '{set}' refers to node {node}, which does not exist")]
    NodeSetOutOfRange {
        /// Set name.
        set: String,
        /// Offending node.
        node: usize,
    },
    /// Bad parameters of the structured rectangle mesher.
    #[error("rectangle mesh: {0}")]
    BadRectangle(String),
}

/// The names that exist, for [`MeshError::NoSuchBoundary`]; a mesh without any says where names
/// come from.
fn known_names(known: &[String]) -> String {
    if known.is_empty() {
        "the mesh has no named boundaries: a rectangle has left, right, bottom and top; a Gmsh \
         file names them with physical curves and points"
            .to_string()
    } else {
        format!("known: {}", known.join(", "))
    }
}

/// A Gmsh file that cannot be read.
#[derive(Debug, Error)]
pub enum GmshError {
    /// The file could not be read.
    #[error("cannot read '{path}': {source}")]
    Io {
        /// File path.
        path: String,
        /// Underlying error.
        source: std::io::Error,
    },
    /// Malformed content.
    #[error("line {line}: {message}")]
    Parse {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// No physical surface of the requested name, or several bodies and none requested.
    #[error("{0}")]
    Surface(String),
    /// Valid Gmsh, but not something contactdd reads.
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// The resulting mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// 3D reader: no physical volume of the requested name, or several physical volumes and
    /// none requested.
    #[error("{0}")]
    Volume(String),
    /// 3D reader: the file has no tetrahedra.
    #[error(
        "the file has no tetrahedra (4- or 10-node); contactdd needs a 3D tetrahedral mesh. \
         When a model has physical groups, Gmsh saves only their elements: add a physical volume \
         for each body (Physical Volume(\"name\") = {{...}}), or set Mesh.SaveAll = 1"
    )]
    NoTetrahedra,
    /// 3D reader: 4-node and 10-node tetrahedra in one body.
    #[error(
        "line {line}: tetrahedron {tag} has {nodes} nodes, but the body's first tetrahedron \
         (line {first_line}) has {first_nodes}; a mesh has tetrahedra of one order"
    )]
    MixedTetrahedra {
        /// 1-based line of the tetrahedron.
        line: usize,
        /// The tetrahedron's element tag.
        tag: u64,
        /// Its number of nodes.
        nodes: usize,
        /// 1-based line of the body's first tetrahedron.
        first_line: usize,
        /// The first tetrahedron's number of nodes.
        first_nodes: usize,
    },
    /// 3D reader: a face triangle of another order than the tetrahedra.
    #[error(
        "line {line}: triangle {tag} of physical surface '{group}' has {nodes} nodes, but the \
         tetrahedra have {tet_nodes}; the faces of 4-node tetrahedra are 3-node triangles, \
         those of 10-node tetrahedra 6-node triangles"
    )]
    FaceOrder {
        /// 1-based line of the triangle.
        line: usize,
        /// The triangle's element tag.
        tag: u64,
        /// The physical surface's name (its tag number if unnamed).
        group: String,
        /// The triangle's number of nodes.
        nodes: usize,
        /// The tetrahedra's number of nodes.
        tet_nodes: usize,
    },
    /// 3D reader: a triangle of a physical surface that is not a boundary face of the body.
    #[error(
        "line {line}: triangle {tag} of physical surface '{group}' is not a boundary face of the \
         body: {reason}"
    )]
    NotABoundaryFace {
        /// 1-based line of the triangle.
        line: usize,
        /// The triangle's element tag.
        tag: u64,
        /// The physical surface's name (its tag number if unnamed).
        group: String,
        /// Why not.
        reason: String,
    },
    /// 3D reader: the tetrahedral mesh is invalid. `source` is the
    /// `contactdd_core::solid::SolidError` of `SolidMesh::new` (boxed so that this module does
    /// not depend on the 3D layer, which depends on it: `source.downcast_ref::<SolidError>()`
    /// gives it back); `line` is the file line of the tetrahedron it names, if any.
    #[error("{}{source}", at_line(*.line))]
    Solid {
        /// 1-based line of the tetrahedron the error names, if it names one.
        line: Option<usize>,
        /// The `SolidError`.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
}

/// `"line N: "`, or nothing without a line.
fn at_line(line: Option<usize>) -> String {
    line.map_or_else(String::new, |l| format!("line {l}: "))
}

/// Bad material constants.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MaterialError {
    /// E must be positive and finite.
    #[error("Young's modulus must be positive and finite, got {}", short(*.0))]
    YoungModulus(f64),
    /// ν must lie in (−1, 0.5).
    #[error("Poisson's ratio must lie in (-1, 0.5), got {}", short(*.0))]
    PoissonRatio(f64),
}

/// Errors of assembling, constraining and factorising one body.
#[derive(Debug, Error)]
pub enum BodyError {
    /// Mesh problem.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Material problem.
    #[error(transparent)]
    Material(#[from] MaterialError),
    /// The body can move without deformation: supports and contact springs leave rigid modes.
    #[error("body '{body}' is not held: {modes} rigid-body mode(s) ({description}) are not removed by its supports{contact}; add a support or a contact zone")]
    Floating {
        /// Body name.
        body: String,
        /// Number of free rigid modes.
        modes: usize,
        /// Which modes (e.g. "translation in y").
        description: String,
        /// " or contact zones" if contact zones were taken into account.
        contact: &'static str,
    },
    /// Cholesky failed although the body looked supported.
    #[error("body '{body}': the stiffness matrix is not positive definite (Cholesky failed at pivot {pivot}); check supports and material")]
    NotPositiveDefinite {
        /// Body name.
        body: String,
        /// Where the factorisation failed: the pivot index faer reports, in the factor's
        /// elimination order.
        pivot: usize,
    },
    /// A non-finite load or prescribed value.
    #[error("body '{body}': {what} is not finite")]
    NonFinite {
        /// Body name.
        body: String,
        /// What is not finite.
        what: String,
    },
    /// The sparse solver ran out of memory or index range.
    #[error("body '{body}': sparse factorization failed: {message}")]
    Factorization {
        /// Body name.
        body: String,
        /// faer's message.
        message: String,
    },
}

/// A support that cannot be applied.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SupportError {
    /// Unknown boundary.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A `normal` support needs a straight boundary.
    #[error("boundary '{boundary}': a 'normal' support needs a straight boundary (all its nodes on one line, within 1e-9 of the mesh size, the body on one side)")]
    NotStraight {
        /// Boundary name.
        boundary: String,
    },
    /// A `normal` support on a node set, which has no normal.
    #[error(
        "'{name}' is a node set: a 'normal' support needs a boundary, whose edges give its normal"
    )]
    NormalOnNodeSet {
        /// Node set name.
        name: String,
    },
    /// A non-finite prescribed value.
    #[error("boundary '{boundary}': prescribed displacement {value} is not finite")]
    NonFinite {
        /// Boundary name.
        boundary: String,
        /// Value.
        value: f64,
    },
}

/// `x` for a message: `Display` (shortest round trip) unless that is long, as for 1e-300; then with
/// an exponent. The rule of `contactdd_io::number`, which this crate cannot depend on.
fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
