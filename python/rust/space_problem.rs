//! `contactdd.space.Problem`: a contact problem in space read from a problem file or built in
//! code.
//!
//! The problem holds its problem-file schema (`contactdd_io::solid_problem::SolidProblem`) and the
//! model resolved from it (`contactdd_io::solid_setup::resolve_solid`). Every `add_*` call adds a
//! schema entry to a copy of the schema and resolves the copy, which checks the entry as it
//! checks the same entry of a file; the problem keeps the copy only if it resolves, so a bad
//! value gets the message a problem file would get and leaves the problem as it was. Supports,
//! loads and penalties are Python dicts and keywords deserialized into the schema (the keys,
//! kinds and defaults of the TOML tables); meshes given as arrays or as Gmsh text become inline
//! mesh tables, which :meth:`to_toml` writes out.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple, PyType};

use contactdd_core::gmsh::parse_solid_msh;
use contactdd_core::names::shown;
use contactdd_core::Order;
use contactdd_io::problem::{LoadStepsSpec, MaterialSpec, MonitorSpec, PenaltySpec};
use contactdd_io::solid_problem::{
    is_solid_text, SolidBodyEntry, SolidContactSpec, SolidMeshSpec, SolidProblem,
};
use contactdd_io::solid_setup::{resolve_solid, SolidLoadError, SolidModel};

use crate::convert::from_name;
use crate::error::{input_error, os_error, setup_error};
use crate::schema::{pair_option, specs, text};
use crate::space_schema::{absolute_solid_paths, inline_arrays, inline_solid, mesh_error};

/// A contact problem in space: tetrahedral bodies, their supports and loads, the contact pairs
/// and the solver settings of a problem file with ``dimension = 3`` (``docs/three-d.md``,
/// "Problem files and results"), every value checked and every body meshed.
///
/// Read one from a problem file with :meth:`from_toml` or :meth:`from_toml_str`, or build it in
/// code::
///
///     p = space.Problem(name="blocks", units="m, MPa")
///     p.add_material("steel", young=2.1e5, poisson=0.3)
///     p.add_box_body("lower", x=(0, 1), y=(0, 1), z=(0, 0.5), nx=6, ny=6, nz=3,
///                    material="steel",
///                    supports=[{"boundary": "z-", "component": "z"}])
///     ...
///     p.add_contact(bodies=("upper", "lower"), boundaries=("z-", "z+"), theta=1e-7)
///
/// Every ``add_*`` call checks its input at once and raises :class:`contactdd.ContactddError`
/// with the message a problem file would get (naming the body, pair or key); the problem is left
/// as it was. Solved by :func:`contactdd.space.solve` (the decomposition) or
/// :func:`contactdd.space.monolithic` (the reference).
#[pyclass(module = "contactdd.space", name = "Problem")]
pub struct SpaceProblem {
    /// The problem as a problem file says it (Gmsh paths absolute): what `to_toml` writes.
    spec: SolidProblem,
    /// The resolved problem; `None` while the problem has no body.
    model: Option<Arc<SolidModel>>,
}

impl SpaceProblem {
    /// The resolved problem, for a solve.
    pub(crate) fn model(&self) -> PyResult<Arc<SolidModel>> {
        self.model.clone().ok_or_else(|| {
            input_error(format!(
                "problem '{}': no body: add one with add_body, add_box_body or add_msh_body",
                shown(&self.name())
            ))
        })
    }

    fn name(&self) -> String {
        self.spec.name.clone().unwrap_or_else(|| "problem".into())
    }

    /// Parses and resolves `text`, a problem file in space named `source` in messages, whose
    /// relative Gmsh paths resolve against `base`; `stem` is the default name.
    fn parse(
        py: Python<'_>,
        text: &str,
        source: &str,
        base: &Path,
        stem: &str,
    ) -> PyResult<SpaceProblem> {
        if !is_solid_text(text) {
            return Err(input_error(format!(
                "{source}: not a problem in space: it has no top-level `dimension = 3` \
                 (contactdd.Problem.from_toml reads a planar problem)"
            )));
        }
        let mut spec: SolidProblem = toml::from_str(text).map_err(|e| {
            input_error(SolidLoadError::Toml {
                file: source.to_string(),
                source: e,
            })
        })?;
        let invalid = |message: String| {
            input_error(SolidLoadError::Invalid {
                file: source.to_string(),
                message,
            })
        };
        let resolving = spec.clone();
        let model = py
            .detach(|| resolve_solid(resolving, base, stem))
            .map_err(invalid)?;
        absolute_solid_paths(&mut spec, base)?;
        spec.name = Some(model.name.clone());
        Ok(SpaceProblem {
            spec,
            model: Some(Arc::new(model)),
        })
    }

    /// Resolves `candidate` (a copy of the schema with one entry more) and keeps it if it
    /// resolves; a problem without bodies is only kept (there is nothing to resolve yet).
    fn commit(&mut self, py: Python<'_>, candidate: SolidProblem) -> PyResult<()> {
        if candidate.bodies.is_empty() {
            self.spec = candidate;
            return Ok(());
        }
        let resolving = candidate.clone();
        let model = py
            .detach(|| resolve_solid(resolving, Path::new(""), "problem"))
            .map_err(input_error)?;
        self.spec = candidate;
        self.model = Some(Arc::new(model));
        Ok(())
    }

    /// Adds body `name` on `mesh` with its supports and loads (Python lists of dicts).
    fn add_entry(
        &mut self,
        py: Python<'_>,
        name: &str,
        material: &str,
        mesh: SolidMeshSpec,
        supports: Option<&Bound<'_, PyAny>>,
        loads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let entry = SolidBodyEntry {
            name: name.to_string(),
            material: material.to_string(),
            mesh,
            supports: specs(name, "supports", supports)?,
            loads: specs(name, "loads", loads)?,
        };
        let mut candidate = self.spec.clone();
        candidate.bodies.push(entry);
        self.commit(py, candidate)
    }

    /// Refuses a body name the problem already has, before its mesh is read.
    fn check_new_body(&self, name: &str) -> PyResult<()> {
        if self.spec.bodies.iter().any(|b| b.name == name) {
            return Err(input_error(format!(
                "two bodies are called '{}'",
                shown(name)
            )));
        }
        Ok(())
    }

    /// The problem file text of the problem (see :meth:`to_toml`).
    fn toml_text(&self) -> PyResult<String> {
        toml::to_string(&self.spec)
            .map_err(|e| input_error(format!("cannot write the problem as TOML: {e}")))
    }
}

#[pymethods]
impl SpaceProblem {
    /// An empty problem in space.
    ///
    /// Args:
    ///     name: problem name used in output files.
    ///     units: a free-text note on the (consistent) units used, written to the result
    ///         files; not interpreted.
    #[new]
    #[pyo3(signature = (name = None, units = None), text_signature = "(name='problem', units=None)")]
    fn new(name: Option<&Bound<'_, PyAny>>, units: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        // Strings checked here, so that another type raises a `ContactddError` naming the
        // argument (the methods get theirs from `contactdd._arguments`).
        let name = name.map_or(Ok("problem".into()), |n| text(n, "name"))?;
        let units = units
            .filter(|u| !u.is_none())
            .map(|u| text(u, "units"))
            .transpose()?;
        Ok(SpaceProblem {
            spec: SolidProblem {
                name: Some(name),
                dimension: 3,
                units,
                materials: BTreeMap::new(),
                bodies: Vec::new(),
                contact: Vec::new(),
                solver: Default::default(),
                output: Default::default(),
            },
            model: None,
        })
    }

    /// Reads a problem file in space (``dimension = 3``).
    ///
    /// Relative Gmsh mesh paths resolve against the file's folder; the problem's name defaults
    /// to the file's stem.
    ///
    /// Args:
    ///     path: the problem file.
    ///
    /// Raises:
    ///     ContactddIOError: the file cannot be read (an ``OSError``).
    ///     ContactddError: the file is not a valid problem in space; the message names the
    ///         body, pair or key.
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<SpaceProblem> {
        let text = py.detach(|| std::fs::read_to_string(&path)).map_err(|e| {
            let errno = e.raw_os_error();
            let message = SolidLoadError::Io {
                path: path.display().to_string(),
                source: e,
            };
            os_error(py, message.to_string(), errno)
        })?;
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("problem");
        let base = path.parent().unwrap_or(Path::new(""));
        let source = path.display().to_string();
        SpaceProblem::parse(py, &text, &source, base, stem)
    }

    /// Parses the text of a problem file in space (``dimension = 3``).
    ///
    /// Args:
    ///     text: the file's content.
    ///     base_dir: folder against which relative mesh paths resolve (default: the current
    ///         folder).
    ///     source: name of the text in error messages.
    ///
    /// Raises:
    ///     ContactddError: the text is not a valid problem in space.
    #[staticmethod]
    #[pyo3(signature = (text, base_dir = None, source = "<string>"))]
    fn from_toml_str(
        py: Python<'_>,
        text: &str,
        base_dir: Option<PathBuf>,
        source: &str,
    ) -> PyResult<SpaceProblem> {
        let base = base_dir.unwrap_or_else(|| PathBuf::from("."));
        SpaceProblem::parse(py, text, source, &base, "problem")
    }

    /// The problem as the text of a problem file in space, which :meth:`from_toml_str` reads
    /// back to the same problem (the same solve results, bit for bit).
    ///
    /// A Gmsh mesh path is written absolute (a relative one resolved when the problem was
    /// read), so the text reads the same meshes whatever ``base_dir`` it is given. A body added
    /// from arrays or Gmsh text (:meth:`add_body`, :meth:`add_msh_body`) is written inline, as a
    /// ``kind = "inline"`` mesh with its ``nodes``, ``tetrahedra`` and ``faces``.
    fn to_toml(&self) -> PyResult<String> {
        self.toml_text()
    }

    /// Defines a linear elastic isotropic material.
    ///
    /// Args:
    ///     name: the name bodies refer to.
    ///     young: Young's modulus E > 0.
    ///     poisson: Poisson's ratio ν in (-1, 0.5).
    #[pyo3(signature = (name, young, poisson))]
    fn add_material(&mut self, name: &str, young: f64, poisson: f64) -> PyResult<()> {
        if let Some(why) = contactdd_core::names::name_problem(name) {
            return Err(input_error(format!("materials: {why}")));
        }
        if self.spec.materials.contains_key(name) {
            return Err(input_error(format!(
                "material '{}': is already defined",
                shown(name)
            )));
        }
        contactdd_io::setup::material(name, young, poisson).map_err(setup_error)?;
        let spec = MaterialSpec { young, poisson };
        self.spec.materials.insert(name.to_string(), spec);
        Ok(())
    }

    /// Adds a body on a tetrahedral mesh given as arrays (a ``kind = "inline"`` mesh).
    ///
    /// Args:
    ///     name: unique body name.
    ///     nodes: ``(n, 3)`` node coordinates.
    ///     tetrahedra: ``(m, 4)`` (P1) or ``(m, 10)`` (P2, Gmsh's order: vertices, then the
    ///         mid-edge nodes of edges 0-1, 1-2, 0-2, 0-3, 2-3, 1-3) node indices, each
    ///         tetrahedron positively oriented; every node belongs to one.
    ///     faces: named faces, ``{name: (k, 3) array}`` of boundary triangles (``(k, 6)`` on
    ///         P2 tetrahedra: vertices, then the mid-edge nodes of edges 0-1, 1-2, 2-0, the
    ///         ones the tetrahedra give the edges); each triangle is a face of exactly one
    ///         tetrahedron, in any orientation.
    ///     material: name of a material added with :meth:`add_material`.
    ///     supports: list of ``{"boundary": str, "component": "x"|"y"|"z"|"all",
    ///         "value": float = 0}``.
    ///     loads: list of ``{"kind": "pressure", "boundary": str, "value": float}`` (positive:
    ///         pushing into the body), ``{"kind": "traction", "boundary": str, "value": [tx, ty,
    ///         tz]}`` or ``{"kind": "body-force", "value": [fx, fy, fz]}``.
    ///
    /// Raises:
    ///     ContactddError: bad arrays (a shape, a node index out of range, an inverted
    ///         tetrahedron, a triangle that is no boundary face) or values; the message names
    ///         the body.
    #[pyo3(signature = (name, nodes, tetrahedra, faces, material, supports = None, loads = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        py: Python<'_>,
        name: &str,
        nodes: &Bound<'_, PyAny>,
        tetrahedra: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        material: &str,
        supports: Option<&Bound<'_, PyAny>>,
        loads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        self.check_new_body(name)?;
        let mesh = inline_arrays(name, nodes, tetrahedra, faces)?;
        self.add_entry(py, name, material, mesh, supports, loads)
    }

    /// Adds a body meshed as a structured box ``x[0] ≤ x ≤ x[1]``, ``y[0] ≤ y ≤ y[1]``,
    /// ``z[0] ≤ z ≤ z[1]`` with ``nx × ny × nz`` cubes of six tetrahedra each (a ``kind =
    /// "box"`` mesh); its faces are ``x-``, ``x+``, ``y-``, ``y+``, ``z-`` and ``z+``.
    ///
    /// Args:
    ///     order: ``"p1"`` (4-node tetrahedra) or ``"p2"`` (10-node).
    ///     supports, loads: as for :meth:`add_body`.
    #[pyo3(signature = (name, x, y, z, nx, ny, nz, material, order = "p1", supports = None, loads = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_box_body(
        &mut self,
        py: Python<'_>,
        name: &str,
        x: (f64, f64),
        y: (f64, f64),
        z: (f64, f64),
        nx: usize,
        ny: usize,
        nz: usize,
        material: &str,
        order: &str,
        supports: Option<&Bound<'_, PyAny>>,
        loads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        self.check_new_body(name)?;
        let order: Order = from_name(order)
            .map_err(|e| input_error(format!("body '{}': mesh.order: {e}", shown(name))))?;
        let mesh = SolidMeshSpec::Box {
            x: [x.0, x.1],
            y: [y.0, y.1],
            z: [z.0, z.1],
            nx,
            ny,
            nz,
            order,
        };
        self.add_entry(py, name, material, mesh, supports, loads)
    }

    /// Adds a body on a mesh given as the text of a Gmsh ``.msh`` file (ASCII 4.1 or 2.2), read
    /// by the reader of ``kind = "gmsh"`` meshes with its rules: the tetrahedra of the physical
    /// volume ``volume`` are the body (default: every tetrahedron of a text with at most one
    /// physical volume), the physical surfaces are its faces (the triangles of another body
    /// left out), negatively oriented tetrahedra are reoriented. The mesh is kept in the
    /// problem (a ``kind = "inline"`` mesh for :meth:`to_toml`).
    /// :func:`contactdd.space.add_meshio_body` and :func:`contactdd.space.add_gmsh_body` use it.
    ///
    /// Args:
    ///     name: unique body name.
    ///     text: the ``.msh`` text.
    ///     material: name of a material added with :meth:`add_material`.
    ///     volume: the body's physical volume (name, or tag number of an unnamed group).
    ///     supports, loads: as for :meth:`add_body`.
    ///     source: what the text is, in error messages.
    #[pyo3(signature = (name, text, material, volume = None, supports = None, loads = None, source = "<msh text>"))]
    #[allow(clippy::too_many_arguments)]
    fn add_msh_body(
        &mut self,
        py: Python<'_>,
        name: &str,
        text: &str,
        material: &str,
        volume: Option<&str>,
        supports: Option<&Bound<'_, PyAny>>,
        loads: Option<&Bound<'_, PyAny>>,
        source: &str,
    ) -> PyResult<()> {
        self.check_new_body(name)?;
        let mesh = py
            .detach(|| parse_solid_msh(text, volume))
            .map_err(|e| mesh_error(name, format!("{source}: {e}")))?;
        self.add_entry(py, name, material, inline_solid(&mesh), supports, loads)
    }

    /// Adds a contact pair: face ``boundaries[0]`` of body ``bodies[0]`` (the reference side:
    /// its nodes are the contact points) may touch face ``boundaries[1]`` of body ``bodies[1]``.
    ///
    /// The penalty is either the rod model θ = c·h·(1/E*₁ + 1/E*₂) (give ``c`` and ``h``) or
    /// ``theta`` itself.
    ///
    /// Args:
    ///     search: how far along the reference normals a partner counts (default: a tenth of
    ///         the smaller body's bounding-box diameter).
    ///     name: pair name (default ``"<body0>-<body1>"``).
    ///     enforcement: ``"penalty"`` (default: the pressure max(0, s − d)/θ) or
    ///         ``"augmented"`` (the exact Signorini conditions, whatever θ).
    ///     friction: the tangential law: ``None`` (frictionless, the default),
    ///         ``{"law": "coulomb", "mu": float}`` (|τ| ≤ μp), ``{"law": "tresca", "bound":
    ///         float}`` (|τ| ≤ bound) or ``{"law": "none"}``.
    #[pyo3(signature = (bodies, boundaries, c = None, h = None, theta = None, search = None, name = None, enforcement = None, friction = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_contact(
        &mut self,
        py: Python<'_>,
        bodies: (String, String),
        boundaries: (String, String),
        c: Option<f64>,
        h: Option<f64>,
        theta: Option<f64>,
        search: Option<f64>,
        name: Option<String>,
        enforcement: Option<String>,
        friction: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let enforcement = (enforcement.as_deref())
            .map(|e| from_name(e).map_err(|m| input_error(format!("enforcement: {m}"))))
            .transpose()?;
        let mut spec = SolidContactSpec {
            name,
            bodies: vec![bodies.0, bodies.1],
            boundaries: vec![boundaries.0, boundaries.1],
            penalty: PenaltySpec { c, h, theta },
            search,
            enforcement,
            friction: None,
        };
        let pair = spec.pair_name();
        spec.friction = pair_option(friction, "friction", &pair)?;
        if self.spec.contact.iter().any(|p| p.pair_name() == pair) {
            return Err(input_error(format!(
                "two contact pairs are called '{}'",
                shown(&pair)
            )));
        }
        let mut candidate = self.spec.clone();
        candidate.contact.push(spec);
        self.commit(py, candidate)
    }

    /// Sets the problem's ``[solver]`` table: the defaults of :func:`contactdd.space.solve` and
    /// :func:`contactdd.space.monolithic`, which can still override each. Arguments left at
    /// ``None`` keep their value.
    ///
    /// Args:
    ///     balance_tol: the force balance's tolerance of a converged result (default 1e-6).
    ///     threads: worker threads (default: all cores).
    ///     load_steps: solve at increasing loads: a number of equal steps, or the list of load
    ///         factors (``[solver] load-steps``); the result's ``summary()["load_steps"]`` holds
    ///         every step.
    ///     monitor: ``(body, face)`` whose mean displacement each load step reports.
    #[pyo3(signature = (balance_tol = None, threads = None, load_steps = None, monitor = None))]
    fn solver(
        &mut self,
        py: Python<'_>,
        balance_tol: Option<f64>,
        threads: Option<usize>,
        load_steps: Option<&Bound<'_, PyAny>>,
        monitor: Option<(String, String)>,
    ) -> PyResult<()> {
        if let Some(b) = balance_tol.filter(|b| !(b.is_finite() && *b > 0.0)) {
            return Err(input_error(format!(
                "solver.balance-tol = {b}: must be positive"
            )));
        }
        if threads == Some(0) {
            return Err(input_error("solver.threads = 0: must be at least 1"));
        }
        let load_steps = load_steps.map(load_steps_arg).transpose()?;
        let mut candidate = self.spec.clone();
        let solver = &mut candidate.solver;
        solver.balance_tol = balance_tol.or(solver.balance_tol);
        solver.threads = threads.or(solver.threads);
        solver.load_steps = load_steps.or(solver.load_steps.take());
        if let Some((body, boundary)) = monitor {
            solver.monitor = Some(MonitorSpec { body, boundary });
        }
        self.commit(py, candidate)
    }

    /// The names of the faces of a body.
    fn boundaries(&self, body: &str) -> PyResult<Vec<String>> {
        let found = (self.model.iter())
            .flat_map(|m| m.bodies.iter())
            .find(|b| b.name == body)
            .ok_or_else(|| input_error(format!("no body named '{}'", shown(body))))?;
        Ok(found.mesh.face_names().map(str::to_string).collect())
    }

    /// The problem's name.
    #[getter(name)]
    fn get_name(&self) -> String {
        self.name()
    }

    /// The free-text note on the units, or ``None``.
    #[getter]
    fn units(&self) -> Option<String> {
        self.spec.units.clone()
    }

    /// Materials: ``{name: {"young": E, "poisson": ν}}``.
    #[getter]
    fn materials<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, m) in &self.spec.materials {
            let entry = PyDict::new(py);
            entry.set_item("young", m.young)?;
            entry.set_item("poisson", m.poisson)?;
            d.set_item(name, entry)?;
        }
        Ok(d)
    }

    /// The bodies' names, in problem order.
    #[getter]
    fn bodies(&self) -> Vec<String> {
        self.spec.bodies.iter().map(|b| b.name.clone()).collect()
    }

    /// The contact pairs' names, in problem order.
    #[getter]
    fn contacts(&self) -> Vec<String> {
        self.spec.contact.iter().map(|p| p.pair_name()).collect()
    }

    /// The force balance's tolerance of a converged result (``[solver] balance-tol``, default
    /// 1e-6).
    #[getter]
    fn balance_tol(&self) -> f64 {
        (self.spec.solver.balance_tol).unwrap_or(contactdd_io::solid_setup::SOLID_BALANCE_TOL)
    }

    /// The worker threads of ``[solver] threads``, or ``None`` (all cores).
    #[getter]
    fn threads(&self) -> Option<usize> {
        self.spec.solver.threads
    }

    fn __repr__(&self) -> String {
        let nodes: usize = (self.model.iter())
            .flat_map(|m| m.bodies.iter())
            .map(|b| b.mesh.num_nodes())
            .sum();
        format!(
            "<contactdd.space.Problem '{}': {} bodies ({} nodes), {} contact pairs>",
            self.name(),
            self.spec.bodies.len(),
            nodes,
            self.spec.contact.len()
        )
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
    fn _from_toml_text(
        _cls: &Bound<'_, PyType>,
        py: Python<'_>,
        text: &str,
    ) -> PyResult<SpaceProblem> {
        SpaceProblem::parse(py, text, "<pickle>", Path::new("."), "problem")
    }
}

/// The `load_steps=` keyword: a number of equal steps or a list of load factors.
fn load_steps_arg(obj: &Bound<'_, PyAny>) -> PyResult<LoadStepsSpec> {
    if let Ok(n) = obj.extract::<usize>() {
        return Ok(LoadStepsSpec::Count(n));
    }
    obj.extract::<Vec<f64>>()
        .map(LoadStepsSpec::Factors)
        .map_err(|_| {
            input_error("load_steps: expected a number of steps or a list of load factors")
        })
}
