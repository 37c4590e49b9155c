//! The independent check that decides whether a result is a solution: on every body, the applied
//! loads, the contact forces of the reported pressures and the support reactions of the recovered
//! field must balance, in force and in moment.
//!
//! It uses nothing of the iteration: the element stiffness matrices of the cells at the supports
//! give the reactions, the residual `K u − f − f_c` on the prescribed directions, and the net force and moment are the
//! rigid-motion projections of the loads, contact forces and reactions. A factorisation that lost a floating
//! body's rigid motion (a stiffness far above its contact springs), interface loads that do not
//! carry the reported pressures, or an iteration stopped early all show here, whatever the
//! iteration's own measure says.
//!
//! The rounding of the reactions is about ε Σ|K||u| over the supported rows: a body that moves far
//! more than it deforms (a huge prescribed displacement) carries reactions drowned in it. This floor is reported with the imbalance, so that a failure says which
//! of the two it is.

use contactdd_core::element::Geometry;
use contactdd_core::rigid::{RigidBasis, NUM_MODES};
use contactdd_core::{dof, ElasticBody, DIM};

use crate::exchange::{share_vectors, Exchange};
use crate::model::Model;

/// One body's balance, relative to the largest force total of a body of the model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyBalance {
    /// |net force and moment| of the applied loads, contact forces and reactions (the moment
    /// over the body's bounding box diameter, a force).
    pub imbalance: f64,
    /// ε Σ|K||u| over the supported rows: the rounding the reactions carry.
    pub floor: f64,
    /// The largest displacement over the body's bounding box diameter.
    pub motion: f64,
}

/// The balance of a result: per body, and of the whole problem.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Balance {
    /// Per body.
    pub bodies: Vec<BodyBalance>,
    /// |Σ applied loads + Σ reactions| over Σ (|applied load| + |reaction|) of the bodies (the
    /// resultants of each body): the problem's loads against its supports. The contact forces
    /// cancel between the bodies only where action equals reaction, so this catches own-side
    /// pairs whose sides carry different forces, which each body alone does not see.
    pub loads: f64,
}

/// The forces of one body whose field this process holds.
pub struct BodyForces<'a> {
    /// The displacement field.
    pub displacement: &'a [f64],
    /// The applied nodal loads (at the solve's load factors).
    pub load: Vec<f64>,
    /// The nodal contact forces of the reported pressures.
    pub contact: Vec<f64>,
    /// The resultant contact force of each pair side on the body.
    pub pair_forces: Vec<[f64; DIM]>,
}

/// The balance of every body and of the whole problem (the same on every process): `fields`
/// holds the forces of every body whose field this process holds; the totals travel through
/// `exchange`. A body's force total is |its load| + |its reaction| + Σ |a pair's force on it|
/// (resultants); imbalances are relative to the largest total of a body.
pub fn balance(
    model: &Model,
    fields: &[Option<BodyForces<'_>>],
    exchange: &dyn Exchange,
) -> Balance {
    let own: Vec<Vec<f64>> = (fields.iter().enumerate())
        .map(|(b, field)| match field {
            Some(f) => body_forces(&model.bodies[b], f).to_vec(),
            None => Vec::new(),
        })
        .collect();
    let all = share_vectors(exchange, own);
    let scale = all
        .iter()
        .filter_map(|v| v.get(1).copied())
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let bodies = all
        .iter()
        .map(|v| match v.as_slice() {
            [imbalance, _, floor, _, _, _, motion] => BodyBalance {
                imbalance: imbalance / scale,
                floor: floor / scale,
                motion: *motion,
            },
            _ => BodyBalance {
                imbalance: f64::NAN,
                floor: f64::NAN,
                motion: f64::NAN,
            },
        })
        .collect();
    let (mut net, mut size) = ([0.0; DIM], 0.0);
    for v in &all {
        if let [_, _, _, x, y, total, _] = v[..] {
            net = [net[0] + x, net[1] + y];
            size += total;
        } else {
            net = [f64::NAN; DIM];
        }
    }
    let loads = norm(net) / size.max(f64::MIN_POSITIVE);
    Balance { bodies, loads }
}

/// One body's [imbalance, force total, rounding floor, net load and reaction x, y, |load| +
/// |reaction|, motion], absolute: the net force and moment of its loads, contact forces and support
/// reactions (the residual `K u − f − f_c` on the prescribed directions), its force total, ε
/// Σ|K||u| over the supported rows (the rounding the reactions carry), its load and reaction
/// resultants, and its largest displacement over its size. Along a motion no support holds, the net force is that of the loads
/// and contact forces alone, free of the rounding of `K u`.
pub fn body_forces(body: &ElasticBody, forces: &BodyForces<'_>) -> [f64; 7] {
    let (u, load, contact) = (forces.displacement, &forces.load, &forces.contact);
    let (ku, size) = held_rows(body, u);
    let r: Vec<f64> = (0..u.len()).map(|d| ku[d] - load[d] - contact[d]).collect();
    let mut free = r.clone();
    body.constraints.remove_prescribed(&mut free);
    let basis = RigidBasis::new(&body.mesh);
    let mut net = [0.0; NUM_MODES];
    let (mut applied, mut reacted) = ([0.0; DIM], [0.0; DIM]);
    for (v, &x) in body.mesh.nodes().iter().enumerate() {
        let m = basis.at(x);
        for c in 0..DIM {
            let d = dof(v, c);
            let reaction = r[d] - free[d];
            for (i, n) in net.iter_mut().enumerate() {
                *n += m[c][i] * (load[d] + contact[d] + reaction);
            }
            applied[c] += load[d];
            reacted[c] += reaction;
        }
    }
    let pairs: f64 = forces.pair_forces.iter().map(|&f| norm(f)).sum();
    let loads = norm(applied) + norm(reacted);
    let imbalance = net.iter().map(|x| x * x).sum::<f64>().sqrt();
    let floor = f64::EPSILON * size.iter().sum::<f64>();
    let [x, y] = [applied[0] + reacted[0], applied[1] + reacted[1]];
    let largest = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let motion = largest / body.mesh.bounding_box_diameter().max(f64::MIN_POSITIVE);
    [imbalance, loads + pairs, floor, x, y, loads, motion]
}

/// `K u` and Σ|K_ij u_j| on the rows of the supported nodes (zero elsewhere), element by element
/// over the cells that touch such a node: the reactions need no other row, and no matrix.
fn held_rows(body: &ElasticBody, u: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mesh = &body.mesh;
    let held = |v: usize| (0..DIM).any(|c| body.constraints.holds(dof(v, c)));
    let d = body.material.elasticity(body.plane);
    let (mut ku, mut size) = (vec![0.0; u.len()], vec![0.0; u.len()]);
    for e in 0..mesh.num_cells() {
        let c = mesh.cell(e);
        if !c.iter().any(|&v| held(v)) {
            continue;
        }
        let ke = Geometry::of_cell(mesh, e).stiffness(mesh.order(), &d);
        for (a, &i) in c.iter().enumerate() {
            for ci in 0..DIM {
                for (b, &j) in c.iter().enumerate() {
                    for cj in 0..DIM {
                        let t = ke[dof(a, ci)][dof(b, cj)] * u[dof(j, cj)];
                        ku[dof(i, ci)] += t;
                        size[dof(i, ci)] += t.abs();
                    }
                }
            }
        }
    }
    (ku, size)
}

fn norm(v: [f64; DIM]) -> f64 {
    v[0].hypot(v[1])
}
