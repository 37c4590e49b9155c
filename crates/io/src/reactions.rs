//! Support reactions of a solved model: the force the supports exert on each body, per supported
//! boundary and in total.
//!
//! Computed here, from the model and the displacement fields, so that every solver's result (DD or
//! monolithic) gets the same numbers. On a supported DOF the residual `K u − f` is the support
//! reaction plus the contact force at that node, if it is a contact node too; the nodal contact
//! forces of the reported pressures (w σ_n n) are subtracted, so that a body's balance reads
//! `applied load + reactions + contact force = 0` up to the solver's equilibrium residual.

use contactdd_core::assembly::residual_rows;
use contactdd_core::{dof, Constraints, Vector, DIM};
use contactdd_ddm::solution::{nodal_contact_force, BodyResult, PairResult};
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
    /// One entry per supported boundary, in name order (boundaries, then node sets). Each
    /// supported DOF counts in one entry ([`reactions`] says which), so these add up to `total`.
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
/// reactions of its nodes: the prescribed components, both components on a node of an inclined
/// support, whose reaction lies along its normal.
///
/// Each node's reaction counts once, split between the supported boundaries it lies on (a corner
/// lies on two) along their supports' directions. A boundary's directions are the axes x, y its
/// support prescribes on every one of its nodes and the normal of an inclined `normal` support.
/// A node held in one direction gives its reaction to the first boundary, in the order listed,
/// with that direction (to the first one it lies on if none has it). A node held in both gives
/// r = α d₁ + β d₂ along the first two independent directions d₁, d₂ of its boundaries, in the
/// order listed: α d₁ to the boundary of d₁, β d₂ to that of d₂ (all of r to one boundary when it
/// has both, as a `both` support does). So at the corner of a floor (u_y = 0 on `bottom`) and a
/// symmetry line (u_x = 0 on `right`), the corner's x reaction belongs to `right` and its y
/// reaction to `bottom`; the split turns with the model.
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
    let constraints = &body.constraints;
    // A node of an inclined normal support counts with both components: its reaction lies
    // along the normal.
    let held = |v: usize, c: usize| constraints.holds(dof(v, c));
    let mesh = &body.mesh;
    // K u − f in the supported rows only: the rest of K is not needed.
    let rows: Vec<usize> = (0..mesh.num_nodes())
        .filter(|&v| (0..DIM).any(|c| held(v, c)))
        .collect();
    let d = body.material.elasticity(body.plane);
    let r = residual_rows(mesh, &d, (&fields.displacement, &body.load), &rows);
    let names = mesh.boundaries().keys().chain(mesh.node_sets().keys());
    let supported: Vec<(&String, Vec<usize>)> = names
        .filter_map(|name| {
            let nodes = mesh.boundary_nodes(name).ok()?;
            let any = |&v: &usize| (0..DIM).any(|c| held(v, c));
            (!nodes.is_empty() && nodes.iter().all(any)).then_some((name, nodes))
        })
        .collect();
    let directions: Vec<Vec<Vector>> = (supported.iter())
        .map(|(_, nodes)| support_directions(constraints, nodes))
        .collect();
    let mut on: Vec<Vec<usize>> = vec![Vec::new(); mesh.num_nodes()];
    for (s, (_, nodes)) in supported.iter().enumerate() {
        for &v in nodes {
            on[v].push(s);
        }
    }
    let mut supports: Vec<SupportReaction> = (supported.iter())
        .map(|(name, _)| SupportReaction {
            boundary: (*name).clone(),
            force: [0.0; DIM],
        })
        .collect();
    let mut total = [0.0; DIM];
    for v in 0..mesh.num_nodes() {
        let mut node = [0.0; DIM];
        for c in (0..DIM).filter(|&c| held(v, c)) {
            node[c] = r[dof(v, c)] - fc[dof(v, c)];
            total[c] += node[c];
        }
        // The node's one prescribed direction; none when it is held in both.
        let inclined = constraints.inclined_normal(v).map(|(n, _)| n);
        let direction = match (held(v, 0), held(v, 1)) {
            (false, false) => continue,
            (true, true) => inclined,
            (true, false) => Some([1.0, 0.0]),
            (false, true) => Some([0.0, 1.0]),
        };
        for (s, f) in split(node, direction, &on[v], &directions) {
            supports[s].force[0] += f[0];
            supports[s].force[1] += f[1];
        }
    }
    BodyReactions {
        body: body.name.clone(),
        supports,
        total,
    }
}

/// The directions of the support of a boundary with nodes `nodes`: each axis prescribed on all of
/// them, and the normal of its nodes held along an inclined normal only.
fn support_directions(constraints: &Constraints, nodes: &[usize]) -> Vec<Vector> {
    let mut directions: Vec<Vector> = (0..DIM)
        .filter(|&c| nodes.iter().all(|&v| constraints.get(dof(v, c)).is_some()))
        .map(|c| if c == 0 { [1.0, 0.0] } else { [0.0, 1.0] })
        .collect();
    if let Some((n, _)) = nodes.iter().find_map(|&v| constraints.inclined_normal(v)) {
        directions.push(n);
    }
    directions
}

/// Below this |sin| of the angle between two directions they count as the same one.
const PARALLEL: f64 = 1e-6;

/// |sin| of the angle between two unit vectors.
fn sine(a: Vector, b: Vector) -> f64 {
    (a[0] * b[1] - a[1] * b[0]).abs()
}

/// The shares of a node's reaction `r` among the supported boundaries `on` it lies on (indices
/// into `directions`): `direction` is the node's one prescribed direction, `None` when it is held
/// in both (the rule of [`reactions`]).
fn split(
    r: Vector,
    direction: Option<Vector>,
    on: &[usize],
    directions: &[Vec<Vector>],
) -> Vec<(usize, Vector)> {
    let Some(&first) = on.first() else {
        return Vec::new();
    };
    let candidates: Vec<(usize, Vector)> = (on.iter())
        .flat_map(|&s| directions[s].iter().map(move |&d| (s, d)))
        .collect();
    if let Some(d) = direction {
        let owner = candidates.iter().find(|(_, e)| sine(*e, d) < PARALLEL);
        return vec![(owner.map_or(first, |&(s, _)| s), r)];
    }
    let Some(&(s1, d1)) = candidates.first() else {
        return vec![(first, r)];
    };
    let second = candidates[1..]
        .iter()
        .find(|(_, d)| sine(d1, *d) >= PARALLEL);
    match second {
        Some(&(s2, d2)) if s2 != s1 => {
            // r = α d1 + β d2 (Cramer's rule).
            let det = d1[0] * d2[1] - d1[1] * d2[0];
            let alpha = (r[0] * d2[1] - r[1] * d2[0]) / det;
            let beta = (d1[0] * r[1] - d1[1] * r[0]) / det;
            vec![
                (s1, [alpha * d1[0], alpha * d1[1]]),
                (s2, [beta * d2[0], beta * d2[1]]),
            ]
        }
        _ => vec![(s1, r)],
    }
}
