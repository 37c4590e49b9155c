//! Contact geometry: contact points with nodal normals and quadrature weights, initial gaps, and
//! the projection of every contact point onto the opposite body's contact boundary.
//!
//! Every body integrates the contact terms over its own contact zone with nodal quadrature
//! (trapezoid weights for P1, Simpson for P2; docs/method.md §4), so each node of a contact boundary is
//! a *contact point* of its body. For a point x of body α, the ray x + t n_α(x) is intersected with
//! the edges of the partner boundary of body β; the hit x' gives the initial gap
//! d = t + d_profile(x) and the interpolation coefficients of β's normal displacement at x', so
//! that s = u_αn(x) + Σ_k c_k u_βn(x_k). Nodal normals are length-weighted averages of the
//! adjacent edge normals of the zone, which makes curved boundaries work.

use std::collections::HashMap;
use std::ops::Range;

use contactdd_core::element::{edge_nodal_weights, edge_shape};
use contactdd_core::geometry::dot;
use contactdd_core::mesh::dist;
use contactdd_core::{Edge, Mesh, Order, Point, Vector, DIM};

use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};

use crate::error::SetupError;
use crate::model::{Enforcement, Forces, InnerPenalty, Model, Penalty};

/// The rod model's factor c of the inner penalty of an augmented balanced pair's point, with the
/// point's share of its boundary as h: the spring w/θ is then E*/c (E* = 1/(1/E*_α + 1/E*_β)),
/// about 1/c times the stiffness that the bodies oppose to one node, so each multiplier update
/// leaves about c/(1 + c) of the error (`docs/augmented-lagrangian.md`). 0.05 is the paper's
/// factor. The pair's own θ is used where it is stiffer.
pub const AUGMENTED_C: f64 = 0.05;

/// One contact point: a node of a contact boundary of one body, in one contact pair.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPoint {
    /// Owning body.
    pub body: usize,
    /// Node of the owning body.
    pub node: usize,
    /// Contact pair index.
    pub pair: usize,
    /// Outward unit normal of the owning body at the node.
    pub normal: Vector,
    /// Nodal quadrature weight (length).
    pub weight: f64,
    /// Initial gap d (geometric normal distance plus the pair's profile).
    pub gap: f64,
    /// Penalty θ of the pair.
    pub theta: f64,
    /// Lagrange multiplier estimate λ ≥ 0 of the augmented Lagrangian (a contact pressure; 0 for
    /// the penalty formulation): the penalty acts on the gap d − θλ, so that the pressure is
    /// λ + (s − d)/θ where positive (docs/augmented-lagrangian.md).
    pub multiplier: f64,
    /// Interpolation of the partner's normal displacement at the projection: (global point index,
    /// coefficient). Empty if the normal ray misses the partner boundary (the point stays open).
    /// For a balanced pair the partner's displacement is read along this point's normal, through
    /// the partner's normal and tangential unknowns ([`crate::balance`]).
    pub partner: Vec<(usize, f64)>,
    /// The reference spring D₀ of this interface unknown: w/θ, or for a balanced pair the lumped
    /// penalty stiffness of the pressures that load it.
    pub spring: f64,
    /// What the unknown is and how its point's pressure loads the bodies.
    pub role: Role,
}

/// The role of an interface unknown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A contact point whose pressure loads its own node along its own normal (the paper's
    /// formulation, and every pair whose sides match node for node).
    OwnSide,
    /// A contact point of the reference side of a balanced pair: its pressure acts on its own
    /// node and, with the opposite sign, on the partner's nodes through its gap's coefficients.
    Carrier,
    /// A contact point of the other side of a balanced pair: the carriers' pressures load it; its
    /// own gap only sets its Robin coefficient and is reported.
    Follower,
    /// The tangential displacement of a contact node of a balanced pair (`normal` is the tangent):
    /// it has no gap or pressure of its own, and carries the tangential part of the gaps and
    /// forces.
    Tangent,
}

impl ContactPoint {
    /// True if the point has a partner (can close).
    pub fn has_partner(&self) -> bool {
        !self.partner.is_empty()
    }

    /// True for a contact point (not a tangential unknown).
    pub fn is_contact(&self) -> bool {
        self.role != Role::Tangent
    }

    /// True for a point whose own pressure loads the bodies (own-side or carrier).
    pub fn carries(&self) -> bool {
        matches!(self.role, Role::OwnSide | Role::Carrier)
    }

    /// The unknowns that point `j` (this point) loads, with the share of its nodal force w σ_n
    /// each receives: itself for an own-side point; its gap's row for a carrier; nothing else.
    pub fn load_row(&self, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let own = self.carries().then_some((j, 1.0));
        let through = match self.role {
            Role::Carrier => self.partner.as_slice(),
            _ => &[],
        };
        own.into_iter().chain(through.iter().copied())
    }

    /// The gap the penalty acts on: d − θλ (d itself for the penalty formulation, λ = 0).
    pub fn penalty_gap(&self) -> f64 {
        // d − θ·0 is d to the bit, so the penalty formulation is unchanged.
        self.gap - self.theta * self.multiplier
    }

    /// The penalty overlap (d − θλ − s)⁻ ≤ 0 for the sum `s` of the normal displacements across
    /// the pair (0 for a point without partner).
    pub fn overlap(&self, s: f64) -> f64 {
        if self.has_partner() {
            (self.penalty_gap() - s).min(0.0)
        } else {
            0.0
        }
    }

    /// The normal contact stress σ_n = (d − θλ − s)⁻/θ ≤ 0 (docs/method.md §2; λ = 0 for the
    /// penalty formulation) for the sum `s`.
    pub fn pressure(&self, s: f64) -> f64 {
        self.overlap(s) / self.theta
    }
}

/// All contact points of a model, grouped by body (the interface unknowns are their normal
/// displacements, in this order).
#[derive(Clone, Debug, PartialEq)]
pub struct Interface {
    /// The points, body by body.
    pub points: Vec<ContactPoint>,
    /// Index range of each body's points.
    pub body_range: Vec<Range<usize>>,
    /// Per unknown q, the points whose pressure loads it and their shares a: the contact force
    /// along q is F_q = Σ a w_j σ_n,j (the transpose of [`ContactPoint::load_row`]).
    pub carried: Vec<Vec<(usize, f64)>>,
}

impl Interface {
    /// Builds the contact points of a model, every pair with its own θ.
    pub fn new(model: &Model) -> Result<Interface, SetupError> {
        Interface::with_inner(model, InnerPenalty::AsGiven)
    }

    /// [`Interface::new`] with the augmented balanced pairs' inner penalty `inner`.
    pub fn with_inner(model: &Model, inner: InnerPenalty) -> Result<Interface, SetupError> {
        // Points per (pair, side) before global numbering.
        struct Side {
            body: usize,
            pair: usize,
            nodes: Vec<usize>,
            normals: Vec<Vector>,
            weights: Vec<f64>,
            /// Balanced pairs: the dual mortar integrals per node (`crate::mortar`).
            mortar: HashMap<usize, crate::mortar::Integrals>,
        }
        let mut sides = Vec::new();
        // The contact boundary of every (pair, side), indexed for the projections.
        let mut boundaries: Vec<EdgeIndex> = Vec::with_capacity(2 * model.pairs.len());
        for (p, pair) in model.pairs.iter().enumerate() {
            let mut zone = Vec::with_capacity(2);
            for s in 0..2 {
                let b = pair.bodies[s];
                let body = model.bodies.get(b).ok_or_else(|| SetupError::Pair {
                    pair: pair.name.clone(),
                    message: format!("body index {b} does not exist"),
                })?;
                let edges =
                    body.mesh
                        .boundary(&pair.boundaries[s])
                        .map_err(|e| SetupError::Pair {
                            pair: pair.name.clone(),
                            message: format!("body '{}': {e}", body.name),
                        })?;
                zone.push((b, &body.mesh, edges));
            }
            let index = [0, 1].map(|s| EdgeIndex::new(zone[s].1, zone[s].2));
            for s in 0..2 {
                let (b, mesh, edges) = zone[s];
                let (nodes, normals, weights) = nodal_quadrature(mesh, edges, &index[1 - s]);
                let mortar = if pair.forces == crate::model::Forces::Balanced {
                    let profile = |x| pair.profile.as_ref().map_or(0.0, |p| p.at(x));
                    crate::mortar::dual_integrals(mesh, edges, &index[1 - s], &profile)
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
        // Global numbering: body by body, then pair by pair, then node order.
        let nb = model.bodies.len();
        let mut order: Vec<usize> = (0..sides.len()).collect();
        order.sort_by_key(|&i| (sides[i].body, sides[i].pair, i));
        let mut offset = vec![0usize; sides.len()];
        let mut body_range = vec![0..0; nb];
        let mut next = 0;
        for b in 0..nb {
            let start = next;
            for &i in order.iter().filter(|&&i| sides[i].body == b) {
                offset[i] = next;
                next += sides[i].nodes.len();
            }
            body_range[b] = start..next;
        }
        let mut points: Vec<Option<ContactPoint>> = vec![None; next];
        // Per point, the length of its ray to the partner, and its dual mortar coefficients.
        let mut hits: Vec<Option<f64>> = vec![None; next];
        let mut mortar: Vec<Option<crate::balance::Mortar>> = vec![None; next];
        for (i, side) in sides.iter().enumerate() {
            let pair = &model.pairs[side.pair];
            let other = i ^ 1; // sides come in pairs (2p, 2p + 1)
            let partner_side = &sides[other];
            let a = &model.bodies[side.body];
            let theta = model.theta(side.pair);
            if !(theta.is_finite() && theta > 0.0) {
                return Err(SetupError::Pair {
                    pair: pair.name.clone(),
                    message: format!("the penalty θ must be positive and finite, got {theta}"),
                });
            }
            let partner_index: HashMap<usize, usize> = partner_side
                .nodes
                .iter()
                .enumerate()
                .map(|(k, &v)| (v, offset[other] + k))
                .collect();
            for (k, &v) in side.nodes.iter().enumerate() {
                let x = a.mesh.nodes()[v];
                let n = side.normals[k];
                let hit = boundaries[other].project(x, n);
                let (gap, partner) = match hit {
                    Some((t, coeffs)) => {
                        hits[offset[i] + k] = Some(t);
                        (
                            t,
                            coeffs
                                .into_iter()
                                .filter_map(|(node, c)| partner_index.get(&node).map(|&g| (g, c)))
                                .collect(),
                        )
                    }
                    None => (f64::INFINITY, Vec::new()),
                };
                mortar[offset[i] + k] = side
                    .mortar
                    .get(&v)
                    .and_then(|node| normalised(node, &partner_index));
                let profile = pair.profile.as_ref().map_or(0.0, |p| p.at(x));
                // Own-side pairs keep θ: on non-matching meshes their two sides' multipliers
                // are tied only through the penalty, and a stiffer one lets them drift apart
                // (the non-matching notch then stalls at 5e−5). A weightless point (a P2 vertex
                // on a coarse side, say) keeps θ too: it carries nothing, its spring stays 0.
                let stiffened = inner == InnerPenalty::Stiffened
                    && pair.enforcement == Enforcement::Augmented
                    && pair.forces == Forces::Balanced
                    && side.weights[k] > 0.0;
                let theta = if stiffened {
                    theta.min(
                        Penalty::RodModel {
                            c: AUGMENTED_C,
                            h: side.weights[k],
                        }
                        .theta(a, &model.bodies[partner_side.body]),
                    )
                } else {
                    theta
                };
                points[offset[i] + k] = Some(ContactPoint {
                    body: side.body,
                    node: v,
                    pair: side.pair,
                    normal: n,
                    weight: side.weights[k],
                    gap: gap + profile,
                    theta,
                    multiplier: 0.0,
                    partner,
                    // The reference spring w/θ; balanced pairs lump theirs (`crate::balance`).
                    spring: side.weights[k] / theta,
                    role: Role::OwnSide,
                });
            }
        }
        let mut points: Vec<ContactPoint> = points.into_iter().flatten().collect();
        // A remote body's points name their nodes in its own numbering, as on its process.
        for p in &mut points {
            if let Some(remote) = model.remote(p.body) {
                p.node = remote.ids.get(p.node).copied().unwrap_or(usize::MAX);
            }
        }
        let pairs: Vec<(bool, usize)> = model
            .pairs
            .iter()
            .map(|p| (p.forces == crate::model::Forces::Balanced, p.bodies[0]))
            .collect();
        let (points, body_range) =
            crate::balance::balance(points, body_range, &hits, &mortar, &pairs);
        let carried = carried(&points);
        Ok(Interface {
            points,
            body_range,
            carried,
        })
    }

    /// The contact pressure σ_n ≤ 0 at point j for the pair sums `s`: its penalty pressure where
    /// it carries; for a follower the traction of the carriers' forces on its node, F_j/w_j (0
    /// where it has no weight or no partner).
    pub fn pressure(&self, j: usize, s: &[f64]) -> f64 {
        let p = &self.points[j];
        match p.role {
            Role::Follower if p.weight > 0.0 && p.has_partner() => self.force(j, s) / p.weight,
            Role::Follower | Role::Tangent => 0.0,
            Role::OwnSide | Role::Carrier => p.pressure(s[j]),
        }
    }

    /// The contact force along unknown q for the pair sums `s`: F_q = Σ a w_j σ_n,j.
    pub fn force(&self, q: usize, s: &[f64]) -> f64 {
        self.carried[q]
            .iter()
            .map(|&(j, a)| {
                let p = &self.points[j];
                a * (p.weight * p.pressure(s[j]))
            })
            .sum()
    }

    /// The points of body `b`.
    pub fn of_body(&self, b: usize) -> &[ContactPoint] {
        &self.points[self.body_range[b].clone()]
    }

    /// Number of contact points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True if there are no contact points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// s_j = u_n,j + Σ c u_n,partner for every point, from all normal displacements `un`.
    pub fn sum_normal(&self, un: &[f64], out: &mut [f64]) {
        for (j, p) in self.points.iter().enumerate() {
            out[j] = un[j] + p.partner.iter().map(|&(k, c)| c * un[k]).sum::<f64>();
        }
    }

    /// Per body, the other bodies whose normal displacements a Robin sweep of the body and its
    /// contact summary read: those of its points' partners (the pair sums s_j), and for the
    /// unknowns of a balanced pair those of the points that load them and of their partners.
    pub fn reads(&self) -> Vec<Vec<usize>> {
        let partners = |j: usize| self.points[j].partner.iter().map(|&(k, _)| k);
        self.body_range
            .iter()
            .enumerate()
            .map(|(b, range)| {
                let mut points: Vec<usize> = Vec::new();
                for j in range.clone() {
                    points.extend(partners(j));
                    for &(i, _) in &self.carried[j] {
                        points.push(i);
                        points.extend(partners(i));
                    }
                }
                let mut bodies: Vec<usize> = points
                    .into_iter()
                    .map(|k| self.points[k].body)
                    .filter(|&c| c != b)
                    .collect();
                bodies.sort_unstable();
                bodies.dedup();
                bodies
            })
            .collect()
    }
}

/// The mortar integrals of one point normalised by ∫ ψ: the coefficients over the partner's
/// points (they sum to 1, which makes the gap invariant under a joint translation), in point
/// order, with the weighted ray vector and profile; `None` where ∫ ψ is not a positive share of
/// the point.
fn normalised(
    node: &crate::mortar::Integrals,
    partner_index: &HashMap<usize, usize>,
) -> Option<crate::balance::Mortar> {
    let mut out: Vec<(usize, f64)> = node
        .coupling
        .iter()
        .filter_map(|(node, &c)| partner_index.get(node).map(|&g| (g, c)))
        .collect();
    out.sort_by_key(|e| e.0);
    let total: f64 = out.iter().map(|e| e.1).sum();
    let size: f64 = out.iter().map(|e| e.1.abs()).sum();
    // Also refuses NaN.
    if total.is_nan() || total <= 1e-9 * size {
        return None;
    }
    Some(crate::balance::Mortar {
        coefficients: out.into_iter().map(|(g, c)| (g, c / total)).collect(),
        ray: [node.ray[0] / total, node.ray[1] / total],
        profile: node.profile / total,
    })
}

/// Per unknown, the points that load it with their shares (see [`Interface::carried`]).
pub(crate) fn carried(points: &[ContactPoint]) -> Vec<Vec<(usize, f64)>> {
    let mut out = vec![Vec::new(); points.len()];
    for (j, p) in points.iter().enumerate() {
        for (q, a) in p.load_row(j) {
            // A row may name its own unknown twice (the implicit 1 and a correction): one share.
            match out[q].last_mut() {
                Some((i, b)) if *i == j => *b += a,
                _ => out[q].push((j, a)),
            }
        }
    }
    out
}

/// Nodes of a boundary with their nodal normals and quadrature weights.
///
/// The weights are the integrals of the edge shape functions over the part of each edge that faces
/// the partner boundary: trapezoid (P1) and Simpson (P2) weights for edges facing it entirely (the
/// usual case), and a share of the covered part for an edge that sticks out past the end of the
/// partner, so that a short body on a long one is loaded over its own length only.
fn nodal_quadrature(
    mesh: &Mesh,
    edges: &[Edge],
    partner: &EdgeIndex,
) -> (Vec<usize>, Vec<Vector>, Vec<f64>) {
    let mut index: HashMap<usize, usize> = HashMap::new();
    let (mut nodes, mut normals, mut weights) = (Vec::new(), Vec::new(), Vec::new());
    for e in edges {
        let (n, len) = mesh.edge_normal(e);
        let (t0, t1) = covered_part(mesh, e, n, partner);
        let w = partial_edge_weights(mesh.order(), len, t0, t1);
        for (k, v) in e.nodes().enumerate() {
            let i = *index.entry(v).or_insert_with(|| {
                nodes.push(v);
                normals.push([0.0; DIM]);
                weights.push(0.0);
                nodes.len() - 1
            });
            weights[i] += w[k];
            for c in 0..DIM {
                normals[i][c] += len * n[c];
            }
        }
    }
    for n in &mut normals {
        let l = n[0].hypot(n[1]);
        if l > 0.0 {
            *n = [n[0] / l, n[1] / l];
        }
    }
    (nodes, normals, weights)
}

/// The parameter interval [t0, t1] ⊂ [0, 1] of edge `e` whose normal rays hit the partner
/// boundary (empty as t0 = t1 = 0). Found by sampling and bisection.
fn covered_part(mesh: &Mesh, e: &Edge, n: Vector, partner: &EdgeIndex) -> (f64, f64) {
    const SAMPLES: usize = 8;
    let (a, b) = (mesh.nodes()[e.a], mesh.nodes()[e.b]);
    let hits = |t: f64| {
        let x = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        partner.project(x, n).is_some()
    };
    let covered: Vec<bool> = (0..=SAMPLES)
        .map(|i| hits(i as f64 / SAMPLES as f64))
        .collect();
    if covered.iter().all(|&c| c) {
        return (0.0, 1.0);
    }
    let (Some(first), Some(last)) = (
        covered.iter().position(|&c| c),
        covered.iter().rposition(|&c| c),
    ) else {
        return (0.0, 0.0);
    };
    // Bisect between the last uncovered and first covered sample (and vice versa at the end).
    let refine = |mut lo: f64, mut hi: f64, covered_hi: bool| {
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if hits(mid) == covered_hi {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    };
    let step = 1.0 / SAMPLES as f64;
    let t0 = if first == 0 {
        0.0
    } else {
        refine((first - 1) as f64 * step, first as f64 * step, true)
    };
    let t1 = if last == SAMPLES {
        1.0
    } else {
        refine((last + 1) as f64 * step, last as f64 * step, true)
    };
    (t0, t1.max(t0))
}

/// Integrals of the edge shape functions (order `a, b, [mid]`) over [t0, t1] of an edge of length
/// `len`: trapezoid / Simpson weights for [0, 1]. Negative P2 vertex shares of a partial edge are
/// dropped and the rest rescaled to the covered length.
fn partial_edge_weights(order: Order, len: f64, t0: f64, t1: f64) -> [f64; 3] {
    if t0 == 0.0 && t1 == 1.0 {
        return edge_nodal_weights(order, len);
    }
    let integral = |f: &dyn Fn(f64) -> f64| len * (f(t1) - f(t0));
    let w = match order {
        Order::P1 => [
            integral(&|t| t - 0.5 * t * t),
            integral(&|t| 0.5 * t * t),
            0.0,
        ],
        Order::P2 => [
            integral(&|t| t - 1.5 * t * t + 2.0 / 3.0 * t.powi(3)),
            integral(&|t| 2.0 / 3.0 * t.powi(3) - 0.5 * t * t),
            integral(&|t| 2.0 * t * t - 4.0 / 3.0 * t.powi(3)),
        ],
    };
    let positive = w.map(|x| x.max(0.0));
    let sum: f64 = positive.iter().sum();
    let covered = len * (t1 - t0);
    if sum > 0.0 {
        positive.map(|x| x * covered / sum)
    } else {
        [0.0; 3]
    }
}

fn cross(a: Vector, b: Vector) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The edges of one contact boundary in an R-tree of their bounding boxes, for the ray
/// projections of the partner's points: each query looks only at the edges near the ray, so
/// projecting all m points of a zone costs O(m log m) instead of O(m²).
pub struct EdgeIndex<'m> {
    mesh: &'m Mesh,
    edges: &'m [Edge],
    tree: RTree<GeomWithData<Rectangle<Point>, usize>>,
    /// Centre and half-diagonal of the bounding box of all the edges.
    centre: Point,
    radius: f64,
    /// First search half-length: the mean edge length.
    start: f64,
}

impl<'m> EdgeIndex<'m> {
    /// Indexes `edges` of `mesh`.
    pub fn new(mesh: &'m Mesh, edges: &'m [Edge]) -> EdgeIndex<'m> {
        let p = mesh.nodes();
        let boxes: Vec<GeomWithData<Rectangle<Point>, usize>> = edges
            .iter()
            .enumerate()
            .map(|(k, e)| {
                let (a, b) = (p[e.a], p[e.b]);
                // Inflated by the projection's tolerance on the edge parameter (1e−9).
                let pad = 1e-8 * dist(a, b) + f64::MIN_POSITIVE;
                let lo = [a[0].min(b[0]) - pad, a[1].min(b[1]) - pad];
                let hi = [a[0].max(b[0]) + pad, a[1].max(b[1]) + pad];
                GeomWithData::new(Rectangle::from_corners(lo, hi), k)
            })
            .collect();
        let (mut lo, mut hi) = ([f64::INFINITY; DIM], [f64::NEG_INFINITY; DIM]);
        for e in edges {
            for v in [e.a, e.b] {
                for c in 0..DIM {
                    lo[c] = lo[c].min(p[v][c]);
                    hi[c] = hi[c].max(p[v][c]);
                }
            }
        }
        let total: f64 = edges.iter().map(|e| dist(p[e.a], p[e.b])).sum();
        EdgeIndex {
            mesh,
            edges,
            tree: RTree::bulk_load(boxes),
            centre: std::array::from_fn(|c| 0.5 * (lo[c] + hi[c])),
            radius: 0.5 * dist(lo, hi),
            start: (total / edges.len().max(1) as f64).max(f64::MIN_POSITIVE),
        }
    }

    /// The nearest hit of the ray x + t n (see `project`): edges are searched in growing boxes
    /// around the segment [x − R n, x + R n] until a hit with |t| ≤ R is found (no nearer hit can
    /// lie outside the box) or the box holds every edge.
    pub fn project(&self, x: Point, n: Vector) -> Option<(f64, Vec<(usize, f64)>)> {
        if self.edges.is_empty() {
            return None;
        }
        let reach = dist(x, self.centre) + self.radius;
        let mut r = self.start;
        loop {
            let (a, b) = (
                [x[0] - r * n[0], x[1] - r * n[1]],
                [x[0] + r * n[0], x[1] + r * n[1]],
            );
            let envelope = AABB::from_corners(
                [a[0].min(b[0]), a[1].min(b[1])],
                [a[0].max(b[0]), a[1].max(b[1])],
            );
            let mut near: Vec<usize> = self
                .tree
                .locate_in_envelope_intersecting(&envelope)
                .map(|g| g.data)
                .collect();
            // The edge order of a full scan, so that ties go to the same edge.
            near.sort_unstable();
            let hit = project(x, n, self.mesh, near.iter().map(|&k| &self.edges[k]));
            match hit {
                Some((t, _)) if t.abs() <= r => return hit,
                _ if r > reach => return hit,
                _ => r *= 2.0,
            }
        }
    }
}

impl EdgeIndex<'_> {
    /// Where the vertices of the partner edges facing the edge a → b (outward normal `n`) project
    /// onto its line, as parameters t of a + t (b − a): the breakpoints of the partner's shape
    /// functions along the edge. Searched in the band the edge sweeps along n out to its rays'
    /// hits, widened by its length; empty if no ray from it hits.
    pub(crate) fn vertices_facing(&self, a: Point, b: Point, n: Vector) -> Vec<f64> {
        let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let reach: Vec<f64> = [a, mid, b]
            .iter()
            .filter_map(|&x| self.project(x, n).map(|h| h.0))
            .collect();
        if reach.is_empty() {
            return Vec::new();
        }
        let len = dist(a, b);
        let lo = reach.iter().fold(f64::INFINITY, |m, &t| m.min(t)) - len;
        let hi = reach.iter().fold(f64::NEG_INFINITY, |m, &t| m.max(t)) + len;
        let corners = [a, b].map(|x| [lo, hi].map(|s| [x[0] + s * n[0], x[1] + s * n[1]]));
        let all = corners.iter().flatten();
        let (mut min, mut max) = ([f64::INFINITY; DIM], [f64::NEG_INFINITY; DIM]);
        for x in all {
            for c in 0..DIM {
                min[c] = min[c].min(x[c]);
                max[c] = max[c].max(x[c]);
            }
        }
        let dir: Vector = [b[0] - a[0], b[1] - a[1]];
        let dd = dot(dir, dir);
        let p = self.mesh.nodes();
        let mut out = Vec::new();
        for g in self
            .tree
            .locate_in_envelope_intersecting(&AABB::from_corners(min, max))
        {
            let e = &self.edges[g.data];
            if dot(self.mesh.edge_normal(e).0, n) >= -1e-3 {
                continue;
            }
            for v in [e.a, e.b] {
                out.push(dot([p[v][0] - a[0], p[v][1] - a[1]], dir) / dd);
            }
        }
        out
    }
}

/// Intersects the ray x + t n with the edges (facing the ray) and returns the signed distance t
/// of the nearest hit and the partner node coefficients there.
fn project<'e>(
    x: Point,
    n: Vector,
    mesh: &Mesh,
    edges: impl IntoIterator<Item = &'e Edge>,
) -> Option<(f64, Vec<(usize, f64)>)> {
    let p = mesh.nodes();
    let mut best: Option<(f64, Vec<(usize, f64)>)> = None;
    for e in edges {
        let (ne, len) = mesh.edge_normal(e);
        // Only edges facing the point: their outward normal opposes n.
        if dot(ne, n) >= -1e-3 {
            continue;
        }
        let (a, b) = (p[e.a], p[e.b]);
        let dir: Vector = std::array::from_fn(|c| b[c] - a[c]);
        let den = cross(n, dir);
        if den.abs() < 1e-14 * len {
            continue;
        }
        let ax: Vector = std::array::from_fn(|c| a[c] - x[c]);
        let t = cross(ax, dir) / den;
        let s = cross(ax, n) / den;
        let tol = 1e-9;
        if !(-tol..=1.0 + tol).contains(&s) {
            continue;
        }
        let s = s.clamp(0.0, 1.0);
        if best.as_ref().is_some_and(|(bt, _)| bt.abs() <= t.abs()) {
            continue;
        }
        let shape = edge_shape(mesh.order(), s);
        let coeffs = e.nodes().zip(shape).filter(|(_, c)| *c != 0.0).collect();
        best = Some((t, coeffs));
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use contactdd_core::{Diagonal, Rectangle};

    /// The R-tree search finds exactly the hit of a scan over all edges (same t, same edge and
    /// coefficients), for rays from many points in many directions, hitting or missing.
    #[test]
    fn the_edge_index_finds_the_same_hit_as_a_full_scan() {
        let mesh = Rectangle {
            origin: [0.0, 0.0],
            corner: [3.0, 1.0],
            nx: 37,
            ny: 3,
            diagonal: Diagonal::Right,
            mirror: false,
            order: Order::P1,
        }
        .mesh()
        .unwrap()
        .map_nodes(|p| [p[0], p[1] + 0.1 * (2.0 * p[0]).sin() * p[1]])
        .unwrap();
        let edges = mesh.boundary("top").unwrap();
        let index = EdgeIndex::new(&mesh, edges);
        let mut checked = 0;
        for i in 0..200 {
            let x = [
                -0.5 + 4.0 * (i as f64 * 0.618).fract(),
                1.05 + 0.3 * (i as f64 * 0.37).fract(),
            ];
            let angle = -std::f64::consts::FRAC_PI_2 + 1.4 * ((i as f64 * 0.29).fract() - 0.5);
            let n = [angle.cos(), angle.sin()];
            let (fast, slow) = (index.project(x, n), project(x, n, &mesh, edges));
            assert_eq!(fast, slow, "ray {i} from {x:?} along {n:?}");
            checked += usize::from(slow.is_some());
        }
        assert!(checked > 100, "only {checked} rays hit");
    }
}
