//! What the whole solve needs to know of a body beyond its contact zones: its size, its rigid
//! motions and the work of its loads along them, its counts and its applied load. Computed from
//! the body where it is meshed; for a body another process meshes (`docs/mpi.md`), the facts
//! travel instead of the mesh ([`crate::model::Remote`]).

use contactdd_core::geometry::dot;
use contactdd_core::loads::applied_load;
use contactdd_core::rigid::{free_modes, RigidBasis, NUM_MODES};
use contactdd_core::{node_vector, ElasticBody, Order, Point, Vector};

/// The facts of one body.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyFacts {
    /// Number of nodes.
    pub nodes: usize,
    /// Number of elements.
    pub cells: usize,
    /// Number of prescribed displacement values (supports).
    pub prescribed: usize,
    /// Element order.
    pub order: Order,
    /// Lower corner of the bounding box of the nodes.
    pub lo: Point,
    /// Upper corner of the bounding box of the nodes.
    pub hi: Point,
    /// The rigid-body basis of the body's nodes.
    pub basis: RigidBasis,
    /// The rigid motions its supports leave free (coefficient vectors of `basis`).
    pub free: Vec<[f64; NUM_MODES]>,
    /// Per free mode R, the work Rᵀf of the body's load along it (at the full load).
    pub free_load: Vec<f64>,
    /// The sum of the nodal loads `[fx, fy]`.
    pub applied_load: Vector,
}

impl BodyFacts {
    /// The facts of `body`.
    pub fn of(body: &ElasticBody) -> BodyFacts {
        let mesh = &body.mesh;
        let (lo, hi) = mesh.bounding_box();
        let basis = RigidBasis::new(mesh);
        let free = free_modes(mesh, &body.constraints, &[]);
        let free_load = free
            .iter()
            .map(|v| {
                mesh.nodes()
                    .iter()
                    .enumerate()
                    .map(|(i, &x)| dot(basis.motion(x, v), node_vector(&body.load, i)))
                    .sum()
            })
            .collect();
        BodyFacts {
            nodes: mesh.num_nodes(),
            cells: mesh.num_cells(),
            prescribed: body.constraints.num_prescribed(),
            order: mesh.order(),
            lo,
            hi,
            basis,
            free,
            free_load,
            applied_load: applied_load(&body.load),
        }
    }
}
