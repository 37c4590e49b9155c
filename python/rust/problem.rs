//! `contactdd.Problem`: a contact problem read from a TOML file or built in code.
//!
//! The problem holds a `contactdd_io::setup::ModelBuilder`, the resolve step of a problem file:
//! every `add_*` call builds a schema entry (`contactdd_io::problem`) and hands it to the builder,
//! which checks it as it checks the same entry of a file, so a bad value gets the message a
//! problem file would get. Supports, loads and gap profiles are Python dicts deserialized into the
//! schema (the same keys, kinds and defaults as the TOML tables); only a mesh given as arrays has
//! no schema entry and goes through `setup::mesh_from_arrays`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use numpy::PyUntypedArrayMethods;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple, PyType};

use contactdd_core::gmsh::parse_msh_surface;
use contactdd_core::{Material, Order, Plane, Vector, DIM};
use contactdd_ddm::{Model, Settings, SetupError};
use contactdd_io::problem::{
    BodySpec, ContactSpec, LoadStepsSpec, MaterialSpec, MeshSpec, MonitorSpec, PenaltySpec,
    Problem as ProblemSpec, SolverSpec,
};
use contactdd_io::setup::{self, ModelBuilder};
use contactdd_io::write_problem;
use contactdd_io::{LoadError, Loaded};

use crate::convert::{from_name, name_of};
use crate::error::{input_error, planar_file, planar_text, setup_error};
use crate::options::{gamma_to_py, GammaArg, SolverOptions};
use crate::schema::{
    absolute_mesh_paths, body_error, boundary_edges, float_array, indices, inline_spec,
    node_set_indices, pair_option, specs, text,
};
use crate::steps::{self, load_steps_spec, load_steps_to_py, monitor_spec, monitor_to_py};

/// A contact problem: materials, bodies, contact pairs and default solver settings.
///
/// Read one from a problem file with :meth:`Problem.from_toml` or build it in code::
///
///     p = contactdd.Problem(name="notch", plane="strain")
///     p.add_material("steel", young=2.1e5, poisson=0.3)
///     p.add_rectangle_body("lower", x=(0, 4), y=(0, 1), nx=32, ny=16, material="steel",
///                          supports=[{"boundary": "right", "component": "x"}],
///                          loads=[{"kind": "pressure", "boundary": "bottom", "value": 2100.0}])
///     ...
///     p.add_contact(bodies=("lower", "upper"), boundaries=("top", "bottom"), c=0.05, h=1.0)
///
/// Every ``add_*`` call checks its input at once and raises :class:`ContactddError` with the
/// message a problem file would get.
#[pyclass(module = "contactdd", name = "Problem")]
pub struct Problem {
    pub(crate) name: String,
    /// Materials, bodies and pairs, resolved entry by entry as a problem file is.
    pub(crate) model: ModelBuilder,
    pub(crate) settings: Settings,
    pub(crate) threads: Option<usize>,
    /// The problem as a problem file says it, entry by entry as added (Gmsh paths absolute):
    /// what :meth:`to_toml` writes, with the current settings.
    pub(crate) spec: ProblemSpec,
}

impl Problem {
    /// A problem from its problem-file schema (relative Gmsh paths resolve against `base_dir`).
    pub fn from_spec(spec: ProblemSpec, base_dir: &Path) -> PyResult<Problem> {
        let loaded = contactdd_io::resolve(spec, base_dir).map_err(setup_error)?;
        Problem::from_loaded(loaded, None, base_dir)
    }

    /// A problem from a resolved problem file whose relative Gmsh paths resolved against
    /// `base_dir`.
    fn from_loaded(
        loaded: Loaded,
        default_name: Option<&str>,
        base_dir: &Path,
    ) -> PyResult<Problem> {
        // The file's materials are resolved again only to be listed by `Problem.materials`.
        let mut materials: BTreeMap<String, Material> = BTreeMap::new();
        for (name, m) in &loaded.problem.materials {
            let mat = setup::material(name, m.young, m.poisson).map_err(setup_error)?;
            materials.insert(name.clone(), mat);
        }
        let name = match (&loaded.problem.name, default_name) {
            (None, Some(d)) => d.to_string(),
            _ => loaded.model.name.clone(),
        };
        let mut spec = loaded.problem;
        absolute_mesh_paths(&mut spec, base_dir)?;
        Ok(Problem {
            name,
            model: ModelBuilder::from_model(loaded.model, materials),
            settings: loaded.settings,
            threads: loaded.threads,
            spec,
        })
    }

    /// The problem file text of the problem (see :meth:`to_toml`).
    pub fn toml_text(&self) -> PyResult<String> {
        let mut spec = self.spec.clone();
        spec.name = Some(self.name.clone());
        spec.solver = write_problem::solver_spec(&self.settings, self.threads, &spec.solver);
        write_problem::to_toml(&spec)
            .map_err(|e| input_error(format!("cannot write the problem as TOML: {e}")))
    }

    /// Adds a `[[bodies]]` entry, the step of a problem file (no Gmsh path to resolve), and
    /// keeps it for `to_toml`.
    fn add_body_spec(&mut self, spec: BodySpec) -> PyResult<()> {
        self.model
            .add_body(&spec, Path::new(""))
            .map_err(setup_error)?;
        self.spec.bodies.push(spec);
        Ok(())
    }

    /// The solver input, checked as a whole as a problem file is: at least one body, and every
    /// body held by supports or a contact pair.
    pub fn model(&self) -> PyResult<Model> {
        self.model.model(&self.name).map_err(setup_error)
    }

    /// The solver input, settings and thread count with `options` applied (the checks of a
    /// `[solver]` table, after those of the model).
    pub fn configured(
        &self,
        options: &SolverOptions,
    ) -> PyResult<(Model, Settings, Option<usize>)> {
        let model = options.enforce(self.model()?)?;
        let settings = options.apply(&self.settings)?;
        Ok((model, settings, options.threads_or(self.threads)))
    }

    /// The problem's load steps (the `load-steps` key of its `[solver]` table), if any.
    pub fn load_steps(&self) -> Option<&LoadStepsSpec> {
        self.spec.solver.load_steps.as_ref()
    }

    /// The problem's monitored boundary (the `monitor` key of its `[solver]` table), if any.
    pub fn monitor(&self) -> Option<&MonitorSpec> {
        self.spec.solver.monitor.as_ref()
    }

    /// The problem's units note (`units` of a problem file), for the result files.
    pub fn units(&self) -> Option<&str> {
        self.spec.units.as_deref()
    }
}

#[pymethods]
impl Problem {
    /// An empty problem.
    ///
    /// Args:
    ///     name: problem name used in output files.
    ///     plane: ``"strain"`` (thick bodies) or ``"stress"`` (thin plates), for all bodies.
    #[new]
    #[pyo3(signature = (name = None, plane = None), text_signature = "(name='problem', plane='strain')")]
    fn new(name: Option<&Bound<'_, PyAny>>, plane: Option<&Bound<'_, PyAny>>) -> PyResult<Problem> {
        // Strings checked here, so that another type raises a `ContactddError` naming the
        // argument (the methods get theirs from `contactdd._arguments`).
        let name = &name.map_or(Ok("problem".into()), |n| text(n, "name"))?;
        let plane = plane.map_or(Ok("strain".into()), |p| text(p, "plane"))?;
        let plane: Plane = from_name(&plane).map_err(|e| {
            setup_error(SetupError::Invalid {
                key: "plane".into(),
                message: e,
            })
        })?;
        Ok(Problem {
            name: name.to_string(),
            model: ModelBuilder::new(plane),
            settings: Settings::default(),
            threads: None,
            spec: ProblemSpec {
                name: Some(name.to_string()),
                plane,
                units: None,
                materials: BTreeMap::new(),
                bodies: Vec::new(),
                contact: Vec::new(),
                solver: SolverSpec::default(),
                steps: Vec::new(),
                output: Default::default(),
            },
        })
    }

    /// Reads a TOML problem file (the format of the command line tool).
    ///
    /// Relative mesh paths resolve against the file's folder. The ``[solver]`` table becomes the
    /// problem's default settings.
    ///
    /// Raises:
    ///     ContactddIOError: the file (or a mesh file it names) cannot be read; an ``OSError``.
    ///     ContactddError: the file is not a valid problem.
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<Problem> {
        let loaded = py
            .detach(|| contactdd_io::load_file(&path))
            .map_err(|e| planar_file(e, &path))?;
        let base = path.parent().unwrap_or(Path::new(""));
        Problem::from_loaded(loaded, None, base)
    }

    /// Parses the text of a TOML problem file.
    ///
    /// Args:
    ///     text: the file's content.
    ///     base_dir: folder against which relative mesh paths resolve (default: the current
    ///         folder).
    ///     source: name of the text in error messages.
    #[staticmethod]
    #[pyo3(signature = (text, base_dir = None, source = "<string>"))]
    fn from_toml_str(
        py: Python<'_>,
        text: &str,
        base_dir: Option<PathBuf>,
        source: &str,
    ) -> PyResult<Problem> {
        let base = base_dir.unwrap_or_else(|| PathBuf::from("."));
        let loaded = py
            .detach(|| contactdd_io::load_str(text, source, Path::new(&base)))
            .map_err(|e| planar_text(e, text, source))?;
        Problem::from_loaded(loaded, Some("problem"), &base)
    }

    /// The problem as the text of a problem file, which :meth:`from_toml_str` reads back to the
    /// same problem (the same solve results, bit for bit).
    ///
    /// Every solver setting is written explicitly (the current values, see :attr:`settings`). A
    /// Gmsh mesh path is written absolute (a relative one resolved when the problem was read), so
    /// the text reads the same meshes whatever ``base_dir`` it is given. A body added from arrays
    /// (:meth:`add_body`) is written inline, as a ``kind = "inline"`` mesh.
    fn to_toml(&self) -> PyResult<String> {
        self.toml_text()
    }

    /// Pickles the problem as its problem file text (:meth:`to_toml`).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let restore = slf.get_type().getattr("_from_toml_text")?;
        let text = slf.borrow().toml_text()?;
        PyTuple::new(py, [restore, PyTuple::new(py, [text])?.into_any()])
    }

    /// Unpickles a problem written by :meth:`to_toml` (used by pickle).
    #[classmethod]
    fn _from_toml_text(_cls: &Bound<'_, PyType>, py: Python<'_>, text: &str) -> PyResult<Problem> {
        Problem::from_toml_str(py, text, None, "<pickle>")
    }

    /// Defines a linear elastic isotropic material.
    ///
    /// Args:
    ///     name: the name bodies refer to.
    ///     young: Young's modulus E > 0.
    ///     poisson: Poisson's ratio ν in (-1, 0.5).
    #[pyo3(signature = (name, young, poisson))]
    fn add_material(&mut self, name: &str, young: f64, poisson: f64) -> PyResult<()> {
        let spec = MaterialSpec { young, poisson };
        self.model.add_material(name, &spec).map_err(setup_error)?;
        self.spec.materials.insert(name.to_string(), spec);
        Ok(())
    }

    /// Adds a body on a triangle mesh given as arrays.
    ///
    /// Args:
    ///     name: unique body name.
    ///     nodes: ``(n, 2)`` node coordinates.
    ///     triangles: ``(m, 3)`` (P1) or ``(m, 6)`` (P2: vertices, then the mid-side nodes of edges
    ///         (0,1), (1,2), (2,0)) node indices; clockwise triangles are reordered
    ///         counter-clockwise, as the Gmsh reader does.
    ///     boundaries: named boundary edge sets, ``{name: (k, 2) array of node pairs}``; for
    ///         P2 triangles also ``(k, 3)`` with each edge's mid-side node, which must be the
    ///         one the triangles give the edge (3 nodes per edge on P1 triangles are refused).
    ///     material: name of a material added with :meth:`add_material`.
    ///     supports: list of ``{"boundary": str, "component": "x"|"y"|"both"|"normal",
    ///         "value": float = 0}``.
    ///     loads: list of ``{"kind": "pressure", "boundary": str, "value": float}``,
    ///         ``{"kind": "traction", "boundary": str, "value": [tx, ty]}`` or
    ///         ``{"kind": "body-force", "value": [fx, fy]}``.
    ///     node_sets: named node sets, ``{name: array of node indices}``, usable as a support's
    ///         ``boundary``.
    #[pyo3(signature = (name, nodes, triangles, boundaries, material, supports = None, loads = None, node_sets = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        name: &str,
        nodes: &Bound<'_, PyAny>,
        triangles: &Bound<'_, PyAny>,
        boundaries: &Bound<'_, PyAny>,
        material: &str,
        supports: Option<&Bound<'_, PyAny>>,
        loads: Option<&Bound<'_, PyAny>>,
        node_sets: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        self.model.check_body_name(name).map_err(setup_error)?;
        // The checks of the arrays' shapes and signs: what numpy can get wrong and a mesh file
        // cannot; the mesh itself is checked by `setup::mesh_from_arrays`.
        let mesh_error = |message: String| setup_error(body_error(name, "mesh", message));
        let nodes = float_array(nodes, &format!("body '{name}': mesh: nodes"))?;
        let [n, dim] = [nodes.shape()[0], nodes.shape()[1]];
        if dim != DIM {
            return Err(mesh_error(format!(
                "nodes must have shape (n, {DIM}), got ({n}, {dim})"
            )));
        }
        let points: Vec<Vector> = nodes
            .as_array()
            .rows()
            .into_iter()
            .map(|r| std::array::from_fn(|c| r[c]))
            .collect();
        let (cells, width) = indices(triangles, &format!("body '{name}': mesh: triangles"))?;
        if width != 3 && width != 6 {
            return Err(mesh_error(format!(
                "triangles must have 3 (P1) or 6 (P2) columns, got {width}"
            )));
        }
        let edge_sets = boundary_edges(name, boundaries, &cells, width)?;
        let sets = node_set_indices(name, node_sets)?;
        // The arrays as given become an inline mesh table, resolved as a problem file's is (and
        // written back out by `to_toml`).
        let spec = BodySpec {
            name: name.to_string(),
            material: material.to_string(),
            mesh: MeshSpec::Inline {
                nodes: points,
                triangles: cells.chunks(width).map(<[usize]>::to_vec).collect(),
                boundaries: edge_sets,
                node_sets: sets,
            },
            supports: specs(name, "supports", supports)?,
            loads: specs(name, "loads", loads)?,
        };
        self.add_body_spec(spec)
    }

    /// Adds a body on a mesh given as the text of a Gmsh ``.msh`` file (ASCII 4.1 or 2.2), read
    /// by the reader of ``kind = "gmsh"`` meshes with its rules: the physical surface
    /// ``surface`` is the body (default: the text's only one), the physical curves and points
    /// that touch it are its boundaries and node sets, clockwise triangles are reordered, and
    /// curved P2 triangles are used isoparametrically (folded ones are refused). The mesh is kept in the problem (a
    /// ``kind = "inline"`` mesh for :meth:`to_toml`). :func:`contactdd.add_meshio_body` and
    /// :func:`contactdd.add_gmsh_body` use it.
    ///
    /// Args:
    ///     name: unique body name.
    ///     text: the ``.msh`` text.
    ///     material: name of a material added with :meth:`add_material`.
    ///     surface: the body's physical surface (name, or tag number of an unnamed group).
    ///     order: ``"p2"`` promotes P1 triangles to P2; default: as in the text.
    ///     supports, loads: as for :meth:`add_body`.
    ///     source: what the text is, in error messages.
    #[pyo3(signature = (name, text, material, surface = None, order = None, supports = None, loads = None, source = "<msh text>"))]
    #[allow(clippy::too_many_arguments)]
    fn add_msh_body(
        &mut self,
        py: Python<'_>,
        name: &str,
        text: &str,
        material: &str,
        surface: Option<&str>,
        order: Option<&str>,
        supports: Option<&Bound<'_, PyAny>>,
        loads: Option<&Bound<'_, PyAny>>,
        source: &str,
    ) -> PyResult<()> {
        self.model.check_body_name(name).map_err(setup_error)?;
        let order: Option<Order> = order
            .map(from_name)
            .transpose()
            .map_err(|e| setup_error(body_error(name, "mesh.order", e)))?;
        let mesh = py
            .detach(|| {
                let mesh = parse_msh_surface(text, surface).map_err(|e| LoadError::Gmsh {
                    body: name.to_string(),
                    path: source.to_string(),
                    source: e,
                })?;
                setup::gmsh_order(name, mesh, order, source)
            })
            .map_err(setup_error)?;
        let spec = BodySpec {
            name: name.to_string(),
            material: material.to_string(),
            mesh: inline_spec(&mesh),
            supports: specs(name, "supports", supports)?,
            loads: specs(name, "loads", loads)?,
        };
        self.add_body_spec(spec)
    }

    /// Adds a body meshed as a structured rectangle ``x[0] ≤ x ≤ x[1]``, ``y[0] ≤ y ≤ y[1]`` with
    /// ``nx × ny`` cells of two triangles each; its boundaries are ``left``, ``right``,
    /// ``bottom`` and ``top``.
    ///
    /// Args:
    ///     diagonal: cell diagonal, ``"right"`` ("/"), ``"left"`` ("\\") or ``"alternate"``.
    ///     mirror: mirror the mesh about its horizontal centre line (for the upper body of a
    ///         stack, so that the two meshes are mirror images).
    ///     order: ``"p1"`` or ``"p2"``.
    ///     supports, loads: as for :meth:`add_body`.
    #[pyo3(signature = (name, x, y, nx, ny, material, diagonal = "right", mirror = false, order = "p1", supports = None, loads = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_rectangle_body(
        &mut self,
        name: &str,
        x: (f64, f64),
        y: (f64, f64),
        nx: usize,
        ny: usize,
        material: &str,
        diagonal: &str,
        mirror: bool,
        order: &str,
        supports: Option<&Bound<'_, PyAny>>,
        loads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        self.model.check_body_name(name).map_err(setup_error)?;
        let err = |key: &str, m: String| setup_error(body_error(name, key, m));
        let spec = BodySpec {
            name: name.to_string(),
            material: material.to_string(),
            mesh: MeshSpec::Rectangle {
                x: [x.0, x.1],
                y: [y.0, y.1],
                nx,
                ny,
                diagonal: from_name(diagonal).map_err(|e| err("mesh.diagonal", e))?,
                mirror,
                grading: None,
                mirror_x: false,
                order: from_name(order).map_err(|e| err("mesh.order", e))?,
            },
            supports: specs(name, "supports", supports)?,
            loads: specs(name, "loads", loads)?,
        };
        self.add_body_spec(spec)
    }

    /// Adds a contact pair: boundary ``boundaries[0]`` of body ``bodies[0]`` may touch boundary
    /// ``boundaries[1]`` of body ``bodies[1]``.
    ///
    /// The penalty is either the rod model θ = c·h·(1/E*₁ + 1/E*₂) (give ``c`` and ``h``) or
    /// ``theta`` itself.
    ///
    /// Args:
    ///     gap: an optional prescribed gap profile added to the geometric gap:
    ///         ``{"kind": "notch", "r0": float, "b": float, "centre": float, "power": 1.5,
    ///         "along": "x"}`` or ``{"kind": "uniform", "value": float}``.
    ///     name: pair name (default ``"<body0>-<body1>"``).
    ///     enforcement: ``"penalty"`` (the paper's formulation, the default) or ``"augmented"``
    ///         (augmented Lagrangian: the exact unilateral contact for any penalty).
    ///     forces: ``"balanced"`` (the default: the two sides receive equal and opposite forces)
    ///         or ``"own-side"`` (the paper's formulation: each side loaded by its own points).
    ///     friction: the tangential law: ``None`` (frictionless, the default),
    ///         ``{"law": "coulomb", "mu": float}`` (|σ_t| ≤ μ p), ``{"law": "tresca", "bound":
    ///         float}`` (|σ_t| ≤ bound) or ``{"law": "none"}``; friction needs balanced forces.
    #[pyo3(signature = (bodies, boundaries, c = None, h = None, theta = None, gap = None, name = None, enforcement = None, forces = None, friction = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_contact(
        &mut self,
        bodies: (String, String),
        boundaries: (String, String),
        c: Option<f64>,
        h: Option<f64>,
        theta: Option<f64>,
        gap: Option<&Bound<'_, PyAny>>,
        name: Option<String>,
        enforcement: Option<&Bound<'_, PyAny>>,
        forces: Option<&Bound<'_, PyAny>>,
        friction: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let mut spec = ContactSpec {
            name,
            bodies: vec![bodies.0, bodies.1],
            boundaries: vec![boundaries.0, boundaries.1],
            penalty: PenaltySpec { c, h, theta },
            gap: None,
            enforcement: None,
            forces: None,
            friction: None,
        };
        let pair = spec.pair_name();
        spec.friction = pair_option(friction, "friction", &pair)?;
        spec.forces = pair_option(forces, "forces", &pair)?;
        spec.enforcement = pair_option(enforcement, "enforcement", &pair)?;
        spec.gap = pair_option(gap, "gap", &pair)?;
        self.model.add_pair(&spec).map_err(setup_error)?;
        self.spec.contact.push(spec);
        Ok(())
    }

    /// Sets the default solver settings of the problem: the ``[solver]`` table of a problem
    /// file, one keyword per key (``max-iter`` is ``max_iter``, ...). Arguments left at ``None``
    /// keep their value. :func:`solve`, :func:`solve_steps` and :func:`sweep` can still override
    /// each of them.
    ///
    /// Args:
    ///     method: ``"neumann"``, ``"robin"``, ``"active-set"``, ``"newton-chord"`` or
    ///         ``"newton-kurchatov"``.
    ///     gamma: relaxation parameter γ > 0, or ``"auto"`` (safeguarded Aitken).
    ///     tol: stopping tolerance ε_u on every body's relative change.
    ///     max_iter: iteration cap.
    ///     u0: initial normal displacement u⁰ₙ on the contact zones.
    ///     u_prev: initial u⁻¹ₙ of the two-point methods.
    ///     threads: worker threads (default: all cores).
    ///     accelerator: ``"newton"`` (the default: the interface semismooth Newton
    ///         method, which uses neither method nor γ), ``"none"`` (Robin sweeps relaxed with
    ///         γ; the default when ``method`` or ``gamma`` is given) or ``"anderson"``.
    ///     coarse: the rigid-body coarse correction: ``"chains"`` (floating bodies that touch
    ///         each other), ``"all"`` or ``"off"``. A constant ``gamma`` alone selects the
    ///         paper's one-level iteration (no accelerator, coarse ``"off"``).
    ///     equilibrium_tol: a result counts as converged only if every body's contact forces
    ///         match its contact pressures to this fraction of the total contact force
    ///         (default 1e-2).
    ///     balance_tol: a result counts as converged only if, on every body, the applied
    ///         loads, contact forces and support reactions balance in force and moment to this
    ///         fraction of the largest force total of a body (default 1e-6 under the interface
    ///         Newton method, ``equilibrium_tol`` under the Robin sweeps).
    ///     gap_tol: augmented pairs: the largest violation of the Signorini conditions of a
    ///         converged result, a length.
    ///     max_updates: augmented pairs: the cap on multiplier updates (default 100).
    ///     load_steps: a number N of equal steps (load factors 1/N, …, 1) or the list of load
    ///         factors, run by :func:`solve_steps`; :func:`solve` refuses a problem with load
    ///         steps (other than the single factor 1).
    ///     monitor: the boundary whose mean displacement each result reports
    ///         (``Result.monitor``): ``{"body": name, "boundary": name}`` or
    ///         ``(body, boundary)``.
    ///     condensation: ``"auto"`` (the default), ``"dense"`` or ``"sparse"``: how each body
    ///         answers for its contact points (the results agree, the costs differ).
    #[pyo3(signature = (method = None, gamma = None, tol = None, max_iter = None, u0 = None, u_prev = None, threads = None, accelerator = None, coarse = None, equilibrium_tol = None, balance_tol = None, gap_tol = None, max_updates = None, load_steps = None, monitor = None, condensation = None))]
    #[allow(clippy::too_many_arguments)]
    fn solver(
        &mut self,
        method: Option<String>,
        gamma: Option<GammaArg>,
        tol: Option<f64>,
        max_iter: Option<usize>,
        u0: Option<f64>,
        u_prev: Option<f64>,
        threads: Option<usize>,
        accelerator: Option<String>,
        coarse: Option<String>,
        equilibrium_tol: Option<f64>,
        balance_tol: Option<f64>,
        gap_tol: Option<f64>,
        max_updates: Option<usize>,
        load_steps: Option<&Bound<'_, PyAny>>,
        monitor: Option<&Bound<'_, PyAny>>,
        condensation: Option<String>,
    ) -> PyResult<()> {
        let options = SolverOptions {
            method,
            gamma,
            accelerator,
            coarse,
            tol,
            max_iter,
            u0,
            u_prev,
            threads,
            gap_tol,
            equilibrium_tol,
            balance_tol,
            max_updates,
            condensation,
            enforcement: None,
            friction: None,
        };
        let settings = options.apply(&self.settings)?;
        // Every value is checked before any is kept.
        let load_steps = load_steps.map(load_steps_spec).transpose()?;
        let monitor = monitor.map(monitor_spec).transpose()?;
        if let Some(m) = &monitor {
            steps::monitor(self.model.bodies(), m)?;
        }
        self.settings = settings;
        if threads.is_some() {
            self.threads = threads;
        }
        if load_steps.is_some() {
            self.spec.solver.load_steps = load_steps;
        }
        if monitor.is_some() {
            self.spec.solver.monitor = monitor;
        }
        Ok(())
    }

    /// The names of the boundaries (and node sets) of a body.
    fn boundaries(&self, body: &str) -> PyResult<Vec<String>> {
        let b = self
            .model
            .bodies()
            .iter()
            .find(|b| b.name == body)
            .ok_or_else(|| input_error(format!("no body named '{body}'")))?;
        Ok(b.mesh
            .boundaries()
            .keys()
            .chain(b.mesh.node_sets().keys())
            .cloned()
            .collect())
    }

    /// Problem name.
    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }

    /// ``"strain"`` or ``"stress"``.
    #[getter]
    fn plane(&self) -> String {
        name_of(&self.model.plane())
    }

    /// Materials: ``{name: {"young": E, "poisson": ν}}``.
    #[getter]
    fn materials<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, m) in self.model.materials() {
            let entry = PyDict::new(py);
            entry.set_item("young", m.young())?;
            entry.set_item("poisson", m.poisson())?;
            d.set_item(name, entry)?;
        }
        Ok(d)
    }

    /// Body names, in order.
    #[getter]
    fn bodies(&self) -> Vec<String> {
        self.model.bodies().iter().map(|b| b.name.clone()).collect()
    }

    /// Contact pair names, in order.
    #[getter]
    fn contacts(&self) -> Vec<String> {
        self.model.pairs().iter().map(|p| p.name.clone()).collect()
    }

    /// Default solver settings, the keys of :meth:`solver`: ``method``, ``gamma``, ``tol``,
    /// ``max_iter``, ``u0``, ``u_prev``, ``threads``, ``accelerator``, ``coarse``,
    /// ``equilibrium_tol``, ``balance_tol``, ``gap_tol``, ``max_updates``, ``load_steps``, ``monitor`` and
    /// ``condensation`` (``None`` where unset: ``threads``, ``gap_tol``, ``load_steps``,
    /// ``monitor``).
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.settings;
        let d = PyDict::new(py);
        d.set_item("method", s.method.name())?;
        d.set_item("gamma", gamma_to_py(py, s.gamma)?)?;
        d.set_item("tol", s.tol)?;
        d.set_item("max_iter", s.max_iter)?;
        d.set_item("u0", s.u0)?;
        d.set_item("u_prev", s.u_prev)?;
        d.set_item("threads", self.threads)?;
        // The remaining keys as a problem file writes them.
        let written = write_problem::solver_spec(s, self.threads, &self.spec.solver);
        d.set_item("accelerator", written.accelerator.as_ref().map(name_of))?;
        d.set_item("coarse", written.coarse.as_ref().map(name_of))?;
        d.set_item("equilibrium_tol", s.equilibrium_tol)?;
        d.set_item("balance_tol", s.balance_tol)?;
        d.set_item("gap_tol", s.gap_tol)?;
        d.set_item("max_updates", s.max_updates)?;
        let steps = written.load_steps.as_ref();
        d.set_item(
            "load_steps",
            steps.map(|l| load_steps_to_py(py, l)).transpose()?,
        )?;
        let monitor = written.monitor.as_ref();
        d.set_item(
            "monitor",
            monitor.map(|m| monitor_to_py(py, m)).transpose()?,
        )?;
        d.set_item("condensation", s.condensation.to_string())?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let bodies = self.model.bodies();
        let nodes: usize = bodies.iter().map(|b| b.mesh.num_nodes()).sum();
        format!(
            "<contactdd.Problem '{}': {} bodies ({} nodes), {} contact pairs, plane {}, method {}, gamma {}>",
            self.name,
            bodies.len(),
            nodes,
            self.model.pairs().len(),
            name_of(&self.model.plane()),
            self.settings.method,
            self.settings.gamma
        )
    }
}
