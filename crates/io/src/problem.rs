//! The problem file schema: plain serde data, exactly what a TOML problem file says.
//!
//! These types only describe; they check nothing beyond the shape of the data (types, required
//! keys, no unknown keys). [`crate::setup::resolve`] turns a [`Problem`] into solver input
//! (`Model` + `Settings` of `contactdd_ddm`), validating every value and naming the
//! key and the body or pair when something is wrong. Solver state never derives `Deserialize`.
//!
//! Keys are kebab-case and use the names of `docs/method.md`. A complete file:
//!
//! ```toml
//! name = "notch"                  # optional; default: the file stem
//! plane = "strain"                # "strain" | "stress"
//! units = "cm, N/cm^2"            # optional free-text note
//!
//! [materials.steel]
//! young = 2.1e5
//! poisson = 0.3
//!
//! [[bodies]]
//! name = "lower"
//! material = "steel"
//! mesh = { kind = "rectangle", x = [0.0, 4.0], y = [0.0, 1.0], nx = 32, ny = 16 }
//! supports = [{ boundary = "right", component = "x" }]
//! loads = [{ kind = "pressure", boundary = "bottom", value = 2100.0 }]
//!
//! [[contact]]
//! bodies = ["lower", "upper"]
//! boundaries = ["top", "bottom"]
//! penalty = { c = 0.05, h = 1.0 }
//!
//! [solver]
//! method = "newton-kurchatov"
//! gamma = 0.5
//! ```
//!
//! `docs/problem-format.md` documents every key for users.

use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;

use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize, Serializer};

use contactdd_core::{Component, Diagonal, Load, Order, Plane, Vector};

use contactdd_ddm::contact::gap_profile::Along;
use contactdd_ddm::{Gamma, Method};

use crate::vtu::{VtuFormat, VtuLayout, VtuOptions};

/// A whole problem file.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct Problem {
    /// Problem name used in output; default: the file stem.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Plane strain or plane stress, for all bodies.
    pub plane: Plane,
    /// Free-text note on the (consistent) units used; not interpreted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<String>,
    /// Named materials (`[materials.NAME]` tables).
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialSpec>,
    /// The bodies (`[[bodies]]`), at least one.
    pub bodies: Vec<BodySpec>,
    /// The contact pairs (`[[contact]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contact: Vec<ContactSpec>,
    /// Solver settings (`[solver]`); every key is optional.
    #[serde(default)]
    pub solver: SolverSpec,
    /// A load history (`[[steps]]`): the load groups' factors, step by step.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<StepSpec>,
    /// Output settings (`[output]`); every key is optional.
    #[serde(default, skip_serializing_if = "OutputSpec::is_default")]
    pub output: OutputSpec,
}

/// The `[output]` table: how the result files are written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct OutputSpec {
    /// The encoding of the `.vtu` files: `"zlib"` (appended binary in zlib blocks, the
    /// default), `"binary"` (appended raw binary) or `"ascii"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vtu: Option<VtuFormat>,
    /// The layout of the `.vtu` files: `"per-body"` (one file per body, the default) or
    /// `"collection"` (one file per result holding every body as its own `Piece`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vtu_layout: Option<VtuLayout>,
}

impl OutputSpec {
    /// Whether no key is set (the table is then left out of a written problem file).
    pub fn is_default(&self) -> bool {
        *self == OutputSpec::default()
    }

    /// The encoding and layout of the `.vtu` files the table asks for (the defaults for the keys
    /// it leaves out).
    pub fn vtu_options(&self) -> VtuOptions {
        VtuOptions {
            format: self.vtu.unwrap_or_default(),
            layout: self.vtu_layout.unwrap_or_default(),
        }
    }
}

/// One step of a load history (`[[steps]]`): every group it names is ramped linearly, in
/// `increments` equal increments, from its factor at the end of the step before (0 at the start)
/// to the factor given; groups it does not name keep theirs.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct StepSpec {
    /// The step's name (default `step<k>`, k from 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The target factor of each group it ramps, by group name (`default`: the loads without a
    /// group and the prescribed displacements).
    #[serde(default)]
    pub factors: BTreeMap<String, f64>,
    /// Equal increments (≥ 1, default 1); each is one solve. Signed so that a negative count gets
    /// a message naming the step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub increments: Option<i64>,
}

impl StepSpec {
    /// The step's name: `name`, or `step<k>` for the step at `index` (from 0).
    pub fn step_name(&self, index: usize) -> String {
        self.name
            .clone()
            .unwrap_or_else(|| format!("step{}", index + 1))
    }
}

/// One load of a body: a [`Load`] (selected by `kind`) and the load group it belongs to.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
pub struct LoadSpec {
    /// The load.
    #[serde(flatten)]
    pub load: Load,
    /// The load group, whose factor a `[[steps]]` history sets (default: the group `default`,
    /// which is all loads of a problem without a history).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
}

impl LoadSpec {
    /// The group's name (`default` when none is given).
    pub fn group_name(&self) -> &str {
        self.group
            .as_deref()
            .unwrap_or(contactdd_ddm::history::DEFAULT_GROUP)
    }
}

impl From<Load> for LoadSpec {
    fn from(load: Load) -> Self {
        LoadSpec { load, group: None }
    }
}

/// An isotropic linear elastic material.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct MaterialSpec {
    /// Young's modulus E > 0 (stress units).
    pub young: f64,
    /// Poisson's ratio ν ∈ (−1, 0.5).
    pub poisson: f64,
}

/// One body.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct BodySpec {
    /// Unique body name.
    pub name: String,
    /// Key of `[materials]`.
    pub material: String,
    /// How the body is meshed.
    pub mesh: MeshSpec,
    /// Prescribed displacements.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub supports: Vec<SupportSpec>,
    /// Applied loads, each selected by `kind`, with an optional load `group`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub loads: Vec<LoadSpec>,
}

/// A body's mesh, selected by `kind`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(tag = "kind", deny_unknown_fields, rename_all = "kebab-case")]
pub enum MeshSpec {
    /// A structured mesh of the box `x[0] ≤ x ≤ x[1]`, `y[0] ≤ y ≤ y[1]` with `nx × ny` cells of
    /// two triangles each; boundaries `left`, `right`, `bottom`, `top`.
    #[serde(rename_all = "kebab-case")]
    Rectangle {
        /// x range `[x0, x1]`, x0 < x1.
        x: [f64; 2],
        /// y range `[y0, y1]`, y0 < y1.
        y: [f64; 2],
        /// Cells in x (≥ 1).
        nx: usize,
        /// Cells in y (≥ 1).
        ny: usize,
        /// Cell diagonal (default `right`, "/").
        #[serde(default)]
        diagonal: Diagonal,
        /// Mirror the mesh about its horizontal centre line (default false); used for the upper
        /// body of a pair so that the two meshes are mirror images.
        #[serde(default)]
        mirror: bool,
        /// Mirror the mesh about its vertical centre line (default false); used for the right
        /// body of a pair side by side.
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        mirror_x: bool,
        /// Grading of the cells in x and y (default uniform).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        grading: Option<GradingSpec>,
        /// Element order (default `p1`).
        #[serde(default = "default_order")]
        order: Order,
    },
    /// A Gmsh `.msh` file (ASCII 4.1 or 2.2); boundaries are its physical curves and points.
    #[serde(rename_all = "kebab-case")]
    Gmsh {
        /// File path; relative paths resolve against the problem file's folder.
        file: PathBuf,
        /// The body's physical surface, for a file holding several bodies; its boundaries are the
        /// physical curves and points that touch it. Default: the file's only body.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        surface: Option<String>,
        /// Element order: `p2` promotes P1 triangles to P2; default: as in the file.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        order: Option<Order>,
        /// Added to every node after scaling (default `[0, 0]`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        translate: Option<Vector>,
        /// Every coordinate is multiplied by this factor > 0 first (default 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        scale: Option<f64>,
    },
    /// A mesh written out in the file itself: what `Problem.to_toml()` of the Python module writes
    /// for a body added from arrays, so that such a problem reads back to the same model.
    #[serde(rename_all = "kebab-case")]
    Inline {
        /// Node coordinates `[x, y]`.
        nodes: Vec<Vector>,
        /// Node indices per triangle: 3 (P1) or 6 (P2: vertices, then the mid-side nodes of
        /// edges (0,1), (1,2), (2,0)); clockwise triangles are reordered counter-clockwise.
        triangles: Vec<Vec<usize>>,
        /// Named boundaries: the node pairs of their edges.
        #[serde(default)]
        boundaries: BTreeMap<String, Vec<[usize; 2]>>,
        /// Named node sets, usable as a support's `boundary`.
        #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
        node_sets: BTreeMap<String, Vec<usize>>,
    },
}

fn default_order() -> Order {
    Order::P1
}

/// Grading of a rectangle mesh: per axis, the size of the last cell (at x1, y1) over that of the
/// first (at x0, y0), the cell sizes in geometric progression.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct GradingSpec {
    /// Grading in x (> 0, default 1: uniform).
    #[serde(default = "one")]
    pub x: f64,
    /// Grading in y (> 0, default 1: uniform).
    #[serde(default = "one")]
    pub y: f64,
}

fn one() -> f64 {
    1.0
}

/// A prescribed displacement component on a named boundary.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct SupportSpec {
    /// Boundary (or Gmsh physical point) name.
    pub boundary: String,
    /// `x`, `y`, `both`, or `normal` (u·n on a straight boundary: a symmetry line or sliding
    /// support).
    pub component: Component,
    /// Prescribed value (default 0).
    #[serde(default)]
    pub value: f64,
}

/// A contact pair.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct ContactSpec {
    /// Pair name; default `"<body1>-<body2>"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The two (distinct) body names. A list rather than an array so that a wrong length is
    /// reported by [`crate::setup`] with the pair's name (serde would drop extra entries).
    pub bodies: Vec<String>,
    /// The contact boundary of each body, in the same order (exactly two, like `bodies`).
    pub boundaries: Vec<String>,
    /// Penalty: either `{ c, h }` (rod model) or `{ theta }`.
    pub penalty: PenaltySpec,
    /// Prescribed gap profile added to the geometric normal gap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<GapSpec>,
    /// `"penalty"` (the paper's formulation, the default) or `"augmented"` (augmented
    /// Lagrangian: the exact unilateral contact for any θ).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub enforcement: Option<EnforcementSpec>,
    /// `"balanced"` (the default: both sides receive equal and opposite forces) or `"own-side"`
    /// (the paper's formulation: each side loaded by its own points along its own normal).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub forces: Option<ForcesSpec>,
    /// The tangential law: `{ law = "coulomb", mu }`, `{ law = "tresca", bound }` or
    /// `{ law = "none" }`; absent: frictionless.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<FrictionSpec>,
}

/// `friction`: a contact pair's tangential law. Kept as one table of optional keys (like
/// [`PenaltySpec`]) so that a missing or misplaced parameter gets a precise message from
/// [`crate::setup`].
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(
    deny_unknown_fields,
    rename_all = "kebab-case",
    expecting = "a friction table: { law = \"coulomb\", mu = μ }, { law = \"tresca\", bound = b } or { law = \"none\" }"
)]
pub struct FrictionSpec {
    /// `"none"`, `"coulomb"` or `"tresca"`.
    pub law: FrictionLaw,
    /// Coulomb's friction coefficient μ ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// Tresca's bound on the tangential traction (a stress ≥ 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound: Option<f64>,
}

/// `friction.law`: the name of a tangential law.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrictionLaw {
    /// Frictionless.
    None,
    /// Coulomb's law |σ_t| ≤ μ p.
    Coulomb,
    /// Tresca's law |σ_t| ≤ bound.
    Tresca,
}

impl From<contactdd_ddm::Friction> for FrictionSpec {
    fn from(f: contactdd_ddm::Friction) -> Self {
        use contactdd_ddm::Friction;
        let (law, mu, bound) = match f {
            Friction::None => (FrictionLaw::None, None, None),
            Friction::Coulomb { mu } => (FrictionLaw::Coulomb, Some(mu), None),
            Friction::Tresca { bound } => (FrictionLaw::Tresca, None, Some(bound)),
        };
        FrictionSpec { law, mu, bound }
    }
}

/// `forces`: how a contact pair's pressure loads its two bodies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ForcesSpec {
    /// Equal and opposite forces, the gap along one normal per point.
    Balanced,
    /// Each side loaded by its own points along its own normal.
    OwnSide,
}

impl From<ForcesSpec> for contactdd_ddm::Forces {
    fn from(f: ForcesSpec) -> Self {
        match f {
            ForcesSpec::Balanced => contactdd_ddm::Forces::Balanced,
            ForcesSpec::OwnSide => contactdd_ddm::Forces::OwnSide,
        }
    }
}

/// `enforcement`: how a contact pair enforces non-penetration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum EnforcementSpec {
    /// The penalty formulation.
    Penalty,
    /// The augmented Lagrangian.
    Augmented,
}

impl From<EnforcementSpec> for contactdd_ddm::Enforcement {
    fn from(e: EnforcementSpec) -> Self {
        match e {
            EnforcementSpec::Penalty => contactdd_ddm::Enforcement::Penalty,
            EnforcementSpec::Augmented => contactdd_ddm::Enforcement::Augmented,
        }
    }
}

impl ContactSpec {
    /// The pair's name: `name`, or the body names joined by `-` (`"<body1>-<body2>"`).
    pub fn pair_name(&self) -> String {
        self.name.clone().unwrap_or_else(|| self.bodies.join("-"))
    }
}

/// The penalty θ of a pair: give either `theta`, or both `c` and `h` (rod model
/// θ = c·h·(1/E*₁ + 1/E*₂)). Kept as one table of optional keys so that a wrong combination gets a
/// precise message from [`crate::setup`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct PenaltySpec {
    /// Dimensionless rod-model factor c.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub c: Option<f64>,
    /// Characteristic body height h of the rod model.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub h: Option<f64>,
    /// θ given directly (length / stress units).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theta: Option<f64>,
}

/// A prescribed gap profile, selected by `kind`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(tag = "kind", deny_unknown_fields, rename_all = "kebab-case")]
pub enum GapSpec {
    /// d_p(ξ) = r0 · {[1 − ((ξ − centre)/b)²]⁺}^power.
    Notch {
        /// Depth r0.
        r0: f64,
        /// Half-width b > 0.
        b: f64,
        /// Centre ξ_c.
        centre: f64,
        /// Exponent (default 1.5).
        #[serde(default = "default_power")]
        power: f64,
        /// The line of the contact coordinate ξ: `x` (default), `y`, `{ direction = [dx, dy] }`
        /// or `{ angle = degrees }`; ξ = p · d with d the line's unit direction.
        #[serde(default)]
        along: Along,
    },
    /// A constant added gap.
    Uniform {
        /// Added gap (negative: initial interference).
        value: f64,
    },
}

fn default_power() -> f64 {
    1.5
}

/// The `[solver]` table; absent keys take the defaults of `contactdd_ddm::Settings`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct SolverSpec {
    /// Robin coefficient rule (default `newton-kurchatov`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<Method>,
    /// Relaxation parameter γ > 0 or `"auto"` (default `"auto"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gamma: Option<GammaSpec>,
    /// How the sweeps' outputs are combined: `"none"` (relaxation with γ, the default) or
    /// `"anderson"` (Anderson acceleration; γ relaxes its first step).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accelerator: Option<AcceleratorSpec>,
    /// The rigid-body coarse correction: `"chains"` (floating bodies that touch each other; the
    /// default unless a constant γ is given), `"all"` (every floating body) or `"off"` (the
    /// paper's one-level iteration; the default with a constant γ).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coarse: Option<CoarseSpec>,
    /// Stopping tolerance ε_u > 0 (default 1e-6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tol: Option<f64>,
    /// Largest equilibrium residual of a converged result, relative to the total contact force
    /// (default 1e-2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub equilibrium_tol: Option<f64>,
    /// Largest net force and moment of a body of a converged result (applied loads, contact
    /// forces and support reactions), relative to the largest force total of a body (default
    /// 1e-6 under the interface Newton method, `equilibrium-tol` under the Robin sweeps).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balance_tol: Option<f64>,
    /// Iteration cap ≥ 1 (default 500).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_iter: Option<usize>,
    /// Augmented Lagrangian pairs: the largest violation of the Signorini conditions of a
    /// converged result, a length in the problem's units (default: `tol` times the largest normal
    /// displacement of the contact points).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap_tol: Option<f64>,
    /// Augmented Lagrangian pairs: the cap on multiplier updates ≥ 1 (default 100).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_updates: Option<usize>,
    /// Load steps: a number N of equal steps (load factors 1/N, 2/N, …, 1), or the list of load
    /// factors (each > 0). Absent: one solve at the full load.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_steps: Option<LoadStepsSpec>,
    /// A boundary whose mean displacement the load steps report: `{ body, boundary }`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monitor: Option<MonitorSpec>,
    /// Initial normal displacement u⁰ₙ on all contact points (default: the model's size / 20 000,
    /// see [`crate::setup::model_size`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u0: Option<f64>,
    /// Initial u⁻¹ₙ of the two-point methods (default: the model's size / 10 000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_prev: Option<f64>,
    /// Worker threads ≥ 1 (default: the machine's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threads: Option<usize>,
    /// How the bodies are condensed on their contact points: `"auto"` (the default: per body by
    /// the cost model of `docs/sparse-path.md`), `"dense"` or `"sparse"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub condensation: Option<contactdd_ddm::Condensation>,
}

/// `load-steps`: a number of equal steps, or the list of load factors.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum LoadStepsSpec {
    /// N equal steps.
    Count(usize),
    /// The load factors.
    Factors(Vec<f64>),
}

/// `monitor`: the boundary of a body whose mean displacement the load steps report.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct MonitorSpec {
    /// Body name.
    pub body: String,
    /// Boundary name of that body.
    pub boundary: String,
}

/// `accelerator`: how the sweeps' outputs are combined.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum AcceleratorSpec {
    /// Relaxation with γ only.
    None,
    /// Anderson acceleration (IQN-ILS).
    Anderson,
    /// The interface semismooth Newton method.
    Newton,
}

/// `coarse`: which floating bodies the rigid-body coarse correction moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CoarseSpec {
    /// No coarse correction.
    Off,
    /// Floating bodies that touch another floating body.
    Chains,
    /// Every floating body.
    All,
}

/// `gamma`: a number, or the string `"auto"`. Deserialized like an untagged enum, but by hand so
/// that a wrong string gets a message naming the key.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GammaSpec {
    /// A constant γ.
    Value(f64),
    /// Safeguarded Aitken relaxation.
    Auto,
}

impl From<GammaSpec> for Gamma {
    fn from(g: GammaSpec) -> Gamma {
        match g {
            GammaSpec::Value(v) => Gamma::Constant(v),
            GammaSpec::Auto => Gamma::Auto,
        }
    }
}

impl Serialize for GammaSpec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            GammaSpec::Value(v) => s.serialize_f64(v),
            GammaSpec::Auto => s.serialize_str("auto"),
        }
    }
}

impl<'de> Deserialize<'de> for GammaSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<GammaSpec, D::Error> {
        struct GammaVisitor;

        impl Visitor<'_> for GammaVisitor {
            type Value = GammaSpec;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("gamma: a positive number or \"auto\"")
            }

            fn visit_f64<E: de::Error>(self, v: f64) -> Result<GammaSpec, E> {
                Ok(GammaSpec::Value(v))
            }

            fn visit_i64<E: de::Error>(self, v: i64) -> Result<GammaSpec, E> {
                Ok(GammaSpec::Value(v as f64))
            }

            fn visit_u64<E: de::Error>(self, v: u64) -> Result<GammaSpec, E> {
                Ok(GammaSpec::Value(v as f64))
            }

            fn visit_str<E: de::Error>(self, v: &str) -> Result<GammaSpec, E> {
                if v == "auto" {
                    Ok(GammaSpec::Auto)
                } else {
                    Err(E::custom(format!(
                        "gamma: expected a positive number or \"auto\", got \"{v}\""
                    )))
                }
            }
        }

        d.deserialize_any(GammaVisitor)
    }
}
