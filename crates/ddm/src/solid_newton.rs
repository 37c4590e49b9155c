//! The semismooth Newton iteration of the decomposition in space, on the contact points and the
//! amplitudes of the rigid motions that supports leave free (docs/three-d.md, "Floating bodies").
//!
//! With s = s⁰ − G p + E α the approaches (E_jq: the approach of point j under free motion q) and
//! the closed set χ, a step solves
//!
//!   (θ I + G)_χχ p_χ − E_χ α = (s⁰ − d)_χ,     E_χᵀ W_χ p_χ = e,
//!
//! the second block the balance of every free motion: the contact forces do the work e of the
//! loads along it. It closes the points with s_j > d_j, as the monolithic reference does.
//!
//! A point of an augmented pair meets the Signorini conditions exactly: the fixed point λ = p of
//! the augmented Lagrangian p = max(0, λ + (s − d)/θ), which is the complementarity condition
//! p = max(0, p + (s − d)/θ). Its Newton step (Alart and Curnier's, here a primal–dual active
//! set step) drops θ from its row, so that s_j = d_j where it is closed, and it closes where
//! θ p_j + s_j − d_j > 0. θ only scales pressures against gaps in that rule.

use contactdd_core::solid::rigid::free_rigid_motions;
use faer::Mat;
use rayon::prelude::*;

use crate::newton::linear::lu_solve_in_place;
use crate::solid_contact::{Row, SolidBodySpec, SolidContactError, SolidProgress, MAX_STEPS};

/// The rigid motions that supports leave free, of all bodies: E = [E_b] (m × k, the approach of
/// every point under each motion), the loads' work along each, and whose each is.
pub(crate) struct Motions {
    pub(crate) e: Mat<f64>,
    pub(crate) work: Vec<f64>,
    /// The body of every motion.
    pub(crate) body: Vec<usize>,
    /// Where each body's motions start among the k.
    pub(crate) first: Vec<usize>,
    /// Every body's motions as DOF vectors (empty for a held body).
    pub(crate) of_body: Vec<Vec<Vec<f64>>>,
}

impl Motions {
    /// The free motions of `bodies` (their DOFs from `offsets` in the coupled numbering) and
    /// what the `lines` (the points' normal rows, then their tangential ones) read of them.
    pub(crate) fn new(
        bodies: &[SolidBodySpec<'_>],
        offsets: &[usize],
        lines: &[&[(usize, f64)]],
    ) -> Motions {
        let of_body: Vec<Vec<Vec<f64>>> = (bodies.par_iter())
            .map(|b| {
                let prescribed: Vec<usize> = b.prescribed.iter().map(|&(d, _)| d).collect();
                free_rigid_motions(b.mesh, &prescribed)
            })
            .collect();
        let (mut first, mut work, mut body) = (Vec::new(), Vec::new(), Vec::new());
        for (b, (spec, motions)) in bodies.iter().zip(&of_body).enumerate() {
            first.push(work.len());
            for z in motions {
                work.push(z.iter().zip(&spec.load).map(|(a, f)| a * f).sum());
                body.push(b);
            }
        }
        let e = Mat::<f64>::from_fn(lines.len(), work.len(), |j, q| {
            let (b, z) = (body[q], &of_body[body[q]][q - first[body[q]]]);
            let range = offsets[b]..offsets[b] + z.len();
            (lines[j].iter())
                .filter(|(i, _)| range.contains(i))
                .map(|&(i, v)| v * z[i - offsets[b]])
                .sum()
        });
        Motions {
            e,
            work,
            body,
            first,
            of_body,
        }
    }
}

/// The first closed set: the points whose gap is closed (d_j ≤ 0), and for every body whose free
/// motions those leave unresisted, its points of smallest gap, one by one, until they resist
/// every motion (a body that starts apart from its partners, or touches them at one point whose
/// gap rounds above zero). A closed frictional point sticks at first, so its tangential lines
/// (`tangent`, see [`crate::solid_contact::Lines`]) resist motions too. Shared by the
/// decomposition and the monolithic reference.
pub(crate) fn start(rows: &[Row], tangent: &[Option<usize>], motions: &Motions) -> Vec<bool> {
    // An exact point without weight has an empty row: it never closes.
    let can_close = |r: &Row| !r.exact || r.point.weight > 0.0;
    let mut closed: Vec<bool> = (rows.iter())
        .map(|r| r.point.gap <= 0.0 && can_close(r))
        .collect();
    for b in 0..motions.first.len() {
        let cols: Vec<usize> = (0..motions.body.len())
            .filter(|&q| motions.body[q] == b)
            .collect();
        let mut candidates: Vec<usize> = (0..rows.len())
            .filter(|&j| !closed[j] && can_close(&rows[j]))
            .filter(|&j| cols.iter().any(|&q| motions.e[(j, q)] != 0.0))
            .collect();
        candidates.sort_by(|&x, &y| rows[x].point.gap.total_cmp(&rows[y].point.gap));
        let mut next = candidates.into_iter();
        while !cols.is_empty() && !holds(&held_lines(&closed, tangent, None), motions, &cols) {
            let Some(j) = next.next() else { break };
            closed[j] = true;
        }
    }
    closed
}

/// The pressures, the motions' amplitudes and the steps taken (the last one confirms the closed
/// set), from the points whose gap is closed.
/// `s0` and the loads' work along the free motions are those of the full loads, times `factor`.
pub(crate) fn newton(
    rows: &[Row],
    g: &Mat<f64>,
    (s0, factor): (&[f64], f64),
    motions: &Motions,
    report: &dyn Fn(SolidProgress),
) -> Result<(Vec<f64>, Vec<f64>, usize), SolidContactError> {
    let m = rows.len();
    let s0: Vec<f64> = s0.iter().map(|s| factor * s).collect();
    let work: Vec<f64> = motions.work.iter().map(|w| factor * w).collect();
    let k = motions.work.len();
    let mut closed = start(rows, &vec![None; rows.len()], motions);
    for step in 1..=MAX_STEPS {
        let set: Vec<usize> = (0..m).filter(|&j| closed[j]).collect();
        if let Some(body) = unheld(&set, motions) {
            return Err(SolidContactError::NotHeld { body, step });
        }
        let (p, alpha) = step_solve(rows, g, (&s0, &work), motions, &set, step)?;
        report(SolidProgress::NewtonStep {
            step,
            closed: set.len(),
        });
        let s: Vec<f64> = (0..m)
            .map(|j| {
                let contact: f64 = (0..m).map(|l| g[(j, l)] * p[l]).sum();
                let rigid: f64 = (0..k).map(|q| motions.e[(j, q)] * alpha[q]).sum();
                s0[j] - contact + rigid
            })
            .collect();
        let next: Vec<bool> = (0..m).map(|j| closes(&rows[j], p[j], s[j])).collect();
        if next == closed {
            let p = (0..m).map(|j| pressure(&rows[j], p[j], s[j])).collect();
            return Ok((p, alpha, step));
        }
        closed = next;
    }
    Err(SolidContactError::NotSettled { steps: MAX_STEPS })
}

/// Whether point `row` closes at the pressure `p` of the step and the approach `s` it leads to:
/// s > d for a penalty point; θ p + s − d > 0 for an exact one that carries a force (a point of
/// zero weight would leave its exact row empty).
pub(crate) fn closes(row: &Row, p: f64, s: f64) -> bool {
    match row.exact {
        false => s > row.point.gap,
        true => row.point.weight > 0.0 && row.theta * p + s - row.point.gap > 0.0,
    }
}

/// The pressure of point `row` at a settled set: the penalty law of the approach `s`, or the
/// step's own `p` for an exact point (zero where it is open).
pub(crate) fn pressure(row: &Row, p: f64, s: f64) -> f64 {
    match row.exact {
        false => ((s - row.point.gap) / row.theta).max(0.0),
        true => p.max(0.0),
    }
}

/// The Newton system of the closed set `set`, solved: the pressures (zero off the set) and the
/// motions' amplitudes.
fn step_solve(
    rows: &[Row],
    g: &Mat<f64>,
    (s0, work): (&[f64], &[f64]),
    motions: &Motions,
    set: &[usize],
    step: usize,
) -> Result<(Vec<f64>, Vec<f64>), SolidContactError> {
    let (c, k) = (set.len(), motions.work.len());
    let mut p = vec![0.0; rows.len()];
    if c + k == 0 {
        return Ok((p, Vec::new()));
    }
    let e = &motions.e;
    let mut a = Mat::<f64>::from_fn(c + k, c + k, |x, y| match (x < c, y < c) {
        (true, true) => g[(set[x], set[y])],
        (true, false) => -e[(set[x], y - c)],
        (false, true) => rows[set[y]].point.weight * e[(set[y], x - c)],
        (false, false) => 0.0,
    });
    let mut rhs = Mat::<f64>::from_fn(c + k, 1, |x, _| {
        if x < c {
            s0[set[x]] - rows[set[x]].point.gap
        } else {
            work[x - c]
        }
    });
    for (x, &j) in set.iter().enumerate().filter(|(_, &j)| !rows[j].exact) {
        a[(x, x)] += rows[j].theta;
    }
    lu_solve_in_place(a, &mut rhs).ok_or(SolidContactError::Factor {
        step,
        message: "no memory for the Newton system".into(),
    })?;
    // `unheld` has cleared every body's motions, so a non-finite step is a singular system
    // of another kind: say so rather than name a body that may not be the cause.
    if !(0..c + k).all(|x| rhs[(x, 0)].is_finite()) {
        return Err(SolidContactError::Factor {
            step,
            message: "the Newton system is singular".into(),
        });
    }
    set.iter()
        .enumerate()
        .for_each(|(x, &j)| p[j] = rhs[(x, 0)]);
    Ok((p, (0..k).map(|q| rhs[(c + q, 0)]).collect()))
}

/// The lines that resist motions: the normal lines of the `closed` points, and the tangential
/// lines of those of them that stick (`sticks`, or every frictional one without it).
pub(crate) fn held_lines(
    closed: &[bool],
    tangent: &[Option<usize>],
    sticks: Option<&[bool]>,
) -> Vec<bool> {
    let lines = tangent.iter().flatten().map(|&t| t + 2).max();
    let mut held = closed.to_vec();
    held.resize(lines.unwrap_or(closed.len()).max(closed.len()), false);
    for (j, t) in tangent.iter().enumerate() {
        if let (Some(t), true) = (t, closed[j] && sticks.map_or(true, |s| s[j])) {
            held[*t] = true;
            held[t + 1] = true;
        }
    }
    held
}

/// A body some of whose free motions no closed point of `set` resists.
fn unheld(set: &[usize], motions: &Motions) -> Option<usize> {
    let mut closed = vec![false; motions.e.nrows()];
    set.iter().for_each(|&j| closed[j] = true);
    unheld_lines(&closed, motions)
}

/// A body some of whose free motions no line of `closed` (over the lines) resists.
pub(crate) fn unheld_lines(closed: &[bool], motions: &Motions) -> Option<usize> {
    (0..motions.first.len()).find(|&b| {
        let cols: Vec<usize> = (0..motions.body.len())
            .filter(|&q| motions.body[q] == b)
            .collect();
        !cols.is_empty() && !holds(closed, motions, &cols)
    })
}

/// Whether the closed points resist every combination of the motions `cols`: the Gram matrix of
/// their approaches on the closed points, E_χ,bᵀ E_χ,b, has no eigenvalue at rounding level.
fn holds(closed: &[bool], motions: &Motions, cols: &[usize]) -> bool {
    let readings: Vec<Vec<f64>> = (0..closed.len())
        .filter(|&j| closed[j])
        .map(|j| cols.iter().map(|&q| motions.e[(j, q)]).collect())
        .collect();
    full_rank(&readings, cols.len())
}

/// Whether the `readings` (each what one line reads of n motions) resist every combination of
/// the motions: their Gram matrix has no eigenvalue at rounding level.
pub(crate) fn full_rank(readings: &[Vec<f64>], n: usize) -> bool {
    let gram =
        nalgebra::DMatrix::<f64>::from_fn(n, n, |x, y| readings.iter().map(|r| r[x] * r[y]).sum());
    let eigen = gram.symmetric_eigenvalues();
    let largest = eigen.iter().fold(0.0f64, |a, &l| a.max(l.abs()));
    let smallest = eigen.iter().fold(f64::INFINITY, |a, &l| a.min(l));
    // Rounding of a sum of squares: the unit roundoff times the terms.
    smallest > f64::EPSILON * readings.len().max(1) as f64 * largest
}
