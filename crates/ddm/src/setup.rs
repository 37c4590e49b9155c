//! From a problem file to solver input, in one resolve step.
//!
//! [`load_file`] reads a TOML file, [`load_str`] parses text, and both hand the parsed
//! [`Problem`] to [`resolve`], which validates every value and builds the [`Model`] (meshes,
//! materials, supports, load vectors, contact pairs) and the iteration [`Settings`]. Nothing is
//! solved or factorised here; [`crate::prepare`] does that.
//!
//! Every error names what it is about: the file (for [`load_file`] and [`load_str`], wrapped in
//! [`SetupError::InFile`]), the body, pair or material, and the key, e.g.
//! `problem.toml: body 'lower': supports[0]: no boundary named 'rigth' (known: bottom, left,
//! right, top)`. Parse errors carry the toml crate's message with line, column and the offending
//! line. No input makes this module panic.
//!
//! Resolution rules:
//! - a rectangle mesh is built by [`Rectangle::mesh`], a Gmsh file is read by
//!   [`contactdd_core::gmsh::read_msh`] (relative paths against `base_dir`), scaled, translated
//!   and, with `order = "p2"`, promoted by [`Mesh::to_p2`];
//! - supports are applied in file order by [`Constraints::fix`] (a DOF fixed twice keeps the last
//!   value), all loads of a body form one load vector ([`contactdd_core::loads::load_vector`]);
//! - a penalty `{ c, h }` is the rod model θ = c·h·(1/E*₁ + 1/E*₂), `{ theta }` is θ itself;
//! - absent `[solver]` keys take the values of [`Settings::default`].

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use contactdd_core::{
    BodyError, Constraints, ElasticBody, Load, Material, MaterialError, Mesh, Order, Plane,
    Rectangle,
};

use crate::error::SetupError;
use crate::iteration::Settings;
use crate::model::{ContactPair, Model, Penalty};
use crate::problem::{
    BodySpec, ContactSpec, GammaSpec, GapSpec, LoadSpec, MeshSpec, PenaltySpec, Problem, SolverSpec,
};
use crate::profile::GapProfile;
use crate::relaxation::Gamma;

/// Largest number of rectangle cells (nx · ny) per body: far beyond what the solver handles, but it
/// keeps absurd inputs from exhausting memory while allocating the mesh.
pub const MAX_RECTANGLE_CELLS: usize = 4_000_000;

/// A resolved problem: the file's data and the solver input built from it.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The problem as read.
    pub problem: Problem,
    /// Bodies and contact pairs.
    pub model: Model,
    /// Iteration settings.
    pub settings: Settings,
    /// Requested number of worker threads (`None`: the machine's).
    pub threads: Option<usize>,
}

/// Reads, parses and resolves a TOML problem file. Relative mesh paths resolve against the file's
/// folder; the default problem name is the file stem.
pub fn load_file(path: &Path) -> Result<Loaded, SetupError> {
    let text = std::fs::read_to_string(path).map_err(|source| SetupError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let base_dir = path.parent().unwrap_or(Path::new(""));
    load_str(&text, &path.display().to_string(), base_dir)
}

/// Parses and resolves the text of a problem file. `source` names the file in messages (and its
/// stem is the default problem name); relative mesh paths resolve against `base_dir`.
pub fn load_str(text: &str, source: &str, base_dir: &Path) -> Result<Loaded, SetupError> {
    let problem: Problem = toml::from_str(text)
        .map_err(|e| SetupError::Toml(format!("{source}: {}", e.to_string().trim_end())))?;
    let stem = Path::new(source)
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty())
        .unwrap_or("problem");
    resolve_named(problem, base_dir, stem).map_err(|error| SetupError::InFile {
        file: source.to_string(),
        error: Box::new(error),
    })
}

/// Validates a parsed problem and builds the model and settings. Relative mesh paths resolve
/// against `base_dir`; without a `name` the problem is called `"problem"`.
pub fn resolve(problem: Problem, base_dir: &Path) -> Result<Loaded, SetupError> {
    resolve_named(problem, base_dir, "problem")
}

fn resolve_named(
    problem: Problem,
    base_dir: &Path,
    default_name: &str,
) -> Result<Loaded, SetupError> {
    let (settings, threads) = settings(&problem.solver)?;
    if problem.bodies.is_empty() {
        return Err(SetupError::Invalid {
            key: "bodies".into(),
            message: "the problem has no bodies (add a [[bodies]] table)".into(),
        });
    }
    let materials = materials(&problem)?;
    let mut index: HashMap<&str, usize> = HashMap::new();
    for (i, body) in problem.bodies.iter().enumerate() {
        if body.name.trim().is_empty() {
            return Err(SetupError::Invalid {
                key: format!("bodies[{i}].name"),
                message: "a body name must not be empty".into(),
            });
        }
        if let Some(j) = index.insert(&body.name, i) {
            return Err(body_error(
                &body.name,
                "name",
                format!("the name is used by both bodies[{j}] and bodies[{i}]"),
            ));
        }
    }
    let bodies = problem
        .bodies
        .iter()
        .map(|spec| body(spec, &materials, problem.plane, base_dir))
        .collect::<Result<Vec<_>, _>>()?;
    let mut pairs: Vec<ContactPair> = Vec::with_capacity(problem.contact.len());
    for (i, spec) in problem.contact.iter().enumerate() {
        let pair = pair(spec, &index, &bodies, problem.plane)?;
        if let Some(j) = pairs.iter().position(|p| p.name == pair.name) {
            return Err(pair_error(
                &pair.name,
                "name",
                format!(
                    "the name is used by both contact[{j}] and contact[{i}]; give each pair its \
                     own name"
                ),
            ));
        }
        pairs.push(pair);
    }
    for (b, (spec, body)) in problem.bodies.iter().zip(&bodies).enumerate() {
        let in_contact = pairs.iter().any(|p| p.bodies.contains(&b));
        if in_contact {
            continue;
        }
        if spec.supports.is_empty() {
            return Err(SetupError::Floating {
                body: spec.name.clone(),
            });
        }
        // Without contact the supports alone must hold the body.
        if let Err(BodyError::Floating {
            modes, description, ..
        }) = body.check_held(&[])
        {
            return Err(body_error(
                &spec.name,
                "supports",
                format!(
                    "the body has no contact pair and its supports leave {modes} rigid-body \
                     mode(s) free ({description}): it would float"
                ),
            ));
        }
    }
    let name = problem
        .name
        .clone()
        .unwrap_or_else(|| default_name.to_string());
    Ok(Loaded {
        model: Model {
            name,
            plane: problem.plane,
            bodies,
            pairs,
        },
        settings,
        threads,
        problem,
    })
}

fn body_error(body: &str, key: &str, message: impl std::fmt::Display) -> SetupError {
    SetupError::Body {
        body: body.to_string(),
        message: format!("{key}: {message}"),
    }
}

fn pair_error(pair: &str, key: &str, message: impl std::fmt::Display) -> SetupError {
    SetupError::Pair {
        pair: pair.to_string(),
        message: format!("{key}: {message}"),
    }
}

fn solver_error(key: &str, message: impl std::fmt::Display) -> SetupError {
    SetupError::Solver(format!("{key}: {message}"))
}

/// `[solver]` → settings and thread count.
fn settings(spec: &SolverSpec) -> Result<(Settings, Option<usize>), SetupError> {
    let defaults = Settings::default();
    let gamma = match spec.gamma {
        None => defaults.gamma,
        Some(GammaSpec::Auto) => Gamma::Auto,
        Some(GammaSpec::Value(g)) => {
            if !(g.is_finite() && g > 0.0) {
                return Err(solver_error(
                    "gamma",
                    format!("must be a positive number or \"auto\", got {g}"),
                ));
            }
            Gamma::Constant(g)
        }
    };
    let tol = spec.tol.unwrap_or(defaults.tol);
    if !(tol.is_finite() && tol > 0.0) {
        return Err(solver_error(
            "tol",
            format!("must be a positive number, got {tol}"),
        ));
    }
    let max_iter = spec.max_iter.unwrap_or(defaults.max_iter);
    if max_iter == 0 {
        return Err(solver_error("max-iter", "must be at least 1, got 0"));
    }
    let u0 = spec.u0.unwrap_or(defaults.u0);
    let u_prev = spec.u_prev.unwrap_or(defaults.u_prev);
    for (key, v) in [("u0", u0), ("u-prev", u_prev)] {
        if !v.is_finite() {
            return Err(solver_error(key, format!("must be finite, got {v}")));
        }
    }
    if spec.threads == Some(0) {
        return Err(solver_error("threads", "must be at least 1, got 0"));
    }
    let settings = Settings {
        method: spec.method.unwrap_or(defaults.method),
        gamma,
        tol,
        max_iter,
        u0,
        u_prev,
    };
    Ok((settings, spec.threads))
}

/// `[materials]` → validated materials.
fn materials(problem: &Problem) -> Result<BTreeMap<String, Material>, SetupError> {
    problem
        .materials
        .iter()
        .map(|(name, m)| {
            Material::new(m.young, m.poisson)
                .map(|mat| (name.clone(), mat))
                .map_err(|e| {
                    let key = match e {
                        MaterialError::YoungModulus(_) => "young",
                        MaterialError::PoissonRatio(_) => "poisson",
                    };
                    SetupError::Material {
                        material: name.clone(),
                        message: format!("{key}: {e}"),
                    }
                })
        })
        .collect()
}

/// One `[[bodies]]` entry → an elastic body.
fn body(
    spec: &BodySpec,
    materials: &BTreeMap<String, Material>,
    plane: Plane,
    base_dir: &Path,
) -> Result<ElasticBody, SetupError> {
    let name = spec.name.as_str();
    let material = *materials.get(&spec.material).ok_or_else(|| {
        body_error(
            name,
            "material",
            format!(
                "unknown material '{}' (known: {})",
                spec.material,
                known(materials.keys())
            ),
        )
    })?;
    let mesh = mesh(name, &spec.mesh, base_dir)?;
    let mut constraints = Constraints::new(mesh.num_nodes());
    for (i, s) in spec.supports.iter().enumerate() {
        constraints
            .fix(&mesh, &s.boundary, s.component, s.value)
            .map_err(|e| body_error(name, &format!("supports[{i}]"), e))?;
    }
    let mut loads = Vec::with_capacity(spec.loads.len());
    for (i, l) in spec.loads.iter().enumerate() {
        let key = format!("loads[{i}]");
        let (load, values): (Load, Vec<f64>) = match l {
            LoadSpec::Pressure { boundary, value } => (
                Load::Pressure {
                    boundary: boundary.clone(),
                    value: *value,
                },
                vec![*value],
            ),
            LoadSpec::Traction { boundary, value } => (
                Load::Traction {
                    boundary: boundary.clone(),
                    value: *value,
                },
                value.to_vec(),
            ),
            LoadSpec::BodyForce { value } => (Load::BodyForce(*value), value.to_vec()),
        };
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return Err(body_error(
                name,
                &format!("{key}.value"),
                format!("must be finite, got {v}"),
            ));
        }
        if let LoadSpec::Pressure { boundary, .. } | LoadSpec::Traction { boundary, .. } = l {
            mesh.boundary(boundary)
                .map_err(|e| body_error(name, &format!("{key}.boundary"), e))?;
        }
        loads.push(load);
    }
    let load = contactdd_core::loads::load_vector(&mesh, &loads)
        .map_err(|e| body_error(name, "loads", e))?;
    Ok(ElasticBody {
        name: name.to_string(),
        mesh,
        material,
        plane,
        constraints,
        load,
    })
}

/// A body's `mesh` table → a validated mesh.
fn mesh(body: &str, spec: &MeshSpec, base_dir: &Path) -> Result<Mesh, SetupError> {
    match spec {
        MeshSpec::Rectangle {
            x,
            y,
            nx,
            ny,
            diagonal,
            mirror,
            order,
        } => {
            for (key, n) in [("mesh.nx", nx), ("mesh.ny", ny)] {
                if *n == 0 {
                    return Err(body_error(body, key, "must be at least 1, got 0"));
                }
            }
            if !matches!(nx.checked_mul(*ny), Some(c) if c <= MAX_RECTANGLE_CELLS) {
                return Err(body_error(
                    body,
                    "mesh",
                    format!("{nx} × {ny} cells is more than the limit of {MAX_RECTANGLE_CELLS}"),
                ));
            }
            for (key, r) in [("mesh.x", x), ("mesh.y", y)] {
                if !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]) {
                    return Err(body_error(
                        body,
                        key,
                        format!(
                            "need a finite range [min, max] with min < max, got [{}, {}]",
                            r[0], r[1]
                        ),
                    ));
                }
            }
            Rectangle {
                origin: [x[0], y[0]],
                corner: [x[1], y[1]],
                nx: *nx,
                ny: *ny,
                diagonal: *diagonal,
                mirror: *mirror,
                order: *order,
            }
            .mesh()
            .map_err(|e| body_error(body, "mesh", e))
        }
        MeshSpec::Gmsh {
            file,
            order,
            translate,
            scale,
        } => {
            let scale = scale.unwrap_or(1.0);
            if !(scale.is_finite() && scale > 0.0) {
                return Err(body_error(
                    body,
                    "mesh.scale",
                    format!("must be a positive number, got {scale}"),
                ));
            }
            let shift = translate.unwrap_or([0.0, 0.0]);
            if !(shift[0].is_finite() && shift[1].is_finite()) {
                return Err(body_error(
                    body,
                    "mesh.translate",
                    format!("must be finite, got [{}, {}]", shift[0], shift[1]),
                ));
            }
            let path: PathBuf = if file.is_absolute() {
                file.clone()
            } else {
                base_dir.join(file)
            };
            let mut mesh =
                contactdd_core::gmsh::read_msh(&path).map_err(|source| SetupError::Gmsh {
                    body: body.to_string(),
                    path: path.display().to_string(),
                    source,
                })?;
            if scale != 1.0 || shift != [0.0, 0.0] {
                mesh = mesh
                    .map_nodes(|p| [scale * p[0] + shift[0], scale * p[1] + shift[1]])
                    .map_err(|e| body_error(body, "mesh", e))?;
            }
            match (order, mesh.order()) {
                (Some(Order::P2), Order::P1) => Ok(mesh.to_p2()),
                (Some(Order::P1), Order::P2) => Err(body_error(
                    body,
                    "mesh.order",
                    format!(
                        "'{}' has P2 triangles; they cannot be read as p1 (use order = \"p2\" or \
                         leave order out)",
                        path.display()
                    ),
                )),
                _ => Ok(mesh),
            }
        }
    }
}

/// One `[[contact]]` entry → a contact pair.
fn pair(
    spec: &ContactSpec,
    index: &HashMap<&str, usize>,
    bodies: &[ElasticBody],
    plane: Plane,
) -> Result<ContactPair, SetupError> {
    let name = spec
        .name
        .clone()
        .unwrap_or_else(|| format!("{}-{}", spec.bodies[0], spec.bodies[1]));
    let mut ids = [0usize; 2];
    for (s, body) in spec.bodies.iter().enumerate() {
        ids[s] = *index.get(body.as_str()).ok_or_else(|| {
            let mut names: Vec<&str> = index.keys().copied().collect();
            names.sort_unstable();
            pair_error(
                &name,
                &format!("bodies[{s}]"),
                format!("unknown body '{body}' (known: {})", names.join(", ")),
            )
        })?;
    }
    if ids[0] == ids[1] {
        return Err(pair_error(
            &name,
            "bodies",
            format!(
                "names body '{}' twice; a contact pair needs two different bodies",
                spec.bodies[0]
            ),
        ));
    }
    for s in 0..2 {
        let body = &bodies[ids[s]];
        body.mesh.boundary(&spec.boundaries[s]).map_err(|e| {
            pair_error(
                &name,
                &format!("boundaries[{s}]"),
                format!("body '{}': {e}", body.name),
            )
        })?;
    }
    let penalty = penalty(&name, &spec.penalty)?;
    let (a, b) = (&bodies[ids[0]], &bodies[ids[1]]);
    let theta = penalty.theta(plane, &a.material, &b.material);
    if !(theta.is_finite() && theta > 0.0) {
        return Err(pair_error(
            &name,
            "penalty",
            format!("θ = {theta} is not a positive finite number"),
        ));
    }
    let profile = spec
        .gap
        .as_ref()
        .map(|g| gap_profile(&name, g))
        .transpose()?;
    Ok(ContactPair {
        name,
        bodies: ids,
        boundaries: spec.boundaries.clone(),
        penalty,
        profile,
    })
}

fn penalty(pair: &str, spec: &PenaltySpec) -> Result<Penalty, SetupError> {
    let positive = |key: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(pair_error(
                pair,
                &format!("penalty.{key}"),
                format!("must be a positive finite number, got {v}"),
            ))
        }
    };
    match (spec.theta, spec.c, spec.h) {
        (Some(theta), None, None) => Ok(Penalty::Theta(positive("theta", theta)?)),
        (None, Some(c), Some(h)) => Ok(Penalty::RodModel {
            c: positive("c", c)?,
            h: positive("h", h)?,
        }),
        (Some(_), _, _) => Err(pair_error(
            pair,
            "penalty",
            "give either theta, or c and h (rod model), not both",
        )),
        (None, None, None) => Err(pair_error(
            pair,
            "penalty",
            "give either theta = θ or c and h (rod model θ = c·h·(1/E*₁ + 1/E*₂))",
        )),
        (None, _, _) => Err(pair_error(
            pair,
            "penalty",
            "the rod model needs both c and h",
        )),
    }
}

fn gap_profile(pair: &str, spec: &GapSpec) -> Result<GapProfile, SetupError> {
    let check = |key: &str, v: f64, positive: bool| {
        if v.is_finite() && (!positive || v > 0.0) {
            Ok(v)
        } else {
            let what = if positive {
                "a positive finite number"
            } else {
                "finite"
            };
            Err(pair_error(
                pair,
                &format!("gap.{key}"),
                format!("must be {what}, got {v}"),
            ))
        }
    };
    Ok(match *spec {
        GapSpec::Notch {
            r0,
            b,
            centre,
            power,
            along,
        } => GapProfile::Notch {
            r0: check("r0", r0, false)?,
            b: check("b", b, true)?,
            centre: check("centre", centre, false)?,
            power: check("power", power, true)?,
            along,
        },
        GapSpec::Uniform { value } => GapProfile::Uniform {
            value: check("value", value, false)?,
        },
    })
}

fn known<'a>(names: impl Iterator<Item = &'a String>) -> String {
    let names: Vec<&str> = names.map(String::as_str).collect();
    if names.is_empty() {
        "none; add a [materials.NAME] table".into()
    } else {
        names.join(", ")
    }
}
