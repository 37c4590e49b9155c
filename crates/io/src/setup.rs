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
//! - a rectangle mesh is built by [`Rectangle::mesh`](contactdd_core::Rectangle::mesh), a Gmsh
//!   file is read by [`contactdd_core::gmsh::read_msh_surface`] (relative paths against
//!   `base_dir`), scaled, translated and, with `order = "p2"`, promoted by
//!   [`Mesh::to_p2`](contactdd_core::Mesh::to_p2) ([`crate::meshes`]);
//! - supports are applied in file order by [`Constraints::fix`](contactdd_core::Constraints::fix)
//!   (a DOF fixed twice keeps the last value), all loads of a body form one load vector
//!   ([`contactdd_core::loads::load_vector`]) ([`crate::bodies`]);
//! - a penalty `{ c, h }` is the rod model θ = c·h·(1/E*₁ + 1/E*₂), `{ theta }` is θ itself
//!   ([`crate::pairs`]);
//! - absent `[solver]` keys take the values of [`Settings::default`] ([`crate::solver_settings`]);
//!   `load-steps` and `monitor` are read by [`crate::load_steps`], the `[[steps]]` history and
//!   the loads' groups by [`crate::history`].
//!
//! [`resolve`] builds the model one entry at a time with a [`ModelBuilder`]; a problem built in
//! code (the Python module) uses the same builder, so it gets the same validation and the same
//! messages as a file. The checks of single entries are public too, and re-exported here
//! ([`material`], [`check_body_name`], [`mesh`], [`mesh_from_arrays`], [`body_on_mesh`],
//! [`pair`], [`settings`], [`gamma`], [`check_floating`]). A distributed solve meshes each body
//! on one process only ([`crate::distributed_setup`]).

use std::path::{Path, PathBuf};

use contactdd_ddm::exchange::Exchange;
use contactdd_ddm::history::LoadHistory;
use contactdd_ddm::{Model, Settings};

use crate::distributed_setup::{add_bodies, agreed};
use crate::error::{no_bodies, LoadError};
use crate::history::history;
use crate::load_steps::{load_steps, monitor};
use crate::meshes::check_mesh_memory;
use crate::names::check_problem_names;
use crate::problem::Problem;
use crate::solver_settings::starting_values;

pub use crate::bodies::{body_on_mesh, check_body_name, check_floating, material};
pub use crate::load_steps::{Monitor, MAX_LOAD_STEPS};
pub use crate::meshes::{gmsh_order, mesh, mesh_from_arrays, MAX_RECTANGLE_CELLS};
pub use crate::model_builder::ModelBuilder;
pub use crate::pairs::pair;
pub use crate::solver_settings::{gamma, model_size, settings, MAX_THREADS};

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
    /// The load history of `[[steps]]` (`None` without one; never with `steps`).
    pub history: Option<LoadHistory>,
}

impl Loaded {
    /// The warning for a `[solver] monitor` that a command-line run would ignore: without
    /// `load-steps` and without a `[[steps]]` history there are no steps to report it in (Python's
    /// `contactdd.solve` reports it as `Result.monitor`, so it is not an error). `None` when
    /// there is no monitor or some steps report it.
    pub fn unreported_monitor(&self) -> Option<String> {
        let m = self.problem.solver.monitor.as_ref()?;
        if self.steps.is_some() || self.history.is_some() {
            return None;
        }
        Some(format!(
            "[solver] monitor: '{}' of body '{}' is reported only by load steps (`load-steps`) \
             or a [[steps]] load history, and this problem has neither: it is ignored",
            contactdd_core::names::shown(&m.boundary),
            contactdd_core::names::shown(&m.body)
        ))
    }
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
    // Every name first, so that no later message echoes a hostile one.
    check_problem_names(&problem)?;
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
        check_mesh_memory(&problem.bodies)?;
        for spec in &problem.bodies {
            builder.add_body(spec, base_dir)?;
        }
        return finish(builder, problem, settings, default_name);
    };
    // Every process reaches the agreement below, whatever failed on it: each checked the
    // supports of its own bodies only, and a body may arrive damaged on one process alone.
    let rest = add_bodies(&mut builder, &problem, base_dir, exchange)
        .and_then(|()| finish(builder, problem, settings, default_name));
    agreed(exchange, rest)
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
    let history = history(&problem, &model)?;
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
        history,
        problem,
    })
}
