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
//!
//! The points of augmented pairs meet the Signorini conditions by the method of multipliers
//! around that Newton method: λ ← p after each penalty solve with the gaps d − θλ
//! (docs/three-d.md, "Exact contact in space"), a different algorithm from the decomposition's,
//! which makes it a check of it.

use contactdd_core::factor::FactoredBody;
use contactdd_core::solid::assembly::stiffness;
use contactdd_core::supports::Constraints;
use faer::sparse::{SparseColMat, Triplet};

use crate::solid_contact::{contact_rows, offsets, point_dofs, Lines, Row};
pub use crate::solid_contact::{
    SolidBodySpec, SolidContactError, SolidContactPoint, SolidContactSolution, SolidPairSpec,
    MAX_STEPS,
};
use crate::solid_monolithic_friction::frictional;
use crate::solid_newton::{start, Motions};

/// The Signorini conditions at the exact points hold when they are violated by at most this
/// much of the largest approach.
const EXACT_TOL: f64 = 1e-12;

/// The most multiplier updates of the augmented pairs.
const MAX_UPDATES: usize = 200;

/// Solves the contact of `bodies` through `pairs` by the semismooth Newton method, starting
/// from the first closed set of `solid_newton::start`.
pub fn solve_solid_monolithic(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
) -> Result<SolidContactSolution, SolidContactError> {
    solve_solid_monolithic_from(bodies, pairs, None)
}

/// [`solve_solid_monolithic`] for an increment that starts where the solution `last` (of the
/// same pairs at the last load step) ended: its frictional points carry their tractions and
/// slips (docs/three-d.md, "Friction in space"). Without `last` the increment starts from rest.
pub fn solve_solid_monolithic_from(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
    last: Option<&SolidContactSolution>,
) -> Result<SolidContactSolution, SolidContactError> {
    let started = std::time::Instant::now();
    let (offsets, n) = offsets(bodies);
    let rows = contact_rows(bodies, &offsets, pairs)?;
    let (mut system, f) = coupled_system(bodies, (&offsets, n), &rows)?;
    let lines = Lines::new(&rows);
    let mut closed = start(
        &rows,
        &lines.tangent,
        &Motions::new(bodies, &offsets, &lines.rows),
    );
    if lines.frictional() {
        let carried = carried(&rows, last)?;
        let (u, points, newton_steps) = frictional(&mut system, (&rows, &carried), &f, closed)?;
        return Ok(SolidContactSolution {
            displacements: split(bodies, &offsets, &u),
            points,
            newton_steps,
            timings: vec![("solve", started.elapsed().as_secs_f64())],
        });
    }
    let mut newton = Newton {
        system: &mut system,
        rows: &rows,
        f: &f,
        factored: None,
        steps: 0,
    };
    let mut gaps: Vec<f64> = rows.iter().map(|r| r.point.gap).collect();
    let (mut u, mut s) = newton.settle(&gaps, &mut closed)?;
    // Augmented pairs: the method of multipliers, λ ← p, each update a penalty solve with the
    // gaps d − θλ, until the Signorini conditions hold to rounding.
    let scale = s.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut updates = 0;
    while let Some(violation) = unmet(&rows, &gaps, &s, EXACT_TOL * scale) {
        if updates == MAX_UPDATES {
            return Err(SolidContactError::NotEnforced { updates, violation });
        }
        // λ ← p = (s − (d − θλ))⁺/θ, so the next penalty gap is d − θp.
        for (j, r) in rows.iter().enumerate().filter(|(_, r)| r.exact) {
            gaps[j] = r.point.gap - (s[j] - gaps[j]).max(0.0);
        }
        (u, s) = newton.settle(&gaps, &mut closed)?;
        updates += 1;
    }
    let steps = newton.steps;
    let mut sol = solution(bodies, &offsets, rows, (&gaps, &s), u, steps);
    sol.timings = vec![("solve", started.elapsed().as_secs_f64())];
    Ok(sol)
}

/// The coupled stiffness of all bodies, factorised symbolically with every point's springs in
/// its pattern (as zeros, so that one analysis serves every step), and the coupled loads.
fn coupled_system(
    bodies: &[SolidBodySpec<'_>],
    (offsets, n): (&[usize], usize),
    rows: &[Row],
) -> Result<(FactoredBody, Vec<f64>), SolidContactError> {
    let mut trip = Vec::new();
    for (b, at) in bodies.iter().zip(offsets) {
        push_matrix(&stiffness(b.mesh, &b.elasticity), *at, &mut trip);
    }
    for r in rows {
        let dofs = point_dofs(r);
        for &i in &dofs {
            for &k in &dofs {
                trip.push(Triplet::new(i, k, 0.0));
            }
        }
    }
    let fail = |message: String| SolidContactError::Factor { step: 0, message };
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip)
        .map_err(|e| fail(format!("{e:?}")))?;
    let mut constraints = Constraints::for_dofs(n);
    let mut f = vec![0.0; n];
    for (b, at) in bodies.iter().zip(offsets) {
        b.prescribed
            .iter()
            .for_each(|&(d, v)| constraints.prescribe(at + d, v));
        f[*at..*at + b.load.len()].copy_from_slice(&b.load);
    }
    let system = FactoredBody::new("the coupled bodies", k, &constraints, &[])
        .map_err(|e| fail(e.to_string()))?;
    Ok((system, f))
}

/// Every body's part of the coupled vector `u`.
fn split(bodies: &[SolidBodySpec<'_>], offsets: &[usize], u: &[f64]) -> Vec<Vec<f64>> {
    (bodies.iter().zip(offsets))
        .map(|(b, &at)| u[at..at + 3 * b.mesh.num_nodes()].to_vec())
        .collect()
}

/// Per point, the traction and slip the increment starts from: those `last` ended with.
fn carried(
    rows: &[Row],
    last: Option<&SolidContactSolution>,
) -> Result<Vec<[[f64; 2]; 2]>, SolidContactError> {
    let Some(last) = last else {
        return Ok(vec![[[0.0; 2]; 2]; rows.len()]);
    };
    if last.points.len() != rows.len() {
        return Err(SolidContactError::Pair {
            pair: 0,
            message: "the last step's solution has other contact points".into(),
        });
    }
    Ok((last.points.iter())
        .map(|q| {
            q.friction
                .as_ref()
                .map_or([[0.0; 2]; 2], |f| [f.traction, f.slip])
        })
        .collect())
}

/// The largest violation of the Signorini conditions at the exact points, if above `tol`: with
/// the penalty gaps `gaps` = d − θλ, the pressure is p = (s − gaps)⁺/θ, and the conditions ask
/// s ≤ d, and s = d where p > 0.
fn unmet(rows: &[Row], gaps: &[f64], s: &[f64], tol: f64) -> Option<f64> {
    let violation = (rows.iter().enumerate())
        .filter(|(_, r)| r.exact)
        .map(|(j, r)| match s[j] > gaps[j] {
            true => (s[j] - r.point.gap).abs(),
            false => s[j] - r.point.gap,
        })
        .fold(0.0f64, f64::max);
    (violation > tol).then_some(violation)
}

/// The semismooth Newton method on the coupled system, for given penalty gaps.
struct Newton<'a> {
    system: &'a mut FactoredBody,
    rows: &'a [Row],
    f: &'a [f64],
    /// The closed set of the current factorisation.
    factored: Option<Vec<bool>>,
    /// The Newton steps taken in all.
    steps: usize,
}

impl Newton<'_> {
    /// Newton steps from `closed` until the set repeats, with the gaps `gaps`: the displacements
    /// and the approaches. A set already factorised is not factorised again.
    fn settle(
        &mut self,
        gaps: &[f64],
        closed: &mut Vec<bool>,
    ) -> Result<(Vec<f64>, Vec<f64>), SolidContactError> {
        for _ in 1..=MAX_STEPS {
            self.steps += 1;
            let step = self.steps;
            let fail = |e: contactdd_core::BodyError| SolidContactError::Factor {
                step,
                message: e.to_string(),
            };
            let (additions, rhs) = closed_system(self.rows, closed, gaps, self.f);
            if self.factored.as_ref() != Some(closed) {
                self.system.factorize(&additions).map_err(fail)?;
                self.factored = Some(closed.clone());
            }
            let u = self.system.solve(&rhs).map_err(fail)?;
            let s: Vec<f64> = self.rows.iter().map(|r| dot(&r.a, &u)).collect();
            let next: Vec<bool> = (0..s.len()).map(|j| s[j] > gaps[j]).collect();
            if next == *closed {
                return Ok((u, s));
            }
            *closed = next;
        }
        Err(SolidContactError::NotSettled { steps: MAX_STEPS })
    }
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
fn closed_system(
    rows: &[Row],
    closed: &[bool],
    gaps: &[f64],
    f: &[f64],
) -> (Vec<(usize, usize, f64)>, Vec<f64>) {
    let mut additions = Vec::new();
    let mut rhs = f.to_vec();
    for ((r, _), &gap) in rows.iter().zip(closed).zip(gaps).filter(|((_, &c), _)| c) {
        let spring = r.point.weight / r.theta;
        for (x, &(i, ai)) in r.a.iter().enumerate() {
            for &(k, ak) in &r.a[..=x] {
                additions.push((i, k, spring * ai * ak));
            }
            rhs[i] += spring * gap * ai;
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
    (gaps, s): (&[f64], &[f64]),
    u: Vec<f64>,
    steps: usize,
) -> SolidContactSolution {
    let displacements = split(bodies, offsets, &u);
    let points = (rows.into_iter().zip(s).zip(gaps))
        .map(|((r, &s), &gap)| SolidContactPoint {
            pressure: (s - gap).max(0.0) / r.theta,
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
