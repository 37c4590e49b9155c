//! [`ModelBuilder`]: a [`Model`] built entry by entry, each entry checked as it is added. The
//! resolve step of a problem file and a problem built in code (the Python module) share it, so
//! both get the same validation and the same messages.

use std::collections::BTreeMap;
use std::path::Path;

use contactdd_core::{ElasticBody, Material, Mesh, Plane};
use contactdd_ddm::{ContactPair, Model, Remote, SetupError};

use crate::bodies::{body_on_mesh, check_body_name, check_floating, material};
use crate::error::{body_error, no_bodies, LoadError};
use crate::meshes::mesh;
use crate::names::{check_body_names, check_entry_names, check_name, check_pair_names};
use crate::pairs::pair;
use crate::problem::{BodySpec, ContactSpec, LoadSpec, MaterialSpec, SupportSpec};
use contactdd_core::names::{listed, shown};

/// Builds a [`Model`] entry by entry, checking each entry as it is added: the one resolve step of
/// a problem file ([`crate::setup::resolve`]) and of a problem built in code (the Python module).
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
        check_name("materials", name)?;
        if self.materials.contains_key(name) {
            return Err(SetupError::Material {
                material: shown(name),
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
        check_body_names(self.bodies.len(), spec)?;
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

    /// Adds a body on a mesh built by the caller (e.g. [`crate::meshes::mesh_from_arrays`]), checked like a
    /// `[[bodies]]` entry.
    pub fn add_body_on_mesh(
        &mut self,
        name: &str,
        material: &str,
        mesh: Mesh,
        supports: &[SupportSpec],
        loads: &[LoadSpec],
    ) -> Result<(), SetupError> {
        let key = format!("bodies[{}]", self.bodies.len());
        check_name(format!("{key}.name"), name)?;
        check_name(format!("{key}.material"), material)?;
        check_entry_names(&key, supports, loads)?;
        self.check_body_name(name)?;
        let material = self.material_of(name, material)?;
        let body = body_on_mesh(name, mesh, material, self.plane, supports, loads)?;
        self.push_body(body, None);
        Ok(())
    }

    /// Adds a `[[contact]]` entry between two of the bodies added so far.
    pub fn add_pair(&mut self, spec: &ContactSpec) -> Result<(), SetupError> {
        check_pair_names(self.pairs.len(), spec)?;
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
                    "unknown material '{}' (known: {})",
                    shown(material),
                    known(self.materials.keys())
                ),
            )
        })
    }
}

fn known<'a>(names: impl Iterator<Item = &'a String>) -> String {
    let names = listed(names.map(String::as_str));
    if names.is_empty() {
        "none defined".into()
    } else {
        names.join(", ")
    }
}
