//! The contact points of a model and the interface they form: each point's normal, weight, gap,
//! penalty and partner coefficients, its role in its pair's formulation, and the contact
//! pressures and forces that the pair sums s_j give.

use std::ops::Range;

use contactdd_core::Vector;

use super::formulation::Formulation;
use super::friction::{FrictionPoint, Status};

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
    /// the partner's normal and tangential unknowns ([`crate::contact::balanced_pair`]).
    pub partner: Vec<(usize, f64)>,
    /// The reference spring D₀ of this interface unknown: w/θ, or for a balanced pair the lumped
    /// penalty stiffness of the pressures that load it.
    pub spring: f64,
    /// What the unknown is and how its point's pressure loads the bodies.
    pub role: Role,
    /// The friction of a carrier of a frictional pair (`None` elsewhere).
    pub friction: Option<FrictionPoint>,
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
    /// The formulation of every pair, as the points were built from it (resolved: a balanced
    /// pair whose sides match node for node is own-side).
    pub formulations: Vec<Formulation>,
    /// Per unknown q, the frictional points whose tangential traction loads it and their shares
    /// b (the transpose of their tangential rows): F_q gains Σ b w_j σ_t,j. Empty lists without
    /// friction.
    pub carried_tangential: Vec<Vec<(usize, f64)>>,
}

impl Interface {
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

    /// True if some point has friction.
    pub fn has_friction(&self) -> bool {
        self.points.iter().any(|p| p.friction.is_some())
    }

    /// The tangential displacement g_j of every frictional point (0 elsewhere) from all the
    /// interface displacements `u`.
    pub fn slip_sums(&self, u: &[f64]) -> Vec<f64> {
        self.points
            .iter()
            .map(|p| p.friction.as_ref().map_or(0.0, |f| f.slip_sum(u)))
            .collect()
    }

    /// The tangential traction σ_t and status of point j for the pair sums `s` and tangential
    /// displacements `g` (0 and open without friction).
    pub fn traction(&self, j: usize, s: &[f64], g: &[f64]) -> (f64, Status) {
        let p = &self.points[j];
        match &p.friction {
            Some(f) if p.has_partner() => f.traction(g[j], -p.pressure(s[j])),
            _ => (0.0, Status::Open),
        }
    }

    /// Makes the slipping points whose trial traction changed sign since the state with the
    /// tangential displacements `before` stick in a Newton step's statuses `status`; returns
    /// whether there were any. U is affine along a step, so the trial traction passed through
    /// zero, inside the disc, on the way: the slip direction of neither end is one the solution
    /// takes, and a step that slips the point in its new direction swings it back (a cycle of
    /// period two). Nothing without `before` (the first step).
    pub fn hold_reversals(&self, status: &mut [Status], before: &[f64], now: &[f64]) -> bool {
        let mut held = false;
        if before.is_empty() {
            return held;
        }
        for (j, st) in status.iter_mut().enumerate() {
            let Some(f) = &self.points[j].friction else {
                continue;
            };
            if *st == Status::Slip && f.trial(before[j]) * f.trial(now[j]) < 0.0 {
                *st = Status::Stick;
                held = true;
            }
        }
        held
    }

    /// The contact force along unknown q with friction: [`Interface::force`] plus the
    /// tangential tractions' shares Σ b w_j σ_t,j (the normal force alone without friction).
    pub fn total_force(&self, q: usize, s: &[f64], g: &[f64]) -> f64 {
        let normal = self.force(q, s);
        match self.carried_tangential.get(q) {
            Some(list) if !list.is_empty() => {
                normal
                    + list
                        .iter()
                        .map(|&(j, b)| b * (self.points[j].weight * self.traction(j, s, g).0))
                        .sum::<f64>()
            }
            _ => normal,
        }
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

/// Per unknown, the frictional points whose tangential traction loads it with their shares (see
/// [`Interface::carried_tangential`]).
pub(super) fn carried_tangential(points: &[ContactPoint]) -> Vec<Vec<(usize, f64)>> {
    let mut out = vec![Vec::new(); points.len()];
    for (j, p) in points.iter().enumerate() {
        for &(q, b) in p.friction.iter().flat_map(|f| &f.row) {
            out[q].push((j, b));
        }
    }
    out
}

/// Per unknown, the points that load it with their shares (see [`Interface::carried`]).
pub(super) fn carried(points: &[ContactPoint]) -> Vec<Vec<(usize, f64)>> {
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
