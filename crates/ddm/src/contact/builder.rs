//! Builds the [`Interface`] of a model, in stages: the contact zones of every pair, the pairs'
//! formulations, the nodal quadrature and mortar integrals of every (pair, side), the global
//! numbering, the projection of every contact point onto the partner boundary, and the balanced
//! pairs' rewrite.
//!
//! Every body integrates the contact terms over its own contact zone with nodal quadrature
//! (trapezoid weights for P1, Simpson for P2; docs/method.md §4), so each node of a contact
//! boundary is a *contact point* of its body. For a point x of body α, the ray x + t n_α(x) is
//! intersected with the edges of the partner boundary of body β; the hit x' gives the initial gap
//! d = t + d_profile(x) and the interpolation coefficients of β's normal displacement at x', so
//! that s = u_αn(x) + Σ_k c_k u_βn(x_k).

use std::collections::HashMap;
use std::ops::Range;

use contactdd_core::{Edge, Mesh, Vector};

use super::balanced_pair;
use super::edge_index::EdgeIndex;
use super::formulation::{Forces, Formulation, InnerPenalty};
use super::mortar::{self, Mortar};
use super::nodal_quadrature::nodal_quadrature;
use super::points::{carried, carried_tangential, ContactPoint, Interface, Role};
use crate::error::SetupError;
use crate::model::Model;

/// One side of a contact pair: a body's contact boundary.
type Zone<'m> = (usize, &'m Mesh, &'m [Edge]);

/// The points of one (pair, side) before the global numbering.
struct Side {
    body: usize,
    pair: usize,
    nodes: Vec<usize>,
    normals: Vec<Vector>,
    weights: Vec<f64>,
    /// Balanced pairs: the dual mortar integrals per node (`contact::mortar`).
    mortar: HashMap<usize, mortar::Integrals>,
}

/// One contact point as projected onto its partner, with the length of its ray to the partner
/// and its dual mortar coefficients.
struct Projected {
    point: ContactPoint,
    hit: Option<f64>,
    mortar: Option<Mortar>,
}

/// The global numbering of the points: body by body, then pair by pair, then node order.
struct Numbering {
    /// The sides in numbering order.
    order: Vec<usize>,
    /// Index of the first point of every side.
    offset: Vec<usize>,
    /// Index range of each body's points.
    body_range: Vec<Range<usize>>,
}

impl Interface {
    /// Builds the contact points of a model, every pair with its own θ.
    pub fn new(model: &Model) -> Result<Interface, SetupError> {
        Interface::with_inner(model, InnerPenalty::AsGiven)
    }

    /// [`Interface::new`] with the augmented balanced pairs' inner penalty `inner`.
    pub fn with_inner(model: &Model, inner: InnerPenalty) -> Result<Interface, SetupError> {
        let zones = zones(model)?;
        let mut formulations = model
            .pairs
            .iter()
            .map(|pair| pair.formulation(&model.bodies, inner))
            .collect::<Result<Vec<Formulation>, SetupError>>()?;
        let (sides, boundaries) = sides(model, &zones, &formulations);
        let numbering = Numbering::new(&sides, model.bodies.len());
        let (mut points, mut hits, mut mortar) = (Vec::new(), Vec::new(), Vec::new());
        for &i in &numbering.order {
            // Sides come in pairs (2p, 2p + 1).
            let partner = &boundaries[i ^ 1];
            let f = &formulations[sides[i].pair];
            for p in project_side(model, &sides, i, &numbering.offset, partner, f) {
                points.push(p.point);
                hits.push(p.hit);
                mortar.push(p.mortar);
            }
        }
        name_remote_nodes(model, &mut points);
        balanced_pair::resolve(&mut points, &mut formulations);
        let first: Vec<usize> = model.pairs.iter().map(|p| p.bodies[0]).collect();
        let (points, body_range) = balanced_pair::balance(
            points,
            numbering.body_range,
            &hits,
            &mortar,
            &formulations,
            &first,
        );
        let carried = carried(&points);
        let carried_tangential = carried_tangential(&points);
        Ok(Interface {
            points,
            body_range,
            carried,
            formulations,
            carried_tangential,
        })
    }
}

/// The two contact zones of every pair; an error for a body or boundary that does not exist.
fn zones(model: &Model) -> Result<Vec<[Zone<'_>; 2]>, SetupError> {
    let mut out = Vec::with_capacity(model.pairs.len());
    for pair in &model.pairs {
        let mut zone = Vec::with_capacity(2);
        for s in 0..2 {
            let b = pair.bodies[s];
            let body = model.bodies.get(b).ok_or_else(|| SetupError::Pair {
                pair: pair.name.clone(),
                message: format!("body index {b} does not exist"),
            })?;
            let edges = body
                .mesh
                .boundary(&pair.boundaries[s])
                .map_err(|e| SetupError::Pair {
                    pair: pair.name.clone(),
                    message: format!("body '{}': {e}", body.name),
                })?;
            zone.push((b, &body.mesh, edges));
        }
        out.push([zone[0], zone[1]]);
    }
    Ok(out)
}

/// The sides of every pair, (2p, 2p + 1) for pair p, with their nodal quadrature and (balanced
/// pairs) mortar integrals, and the contact boundary of every side, indexed for the projections.
fn sides<'m>(
    model: &Model,
    zones: &[[Zone<'m>; 2]],
    formulations: &[Formulation],
) -> (Vec<Side>, Vec<EdgeIndex<'m>>) {
    let mut sides = Vec::with_capacity(2 * zones.len());
    let mut boundaries: Vec<EdgeIndex> = Vec::with_capacity(2 * zones.len());
    for (p, zone) in zones.iter().enumerate() {
        let pair = &model.pairs[p];
        let index = [0, 1].map(|s| EdgeIndex::new(zone[s].1, zone[s].2));
        for s in 0..2 {
            let (b, mesh, edges) = zone[s];
            let (nodes, normals, weights) = nodal_quadrature(mesh, edges, &index[1 - s]);
            let mortar = if formulations[p].forces == Forces::Balanced {
                let profile = |x| pair.profile.as_ref().map_or(0.0, |p| p.at(x));
                mortar::dual_integrals(mesh, edges, &index[1 - s], &profile)
            } else {
                HashMap::new()
            };
            sides.push(Side {
                body: b,
                pair: p,
                nodes,
                normals,
                weights,
                mortar,
            });
        }
        boundaries.extend(index);
    }
    (sides, boundaries)
}

impl Numbering {
    /// Numbers the points of `sides` among `bodies` bodies.
    fn new(sides: &[Side], bodies: usize) -> Numbering {
        let mut order: Vec<usize> = (0..sides.len()).collect();
        order.sort_by_key(|&i| (sides[i].body, sides[i].pair, i));
        let mut offset = vec![0usize; sides.len()];
        let mut body_range = vec![0..0; bodies];
        let mut next = 0;
        for b in 0..bodies {
            let start = next;
            for &i in order.iter().filter(|&&i| sides[i].body == b) {
                offset[i] = next;
                next += sides[i].nodes.len();
            }
            body_range[b] = start..next;
        }
        Numbering {
            order,
            offset,
            body_range,
        }
    }
}

/// The points of side `i`, each projected along its normal onto the `partner` boundary, under
/// its pair's formulation `f`; `offset` numbers the partner's points.
fn project_side(
    model: &Model,
    sides: &[Side],
    i: usize,
    offset: &[usize],
    partner: &EdgeIndex,
    f: &Formulation,
) -> Vec<Projected> {
    let side = &sides[i];
    let pair = &model.pairs[side.pair];
    let other = i ^ 1;
    let partner_side = &sides[other];
    let a = &model.bodies[side.body];
    let partner_index: HashMap<usize, usize> = partner_side
        .nodes
        .iter()
        .enumerate()
        .map(|(k, &v)| (v, offset[other] + k))
        .collect();
    let mut out = Vec::with_capacity(side.nodes.len());
    for (k, &v) in side.nodes.iter().enumerate() {
        let x = a.mesh.nodes()[v];
        let n = side.normals[k];
        let (hit, gap, partner) = match partner.project(x, n) {
            Some((t, coeffs)) => (
                Some(t),
                t,
                coeffs
                    .into_iter()
                    .filter_map(|(node, c)| partner_index.get(&node).map(|&g| (g, c)))
                    .collect(),
            ),
            None => (None, f64::INFINITY, Vec::new()),
        };
        let mortar = side
            .mortar
            .get(&v)
            .and_then(|node| mortar::normalised(node, &partner_index));
        let profile = pair.profile.as_ref().map_or(0.0, |p| p.at(x));
        let theta = f.point_theta(side.weights[k], a, &model.bodies[partner_side.body]);
        let point = ContactPoint {
            body: side.body,
            node: v,
            pair: side.pair,
            normal: n,
            weight: side.weights[k],
            gap: gap + profile,
            theta,
            multiplier: 0.0,
            partner,
            // The reference spring w/θ; balanced pairs lump theirs (`contact::balanced_pair`).
            spring: side.weights[k] / theta,
            role: Role::OwnSide,
            friction: None,
        };
        out.push(Projected { point, hit, mortar });
    }
    out
}

/// A remote body's points name their nodes in its own numbering, as on its process.
fn name_remote_nodes(model: &Model, points: &mut [ContactPoint]) {
    for p in points {
        if let Some(remote) = model.remote(p.body) {
            p.node = remote.ids.get(p.node).copied().unwrap_or(usize::MAX);
        }
    }
}
