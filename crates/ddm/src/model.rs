//! The resolved multibody contact model: bodies (mesh, material, supports, loads) and contact
//! pairs. This is solver input, built from a problem file by the `contactdd-io` crate or directly
//! in code.

use contactdd_core::{Constraints, ElasticBody, Material, Mesh, Plane, Point, DIM};

use crate::contact::formulation::Formulation;
use crate::contact::formulation::{Enforcement, Forces, InnerPenalty, Penalty};
use crate::contact::friction::Friction;
use crate::contact::gap_profile::GapProfile;
use crate::error::SetupError;
use crate::facts::BodyFacts;

/// A contact pair: boundary `boundaries[0]` of body `bodies[0]` may touch boundary
/// `boundaries[1]` of body `bodies[1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPair {
    /// Pair name used in output.
    pub name: String,
    /// Body indices (distinct).
    pub bodies: [usize; 2],
    /// Boundary names, one per body.
    pub boundaries: [String; 2],
    /// Penalty.
    pub penalty: Penalty,
    /// Prescribed gap profile added to the geometric gap (e.g. the notch).
    pub profile: Option<GapProfile>,
    /// Penalty (the default) or augmented Lagrangian.
    pub enforcement: Enforcement,
    /// How the pressure loads the two bodies.
    pub forces: Forces,
    /// The tangential law (frictionless by default; friction needs balanced forces).
    pub friction: Friction,
}

impl ContactPair {
    /// The pair's formulation between its bodies in `bodies`, under the solve's inner penalty
    /// `inner` of the augmented balanced pairs; an error if its θ is not positive and finite.
    pub fn formulation(
        &self,
        bodies: &[ElasticBody],
        inner: InnerPenalty,
    ) -> Result<Formulation, SetupError> {
        let (a, b) = (&bodies[self.bodies[0]], &bodies[self.bodies[1]]);
        let theta = self.penalty.theta(a, b);
        if !(theta.is_finite() && theta > 0.0) {
            return Err(SetupError::Pair {
                pair: self.name.clone(),
                message: format!("the penalty θ must be positive and finite, got {theta}"),
            });
        }
        let problem = self.friction.problem().or_else(|| {
            (self.friction.is_active() && self.forces == Forces::OwnSide).then(|| {
                "friction needs forces = \"balanced\" (own-side pairs carry no tangential \
                 forces)"
                    .to_string()
            })
        });
        if let Some(message) = problem {
            return Err(SetupError::Pair {
                pair: self.name.clone(),
                message,
            });
        }
        Ok(
            Formulation::new(theta, self.enforcement, self.forces, inner)
                .with_friction(self.friction),
        )
    }
}

/// Bodies and contact pairs.
#[derive(Clone, Debug)]
pub struct Model {
    /// Problem name.
    pub name: String,
    /// Plane strain or stress, as a description of the problem: every body carries its own
    /// (`ElasticBody::plane`), and stiffness, stresses and penalty read only the body's.
    pub plane: Plane,
    /// The bodies.
    pub bodies: Vec<ElasticBody>,
    /// The contact pairs.
    pub pairs: Vec<ContactPair>,
    /// Per body, `Some` where another process meshes it (a distributed solve, docs/mpi.md);
    /// empty, or all `None`, when this process meshes every body.
    pub remote: Vec<Option<Remote>>,
}

/// A body that another process meshes: this process holds only its contact boundaries (the
/// body's `mesh` is that skin, with its nodes numbered compactly, no elements, no supports and
/// no loads) and the facts the solve needs of the rest.
#[derive(Clone, Debug, PartialEq)]
pub struct Remote {
    /// The body's own number of each node of the skin, increasing.
    pub ids: Vec<usize>,
    /// What the solve needs of the whole body.
    pub facts: BodyFacts,
}

impl Remote {
    /// `body` as the processes that do not mesh it hold it: the stand-in on its skin on the
    /// boundaries `contact` (those of its contact pairs), and the remote part.
    pub fn of(body: &ElasticBody, contact: &[&str]) -> (ElasticBody, Remote) {
        let (mesh, ids) = body.mesh.skin(contact);
        let facts = BodyFacts::of(body);
        let stand_in = Remote::stand_in(&body.name, mesh, body.material, body.plane);
        (stand_in, Remote { ids, facts })
    }

    /// The stand-in of a remote body on its skin `mesh`: no supports, no loads.
    pub fn stand_in(name: &str, mesh: Mesh, material: Material, plane: Plane) -> ElasticBody {
        let n = mesh.num_nodes();
        ElasticBody {
            name: name.to_string(),
            constraints: Constraints::new(n),
            load: vec![0.0; DIM * n],
            mesh,
            material,
            plane,
        }
    }
}

impl Model {
    /// The penalty θ of pair `p`.
    pub fn theta(&self, p: usize) -> f64 {
        let pair = &self.pairs[p];
        let (a, b) = (&self.bodies[pair.bodies[0]], &self.bodies[pair.bodies[1]]);
        pair.penalty.theta(a, b)
    }

    /// True if some pair uses the augmented Lagrangian.
    pub fn is_augmented(&self) -> bool {
        self.pairs
            .iter()
            .any(|p| p.enforcement == Enforcement::Augmented)
    }

    /// Body `b` if another process meshes it.
    pub fn remote(&self, b: usize) -> Option<&Remote> {
        self.remote.get(b).and_then(Option::as_ref)
    }

    /// The facts of body `b`: its own, or those its process sent.
    pub fn facts(&self, b: usize) -> BodyFacts {
        match self.remote(b) {
            Some(r) => r.facts.clone(),
            None => BodyFacts::of(&self.bodies[b]),
        }
    }

    /// The bounding box of body `b`'s nodes (lower, upper corner): its own, or the one its
    /// process sent. Cheaper than [`Model::facts`] where only the size is needed.
    pub fn bounds(&self, b: usize) -> (Point, Point) {
        match self.remote(b) {
            Some(r) => (r.facts.lo, r.facts.hi),
            None => self.bodies[b].mesh.bounding_box(),
        }
    }

    /// The position of node `node` (in the body's own numbering) of body `b` (NaN for a node a
    /// remote body's skin does not hold).
    pub fn position(&self, b: usize, node: usize) -> Point {
        let nodes = self.bodies[b].mesh.nodes();
        match self.remote(b) {
            Some(r) => r
                .ids
                .binary_search(&node)
                .map_or([f64::NAN; 2], |k| nodes[k]),
            None => nodes[node],
        }
    }

    /// The boundaries of body `b` that its contact pairs name, in pair order, each once.
    pub fn contact_boundaries(&self, b: usize) -> Vec<&str> {
        let mut names: Vec<&str> = Vec::new();
        for pair in &self.pairs {
            for s in 0..2 {
                let name = pair.boundaries[s].as_str();
                if pair.bodies[s] == b && !names.contains(&name) {
                    names.push(name);
                }
            }
        }
        names
    }

    /// The model as a process that meshes only the bodies `owns` selects holds it: every other
    /// body as its stand-in on its contact skin, with its remote part ([`Remote::of`]). A
    /// distributed solve builds this directly, without meshing the others (`contactdd-io`);
    /// this serves to compare the two.
    pub fn as_seen_by(&self, owns: impl Fn(usize) -> bool) -> Model {
        let mut seen = self.clone();
        seen.remote = vec![None; self.bodies.len()];
        for b in (0..self.bodies.len()).filter(|&b| !owns(b)) {
            let (stand_in, remote) = Remote::of(&self.bodies[b], &self.contact_boundaries(b));
            seen.bodies[b] = stand_in;
            seen.remote[b] = Some(remote);
        }
        seen
    }

    /// θ of every pair.
    pub fn thetas(&self) -> Vec<f64> {
        (0..self.pairs.len()).map(|p| self.theta(p)).collect()
    }
}
