//! Balanced contact pairs: one normal per point for both sides' displacements, and every point's
//! pressure acting on both bodies, so that a pair's two sides receive equal and opposite forces
//! by construction (docs/method.md §4, "Which normal the gap uses").
//!
//! Both sides' gaps are read along the normals of one side of the pair, the *reference* side:
//! the flatter one (the smaller spread of its normals over the points that face the partner; on
//! a tie the side with more points facing the other, then side 0). A point j of the reference
//! side reads along its own normal, ν_j = n_j; a point of the other side reads along the
//! reference side's normal where its ray hits it, ν_j = −n_ref(x′_j), interpolated from the
//! nodal normals. Then
//!   s_j = u_α(x_j)·ν_j − u_β(x′_j)·ν_j
//!       = (n_j·ν_j) U_j + (t_j·ν_j) V_j − Σ_k c_jk [(n_k·ν_j) U_k + (t_k·ν_j) V_k],
//! with U, V the normal and tangential displacements of a node (t = n turned by +90°), and the
//! gap d_j is the distance along ν_j. One normal field for both sides keeps the two passes'
//! gaps consistent; with a flat reference side it is the common normal of Hertz's theory, in
//! which tangential displacements do not change the gap. A tangential unknown V exists only
//! where some coefficient needs it, so a flat zone keeps its normal unknowns alone.
//!
//! Only the reference side's points carry pressure (one pass): point j's nodal force w_j σ_j acts
//! on its own unknown and, with the opposite sign, on the partner's unknowns through its gap row
//! ([`ContactPoint::load_row`]); the other side's points follow. s_j is invariant under a joint
//! translation, so the two sides' forces, the derivatives of Σ_j w_j/(2θ) ((d_j − s_j)⁻)², are
//! equal and opposite. The partner's coefficients are the dual mortar ones (`contact::mortar`).

use std::ops::Range;

use contactdd_core::geometry::dot;
use contactdd_core::Vector;

use super::formulation::{Forces, Formulation};
use super::friction::FrictionPoint;
use super::mortar::Mortar;
use super::points::{carried, carried_tangential, ContactPoint, Role};

/// What a coefficient of a balanced gap row multiplies.
#[derive(Clone, Copy, PartialEq)]
enum Target {
    /// The normal unknown of (old) point k.
    Normal(usize),
    /// The tangential unknown at the node of (old) point k.
    Tangent(usize),
}

/// The points of every pair, found once.
fn of_pairs(points: &[ContactPoint], pairs: usize) -> Vec<Vec<usize>> {
    let mut of_pair: Vec<Vec<usize>> = vec![Vec::new(); pairs];
    for (j, p) in points.iter().enumerate() {
        of_pair[p.pair].push(j);
    }
    of_pair
}

/// Resolves the pairs' forces against their points: a balanced pair whose sides match node for
/// node (the same discrete problem either way) is the own-side formulation and keeps its
/// arithmetic. Its points' partners become the matching node alone, coefficient 1: a rotated or
/// shifted mesh interpolates the partner at a hit a rounding error away from the node.
pub(super) fn resolve(points: &mut [ContactPoint], formulations: &mut [Formulation]) {
    let of_pair = of_pairs(points, formulations.len());
    for (f, of_pair) in formulations.iter_mut().zip(&of_pair) {
        // A frictional pair keeps its carriers: they carry the tangential tractions.
        let frictional = f.friction.is_active();
        if f.forces != Forces::Balanced || frictional {
            continue;
        }
        if let Some(matched) = matches_node_for_node(points, of_pair) {
            f.forces = Forces::OwnSide;
            for (&j, k) in of_pair.iter().zip(matched) {
                if let Some(k) = k {
                    if points[j].partner.as_slice() != [(k, 1.0)] {
                        points[j].partner = vec![(k, 1.0)];
                    }
                }
            }
        }
    }
}

/// Rewrites the points of the balanced pairs (`formulations` resolved by [`resolve`], `first`
/// the body of side 0 of every pair) into balanced form: carriers and followers, new gap rows,
/// tangential unknowns appended to each body's points, and reference springs.
pub(super) fn balance(
    points: Vec<ContactPoint>,
    body_range: Vec<Range<usize>>,
    hits: &[Option<f64>],
    mortar: &[Option<Mortar>],
    formulations: &[Formulation],
    first: &[usize],
) -> (Vec<ContactPoint>, Vec<Range<usize>>) {
    let rewrite: Vec<bool> = formulations
        .iter()
        .map(|f| f.forces == Forces::Balanced)
        .collect();
    if !rewrite.iter().any(|&b| b) {
        return (points, body_range);
    }
    let of_pair = of_pairs(&points, formulations.len());
    let reference: Vec<usize> = (0..formulations.len())
        .map(|pair| reference_body(&points, &of_pair[pair], first[pair]))
        .collect();
    let rows: Vec<Rows> = (0..points.len())
        .map(|j| row(&points, j, mortar[j].as_ref(), reference[points[j].pair]))
        .collect();
    let (frictional, tangent) = tangential_unknowns(&points, &rows, formulations, &reference);
    let numbering = Numbering::new(&body_range, &tangent);
    let mut out: Vec<Option<ContactPoint>> = vec![None; numbering.len];
    for (j, p) in points.iter().enumerate() {
        let mut q = p.clone();
        if rewrite[p.pair] {
            q.role = if p.body == reference[p.pair] {
                Role::Carrier
            } else {
                Role::Follower
            };
            q.gap = match (&mortar[j], hits[j]) {
                // The weighted distance along ν.
                (Some(m), _) => m.profile + dot(m.ray, rows[j].nu),
                // The distance along ν instead of the ray's length.
                (None, Some(t)) => (p.gap - t) + t * dot(p.normal, rows[j].nu),
                (None, None) => p.gap,
            };
            let renumber = |row: &[(Target, f64)]| -> Vec<(usize, f64)> {
                row.iter().map(|&(t, c)| (numbering.of(t), c)).collect()
            };
            q.partner = renumber(&rows[j].gap);
            q.friction = frictional[j].then(|| FrictionPoint {
                law: formulations[p.pair].friction,
                row: renumber(&rows[j].slip),
                theta: p.theta,
                multiplier: 0.0,
                reference: 0.0,
            });
        } else {
            q.partner = p
                .partner
                .iter()
                .map(|&(k, c)| (numbering.of(Target::Normal(k)), c))
                .collect();
        }
        out[numbering.normal[j]] = Some(q);
        if tangent[j] {
            out[numbering.tangent[j]] = Some(ContactPoint {
                normal: turned(p.normal),
                weight: 0.0,
                gap: f64::INFINITY,
                multiplier: 0.0,
                partner: Vec::new(),
                spring: 0.0,
                role: Role::Tangent,
                friction: None,
                ..p.clone()
            });
        }
    }
    let mut points: Vec<ContactPoint> = out.into_iter().flatten().collect();
    lump_springs(&mut points);
    (points, numbering.body_range)
}

/// Which points are frictional carriers (they read their tangential rows), and which nodes need a
/// tangential unknown: those some balanced gap row, or a frictional carrier's tangential row,
/// reads tangentially.
fn tangential_unknowns(
    points: &[ContactPoint],
    rows: &[Rows],
    formulations: &[Formulation],
    reference: &[usize],
) -> (Vec<bool>, Vec<bool>) {
    let frictional: Vec<bool> = points
        .iter()
        .map(|p| {
            formulations[p.pair].friction.is_active()
                && p.body == reference[p.pair]
                && p.has_partner()
        })
        .collect();
    let mut tangent = vec![false; points.len()];
    for (j, p) in points.iter().enumerate() {
        if formulations[p.pair].forces != Forces::Balanced {
            continue;
        }
        let slip = frictional[j].then_some(rows[j].slip.as_slice());
        for (t, _) in rows[j].gap.iter().chain(slip.into_iter().flatten()) {
            if let Target::Tangent(k) = *t {
                tangent[k] = true;
            }
        }
    }
    (frictional, tangent)
}

/// The new numbering of the unknowns: every body's points in their order, then its tangential
/// unknowns.
struct Numbering {
    /// New index of the normal unknown of every (old) point.
    normal: Vec<usize>,
    /// New index of the tangential unknown at the node of every (old) point (where it has one).
    tangent: Vec<usize>,
    body_range: Vec<Range<usize>>,
    len: usize,
}

impl Numbering {
    fn new(body_range: &[Range<usize>], tangent: &[bool]) -> Numbering {
        let mut n = Numbering {
            normal: vec![0; tangent.len()],
            tangent: vec![usize::MAX; tangent.len()],
            body_range: Vec::with_capacity(body_range.len()),
            len: 0,
        };
        for range in body_range {
            let start = n.len;
            for j in range.clone() {
                n.normal[j] = n.len;
                n.len += 1;
            }
            for k in range.clone().filter(|&k| tangent[k]) {
                n.tangent[k] = n.len;
                n.len += 1;
            }
            n.body_range.push(start..n.len);
        }
        n
    }

    fn of(&self, target: Target) -> usize {
        match target {
            Target::Normal(k) => self.normal[k],
            Target::Tangent(k) => self.tangent[k],
        }
    }
}

/// Reference springs of the balanced pairs' unknowns: the lumped stiffness Σ |a| w_j/θ_j of the
/// pressures that load them (w/θ for a carrier), and of the frictional points' tangential
/// tractions, Σ |b| w_j/θ_t,j.
fn lump_springs(points: &mut [ContactPoint]) {
    let tangential = carried_tangential(points);
    for (q, loads) in carried(points).iter().enumerate() {
        if points[q].role != Role::OwnSide {
            let lumped = |list: &[(usize, f64)], theta: &dyn Fn(usize) -> f64| -> f64 {
                list.iter()
                    .map(|&(j, a)| a.abs() * points[j].weight / theta(j))
                    .sum()
            };
            let normal = lumped(loads, &|j| points[j].theta);
            points[q].spring = if tangential[q].is_empty() {
                normal
            } else {
                let theta_t = |j: usize| points[j].friction.as_ref().map_or(1.0, |f| f.theta);
                normal + lumped(&tangential[q], &theta_t)
            };
        }
    }
}

/// The rows of a point of a balanced pair (see [`row`]).
struct Rows {
    /// The gap row (its own normal unknown's coefficient less 1).
    gap: Vec<(Target, f64)>,
    /// The tangential row along ν turned by +90° (every coefficient).
    slip: Vec<(Target, f64)>,
    /// ν.
    nu: Vector,
}

/// The gap row of point j read along ν_j (see the module docs), its tangential row read along ν_j
/// turned by +90°, and ν_j. The gap row holds its own normal unknown's coefficient less 1 (the 1
/// is implicit in `partner`), its own tangential unknown, and the partner's normal and tangential
/// unknowns with the dual mortar coefficients (`contact::mortar`; the ray's interpolation where
/// there are none); zero coefficients left out. The tangential row holds every coefficient.
fn row(points: &[ContactPoint], j: usize, mortar: Option<&Mortar>, reference: usize) -> Rows {
    let p = &points[j];
    if !p.has_partner() {
        return Rows {
            gap: Vec::new(),
            slip: Vec::new(),
            nu: p.normal,
        };
    }
    let nu = if p.body == reference {
        p.normal
    } else {
        let mut n = [0.0; 2];
        for &(k, c) in &p.partner {
            n[0] -= c * points[k].normal[0];
            n[1] -= c * points[k].normal[1];
        }
        let l = n[0].hypot(n[1]);
        [n[0] / l, n[1] / l]
    };
    let coefficients = mortar.map_or(p.partner.as_slice(), |m| m.coefficients.as_slice());
    // Σ over the own node and the partner's of (unknown, coefficient) along the direction `dir`.
    let along = |dir: Vector, own: f64| {
        let mut out = Vec::with_capacity(2 * coefficients.len() + 2);
        let mut push = |t: Target, c: f64| {
            // A tangential coefficient below 1e−12 is a straight zone turned in floating point:
            // no unknown for it (it would carry a spring of that size).
            let negligible = matches!(t, Target::Tangent(_)) && c.abs() <= 1e-12;
            if c != 0.0 && !negligible {
                out.push((t, c));
            }
        };
        push(Target::Normal(j), dot(p.normal, dir) - own);
        push(Target::Tangent(j), dot(turned(p.normal), dir));
        for &(k, c) in coefficients {
            let nk = points[k].normal;
            push(Target::Normal(k), -dot(nk, dir) * c);
            push(Target::Tangent(k), -dot(turned(nk), dir) * c);
        }
        out
    };
    Rows {
        gap: along(nu, 1.0),
        slip: along(turned(nu), 0.0),
        nu,
    }
}

/// The reference body of a pair (its points `of_pair`, `first` the body of side 0): the side
/// whose partnered points' normals spread least (1 − n_j·n̄ at most, n̄ their mean direction).
/// On a tie (two straight sides), the side with more points facing the other: its nodes lie on
/// the other side's surface, so its pressures cover the whole zone (a coarse side can have no
/// node at all under a narrow partner, which would then rest on nothing); then side 0. A side
/// with no point facing the other never carries while the other has one.
fn reference_body(points: &[ContactPoint], of_pair: &[usize], first: usize) -> usize {
    // (spread, points facing the partner) of one side.
    let side = |body: usize| {
        let facing: Vec<&ContactPoint> = of_pair
            .iter()
            .map(|&j| &points[j])
            .filter(|p| p.body == body && p.has_partner())
            .collect();
        let mut mean = [0.0; 2];
        for p in &facing {
            mean[0] += p.normal[0];
            mean[1] += p.normal[1];
        }
        let l = mean[0].hypot(mean[1]);
        if l == 0.0 {
            return (0.0, facing.len());
        }
        let mean = [mean[0] / l, mean[1] / l];
        let spread = facing
            .iter()
            .fold(0.0f64, |m, p| m.max(1.0 - dot(p.normal, mean)));
        (spread, facing.len())
    };
    let second = of_pair
        .iter()
        .map(|&j| points[j].body)
        .find(|&b| b != first)
        .unwrap_or(first);
    let ((s1, n1), (s2, n2)) = (side(first), side(second));
    // Spreads that differ by rounding alone are a tie.
    let tie = (s1 - s2).abs() <= SPREAD_TIE;
    let second_wins = if n1 == 0 || n2 == 0 {
        n1 == 0 && n2 > 0
    } else if tie {
        n2 > n1
    } else {
        s2 < s1
    };
    if second_wins {
        second
    } else {
        first
    }
}

/// Normal spreads (1 − cos of the angle) closer than this are equal: rounding of straight sides.
const SPREAD_TIE: f64 = 1e-12;

/// The matching partner node of every point of a pair (`of_pair`; `None` for a point without
/// partner) if every point faces exactly one partner node, which faces it back, along opposite
/// normals, with the same weight and gap: then each side's pressure equals the other's and the
/// own-side formulation is already balanced. `None` otherwise.
///
/// "Exactly" is up to rounding, relative to the mesh and never to the coordinates, so that a
/// shifted or rotated problem resolves the same way: a coefficient within [`MATCH_TOL`] of 1
/// (the others within it of 0), normals within [`MATCH_TOL`] of opposite, weights within
/// [`MATCH_TOL`] of each other relative to the larger, gaps within [`MATCH_TOL`] times the
/// pair's shortest nodal weight (a length of the order of the shortest contact edge).
fn matches_node_for_node(points: &[ContactPoint], of_pair: &[usize]) -> Option<Vec<Option<usize>>> {
    let length = of_pair
        .iter()
        .map(|&j| points[j].weight)
        .filter(|&w| w > 0.0)
        .fold(f64::INFINITY, f64::min);
    let matched: Vec<Option<usize>> = of_pair.iter().map(|&j| dominant(&points[j])).collect();
    let all = of_pair.iter().zip(&matched).all(|(&j, &k)| {
        let p = &points[j];
        match k {
            None => p.partner.is_empty(),
            Some(k) => {
                let q = &points[k];
                let normals = (p.normal[0] + q.normal[0]).hypot(p.normal[1] + q.normal[1]);
                dominant(q) == Some(j)
                    && normals <= MATCH_TOL
                    && (q.weight - p.weight).abs() <= MATCH_TOL * q.weight.max(p.weight)
                    && (q.gap - p.gap).abs() <= MATCH_TOL * length
            }
        }
    });
    all.then_some(matched)
}

/// The partner node of a point whose partner coefficients are 1 at one node and 0 elsewhere,
/// within [`MATCH_TOL`]; `None` for any other point (none, or an interpolation between nodes).
fn dominant(p: &ContactPoint) -> Option<usize> {
    let &(k, c) = p.partner.iter().max_by(|a, b| a.1.total_cmp(&b.1))?;
    let rest_zero = p
        .partner
        .iter()
        .all(|&(i, d)| i == k || d.abs() <= MATCH_TOL);
    ((c - 1.0).abs() <= MATCH_TOL && rest_zero).then_some(k)
}

/// The relative tolerance of [`matches_node_for_node`]: far above the rounding of coordinates
/// (about 1e−16 of their size, so up to 1e−9 of the mesh size for a problem 1e7 mesh sizes from
/// the origin), far below any mesh detail.
const MATCH_TOL: f64 = 1e-9;

/// n turned by +90°.
fn turned(n: [f64; 2]) -> [f64; 2] {
    [-n[1], n[0]]
}
