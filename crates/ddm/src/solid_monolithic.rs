//! The monolithic reference for bodies in space: frictionless penalty contact between
//! tetrahedral bodies (`contactdd_core::solid`) through the dual mortar rows of
//! [`crate::contact3d`], solved by a semismooth Newton method (a primal active set) on the
//! assembled system of all bodies (docs/three-d.md, "The monolithic reference in space").
//!
//! Point j of a pair (a node of its reference surface) reads the approach s_j = a_jᵀu, a_j its
//! normal row over both bodies' DOFs ([`PointRows`]), and carries the pressure
//! p_j = max(0, s_j − d_j)/θ, d_j its mortar gap. Its force w_j p_j acts along −a_j, so the two
//! sides receive equal and opposite forces. With the closed set χ fixed the equations are linear,
//!
//!   (K + Σ_{j∈χ} (w_j/θ) a_j a_jᵀ) u = f + Σ_{j∈χ} (w_j/θ) d_j a_j,
//!
//! and each Newton step solves them and closes exactly the points with s_j > d_j, until the set
//! repeats. The symbolic analysis of the coupled matrix, with every point's springs in its
//! pattern, is done once; each step refactorises the values.

use contactdd_core::factor::FactoredBody;
use contactdd_core::solid::assembly::stiffness;
use contactdd_core::solid::{dof, SolidMesh, TetOrder};
use contactdd_core::supports::Constraints;
use faer::sparse::{SparseColMat, Triplet};

use crate::contact3d::{dual_mortar, PointRows, Side, Surface, SurfaceError, TriangleIndex};

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

/// Solves the contact of `bodies` through `pairs` by the semismooth Newton method, starting
/// from the points whose gap is closed (d_j ≤ 0).
pub fn solve_solid_monolithic(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
) -> Result<SolidContactSolution, SolidContactError> {
    let started = std::time::Instant::now();
    let (offsets, n) = offsets(bodies);
    let rows = contact_rows(bodies, &offsets, pairs)?;
    let mut trip = Vec::new();
    for (b, at) in bodies.iter().zip(&offsets) {
        push_matrix(&stiffness(b.mesh, &b.elasticity), *at, &mut trip);
    }
    // Every point's springs in the pattern (as zeros), so that one analysis serves every step.
    for r in &rows {
        for &(i, _) in &r.a {
            for &(k, _) in &r.a {
                trip.push(Triplet::new(i, k, 0.0));
            }
        }
    }
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip).map_err(|e| {
        SolidContactError::Factor {
            step: 0,
            message: format!("{e:?}"),
        }
    })?;
    let mut constraints = Constraints::for_dofs(n);
    let mut f = vec![0.0; n];
    for (b, at) in bodies.iter().zip(&offsets) {
        b.prescribed
            .iter()
            .for_each(|&(d, v)| constraints.prescribe(at + d, v));
        f[*at..*at + b.load.len()].copy_from_slice(&b.load);
    }
    let fail = |step: usize| {
        move |e: contactdd_core::BodyError| SolidContactError::Factor {
            step,
            message: e.to_string(),
        }
    };
    let mut system =
        FactoredBody::new("the coupled bodies", k, &constraints, &[]).map_err(fail(0))?;
    let mut closed: Vec<bool> = rows.iter().map(|r| r.point.gap <= 0.0).collect();
    for step in 1..=MAX_STEPS {
        let (additions, rhs) = closed_system(&rows, &closed, &f);
        system.factorize(&additions).map_err(fail(step))?;
        let u = system.solve(&rhs).map_err(fail(step))?;
        let s: Vec<f64> = rows.iter().map(|r| dot(&r.a, &u)).collect();
        let next: Vec<bool> = (rows.iter().zip(&s))
            .map(|(r, &s)| s > r.point.gap)
            .collect();
        if next == closed {
            let mut sol = solution(bodies, &offsets, rows, &s, u, step);
            sol.timings = vec![("solve", started.elapsed().as_secs_f64())];
            return Ok(sol);
        }
        closed = next;
    }
    Err(SolidContactError::NotSettled { steps: MAX_STEPS })
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
        let nu = point.frame[0];
        let a = (point.terms.iter())
            .flat_map(|&(side, k, c)| {
                let at = match side {
                    Side::Reference => ref_at + dof(ref_nodes[k], 0),
                    Side::Partner => par_at + dof(par_nodes[k], 0),
                };
                (0..3).map(move |d| (at + d, c * nu[d]))
            })
            .filter(|e| e.1 != 0.0)
            .collect();
        let weight = reference.weights()[j];
        rows.push(Row {
            point: SolidContactPoint {
                pair: p,
                node: ref_nodes[j],
                position: reference.points()[j],
                weight,
                gap: row.gap,
                pressure: 0.0,
            },
            a,
            theta: pair.theta,
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

/// Pushes the entries of `k` shifted by `at` on both axes.
fn push_matrix(
    k: &SparseColMat<usize, f64>,
    at: usize,
    trip: &mut Vec<Triplet<usize, usize, f64>>,
) {
    let (col_ptr, row_idx, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    for c in 0..k.ncols() {
        for i in col_ptr[c]..col_ptr[c + 1] {
            trip.push(Triplet::new(at + row_idx[i], at + c, val[i]));
        }
    }
}

/// The springs of the closed points (each unordered pair of DOFs once, as
/// [`FactoredBody::factorize`] adds them symmetrically) and the load with their gap terms.
fn closed_system(rows: &[Row], closed: &[bool], f: &[f64]) -> (Vec<(usize, usize, f64)>, Vec<f64>) {
    let mut additions = Vec::new();
    let mut rhs = f.to_vec();
    for (r, _) in rows.iter().zip(closed).filter(|(_, &c)| c) {
        let spring = r.point.weight / r.theta;
        for (x, &(i, ai)) in r.a.iter().enumerate() {
            for &(k, ak) in &r.a[..=x] {
                additions.push((i, k, spring * ai * ak));
            }
            rhs[i] += spring * r.point.gap * ai;
        }
    }
    (additions, rhs)
}

fn dot(a: &[(usize, f64)], u: &[f64]) -> f64 {
    a.iter().map(|&(i, x)| x * u[i]).sum()
}

/// The solution of the settled set: the bodies' displacements and the points' pressures.
fn solution(
    bodies: &[SolidBodySpec<'_>],
    offsets: &[usize],
    rows: Vec<Row>,
    s: &[f64],
    u: Vec<f64>,
    steps: usize,
) -> SolidContactSolution {
    let displacements = (bodies.iter().zip(offsets))
        .map(|(b, &at)| u[at..at + 3 * b.mesh.num_nodes()].to_vec())
        .collect();
    let points = (rows.into_iter().zip(s))
        .map(|(r, &s)| SolidContactPoint {
            pressure: (s - r.point.gap).max(0.0) / r.theta,
            ..r.point
        })
        .collect();
    SolidContactSolution {
        displacements,
        points,
        newton_steps: steps,
        timings: Vec::new(),
    }
}
