//! The resolved multibody contact model: bodies (mesh, material, supports, loads) and contact
//! pairs. This is solver input, built from a problem file by the `contactdd-io` crate or directly
//! in code.

use contactdd_core::{Constraints, ElasticBody, Material, Mesh, Plane, Point, DIM};

use crate::facts::BodyFacts;
use crate::profile::GapProfile;

/// How the penalty parameter θ of a contact pair is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Penalty {
    /// θ given directly (length / stress units).
    Theta(f64),
    /// The rod model of docs/method.md §2: θ = c · h · (1/E*_α + 1/E*_β), which for equal materials is
    /// θ = 2 c h (1 − ν²)/E in plane strain (2 c h / E in plane stress). `c` is dimensionless, `h` a
    /// characteristic body height.
    RodModel {
        /// Dimensionless factor c (the benchmark uses 0.05).
        c: f64,
        /// Characteristic height h.
        h: f64,
    },
}

impl Penalty {
    /// θ for a pair of materials.
    pub fn theta(&self, a: &ElasticBody, b: &ElasticBody) -> f64 {
        let modulus = |body: &ElasticBody| body.material.plane_modulus(body.plane);
        match *self {
            Penalty::Theta(t) => t,
            Penalty::RodModel { c, h } => c * h * (1.0 / modulus(a) + 1.0 / modulus(b)),
        }
    }
}

/// The inner penalty of the augmented balanced pairs (`docs/augmented-lagrangian.md`, "Speed").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InnerPenalty {
    /// Every point's θ at most the rod model's with c = [`crate::contact::AUGMENTED_C`] and h
    /// the point's share of its boundary: each multiplier update then contracts by about the
    /// same factor whatever the pair's θ and the mesh. For the interface Newton method, whose
    /// count does not depend on θ.
    #[default]
    Stiffened,
    /// The pair's θ as given: for the Robin sweeps, whose count grows as θ stiffens.
    AsGiven,
}

/// How a contact pair enforces non-penetration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Enforcement {
    /// The paper's penalty formulation: the contact pressure is (s − d)⁺/θ, and the answer
    /// depends on θ (the bodies interpenetrate by θ·p).
    #[default]
    Penalty,
    /// The augmented Lagrangian (Uzawa) loop of [`crate::augmented`] around the penalty solves:
    /// converges to the exact unilateral (Signorini) contact for any fixed θ.
    Augmented,
}

impl std::fmt::Display for Enforcement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Enforcement::Penalty => "penalty",
            Enforcement::Augmented => "augmented",
        })
    }
}

/// How a contact pair's pressure loads its two bodies (docs/method.md §4, "Which normal the gap
/// uses").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Forces {
    /// Both sides read the gap along the normals of the flatter side, whose pressure loads both
    /// bodies with equal and opposite forces (dual mortar coefficients): the pair's forces
    /// balance on non-matching and curved zones. A pair whose sides match node for node on a
    /// flat zone is the same discrete problem as `OwnSide` and keeps its arithmetic.
    #[default]
    Balanced,
    /// The paper's formulation: each side is loaded only by its own points' pressure along its own
    /// normal, with the partner's displacement read along the partner's normal.
    OwnSide,
}

impl std::fmt::Display for Forces {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Forces::Balanced => "balanced",
            Forces::OwnSide => "own-side",
        })
    }
}

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
