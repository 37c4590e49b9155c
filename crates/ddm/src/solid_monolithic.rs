//! The monolithic reference for bodies in space: frictionless penalty contact between
//! tetrahedral bodies (`contactdd_core::solid`) through the contact rows of
//! [`crate::solid_contact`], solved by a semismooth Newton method (a primal active set) on the
//! assembled system of all bodies (docs/three-d.md, "The monolithic reference in space").
//!
//! With the closed set χ fixed the equations are linear,
//!
//!   (K + Σ_{j∈χ} (w_j/θ) a_j a_jᵀ) u = f + Σ_{j∈χ} (w_j/θ) d_j a_j,
//!
//! and each Newton step solves them and closes exactly the points with s_j > d_j, until the set
//! repeats. It starts from the set of `solid_newton`'s `start`, as the decomposition
//! does. The symbolic analysis of the coupled matrix, with every point's springs in its
//! pattern, is done once; each step refactorises the values.

use contactdd_core::factor::FactoredBody;
use contactdd_core::solid::assembly::stiffness;
use contactdd_core::supports::Constraints;
use faer::sparse::{SparseColMat, Triplet};

use crate::solid_contact::{contact_rows, offsets, Row};
pub use crate::solid_contact::{
    SolidBodySpec, SolidContactError, SolidContactPoint, SolidContactSolution, SolidPairSpec,
    MAX_STEPS,
};
use crate::solid_newton::{start, Motions};
use crate::Enforcement;

/// Solves the contact of `bodies` through `pairs` by the semismooth Newton method, starting
/// from the first closed set of `solid_newton::start`.
pub fn solve_solid_monolithic(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
) -> Result<SolidContactSolution, SolidContactError> {
    let started = std::time::Instant::now();
    if let Some(pair) = (pairs.iter()).position(|p| p.enforcement == Enforcement::Augmented) {
        return Err(SolidContactError::Enforcement {
            pair,
            message: "the monolithic reference in space solves penalty contact only; the \
                      decomposition (contactdd solve) meets `enforcement = \"augmented\"` exactly"
                .into(),
        });
    }
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
    let mut closed = start(&rows, &Motions::new(bodies, &offsets, &rows));
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
