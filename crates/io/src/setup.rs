//! From a problem file to solver input, in one resolve step.
//!
//! [`load_file`] reads a TOML file, [`load_str`] parses text, and both hand the parsed
//! [`Problem`] to [`resolve`], which validates every value and builds the [`Model`] (meshes,
//! materials, supports, load vectors, contact pairs) and the iteration [`Settings`]. Nothing is
//! solved or factorised here; `contactdd_ddm::prepare` does that.
//!
//! Every error names what it is about: the file (for [`load_file`] and [`load_str`], wrapped in
//! [`LoadError::InFile`]), the body, pair or material, and the key, e.g.
//! `problem.toml: body 'lower': supports[0]: no boundary named 'rigth' (known: bottom, left,
//! right, top)`. Parse errors carry the toml crate's message with line, column and the offending
//! line. No input makes this module panic.
//!
//! Resolution rules:
//! - a rectangle mesh is built by [`Rectangle::mesh`], a Gmsh file is read by
//!   [`contactdd_core::gmsh::read_msh_surface`] (relative paths against `base_dir`), scaled, translated
//!   and, with `order = "p2"`, promoted by [`Mesh::to_p2`];
//! - supports are applied in file order by [`Constraints::fix`] (a DOF fixed twice keeps the last
//!   value), all loads of a body form one load vector ([`contactdd_core::loads::load_vector`]);
//! - a penalty `{ c, h }` is the rod model θ = c·h·(1/E*₁ + 1/E*₂), `{ theta }` is θ itself;
//! - absent `[solver]` keys take the values of [`Settings::default`].
//!
//! [`resolve`] builds the model one entry at a time with a [`ModelBuilder`]; a problem built in
//! code (the Python module) uses the same builder, so it gets the same validation and the same
//! messages as a file. The checks of single entries are public too ([`material`],
//! [`check_body_name`], [`mesh`], [`mesh_from_arrays`], [`body_on_mesh`], [`pair`], [`settings`],
//! [`gamma`], [`check_floating`]).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use contactdd_core::{
    BodyError, Constraints, Edge, ElasticBody, Layout, Load, Material, Mesh, MeshError, Order,
    Plane, Point, Rectangle, DIM,
};

use contactdd_core::gmsh::read_msh_surface;
use contactdd_ddm::exchange::Exchange;
use contactdd_ddm::iteration::ANDERSON_DEPTH;
use contactdd_ddm::steps::{check_factors, equal_steps};
use contactdd_ddm::{
    Accelerator, CoarseMode, ContactPair, Gamma, GapProfile, Model, Penalty, Remote, Settings,
    SetupError,
};

use crate::error::LoadError;
use crate::number::format_f64 as num;
use crate::problem::{
    AcceleratorSpec, BodySpec, CoarseSpec, ContactSpec, GammaSpec, GapSpec, LoadSpec,
    LoadStepsSpec, MaterialSpec, MeshSpec, MonitorSpec, PenaltySpec, Problem, SolverSpec,
    SupportSpec,
};

/// Largest number of rectangle cells (nx · ny) per body: far beyond what the solver handles, but it
/// keeps absurd inputs from exhausting memory while allocating the mesh.
pub const MAX_RECTANGLE_CELLS: usize = 4_000_000;

/// Most worker threads a problem file (`solver.threads`) or the command line (`--threads`) may ask
/// for: more than any machine this runs on, low enough that a typo cannot make the thread pool
/// exhaust the system.
pub const MAX_THREADS: usize = 1024;

/// The most load steps a file may ask for: each writes a set of VTU files.
pub const MAX_LOAD_STEPS: usize = 10_000;

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
    /// The load factors of the load steps (`None`: one solve at the full load).
    pub steps: Option<Vec<f64>>,
    /// The boundary whose mean displacement the load steps report.
    pub monitor: Option<Monitor>,
}

/// A boundary of a body, by index and name (checked to exist).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Monitor {
    /// Body index.
    pub body: usize,
    /// Boundary name.
    pub boundary: String,
}

/// Reads, parses and resolves a TOML problem file. Relative mesh paths resolve against the file's
/// folder; the default problem name is the file stem.
pub fn load_file(path: &Path) -> Result<Loaded, LoadError> {
    read_problem(path)?.resolve()
}

/// Parses and resolves the text of a problem file. `source` names the file in messages (and its
/// stem is the default problem name); relative mesh paths resolve against `base_dir`.
pub fn load_str(text: &str, source: &str, base_dir: &Path) -> Result<Loaded, LoadError> {
    parse_problem(text, source, base_dir)?.resolve()
}

/// A parsed problem file whose bodies are not built yet.
#[derive(Clone, Debug)]
pub struct ProblemFile {
    /// The problem as read.
    pub problem: Problem,
    /// The file's name, for messages (its stem is the default problem name).
    pub source: String,
    /// The folder relative mesh paths resolve against.
    pub base_dir: PathBuf,
}

/// Reads and parses a TOML problem file.
pub fn read_problem(path: &Path) -> Result<ProblemFile, LoadError> {
    let text = std::fs::read_to_string(path).map_err(|source| LoadError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let base_dir = path.parent().unwrap_or(Path::new(""));
    parse_problem(&text, &path.display().to_string(), base_dir)
}

fn parse_problem(text: &str, source: &str, base_dir: &Path) -> Result<ProblemFile, LoadError> {
    let problem: Problem = toml::from_str(text).map_err(|e| LoadError::Toml {
        file: source.to_string(),
        source: e,
    })?;
    Ok(ProblemFile {
        problem,
        source: source.to_string(),
        base_dir: base_dir.to_path_buf(),
    })
}

impl ProblemFile {
    /// Builds the model and settings, every body in this process.
    pub fn resolve(self) -> Result<Loaded, LoadError> {
        self.resolve_with(None)
    }

    /// Builds the model and settings on one process of a distributed solve (docs/mpi.md): it
    /// meshes only the bodies `exchange` gives it and holds the others as their contact skins
    /// ([`contactdd_ddm::Remote`]). A collective; an error of any process is every process's.
    pub fn resolve_on(self, exchange: &dyn Exchange) -> Result<Loaded, LoadError> {
        self.resolve_with(Some(exchange))
    }

    fn resolve_with(self, exchange: Option<&dyn Exchange>) -> Result<Loaded, LoadError> {
        let stem = Path::new(&self.source)
            .file_stem()
            .and_then(|s| s.to_str())
            .filter(|s| !s.is_empty())
            .unwrap_or("problem")
            .to_string();
        let source = self.source;
        resolve_named(self.problem, &self.base_dir, &stem, exchange).map_err(|error| {
            LoadError::InFile {
                file: source,
                error: Box::new(error),
            }
        })
    }
}

/// Validates a parsed problem and builds the model and settings. Relative mesh paths resolve
/// against `base_dir`; without a `name` the problem is called `"problem"`.
pub fn resolve(problem: Problem, base_dir: &Path) -> Result<Loaded, LoadError> {
    resolve_named(problem, base_dir, "problem", None)
}

fn resolve_named(
    problem: Problem,
    base_dir: &Path,
    default_name: &str,
    exchange: Option<&dyn Exchange>,
) -> Result<Loaded, LoadError> {
    let settings = settings(&problem.solver, &Settings::default())?;
    // Checked before the materials and bodies so that an empty file gets this message first.
    if problem.bodies.is_empty() {
        return Err(no_bodies().into());
    }
    let mut builder = ModelBuilder::new(problem.plane);
    for (name, m) in &problem.materials {
        builder.add_material(name, m)?;
    }
    // Every name is checked before any mesh is built (a duplicate name is reported even when an
    // earlier body's mesh is also wrong).
    for (i, body) in problem.bodies.iter().enumerate() {
        check_body_name(
            &body.name,
            problem.bodies[..i].iter().map(|b| b.name.as_str()),
        )?;
    }
    let Some(exchange) = exchange else {
        for spec in &problem.bodies {
            builder.add_body(spec, base_dir)?;
        }
        return finish(builder, problem, settings, default_name);
    };
    // Every process reaches the agreement below, whatever failed on it: each checked the
    // supports of its own bodies only, and a body may arrive damaged on one process alone.
    let rest = crate::shared_setup::add_bodies(&mut builder, &problem, base_dir, exchange)
        .and_then(|()| finish(builder, problem, settings, default_name));
    crate::shared_setup::agreed(exchange, rest)
}

/// The pairs, the model and the settings that depend on it.
fn finish(
    mut builder: ModelBuilder,
    problem: Problem,
    settings: Settings,
    default_name: &str,
) -> Result<Loaded, LoadError> {
    for spec in &problem.contact {
        builder.add_pair(spec)?;
    }
    let name = problem
        .name
        .clone()
        .unwrap_or_else(|| default_name.to_string());
    let model = builder.into_model(&name)?;
    let settings = starting_values(settings, &problem.solver, &model);
    let steps = problem
        .solver
        .load_steps
        .as_ref()
        .map(load_steps)
        .transpose()?;
    let monitor = problem
        .solver
        .monitor
        .as_ref()
        .map(|m| monitor(&model, m))
        .transpose()?;
    Ok(Loaded {
        model,
        settings,
        threads: problem.solver.threads,
        steps,
        monitor,
        problem,
    })
}

/// The model's size: the longest side of the bounding box of every body's nodes.
pub fn model_size(model: &Model) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; DIM], [f64::NEG_INFINITY; DIM]);
    for (l, h) in (0..model.bodies.len()).map(|b| model.bounds(b)) {
        for d in 0..DIM {
            lo[d] = lo[d].min(l[d]);
            hi[d] = hi[d].max(h[d]);
        }
    }
    (hi[0] - lo[0]).max(hi[1] - lo[1])
}

/// `settings` with the starting values the `[solver]` table leaves out set relative to the
/// model's size L: u0 = L/20 000 and u-prev = L/10 000. An absolute default would make the
/// iteration depend on the length unit. The fractions give a model 2 units long the former
/// absolute defaults 1e-4 and 2e-4 (bit for bit), so the measured iteration counts of
/// `examples/hertz.toml` and `examples/stack.toml` stand; the notch benchmarks set the paper's
/// values explicitly.
fn starting_values(mut settings: Settings, spec: &SolverSpec, model: &Model) -> Settings {
    let size = model_size(model);
    if spec.u0.is_none() {
        settings.u0 = size / U0_FRACTION;
    }
    if spec.u_prev.is_none() {
        settings.u_prev = size / U_PREV_FRACTION;
    }
    settings
}

/// The model's size over the default u0.
const U0_FRACTION: f64 = 20_000.0;
/// The model's size over the default u-prev.
const U_PREV_FRACTION: f64 = 10_000.0;

/// The load factors of `load-steps`.
fn load_steps(spec: &LoadStepsSpec) -> Result<Vec<f64>, SetupError> {
    let factors = match spec {
        LoadStepsSpec::Count(0) => {
            return Err(solver_error("load-steps", "must be at least 1, got 0"))
        }
        LoadStepsSpec::Count(n) if *n > MAX_LOAD_STEPS => {
            return Err(solver_error(
                "load-steps",
                format!("at most {MAX_LOAD_STEPS} steps, got {n}"),
            ))
        }
        LoadStepsSpec::Count(n) => equal_steps(*n),
        LoadStepsSpec::Factors(f) if f.len() > MAX_LOAD_STEPS => {
            return Err(solver_error(
                "load-steps",
                format!("at most {MAX_LOAD_STEPS} steps, got {}", f.len()),
            ))
        }
        LoadStepsSpec::Factors(f) => f.clone(),
    };
    check_factors(&factors).map_err(|m| solver_error("load-steps", m))?;
    Ok(factors)
}

/// The body index of a `monitor`, whose boundary must exist.
fn monitor(model: &Model, spec: &MonitorSpec) -> Result<Monitor, SetupError> {
    let body = model
        .bodies
        .iter()
        .position(|b| b.name == spec.body)
        .ok_or_else(|| solver_error("monitor", format!("no body named '{}'", spec.body)))?;
    model.bodies[body]
        .mesh
        .boundary(&spec.boundary)
        .map_err(|e| solver_error("monitor", format!("body '{}': {e}", spec.body)))?;
    Ok(Monitor {
        body,
        boundary: spec.boundary.clone(),
    })
}

/// Builds a [`Model`] entry by entry, checking each entry as it is added: the one resolve step of
/// a problem file ([`resolve`]) and of a problem built in code (the Python module).
#[derive(Clone, Debug)]
pub struct ModelBuilder {
    plane: Plane,
    materials: BTreeMap<String, Material>,
    bodies: Vec<ElasticBody>,
    pairs: Vec<ContactPair>,
    /// Per body, its remote part where another process meshes it.
    remote: Vec<Option<Remote>>,
}

impl ModelBuilder {
    /// An empty model of plane strain or plane stress.
    pub fn new(plane: Plane) -> ModelBuilder {
        ModelBuilder {
            plane,
            materials: BTreeMap::new(),
            bodies: Vec::new(),
            pairs: Vec::new(),
            remote: Vec::new(),
        }
    }

    /// A builder holding an already built model (a benchmark built in code) and its named
    /// materials; later entries are checked against it.
    pub fn from_model(model: Model, materials: BTreeMap<String, Material>) -> ModelBuilder {
        ModelBuilder {
            plane: model.plane,
            materials,
            bodies: model.bodies,
            pairs: model.pairs,
            remote: model.remote,
        }
    }

    /// Plane strain or plane stress.
    pub fn plane(&self) -> Plane {
        self.plane
    }

    /// The materials by name.
    pub fn materials(&self) -> &BTreeMap<String, Material> {
        &self.materials
    }

    /// The bodies, in order.
    pub fn bodies(&self) -> &[ElasticBody] {
        &self.bodies
    }

    /// The contact pairs, in order.
    pub fn pairs(&self) -> &[ContactPair] {
        &self.pairs
    }

    /// Adds a `[materials.NAME]` table. (A file cannot define a name twice; code can, and is told.)
    pub fn add_material(&mut self, name: &str, spec: &MaterialSpec) -> Result<(), SetupError> {
        if self.materials.contains_key(name) {
            return Err(SetupError::Material {
                material: name.to_string(),
                message: "is already defined".into(),
            });
        }
        let m = material(name, spec.young, spec.poisson)?;
        self.materials.insert(name.to_string(), m);
        Ok(())
    }

    /// Checks the name of the next body (see [`check_body_name`]).
    pub fn check_body_name(&self, name: &str) -> Result<(), SetupError> {
        check_body_name(name, self.bodies.iter().map(|b| b.name.as_str()))
    }

    /// Adds a `[[bodies]]` entry: name, material, mesh (a relative Gmsh path resolves against
    /// `base_dir`), supports and loads.
    pub fn add_body(&mut self, spec: &BodySpec, base_dir: &Path) -> Result<(), LoadError> {
        self.check_body_name(&spec.name)?;
        let body = self.body(spec, base_dir)?;
        self.push_body(body, None);
        Ok(())
    }

    /// The body of a `[[bodies]]` entry, built but not added (its name is not checked).
    pub fn body(&self, spec: &BodySpec, base_dir: &Path) -> Result<ElasticBody, LoadError> {
        let name = spec.name.as_str();
        let material = self.material_of(name, &spec.material)?;
        let mesh = mesh(name, &spec.mesh, base_dir)?;
        Ok(body_on_mesh(
            name,
            mesh,
            material,
            self.plane,
            &spec.supports,
            &spec.loads,
        )?)
    }

    /// Adds a built body: a whole one, or the stand-in of a body another process meshes with
    /// its remote part.
    pub fn push_body(&mut self, body: ElasticBody, remote: Option<Remote>) {
        self.remote.resize(self.bodies.len(), None);
        self.bodies.push(body);
        self.remote.push(remote);
    }

    /// Adds a body on a mesh built by the caller (e.g. [`mesh_from_arrays`]), checked like a
    /// `[[bodies]]` entry.
    pub fn add_body_on_mesh(
        &mut self,
        name: &str,
        material: &str,
        mesh: Mesh,
        supports: &[SupportSpec],
        loads: &[LoadSpec],
    ) -> Result<(), SetupError> {
        self.check_body_name(name)?;
        let material = self.material_of(name, material)?;
        let body = body_on_mesh(name, mesh, material, self.plane, supports, loads)?;
        self.push_body(body, None);
        Ok(())
    }

    /// Adds a `[[contact]]` entry between two of the bodies added so far.
    pub fn add_pair(&mut self, spec: &ContactSpec) -> Result<(), SetupError> {
        let p = pair(spec, &self.bodies, &self.pairs)?;
        self.pairs.push(p);
        Ok(())
    }

    /// The model so far, checked as a whole: at least one body, and every body held (see
    /// [`check_floating`]).
    pub fn model(&self, name: &str) -> Result<Model, SetupError> {
        self.clone().into_model(name)
    }

    /// As [`ModelBuilder::model`], without copying the bodies.
    pub fn into_model(self, name: &str) -> Result<Model, SetupError> {
        if self.bodies.is_empty() {
            return Err(no_bodies());
        }
        let model = Model {
            name: name.to_string(),
            plane: self.plane,
            bodies: self.bodies,
            pairs: self.pairs,
            // Empty unless some body is remote.
            remote: match self.remote.iter().any(Option::is_some) {
                true => self.remote,
                false => Vec::new(),
            },
        };
        check_floating(&model)?;
        Ok(model)
    }

    /// The material `material` of body `body`.
    fn material_of(&self, body: &str, material: &str) -> Result<Material, SetupError> {
        self.materials.get(material).copied().ok_or_else(|| {
            body_error(
                body,
                "material",
                format!(
                    "unknown material '{material}' (known: {})",
                    known(self.materials.keys())
                ),
            )
        })
    }
}

fn no_bodies() -> SetupError {
    SetupError::Invalid {
        key: "bodies".into(),
        message: "the problem has no bodies; it needs at least one".into(),
    }
}

fn body_error(body: &str, key: &str, message: impl std::fmt::Display) -> SetupError {
    SetupError::Body {
        body: body.to_string(),
        message: format!("{key}: {message}"),
    }
}

fn mesh_error(body: &str, key: &str, source: MeshError) -> SetupError {
    SetupError::Mesh {
        body: body.to_string(),
        key: key.to_string(),
        source,
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

/// A `[solver]` table applied to `base`: every key given is checked and replaces the value of
/// `base`, absent keys keep it. `threads` is checked (1 to [`MAX_THREADS`]) but is not part of
/// [`Settings`]; read it from `spec`.
pub fn settings(spec: &SolverSpec, base: &Settings) -> Result<Settings, SetupError> {
    let mut s = base.clone();
    if let Some(method) = spec.method {
        s.method = method;
    }
    if let Some(g) = spec.gamma {
        s.gamma = gamma(g)?;
    }
    iteration_kind(spec, &mut s);
    if let Some(tol) = spec.tol {
        if !(tol.is_finite() && tol > 0.0) {
            return Err(solver_error(
                "tol",
                format!("must be a positive number, got {}", num(tol)),
            ));
        }
        s.tol = tol;
    }
    if let Some(e) = spec.equilibrium_tol {
        if !(e.is_finite() && e > 0.0) {
            return Err(solver_error(
                "equilibrium-tol",
                format!("must be a positive number, got {}", num(e)),
            ));
        }
        s.equilibrium_tol = e;
    }
    if let Some(max_iter) = spec.max_iter {
        if max_iter == 0 {
            return Err(solver_error("max-iter", "must be at least 1, got 0"));
        }
        s.max_iter = max_iter;
    }
    if let Some(g) = spec.gap_tol {
        if !(g.is_finite() && g > 0.0) {
            return Err(solver_error(
                "gap-tol",
                format!("must be a positive length, got {}", num(g)),
            ));
        }
        s.gap_tol = Some(g);
    }
    if let Some(n) = spec.max_updates {
        if n == 0 {
            return Err(solver_error("max-updates", "must be at least 1, got 0"));
        }
        s.max_updates = n;
    }
    if let Some(c) = spec.condensation {
        s.condensation = c;
    }
    for (key, v, slot) in [
        ("u0", spec.u0, &mut s.u0),
        ("u-prev", spec.u_prev, &mut s.u_prev),
    ] {
        if let Some(v) = v {
            if !v.is_finite() {
                return Err(solver_error(key, format!("must be finite, got {}", num(v))));
            }
            *slot = v;
        }
    }
    match spec.threads {
        Some(0) => return Err(solver_error("threads", "must be at least 1, got 0")),
        Some(n) if n > MAX_THREADS => {
            return Err(solver_error(
                "threads",
                format!("must be at most {MAX_THREADS}, got {n}"),
            ))
        }
        _ => {}
    }
    Ok(s)
}

/// The accelerator and the coarse correction. A constant γ without an `accelerator` or `coarse`
/// key asks for the paper's one-level iteration, so those keys then default to `none` and `off`;
/// a `method` or `gamma = "auto"` alone asks for the two-level sweeps (the default interface
/// Newton method uses neither); with `accelerator = "anderson"`, `coarse` defaults to `off`.
fn iteration_kind(spec: &SolverSpec, s: &mut Settings) {
    let paper = matches!(spec.gamma, Some(GammaSpec::Value(_)));
    if spec.accelerator.is_none() && (spec.method.is_some() || spec.gamma.is_some()) {
        s.use_sweeps();
    }
    s.accelerator = match spec.accelerator {
        Some(AcceleratorSpec::Anderson) => Accelerator::Anderson {
            depth: ANDERSON_DEPTH,
        },
        Some(AcceleratorSpec::None) => Accelerator::None,
        Some(AcceleratorSpec::Newton) => Accelerator::Newton,
        None if paper => Accelerator::None,
        None => s.accelerator,
    };
    s.coarse = match spec.coarse {
        Some(CoarseSpec::Off) => CoarseMode::Off,
        Some(CoarseSpec::Chains) => CoarseMode::Chains,
        Some(CoarseSpec::All) => CoarseMode::All,
        // Anderson's secant columns and the coarse step's rigid jumps do not mix well (measured:
        // docs/two-level.md), so an accelerated solve runs without coarse correction unless asked;
        // the interface Newton method handles rigid motions itself.
        None if paper || s.accelerator != Accelerator::None => CoarseMode::Off,
        None if spec.accelerator == Some(AcceleratorSpec::None) => CoarseMode::Chains,
        None => s.coarse,
    };
}

/// A `gamma` value → a γ rule: `"auto"`, or a constant γ > 0.
pub fn gamma(spec: GammaSpec) -> Result<Gamma, SetupError> {
    match spec {
        GammaSpec::Auto => Ok(Gamma::Auto),
        GammaSpec::Value(g) if g.is_finite() && g > 0.0 => Ok(Gamma::Constant(g)),
        GammaSpec::Value(g) => Err(solver_error(
            "gamma",
            format!("must be a positive number or \"auto\", got {}", num(g)),
        )),
    }
}

/// A `[materials.NAME]` table → a validated material (errors name the material and the key).
pub fn material(name: &str, young: f64, poisson: f64) -> Result<Material, SetupError> {
    Material::new(young, poisson).map_err(|source| SetupError::MaterialValue {
        material: name.to_string(),
        source,
    })
}

/// Checks the name of the next body, `bodies[i]` where i is the number of `earlier` names: not
/// empty, and not one of them.
pub fn check_body_name<'a>(
    name: &str,
    earlier: impl IntoIterator<Item = &'a str>,
) -> Result<(), SetupError> {
    let mut i = 0;
    let mut duplicate = None;
    for other in earlier {
        if duplicate.is_none() && other == name {
            duplicate = Some(i);
        }
        i += 1;
    }
    if name.trim().is_empty() {
        return Err(SetupError::Invalid {
            key: format!("bodies[{i}].name"),
            message: "a body name must not be empty".into(),
        });
    }
    match duplicate {
        Some(j) => Err(body_error(
            name,
            "name",
            format!("the name is used by both bodies[{j}] and bodies[{i}]"),
        )),
        None => Ok(()),
    }
}

/// Checks that every body is held: a body without a contact pair needs supports, and they must
/// remove all its rigid-body modes.
pub fn check_floating(model: &Model) -> Result<(), SetupError> {
    for (b, body) in model.bodies.iter().enumerate() {
        // A remote body's process checks it.
        if model.remote(b).is_some() || model.pairs.iter().any(|p| p.bodies.contains(&b)) {
            continue;
        }
        if !body.constraints.any() {
            return Err(SetupError::Floating {
                body: body.name.clone(),
            });
        }
        // Without contact the supports alone must hold the body.
        if let Err(BodyError::Floating {
            modes, description, ..
        }) = body.check_held(&[])
        {
            return Err(body_error(
                &body.name,
                "supports",
                format!(
                    "the body has no contact pair and its supports leave {modes} rigid-body \
                     mode(s) free ({description}): it would float"
                ),
            ));
        }
    }
    Ok(())
}

/// Body `name` on a built mesh: supports applied in order ([`Constraints::fix`]), loads checked
/// (finite values, known boundaries) and summed into one load vector.
pub fn body_on_mesh(
    name: &str,
    mesh: Mesh,
    material: Material,
    plane: Plane,
    supports: &[SupportSpec],
    loads: &[LoadSpec],
) -> Result<ElasticBody, SetupError> {
    let mut constraints = Constraints::new(mesh.num_nodes());
    for (i, s) in supports.iter().enumerate() {
        constraints
            .fix(&mesh, &s.boundary, s.component, s.value)
            .map_err(|source| SetupError::Support {
                body: name.to_string(),
                key: format!("supports[{i}]"),
                source,
            })?;
    }
    let mut resolved = Vec::with_capacity(loads.len());
    for (i, l) in loads.iter().enumerate() {
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
                format!("must be finite, got {}", num(*v)),
            ));
        }
        if let LoadSpec::Pressure { boundary, .. } | LoadSpec::Traction { boundary, .. } = l {
            mesh.boundary(boundary)
                .map_err(|e| mesh_error(name, &format!("{key}.boundary"), e))?;
        }
        resolved.push(load);
    }
    let load = contactdd_core::loads::load_vector(&mesh, &resolved)
        .map_err(|e| mesh_error(name, "loads", e))?;
    Ok(ElasticBody {
        name: name.to_string(),
        mesh,
        material,
        plane,
        constraints,
        load,
    })
}

/// The `mesh` table of body `body` → a validated mesh; a relative Gmsh path resolves against
/// `base_dir`.
pub fn mesh(body: &str, spec: &MeshSpec, base_dir: &Path) -> Result<Mesh, LoadError> {
    match spec {
        MeshSpec::Rectangle {
            x,
            y,
            nx,
            ny,
            diagonal,
            mirror,
            mirror_x,
            grading,
            order,
        } => {
            for (key, n) in [("mesh.nx", nx), ("mesh.ny", ny)] {
                if *n == 0 {
                    return Err(body_error(body, key, "must be at least 1, got 0").into());
                }
            }
            if !matches!(nx.checked_mul(*ny), Some(c) if c <= MAX_RECTANGLE_CELLS) {
                return Err(body_error(
                    body,
                    "mesh",
                    format!("{nx} × {ny} cells is more than the limit of {MAX_RECTANGLE_CELLS}"),
                )
                .into());
            }
            for (key, r) in [("mesh.x", x), ("mesh.y", y)] {
                if !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]) {
                    return Err(body_error(
                        body,
                        key,
                        format!(
                            "need a finite range [min, max] with min < max, got [{}, {}]",
                            num(r[0]),
                            num(r[1])
                        ),
                    )
                    .into());
                }
            }
            let grading = grading.map_or([1.0; DIM], |g| [g.x, g.y]);
            for (key, g) in [
                ("mesh.grading.x", grading[0]),
                ("mesh.grading.y", grading[1]),
            ] {
                if !(g.is_finite() && g > 0.0) {
                    return Err(body_error(
                        body,
                        key,
                        format!("must be a positive number, got {}", num(g)),
                    )
                    .into());
                }
            }
            let layout = Layout {
                grading,
                mirror_x: *mirror_x,
            };
            Rectangle {
                origin: [x[0], y[0]],
                corner: [x[1], y[1]],
                nx: *nx,
                ny: *ny,
                diagonal: *diagonal,
                mirror: *mirror,
                order: *order,
            }
            .mesh_with(&layout)
            .map_err(|e| mesh_error(body, "mesh", e).into())
        }
        MeshSpec::Gmsh {
            file,
            surface,
            order,
            translate,
            scale,
        } => {
            let scale = scale.unwrap_or(1.0);
            if !(scale.is_finite() && scale > 0.0) {
                return Err(body_error(
                    body,
                    "mesh.scale",
                    format!("must be a positive number, got {}", num(scale)),
                )
                .into());
            }
            let shift = translate.unwrap_or([0.0; DIM]);
            if !shift.iter().all(|x| x.is_finite()) {
                return Err(body_error(
                    body,
                    "mesh.translate",
                    format!("must be finite, got [{}, {}]", num(shift[0]), num(shift[1])),
                )
                .into());
            }
            let path: PathBuf = if file.is_absolute() {
                file.clone()
            } else {
                base_dir.join(file)
            };
            let mut mesh =
                read_msh_surface(&path, surface.as_deref()).map_err(|source| LoadError::Gmsh {
                    body: body.to_string(),
                    path: path.display().to_string(),
                    source,
                })?;
            if scale != 1.0 || shift != [0.0; DIM] {
                mesh = mesh
                    .map_nodes(|p| std::array::from_fn(|c| scale * p[c] + shift[c]))
                    .map_err(|e| mesh_error(body, "mesh", e))?;
            }
            gmsh_order(body, mesh, *order, &path.display().to_string())
        }
        MeshSpec::Inline {
            nodes,
            triangles,
            boundaries,
            node_sets,
        } => Ok(inline_mesh(body, nodes, triangles, boundaries, node_sets)?),
    }
}

/// A mesh read from Gmsh (`source` names it in messages) at the `order` asked for: P1 triangles
/// are promoted to P2 for `p2`; P2 triangles cannot be read as `p1`.
pub fn gmsh_order(
    body: &str,
    mesh: Mesh,
    order: Option<Order>,
    source: &str,
) -> Result<Mesh, LoadError> {
    match (order, mesh.order()) {
        (Some(Order::P2), Order::P1) => Ok(mesh.to_p2()),
        (Some(Order::P1), Order::P2) => Err(body_error(
            body,
            "mesh.order",
            format!(
                "'{source}' has P2 triangles; they cannot be read as p1 (use order = \"p2\" or \
                 leave order out)"
            ),
        )
        .into()),
        _ => Ok(mesh),
    }
}

/// An inline mesh table (`kind = "inline"`) → a validated mesh of body `body`: the order follows
/// from the triangles' length (3 or 6 nodes, the same for all), the rest is [`mesh_from_arrays`].
fn inline_mesh(
    body: &str,
    nodes: &[Point],
    triangles: &[Vec<usize>],
    boundaries: &BTreeMap<String, Vec<[usize; 2]>>,
    node_sets: &BTreeMap<String, Vec<usize>>,
) -> Result<Mesh, SetupError> {
    let width = triangles.first().map_or(3, Vec::len);
    let order = match width {
        3 => Order::P1,
        6 => Order::P2,
        n => {
            return Err(body_error(
                body,
                "mesh.triangles",
                format!("a triangle has 3 (P1) or 6 (P2) nodes, got {n}"),
            ))
        }
    };
    if let Some(i) = triangles.iter().position(|t| t.len() != width) {
        return Err(body_error(
            body,
            "mesh.triangles",
            format!(
                "triangle {i} has {} nodes, the first has {width}",
                triangles[i].len()
            ),
        ));
    }
    let edges = boundaries
        .iter()
        .map(|(name, e)| {
            (
                name.clone(),
                e.iter().map(|&[a, b]| Edge::new(a, b)).collect(),
            )
        })
        .collect();
    let cells = triangles.iter().flatten().copied().collect();
    mesh_from_arrays(body, nodes.to_vec(), order, cells, edges, node_sets.clone())
}

/// A mesh given as arrays (nodes, the node indices of each triangle, named boundary edges and
/// node sets) → a validated mesh of body `body`, with the errors of a mesh read from a file;
/// clockwise triangles are reordered as the Gmsh reader does.
pub fn mesh_from_arrays(
    body: &str,
    nodes: Vec<Point>,
    order: Order,
    mut cells: Vec<usize>,
    boundaries: BTreeMap<String, Vec<Edge>>,
    node_sets: BTreeMap<String, Vec<usize>>,
) -> Result<Mesh, SetupError> {
    // Clockwise triangles are reordered, as the Gmsh reader does.
    contactdd_core::mesh::counter_clockwise(&nodes, order, &mut cells);
    Mesh::new(nodes, order, cells, boundaries, node_sets).map_err(|e| mesh_error(body, "mesh", e))
}

/// One `[[contact]]` entry → a contact pair between two of `bodies`, whose name must differ from
/// those of the `earlier` pairs (this one is `contact[earlier.len()]`).
pub fn pair(
    spec: &ContactSpec,
    bodies: &[ElasticBody],
    earlier: &[ContactPair],
) -> Result<ContactPair, SetupError> {
    let mut name = spec.pair_name();
    if name.is_empty() {
        // No name and no bodies: the entry's position is all that identifies it.
        name = format!("contact[{}]", earlier.len());
    }
    for (key, list) in [("bodies", &spec.bodies), ("boundaries", &spec.boundaries)] {
        if list.len() != 2 {
            return Err(pair_error(
                &name,
                key,
                format!("needs exactly 2 entries, got {}", list.len()),
            ));
        }
    }
    let mut ids = [0usize; 2];
    for (s, body) in spec.bodies.iter().enumerate() {
        ids[s] = bodies.iter().position(|b| b.name == *body).ok_or_else(|| {
            let mut names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
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
        body.mesh
            .boundary(&spec.boundaries[s])
            .map_err(|source| SetupError::PairBoundary {
                pair: name.clone(),
                key: format!("boundaries[{s}]"),
                body: body.name.clone(),
                source,
            })?;
    }
    let penalty = penalty(&name, &spec.penalty)?;
    let (a, b) = (&bodies[ids[0]], &bodies[ids[1]]);
    let theta = penalty.theta(a, b);
    if !(theta.is_finite() && theta > 0.0) {
        return Err(pair_error(
            &name,
            "penalty",
            format!("θ = {} is not a positive finite number", num(theta)),
        ));
    }
    let profile = spec
        .gap
        .as_ref()
        .map(|g| gap_profile(&name, g))
        .transpose()?;
    if let Some(j) = earlier.iter().position(|p| p.name == name) {
        return Err(pair_error(
            &name,
            "name",
            format!(
                "the name is used by both contact[{j}] and contact[{}]; give each pair its own \
                 name",
                earlier.len()
            ),
        ));
    }
    Ok(ContactPair {
        name,
        bodies: ids,
        boundaries: [spec.boundaries[0].clone(), spec.boundaries[1].clone()],
        penalty,
        profile,
        enforcement: spec.enforcement.map(Into::into).unwrap_or_default(),
        forces: spec.forces.map(Into::into).unwrap_or_default(),
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
                format!("must be a positive finite number, got {}", num(v)),
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
                format!("must be {what}, got {}", num(v)),
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
            along: match along.unit() {
                Some(_) => along,
                None => {
                    return Err(pair_error(
                        pair,
                        "gap.along",
                        format!("needs a finite, non-zero direction, got {along:?}"),
                    ))
                }
            },
        },
        GapSpec::Uniform { value } => GapProfile::Uniform {
            value: check("value", value, false)?,
        },
    })
}

fn known<'a>(names: impl Iterator<Item = &'a String>) -> String {
    let names: Vec<&str> = names.map(String::as_str).collect();
    if names.is_empty() {
        "none defined".into()
    } else {
        names.join(", ")
    }
}
