//! The contact problem in space, as the solvers take it: the bodies and pairs, the contact points'
//! rows over the coupled DOFs (the dual mortar rows of [`crate::contact3d`] along each point's
//! normal), the solution and the errors. [`crate::solid_monolithic`] and [`crate::solid_dd`]
//! solve it.
//!
//! Point j of a pair (a node of its reference surface) reads the approach s_j = a_jᵀu, a_j its
//! normal row over both bodies' DOFs ([`PointRows`]), and carries the pressure
//! p_j = max(0, s_j − d_j)/θ, d_j its mortar gap. Its force w_j p_j acts along −a_j, so the two
//! sides receive equal and opposite forces.

use contactdd_core::solid::{dof, SolidMesh, TetOrder};

use crate::contact3d::{
    dual_mortar, DiscStatus, PointRows, Side, Surface, SurfaceError, TriangleIndex,
};
use crate::{Enforcement, Friction};

/// One body: its mesh, its 6 × 6 elasticity matrix, its prescribed DOFs (own numbering) and its
/// nodal loads.
pub struct SolidBodySpec<'a> {
    /// The tetrahedral mesh with named faces.
    pub mesh: &'a SolidMesh,
    /// The elasticity matrix (Voigt).
    pub elasticity: [[f64; 6]; 6],
    /// (DOF, value) of every prescribed DOF.
    pub prescribed: Vec<(usize, f64)>,
    /// The nodal loads (3 per node).
    pub load: Vec<f64>,
}

/// A contact pair: a face of one body (the reference side, whose nodes are the contact points)
/// against a face of another, with its penalty θ and the distance along the reference normals
/// within which the partner is searched.
pub struct SolidPairSpec {
    /// (body, face) of the reference side.
    pub reference: (usize, String),
    /// (body, face) of the partner side.
    pub partner: (usize, String),
    /// The penalty: the overlap per unit pressure.
    pub theta: f64,
    /// How far along the normals a partner counts.
    pub search: f64,
    /// `Penalty`: p = max(0, s − d)/θ; `Augmented`: the exact Signorini conditions (no
    /// penetration, no pressure across a gap), the fixed point of the augmented Lagrangian,
    /// which the Newton method of [`crate::solid_dd`] solves directly.
    pub enforcement: Enforcement,
    /// The tangential law (docs/three-d.md, "Friction in space"): the traction is bounded by
    /// the disc of radius μp (Coulomb) or the bound (Tresca); `Friction::None` is frictionless.
    pub friction: Friction,
}

/// Why the reference cannot solve a problem.
#[derive(Debug, thiserror::Error)]
pub enum SolidContactError {
    /// A pair names a body or face that does not exist, or a face is not a surface.
    #[error("contact pair {pair}: {message}")]
    Pair {
        /// The pair.
        pair: usize,
        /// What is wrong.
        message: String,
    },
    /// A face's triangles are not a contact surface.
    #[error("contact pair {pair}: {source}")]
    Surface {
        /// The pair.
        pair: usize,
        /// The surface's error.
        source: SurfaceError,
    },
    /// The coupled system is singular or cannot be factorised: a body that neither supports nor
    /// closed contact points hold.
    #[error("the coupled system cannot be factorised at Newton step {step}: {message} (a body that neither its supports nor closed contact points hold?)")]
    Factor {
        /// The Newton step.
        step: usize,
        /// The factorisation's message.
        message: String,
    },
    /// A body that its supports leave free to move rigidly, and that the closed points do not
    /// hold at a Newton step (nothing resists one of its free motions).
    #[error("body {body}: at Newton step {step} the closed contact points do not hold it (its supports leave it free to move rigidly, and no closed point resists the motion)")]
    NotHeld {
        /// The body.
        body: usize,
        /// The Newton step.
        step: usize,
    },
    /// The multiplier updates of the augmented pairs did not meet the Signorini conditions.
    #[error("the augmented pairs still violate the contact conditions by {violation:.1e} after {updates} multiplier updates")]
    NotEnforced {
        /// The updates taken.
        updates: usize,
        /// The largest violation left, a length.
        violation: f64,
    },
    /// A floating body's loads do more work along one of its free rigid motions than friction
    /// can oppose there: it slides, and no equilibrium exists.
    #[error("body {body} slides: its loads do {work:.3e} of work along a free rigid motion, and friction opposes at most {resistance:.3e}")]
    Slides {
        /// The body.
        body: usize,
        /// The loads' work along the motion (per unit amplitude).
        work: f64,
        /// The most work friction does against it (Σ w_j b_j |Δg_j|).
        resistance: f64,
    },
    /// The solver does not take the problem.
    #[error("{0}")]
    Unsupported(String),
    /// The closed set did not settle.
    #[error("the closed set did not settle in {steps} Newton steps")]
    NotSettled {
        /// The steps taken.
        steps: usize,
    },
}

/// A contact point of the solution.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidContactPoint {
    /// The pair.
    pub pair: usize,
    /// The node of the reference body.
    pub node: usize,
    /// Its position.
    pub position: [f64; 3],
    /// Its weight ∫ φ_j dA.
    pub weight: f64,
    /// Its initial gap along the normal.
    pub gap: f64,
    /// Its contact pressure (≥ 0).
    pub pressure: f64,
    /// Its tangential state, at a point of a frictional pair.
    pub friction: Option<SolidFrictionPoint>,
}

/// The tangential state of a contact point of a frictional pair, in its frame (t₁, t₂).
#[derive(Clone, Debug, PartialEq)]
pub struct SolidFrictionPoint {
    /// The unit tangents t₁, t₂ ((t₁, t₂, ν) right-handed, ν the outward normal of the
    /// reference side).
    pub tangents: [[f64; 3]; 2],
    /// The tangential traction on the reference side, (t₁, t₂) components: |traction| ≤ b.
    pub traction: [f64; 2],
    /// The slip g: the tangential displacement of the reference side relative to its partner.
    pub slip: [f64; 2],
    /// The traction and the slip the increment started from (zero for a single solve; the last
    /// step's for a load step).
    pub carried: [[f64; 2]; 2],
    /// Stick or slip; `None` where the point is open.
    pub status: Option<DiscStatus>,
}

impl SolidFrictionPoint {
    /// The traction on the reference side as a vector in space.
    pub fn traction_vector(&self) -> [f64; 3] {
        self.in_space(self.traction)
    }

    /// The slip as a vector in space.
    pub fn slip_vector(&self) -> [f64; 3] {
        self.in_space(self.slip)
    }

    /// The vector of (t₁, t₂) components `v`.
    fn in_space(&self, v: [f64; 2]) -> [f64; 3] {
        let [t1, t2] = self.tangents;
        [0, 1, 2].map(|c| v[0] * t1[c] + v[1] * t2[c])
    }
}

/// The solution of the reference.
#[derive(Clone, Debug)]
pub struct SolidContactSolution {
    /// Every body's displacement (3 per node).
    pub displacements: Vec<Vec<f64>>,
    /// The contact points of every pair that have a partner.
    pub points: Vec<SolidContactPoint>,
    /// The Newton steps taken (the last one confirms the closed set).
    pub newton_steps: usize,
    /// (phase, seconds) of the solve, in order.
    pub timings: Vec<(&'static str, f64)>,
}

/// The most Newton steps before the closed set counts as not settling.
pub const MAX_STEPS: usize = 60;

/// A contact point's normal row over the coupled DOFs (the bodies' DOFs one after the other)
/// and its data.
pub(crate) struct Row {
    pub(crate) point: SolidContactPoint,
    pub(crate) a: Vec<(usize, f64)>,
    /// The pair's penalty θ.
    pub(crate) theta: f64,
    /// Whether the point meets the Signorini conditions exactly (an augmented pair).
    pub(crate) exact: bool,
    /// The pair's tangential law (resolved: `None` for μ = 0 or a zero bound).
    pub(crate) friction: Friction,
    /// The two tangential rows of a frictional point (empty otherwise) and its tangents.
    pub(crate) tangents: [Vec<(usize, f64)>; 2],
    pub(crate) frame: [[f64; 3]; 2],
}

/// The rows that the solvers condense: every point's normal row first (line j is point j's),
/// then the two tangential rows of each frictional point.
pub(crate) struct Lines<'a> {
    /// The rows.
    pub(crate) rows: Vec<&'a [(usize, f64)]>,
    /// The weight of each line's point.
    pub(crate) weight: Vec<f64>,
    /// The first of the two tangential lines of every point (`None` for a frictionless one).
    pub(crate) tangent: Vec<Option<usize>>,
}

impl<'a> Lines<'a> {
    /// The lines of `rows`.
    pub(crate) fn new(rows: &'a [Row]) -> Lines<'a> {
        let mut lines = Lines {
            rows: rows.iter().map(|r| r.a.as_slice()).collect(),
            weight: rows.iter().map(|r| r.point.weight).collect(),
            tangent: Vec::with_capacity(rows.len()),
        };
        for r in rows {
            if r.friction.is_active() {
                lines.tangent.push(Some(lines.rows.len()));
                for t in &r.tangents {
                    lines.rows.push(t);
                    lines.weight.push(r.point.weight);
                }
            } else {
                lines.tangent.push(None);
            }
        }
        lines
    }

    /// Whether any point is frictional.
    pub(crate) fn frictional(&self) -> bool {
        self.rows.len() > self.tangent.len()
    }
}

/// The DOFs point `r` couples: its normal row's, and its tangential rows' where it has them.
pub(crate) fn point_dofs(r: &Row) -> Vec<usize> {
    let mut dofs: Vec<usize> = r.a.iter().map(|&(i, _)| i).collect();
    if r.friction.is_active() {
        dofs.extend(r.tangents.iter().flatten().map(|&(i, _)| i));
        dofs.sort_unstable();
        dofs.dedup();
    }
    dofs
}

/// Where every body's DOFs start in the coupled numbering, and their total.
pub(crate) fn offsets(bodies: &[SolidBodySpec<'_>]) -> (Vec<usize>, usize) {
    let mut at = 0;
    let offsets = (bodies.iter())
        .map(|b| {
            let o = at;
            at += 3 * b.mesh.num_nodes();
            o
        })
        .collect();
    (offsets, at)
}

/// The rows of the contact points of every pair.
pub(crate) fn contact_rows(
    bodies: &[SolidBodySpec<'_>],
    offsets: &[usize],
    pairs: &[SolidPairSpec],
) -> Result<Vec<Row>, SolidContactError> {
    let mut rows = Vec::new();
    for (p, pair) in pairs.iter().enumerate() {
        rows.extend(pair_rows(bodies, offsets, p, pair)?);
    }
    Ok(rows)
}

/// The rows of the contact points of pair `p`.
fn pair_rows(
    bodies: &[SolidBodySpec<'_>],
    offsets: &[usize],
    p: usize,
    pair: &SolidPairSpec,
) -> Result<Vec<Row>, SolidContactError> {
    let side =
        |(b, face): &(usize, String)| -> Result<(Surface, Vec<usize>, usize), SolidContactError> {
            let body = bodies.get(*b).ok_or_else(|| SolidContactError::Pair {
                pair: p,
                message: format!("no body {b} (there are {})", bodies.len()),
            })?;
            let (surface, nodes) = face_surface(body.mesh, face).map_err(|e| match e {
                FaceError::Name(message) => SolidContactError::Pair { pair: p, message },
                FaceError::Surface(source) => SolidContactError::Surface { pair: p, source },
            })?;
            Ok((surface, nodes, offsets[*b]))
        };
    let (reference, ref_nodes, ref_at) = side(&pair.reference)?;
    let (partner, par_nodes, par_at) = side(&pair.partner)?;
    let index = TriangleIndex::new(&partner);
    let mortar = dual_mortar(&reference, &partner, &index, pair.search);
    let mut rows = Vec::new();
    for (j, row) in mortar.iter().enumerate() {
        let Some(row) = row else { continue };
        let point = PointRows::new(j, reference.normals()[j], row);
        let along = |dir: [f64; 3]| -> Vec<(usize, f64)> {
            (point.terms.iter())
                .flat_map(|&(side, k, c)| {
                    let at = match side {
                        Side::Reference => ref_at + dof(ref_nodes[k], 0),
                        Side::Partner => par_at + dof(par_nodes[k], 0),
                    };
                    (0..3).map(move |d| (at + d, c * dir[d]))
                })
                .filter(|e| e.1 != 0.0)
                .collect()
        };
        let friction = pair.friction.resolved();
        let tangents = match friction.is_active() {
            true => [along(point.frame[1]), along(point.frame[2])],
            false => [Vec::new(), Vec::new()],
        };
        let a = along(point.frame[0]);
        let weight = reference.weights()[j];
        rows.push(Row {
            point: SolidContactPoint {
                pair: p,
                node: ref_nodes[j],
                position: reference.points()[j],
                weight,
                gap: row.gap,
                pressure: 0.0,
                friction: None,
            },
            a,
            theta: pair.theta,
            exact: pair.enforcement == Enforcement::Augmented,
            friction,
            tangents,
            frame: [point.frame[1], point.frame[2]],
        });
    }
    Ok(rows)
}

/// Why a face is not a contact surface.
enum FaceError {
    Name(String),
    Surface(SurfaceError),
}

/// The triangles of face `name` of `mesh` as a surface over its own nodes (6-node triangles split
/// into four), and each surface node's mesh node.
fn face_surface(mesh: &SolidMesh, name: &str) -> Result<(Surface, Vec<usize>), FaceError> {
    let flat = mesh
        .face(name)
        .map_err(|e| FaceError::Name(e.to_string()))?;
    let mut nodes: Vec<usize> = flat.to_vec();
    nodes.sort_unstable();
    nodes.dedup();
    let local = |v: &usize| nodes.binary_search(v).unwrap_or(0);
    let points = nodes.iter().map(|&v| mesh.nodes()[v]).collect();
    let surface = match mesh.order() {
        TetOrder::P1 => {
            let triangles = flat.chunks(3).map(|t| [0, 1, 2].map(|i| local(&t[i])));
            Surface::new(points, triangles.collect())
        }
        TetOrder::P2 => {
            let triangles: Vec<[usize; 6]> = (flat.chunks(6))
                .map(|t| [0, 1, 2, 3, 4, 5].map(|i| local(&t[i])))
                .collect();
            Surface::from_quadratic(points, &triangles)
        }
    };
    Ok((surface.map_err(FaceError::Surface)?, nodes))
}

/// What the decomposition in space reports while it runs, for a progress display.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolidProgress {
    /// The contact geometry is built: the points with a partner.
    Geometry {
        /// Their number.
        points: usize,
    },
    /// A body is factorised and condensed on the contact points.
    Condensed {
        /// The body.
        body: usize,
        /// The seconds it took.
        seconds: f64,
    },
    /// A load step begins (only where there are several).
    LoadStep {
        /// The step (from 1).
        step: usize,
        /// Their number.
        of: usize,
        /// Its load factor.
        factor: f64,
    },
    /// A Newton step solved its closed set.
    NewtonStep {
        /// The step (from 1).
        step: usize,
        /// The points its set closes.
        closed: usize,
    },
}

/// One contact point's row as a peer solver takes it: its approach a·u over the coupled DOFs,
/// and its data (gap d, nodal weight w, penalty θ: pressure max(0, a·u − d)/θ, force w p along −a).
#[derive(Clone, Debug, PartialEq)]
pub struct SolidContactRow {
    /// The point (pair, node, position, weight, gap; pressure 0).
    pub point: SolidContactPoint,
    /// (coupled DOF, coefficient) of its approach.
    pub approach: Vec<(usize, f64)>,
    /// The pair's penalty θ.
    pub theta: f64,
    /// Whether the point meets the Signorini conditions exactly (an augmented pair: pressure p
    /// with p = max(0, p + (a·u − d)/θ)) rather than the penalty law.
    pub exact: bool,
}

/// The discrete contact problem for another solver (a peer's monolithic Newton method, a
/// check): where every body's DOFs start in the coupled numbering (3 per node, the bodies one
/// after the other), their total, and the contact points' rows, in the order of
/// [`SolidContactSolution::points`].
pub fn solid_contact_rows(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
) -> Result<(Vec<usize>, usize, Vec<SolidContactRow>), SolidContactError> {
    let (offsets, n) = offsets(bodies);
    let rows = contact_rows(bodies, &offsets, pairs)?
        .into_iter()
        .map(|r| SolidContactRow {
            point: r.point,
            approach: r.a,
            theta: r.theta,
            exact: r.exact,
        })
        .collect();
    Ok((offsets, n, rows))
}
