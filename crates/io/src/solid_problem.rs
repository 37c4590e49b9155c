//! The schema of a problem file in space: plain serde data, exactly what a TOML file with
//! `dimension = 3` says.
//!
//! Like [`crate::problem`], these types only describe; [`crate::solid_setup`] validates every
//! value and builds the bodies. A complete file:
//!
//! ```toml
//! name = "blocks"
//! dimension = 3
//!
//! [materials.steel]
//! young = 2.1e5
//! poisson = 0.3
//!
//! [[bodies]]
//! name = "lower"
//! material = "steel"
//! mesh = { kind = "box", x = [0.0, 1.0], y = [0.0, 1.0], z = [0.0, 0.5], nx = 4, ny = 4, nz = 2 }
//! supports = [{ boundary = "z-", component = "all" }]
//!
//! [[bodies]]
//! name = "upper"
//! material = "steel"
//! mesh = { kind = "gmsh", file = "upper.msh" }
//! supports = [{ boundary = "top", component = "z", value = -0.001 }]
//!
//! [[contact]]
//! bodies = ["upper", "lower"]
//! boundaries = ["bottom", "z+"]
//! penalty = { theta = 1e-7 }
//! ```
//!
//! `docs/three-d.md` documents every key for users.

use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use contactdd_core::Order;

use crate::problem::{
    EnforcementSpec, FrictionSpec, LoadStepsSpec, MaterialSpec, MonitorSpec, OutputSpec,
    PenaltySpec,
};

/// A whole problem file in space.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct SolidProblem {
    /// Problem name used in output; default: the file stem.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The space dimension: 3 (a planar problem file has `plane` instead).
    pub dimension: u8,
    /// Free-text note on the (consistent) units used; not interpreted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<String>,
    /// Named materials (`[materials.NAME]` tables).
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialSpec>,
    /// The bodies (`[[bodies]]`), at least one.
    pub bodies: Vec<SolidBodyEntry>,
    /// The contact pairs (`[[contact]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contact: Vec<SolidContactSpec>,
    /// Solver settings (`[solver]`); every key is optional.
    #[serde(default)]
    pub solver: SolidSolverSpec,
    /// Output settings (`[output]`); every key is optional.
    #[serde(default, skip_serializing_if = "OutputSpec::is_default")]
    pub output: OutputSpec,
}

/// One body in space.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct SolidBodyEntry {
    /// Unique body name.
    pub name: String,
    /// Key of `[materials]`.
    pub material: String,
    /// How the body is meshed.
    pub mesh: SolidMeshSpec,
    /// Prescribed displacements.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub supports: Vec<SolidSupportSpec>,
    /// Applied loads, each selected by `kind`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub loads: Vec<SolidLoadSpec>,
}

/// A body's tetrahedral mesh, selected by `kind`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(tag = "kind", deny_unknown_fields, rename_all = "kebab-case")]
pub enum SolidMeshSpec {
    /// A structured mesh of the box `x[0] ≤ x ≤ x[1]`, `y[0] ≤ y ≤ y[1]`, `z[0] ≤ z ≤ z[1]` with
    /// `nx × ny × nz` cubes of six tetrahedra each; faces `x-`, `x+`, `y-`, `y+`, `z-`, `z+`.
    #[serde(rename_all = "kebab-case")]
    Box {
        /// x range `[x0, x1]`, x0 < x1.
        x: [f64; 2],
        /// y range.
        y: [f64; 2],
        /// z range.
        z: [f64; 2],
        /// Cubes in x (≥ 1).
        nx: usize,
        /// Cubes in y (≥ 1).
        ny: usize,
        /// Cubes in z (≥ 1).
        nz: usize,
        /// Element order: `p1` (4-node tetrahedra, the default) or `p2` (10-node).
        #[serde(default = "p1")]
        order: Order,
    },
    /// A Gmsh `.msh` file of tetrahedra; faces are its named physical surfaces.
    #[serde(rename_all = "kebab-case")]
    Gmsh {
        /// File path; relative paths resolve against the problem file's folder.
        file: PathBuf,
        /// The body's physical volume, for a file holding several. Default: every tetrahedron.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        volume: Option<String>,
        /// Added to every node after scaling (default `[0, 0, 0]`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        translate: Option<[f64; 3]>,
        /// Every coordinate is multiplied by this factor > 0 first (default 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        scale: Option<f64>,
    },
    /// A mesh written out in the file itself (what Python writes for a body built from arrays).
    #[serde(rename_all = "kebab-case")]
    Inline {
        /// Node coordinates `[x, y, z]`.
        nodes: Vec<[f64; 3]>,
        /// Node indices per tetrahedron: 4 (P1) or 10 (P2, Gmsh's order: vertices, then the
        /// mid-edge nodes of edges 0-1, 1-2, 0-2, 0-3, 2-3, 1-3).
        tetrahedra: Vec<Vec<usize>>,
        /// Named faces: their triangles, 3 node indices each (6 for P2: vertices, then the
        /// mid-edge nodes of edges 0-1, 1-2, 2-0).
        #[serde(default)]
        faces: BTreeMap<String, Vec<Vec<usize>>>,
    },
}

fn p1() -> Order {
    Order::P1
}

/// A prescribed displacement on a named face.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct SolidSupportSpec {
    /// Face name.
    pub boundary: String,
    /// `x`, `y`, `z` or `all`.
    pub component: SolidComponent,
    /// Prescribed value of each component it names (default 0).
    #[serde(default)]
    pub value: f64,
}

/// The displacement components a support prescribes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SolidComponent {
    /// u_x.
    X,
    /// u_y.
    Y,
    /// u_z.
    Z,
    /// All three.
    All,
}

/// A load of a body in space, selected by `kind`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(tag = "kind", deny_unknown_fields, rename_all = "kebab-case")]
pub enum SolidLoadSpec {
    /// A pressure on a face (positive: pushing into the body), force per unit area.
    Pressure {
        /// Face name.
        boundary: String,
        /// The pressure.
        value: f64,
    },
    /// A traction vector on a face, force per unit area.
    Traction {
        /// Face name.
        boundary: String,
        /// `[tx, ty, tz]`.
        value: [f64; 3],
    },
    /// A uniform body force, force per unit volume.
    BodyForce {
        /// `[fx, fy, fz]`.
        value: [f64; 3],
    },
}

/// A contact pair in space: the first body's face is the reference side (its nodes are the
/// contact points, with dual mortar rows onto the second's face).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct SolidContactSpec {
    /// Pair name; default `"<body1>-<body2>"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The two (distinct) body names.
    pub bodies: Vec<String>,
    /// The contact face of each body, in the same order.
    pub boundaries: Vec<String>,
    /// Penalty: either `{ c, h }` (rod model) or `{ theta }`.
    pub penalty: PenaltySpec,
    /// How far along the reference normals a partner counts (default: a tenth of the smaller
    /// body's bounding-box diameter).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search: Option<f64>,
    /// `"penalty"` (default): p = max(0, s − d)/θ; `"augmented"`: the exact Signorini conditions,
    /// the augmented Lagrangian's fixed point, whatever θ.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub enforcement: Option<EnforcementSpec>,
    /// The tangential law: `{ law = "coulomb", mu }`, `{ law = "tresca", bound }` or
    /// `{ law = "none" }` (default: frictionless).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<FrictionSpec>,
}

impl SolidContactSpec {
    /// The pair's name: `name`, or the body names joined by `-`.
    pub fn pair_name(&self) -> String {
        self.name.clone().unwrap_or_else(|| self.bodies.join("-"))
    }
}

/// The `[solver]` table of a problem in space.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct SolidSolverSpec {
    /// Largest net force and moment of a body of a converged result, relative to the largest
    /// force total of a body (default 1e-6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balance_tol: Option<f64>,
    /// Worker threads ≥ 1 (default: the machine's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threads: Option<usize>,
    /// Solve at increasing loads: N equal steps, or the load factors (as in the plane).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_steps: Option<LoadStepsSpec>,
    /// The face of a body whose mean displacement each load step reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monitor: Option<MonitorSpec>,
}

/// Whether the TOML text is a problem in space: a top-level `dimension` key. Text that is not
/// TOML counts as planar, whose parser then reports the syntax error.
pub fn is_solid_text(text: &str) -> bool {
    text.parse::<toml::Table>()
        .map(|t| t.contains_key("dimension"))
        .unwrap_or(false)
}
