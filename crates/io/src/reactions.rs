//! Support reactions of a solved model: the force the supports exert on each body, per supported
//! boundary and in total.
//!
//! Computed here, from the model and the displacement fields, so that every solver's result (DD or
//! monolithic) gets the same numbers. On a supported DOF the residual `K u − f` is the support
//! reaction plus the contact force at that node, if it is a contact node too; the nodal contact
//! forces of the reported pressures (w σ_n n) are subtracted, so that a body's balance reads
//! `applied load + reactions + contact force = 0` up to the solver's equilibrium residual.

use contactdd_core::post::residual;
use contactdd_core::{dof, Vector, DIM};
use contactdd_ddm::solution::{BodyResult, PairResult};
use contactdd_ddm::Model;

/// The reaction on one supported boundary (or Gmsh node set) of a body.
#[derive(Clone, Debug, PartialEq)]
pub struct SupportReaction {
    /// The boundary or node set name.
    pub boundary: String,
    /// Total force `[Rx, Ry]` the support exerts on the body's nodes on this boundary.
    pub force: Vector,
}

/// The reactions of one body.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyReactions {
    /// Body name.
    pub body: String,
    /// One entry per supported boundary, in name order. A node on two supported boundaries (a
    /// corner) counts in both, so these add up to `total` only when supports share no node.
    pub supports: Vec<SupportReaction>,
    /// Sum over every supported DOF of the body, each counted once.
    pub total: Vector,
}

/// The reactions of every body of `model` whose field this process holds (every body in one
/// process), from the per-body fields `bodies` (same order as `model.bodies`) and the contact
/// results `contact` (same order as `model.pairs`).
///
/// A boundary or node set counts as supported when every one of its nodes has a prescribed
/// displacement component (or lies on an inclined `normal` support); its reaction sums the
/// prescribed components of its nodes, both components on a node of an inclined support, whose
/// reaction lies along its normal.
pub fn reactions(
    model: &Model,
    bodies: &[BodyResult],
    contact: &[PairResult],
) -> Vec<BodyReactions> {
    (bodies.iter().enumerate())
        .filter(|(_, fields)| fields.has_fields())
        .map(|(b, fields)| body_reactions(model, b, fields, contact))
        .collect()
}

/// The reactions of body `b` from its field `fields` (see [`reactions`]).
pub fn body_reactions(
    model: &Model,
    b: usize,
    fields: &BodyResult,
    contact: &[PairResult],
) -> BodyReactions {
    let body = &model.bodies[b];
    let fc = nodal_contact_force(model, b, contact);
    let r = residual(&body.stiffness(), &fields.displacement, &body.load);
    let reaction = |d: usize| r[d] - fc[d];
    // A node of an inclined normal support counts with both components: its reaction lies
    // along the normal.
    let fixed = |d: usize| body.constraints.holds(d);
    let mesh = &body.mesh;
    let names = mesh.boundaries().keys().chain(mesh.node_sets().keys());
    let supports = names
        .filter_map(|name| {
            let nodes = mesh.boundary_nodes(name).ok()?;
            let held = |&v: &usize| (0..DIM).any(|c| fixed(dof(v, c)));
            (!nodes.is_empty() && nodes.iter().all(held)).then(|| SupportReaction {
                boundary: name.clone(),
                force: sum_fixed(nodes.iter().copied(), &fixed, &reaction),
            })
        })
        .collect();
    BodyReactions {
        body: body.name.clone(),
        supports,
        total: sum_fixed(0..mesh.num_nodes(), &fixed, &reaction),
    }
}

/// Σ over `nodes` and their prescribed components of `reaction(dof)`.
fn sum_fixed(
    nodes: impl Iterator<Item = usize>,
    fixed: &impl Fn(usize) -> bool,
    reaction: &impl Fn(usize) -> f64,
) -> Vector {
    let mut sum = [0.0; DIM];
    for v in nodes {
        for (c, s) in sum.iter_mut().enumerate() {
            if fixed(dof(v, c)) {
                *s += reaction(dof(v, c));
            }
        }
    }
    sum
}

/// The nodal contact forces of the result on body `b` (2 per node; w σ_n n for an own-side
/// pair).
fn nodal_contact_force(model: &Model, b: usize, contact: &[PairResult]) -> Vec<f64> {
    let mut f = vec![0.0; model.bodies[b].load.len()];
    for (pair, p) in model.pairs.iter().zip(contact) {
        if !pair.bodies.contains(&b) {
            continue;
        }
        for i in (0..p.side.len()).filter(|&i| pair.bodies[p.side[i]] == b) {
            // A point without a partner has no force (NaN-free by construction, but be safe).
            if p.fx[i].is_finite() && p.fy[i].is_finite() {
                f[dof(p.node[i], 0)] += p.fx[i];
                f[dof(p.node[i], 1)] += p.fy[i];
            }
        }
    }
    f
}
