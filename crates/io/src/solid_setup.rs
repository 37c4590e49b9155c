//! From a problem file in space to the solver's input: every value checked, every body meshed,
//! its supports and loads assembled, its pairs resolved. Messages name the body, pair or key.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use contactdd_core::names::{name_problem, shown};
use contactdd_core::solid::assembly::{add_body_force, add_face_traction};
use contactdd_core::solid::element::elasticity;
use contactdd_core::solid::supports::{constraints, fix};
use contactdd_core::solid::{num_dofs, Axis, BoxMesh, SolidMesh, TetOrder};
use contactdd_core::{Material, Order};
use contactdd_ddm::solid_monolithic::{SolidBodySpec, SolidPairSpec};

use crate::error::excerpt;
use crate::load_steps::load_steps;
use crate::pairs::friction_law;
use crate::problem::{MonitorSpec, OutputSpec, PenaltySpec};
use crate::solid_problem::{
    SolidBodyEntry, SolidComponent, SolidContactSpec, SolidLoadSpec, SolidMeshSpec, SolidProblem,
};

/// The default `balance-tol` in space.
pub const SOLID_BALANCE_TOL: f64 = 1e-6;

/// Why a problem file in space cannot be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SolidLoadError {
    /// The file could not be read.
    #[error("cannot read '{path}': {source}")]
    Io {
        /// Path.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// TOML syntax or schema error (the message names the key and line).
    #[error("{file}: {}", excerpt(&source.to_string()))]
    Toml {
        /// The file.
        file: String,
        /// The parser's error.
        source: toml::de::Error,
    },
    /// A value is invalid: the message names the body, pair or key.
    #[error("{file}: {message}")]
    Invalid {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
}

/// One body, meshed, with its prescribed DOFs and nodal loads.
#[derive(Clone, Debug)]
pub struct SolidBodyModel {
    /// Unique name.
    pub name: String,
    /// The mesh.
    pub mesh: SolidMesh,
    /// The material.
    pub material: Material,
    /// (DOF, value) of every prescribed DOF.
    pub prescribed: Vec<(usize, f64)>,
    /// The nodal loads (3 per node).
    pub load: Vec<f64>,
}

/// One pair: its name, its bodies and faces (reference first), its penalty and search distance.
#[derive(Clone, Debug)]
pub struct SolidPairModel {
    /// The pair's name.
    pub name: String,
    /// (body, face) of the reference side and of the partner.
    pub sides: [(usize, String); 2],
    /// The penalty θ.
    pub theta: f64,
    /// The search distance along the reference normals.
    pub search: f64,
    /// How the pair enforces non-penetration.
    pub enforcement: contactdd_ddm::Enforcement,
    /// The pair's tangential law.
    pub friction: contactdd_ddm::Friction,
}

/// A resolved problem in space.
#[derive(Clone, Debug)]
pub struct SolidModel {
    /// The problem's name.
    pub name: String,
    /// The free-text note on the units, if the file gives one.
    pub units: Option<String>,
    /// The bodies.
    pub bodies: Vec<SolidBodyModel>,
    /// The pairs.
    pub pairs: Vec<SolidPairModel>,
    /// The largest relative imbalance of a converged result.
    pub balance_tol: f64,
    /// Worker threads (`None`: the machine's).
    pub threads: Option<usize>,
    /// The load factors of the solves, in order (`[1.0]` without `load-steps`).
    pub load_factors: Vec<f64>,
    /// The (body, face) whose mean displacement each load step reports.
    pub monitor: Option<(usize, String)>,
    /// The output settings.
    pub output: OutputSpec,
}

impl SolidModel {
    /// The bodies as the solvers take them.
    pub fn body_specs(&self) -> Vec<SolidBodySpec<'_>> {
        (self.bodies.iter())
            .map(|b| SolidBodySpec {
                mesh: &b.mesh,
                elasticity: elasticity(&b.material),
                prescribed: b.prescribed.clone(),
                load: b.load.clone(),
            })
            .collect()
    }

    /// The pairs as the solvers take them.
    pub fn pair_specs(&self) -> Vec<SolidPairSpec> {
        (self.pairs.iter())
            .map(|p| SolidPairSpec {
                reference: p.sides[0].clone(),
                partner: p.sides[1].clone(),
                theta: p.theta,
                search: p.search,
                enforcement: p.enforcement,
                friction: p.friction,
            })
            .collect()
    }
}

/// Reads, parses and resolves a problem file in space.
pub fn load_solid_file(path: &Path) -> Result<SolidModel, SolidLoadError> {
    let text = std::fs::read_to_string(path).map_err(|source| SolidLoadError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let file = path.display().to_string();
    let problem: SolidProblem = toml::from_str(&text).map_err(|source| SolidLoadError::Toml {
        file: file.clone(),
        source,
    })?;
    let stem = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("problem");
    let base = path.parent().unwrap_or(Path::new(""));
    resolve_solid(problem, base, stem).map_err(|message| SolidLoadError::Invalid { file, message })
}

/// Validates `problem` and builds its bodies; relative mesh paths resolve against `base`, and
/// `stem` is the default name.
pub fn resolve_solid(problem: SolidProblem, base: &Path, stem: &str) -> Result<SolidModel, String> {
    if problem.dimension != 3 {
        return Err(format!(
            "dimension = {}: a problem in space has dimension = 3 (a planar problem has `plane` instead)",
            problem.dimension
        ));
    }
    if problem.bodies.is_empty() {
        return Err("no [[bodies]]".into());
    }
    let names: Vec<&str> = problem.bodies.iter().map(|b| b.name.as_str()).collect();
    for (i, name) in names.iter().enumerate() {
        if let Some(why) = name_problem(name) {
            return Err(format!("body name {}: {why}", shown(name)));
        }
        if names[..i].contains(name) {
            return Err(format!("two bodies are called '{}'", shown(name)));
        }
    }
    let bodies = (problem.bodies.par_iter())
        .map(|b| {
            build_body(&problem, b, base).map_err(|e| format!("body '{}': {e}", shown(&b.name)))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let pairs = (problem.contact.iter())
        .map(|c| {
            resolve_pair(c, &bodies)
                .map_err(|e| format!("contact '{}': {e}", shown(&c.pair_name())))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let balance_tol = problem.solver.balance_tol.unwrap_or(SOLID_BALANCE_TOL);
    if !(balance_tol.is_finite() && balance_tol > 0.0) {
        return Err(format!(
            "solver.balance-tol = {balance_tol}: must be positive"
        ));
    }
    if problem.solver.threads == Some(0) {
        return Err("solver.threads = 0: must be at least 1".into());
    }
    let load_factors = match &problem.solver.load_steps {
        Some(spec) => load_steps(spec).map_err(|e| e.to_string())?,
        None => vec![1.0],
    };
    let monitor = (problem.solver.monitor.as_ref())
        .map(|m| solid_monitor(m, &bodies))
        .transpose()?;
    Ok(SolidModel {
        name: problem.name.clone().unwrap_or_else(|| stem.to_string()),
        units: problem.units.clone(),
        bodies,
        pairs,
        balance_tol,
        threads: problem.solver.threads,
        load_factors,
        monitor,
        output: problem.output,
    })
}

/// The body and face of `monitor`, which must exist.
fn solid_monitor(m: &MonitorSpec, bodies: &[SolidBodyModel]) -> Result<(usize, String), String> {
    let body = (bodies.iter())
        .position(|b| b.name == m.body)
        .ok_or_else(|| format!("solver.monitor: no body named '{}'", shown(&m.body)))?;
    bodies[body]
        .mesh
        .face(&m.boundary)
        .map_err(|e| format!("solver.monitor: body '{}': {e}", shown(&m.body)))?;
    Ok((body, m.boundary.clone()))
}

/// Meshes body `b` and assembles its supports and loads.
fn build_body(
    problem: &SolidProblem,
    b: &SolidBodyEntry,
    base: &Path,
) -> Result<SolidBodyModel, String> {
    let spec = problem
        .materials
        .get(&b.material)
        .ok_or_else(|| format!("no material '{}' in [materials]", shown(&b.material)))?;
    let material = Material::new(spec.young, spec.poisson)
        .map_err(|e| format!("material '{}': {e}", shown(&b.material)))?;
    let mesh = build_mesh(&b.mesh, base)?;
    let mut c = constraints(&mesh);
    for s in &b.supports {
        if !s.value.is_finite() {
            return Err(format!(
                "support on '{}': the value is not finite",
                shown(&s.boundary)
            ));
        }
        let axes: &[Axis] = match s.component {
            SolidComponent::X => &[Axis::X],
            SolidComponent::Y => &[Axis::Y],
            SolidComponent::Z => &[Axis::Z],
            SolidComponent::All => &Axis::ALL,
        };
        fix(&mut c, &mesh, &s.boundary, axes, s.value).map_err(|e| format!("support: {e}"))?;
    }
    let mut load = vec![0.0; num_dofs(mesh.num_nodes())];
    for l in &b.loads {
        let added = match l {
            SolidLoadSpec::Pressure { boundary, value } => {
                let p = *value;
                add_face_traction(&mesh, boundary, |_, n| n.map(|c| -p * c), &mut load)
            }
            SolidLoadSpec::Traction { boundary, value } => {
                add_face_traction(&mesh, boundary, |_, _| *value, &mut load)
            }
            SolidLoadSpec::BodyForce { value } => add_body_force(&mesh, |_| *value, &mut load),
        };
        added.map_err(|e| format!("load: {e}"))?;
    }
    Ok(SolidBodyModel {
        name: b.name.clone(),
        material,
        prescribed: c.fixed().collect(),
        load,
        mesh,
    })
}

/// The mesh a body's `mesh` table describes.
fn build_mesh(spec: &SolidMeshSpec, base: &Path) -> Result<SolidMesh, String> {
    match spec {
        SolidMeshSpec::Box {
            x,
            y,
            z,
            nx,
            ny,
            nz,
            order,
        } => {
            let ranges = [x, y, z];
            if let Some(axis) = (0..3).find(|&a| {
                let [lo, hi] = *ranges[a];
                !(lo.is_finite() && hi.is_finite() && hi > lo)
            }) {
                return Err(format!(
                    "mesh: the {} range {:?} is empty or not finite",
                    ["x", "y", "z"][axis],
                    ranges[axis]
                ));
            }
            let mesh = BoxMesh {
                origin: [x[0], y[0], z[0]],
                size: [x[1] - x[0], y[1] - y[0], z[1] - z[0]],
                cells: [*nx, *ny, *nz],
                order: match order {
                    Order::P1 => TetOrder::P1,
                    Order::P2 => TetOrder::P2,
                },
            };
            mesh.mesh().map_err(|e| format!("mesh: {e}"))
        }
        SolidMeshSpec::Inline {
            nodes,
            tetrahedra,
            faces,
        } => inline_mesh(nodes, tetrahedra, faces),
        SolidMeshSpec::Gmsh {
            file,
            volume,
            translate,
            scale,
        } => {
            let path: PathBuf = base.join(file);
            let mesh = contactdd_core::gmsh::read_solid_msh(&path, volume.as_deref())
                .map_err(|e| format!("mesh file '{}': {e}", path.display()))?;
            let s = scale.unwrap_or(1.0);
            let t = translate.unwrap_or([0.0; 3]);
            if !(s.is_finite() && s > 0.0) || t.iter().any(|v| !v.is_finite()) {
                return Err("mesh: scale must be positive and translate finite".into());
            }
            if s == 1.0 && t == [0.0; 3] {
                return Ok(mesh);
            }
            let nodes = mesh
                .nodes()
                .iter()
                .map(|p| std::array::from_fn(|c| s * p[c] + t[c]));
            mesh.with_nodes(nodes.collect())
                .map_err(|e| format!("mesh: {e}"))
        }
    }
}

/// A mesh given in the file: every tetrahedron of 4 or every one of 10 nodes, faces of 3 or 6.
fn inline_mesh(
    nodes: &[[f64; 3]],
    tetrahedra: &[Vec<usize>],
    faces: &std::collections::BTreeMap<String, Vec<Vec<usize>>>,
) -> Result<SolidMesh, String> {
    let order = match tetrahedra.first().map(Vec::len) {
        Some(4) => TetOrder::P1,
        Some(10) => TetOrder::P2,
        Some(n) => return Err(format!("mesh: a tetrahedron has 4 or 10 nodes, not {n}")),
        None => return Err("mesh: no tetrahedra".into()),
    };
    let (npt, npf) = (order.nodes_per_tet(), order.nodes_per_face());
    if let Some(e) = tetrahedra.iter().position(|t| t.len() != npt) {
        return Err(format!(
            "mesh: tetrahedron {e} has {} nodes, the first has {npt}",
            tetrahedra[e].len()
        ));
    }
    let mut named = Vec::with_capacity(faces.len());
    for (name, triangles) in faces {
        if let Some(t) = triangles.iter().position(|t| t.len() != npf) {
            return Err(format!(
                "mesh: face '{}': triangle {t} has not {npf} nodes",
                shown(name)
            ));
        }
        named.push((name.clone(), triangles.concat()));
    }
    SolidMesh::new(nodes.to_vec(), order, tetrahedra.concat(), named)
        .map_err(|e| format!("mesh: {e}"))
}

/// The pair `c` over the built `bodies`.
fn resolve_pair(c: &SolidContactSpec, bodies: &[SolidBodyModel]) -> Result<SolidPairModel, String> {
    if c.bodies.len() != 2 || c.boundaries.len() != 2 {
        return Err("`bodies` and `boundaries` must each name exactly two".into());
    }
    let index = |name: &str| {
        bodies
            .iter()
            .position(|b| b.name == name)
            .ok_or_else(|| format!("no body '{}'", shown(name)))
    };
    let (a, b) = (index(&c.bodies[0])?, index(&c.bodies[1])?);
    if a == b {
        return Err("a pair needs two different bodies".into());
    }
    for (body, face) in [(a, &c.boundaries[0]), (b, &c.boundaries[1])] {
        bodies[body]
            .mesh
            .face(face)
            .map_err(|e| format!("body '{}': {e}", shown(&bodies[body].name)))?;
    }
    let theta = penalty_theta(&c.penalty, &bodies[a].material, &bodies[b].material)?;
    let smaller = bodies[a]
        .mesh
        .bounding_box_diameter()
        .min(bodies[b].mesh.bounding_box_diameter());
    let search = c.search.unwrap_or(0.1 * smaller);
    if !(search.is_finite() && search > 0.0) {
        return Err(format!("search = {search}: must be positive"));
    }
    Ok(SolidPairModel {
        name: c.pair_name(),
        sides: [(a, c.boundaries[0].clone()), (b, c.boundaries[1].clone())],
        theta,
        search,
        enforcement: c.enforcement.map(Into::into).unwrap_or_default(),
        friction: match &c.friction {
            Some(spec) => friction_law(spec).map_err(|(key, m)| format!("{key}: {m}"))?,
            None => contactdd_ddm::Friction::None,
        },
    })
}

/// θ of a pair: given, or the rod model c·h·(1/E*₁ + 1/E*₂) with E* = E/(1 − ν²).
fn penalty_theta(p: &PenaltySpec, m1: &Material, m2: &Material) -> Result<f64, String> {
    let positive = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(format!("penalty.{name} = {v}: must be positive"))
        }
    };
    let star = |m: &Material| m.young() / (1.0 - m.poisson() * m.poisson());
    match (p.theta, p.c, p.h) {
        (Some(t), None, None) => positive("theta", t),
        (None, Some(c), Some(h)) => {
            Ok(positive("c", c)? * positive("h", h)? * (1.0 / star(m1) + 1.0 / star(m2)))
        }
        _ => Err("penalty: give either `theta`, or both `c` and `h`".into()),
    }
}
