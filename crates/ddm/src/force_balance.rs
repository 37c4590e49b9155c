//! The independent check that decides whether a result is a solution: on every body, the applied
//! loads, the contact forces of the reported pressures and the support reactions of the recovered
//! field must balance, in force and in moment.
//!
//! It uses nothing of the iteration: the body's stiffness is assembled again, the reactions are the
//! residual `K u − f − f_c` on the prescribed directions, and the net force and moment are the
//! rigid-motion projections of what is left on the free DOFs. A factorisation that lost a floating
//! body's rigid motion (a stiffness far above its contact springs), interface loads that do not
//! carry the reported pressures, or an iteration stopped early all show here, whatever the
//! iteration's own measure says.
//!
//! The rounding of `K u` bounds what the check can see: ε Σ|K||u| over a body. A body much stiffer
//! than its partners that moves rigidly carries, in `u`, a rigid motion far larger than its
//! elastic part, and past a contrast of about 1/ε its stresses drown in that rounding. The floor is
//! reported with the imbalance, so that a failure says which of the two it is.

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
    /// ε Σ|K||u|: the rounding that computing the reactions from the field can carry.
    pub floor: f64,
}

/// The forces of one body whose field this process holds.
pub struct BodyForces<'a> {
    /// The displacement field.
    pub displacement: &'a [f64],
    /// The applied nodal loads (at the solve's load factors).
    pub load: Vec<f64>,
    /// The nodal contact forces of the reported pressures.
    pub contact: Vec<f64>,
}

/// The balance of every body (the same on every process): `fields` holds the forces of every
/// body whose field this process holds; the totals travel through `exchange`.
pub fn balance(
    model: &Model,
    fields: &[Option<BodyForces<'_>>],
    exchange: &dyn Exchange,
) -> Vec<BodyBalance> {
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
    all.iter()
        .map(|v| match v.as_slice() {
            [imbalance, _, floor] => BodyBalance {
                imbalance: imbalance / scale,
                floor: floor / scale,
            },
            _ => BodyBalance {
                imbalance: f64::NAN,
                floor: f64::NAN,
            },
        })
        .collect()
}

/// One body's [imbalance, force total, rounding floor], absolute: the net force and moment of
/// the residual `K u − f − f_c` off the prescribed directions (equal and opposite to that of the
/// loads, contact forces and reactions together, since K annihilates rigid motions), the sum of
/// the magnitudes of the nodal loads, contact forces and reactions, and ε Σ|K||u|.
pub fn body_forces(body: &ElasticBody, forces: &BodyForces<'_>) -> [f64; 3] {
    let (u, load, contact) = (forces.displacement, &forces.load, &forces.contact);
    let k = body.stiffness();
    let mut r: Vec<f64> = (0..u.len()).map(|d| -load[d] - contact[d]).collect();
    let mut size = vec![0.0; u.len()];
    let (cp, ri, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    for (j, &uj) in u.iter().enumerate() {
        for p in cp[j]..cp[j + 1] {
            r[ri[p]] += val[p] * uj;
            size[ri[p]] += (val[p] * uj).abs();
        }
    }
    let reactions = r.clone();
    body.constraints.remove_prescribed(&mut r);
    let basis = RigidBasis::new(&body.mesh);
    let mut net = [0.0; NUM_MODES];
    let (mut total, mut floor) = (0.0, 0.0);
    for (v, &x) in body.mesh.nodes().iter().enumerate() {
        let m = basis.at(x);
        let node = |w: &[f64]| std::array::from_fn::<f64, DIM, _>(|c| w[dof(v, c)]);
        let reaction: [f64; DIM] = std::array::from_fn(|c| reactions[dof(v, c)] - r[dof(v, c)]);
        for c in 0..DIM {
            for (i, n) in net.iter_mut().enumerate() {
                *n += m[c][i] * r[dof(v, c)];
            }
            floor += size[dof(v, c)];
        }
        total += norm(node(load)) + norm(node(contact)) + norm(reaction);
    }
    let imbalance = net.iter().map(|x| x * x).sum::<f64>().sqrt();
    [imbalance, total, f64::EPSILON * floor]
}

fn norm(v: [f64; DIM]) -> f64 {
    v[0].hypot(v[1])
}
