//! The decomposition for bodies in space: every body factorised once, in parallel, with its
//! contact DOFs ordered last, and the contact solved on the contact points alone
//! (docs/three-d.md, "The decomposition in space").
//!
//! The contact problem is that of [`crate::solid_monolithic`]: point j carries
//! p_j = max(0, s_j − d_j)/θ, and its force w_j p_j acts along −a_j. For a body held by its
//! supports, the displacement of its contact DOFs under loads on them alone is S⁻¹ times those
//! loads, S the Schur complement of its stiffness on them, whose Cholesky factor L_S is the last
//! block of the body's own factor. So the approaches are
//!
//!   s = s⁰ − G p,   G_jl = w_l Σ_b a_jᵀ S_b⁻¹ a_l = w_l Σ_b (L_b⁻¹ a_j)ᵀ (L_b⁻¹ a_l),
//!
//! s⁰ those of the loads alone. A Newton step with the closed set χ solves
//! (θ I + G)_χχ p_χ = (s⁰ − d)_χ on the contact points, and closes the points with s_j > d_j, as
//! the monolithic reference does from the same start: the two take the same steps. Each body then
//! recovers its field by one solve with its contact forces. Floating bodies (held by contact
//! alone) are not handled yet: their stiffness is singular.

use contactdd_core::factor::FactoredBody;
use contactdd_core::solid::assembly::stiffness;
use contactdd_core::supports::Constraints;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Accum, Mat, Par};
use rayon::prelude::*;

use crate::newton::linear::lu_solve_in_place;
use crate::solid_monolithic::{
    contact_rows, offsets, Row, SolidBodySpec, SolidContactError, SolidContactPoint,
    SolidContactSolution, SolidPairSpec, MAX_STEPS,
};

/// One body after its factorisation: the factor, its DOF range in the coupled numbering, and
/// its part of G and of s⁰.
struct Condensed {
    factor: FactoredBody,
    range: std::ops::Range<usize>,
    g: Mat<f64>,
    s0: Vec<f64>,
    /// The seconds of the symbolic analysis and numeric factorisation.
    factorising: f64,
}

/// Solves the contact of `bodies` (each held by its supports) through `pairs`: every body is
/// factorised once and the Newton iteration runs on the contact points.
pub fn solve_solid_dd(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
) -> Result<SolidContactSolution, SolidContactError> {
    let mut clock = Clock::default();
    let (offsets, _) = offsets(bodies);
    let rows = contact_rows(bodies, &offsets, pairs)?;
    clock.lap("contact geometry");
    let condensed: Vec<Condensed> = (bodies.par_iter().zip(&offsets).enumerate())
        .map(|(b, (body, &at))| condense(b, body, at, &rows))
        .collect::<Result<_, _>>()?;
    let m = rows.len();
    let (mut g, mut s0) = (Mat::<f64>::zeros(m, m), vec![0.0; m]);
    for c in &condensed {
        g += &c.g;
        s0.iter_mut().zip(&c.s0).for_each(|(s, x)| *s += x);
    }
    for (l, r) in rows.iter().enumerate() {
        let w = r.point.weight;
        g.col_mut(l).iter_mut().for_each(|x| *x *= w);
    }
    let slowest = condensed.iter().map(|c| c.factorising).fold(0.0, f64::max);
    clock.lap("assemble, factorise and condense");
    clock
        .laps
        .push(("of which the slowest body's factorisation", slowest));
    let (p, steps) = newton(&rows, &g, &s0)?;
    clock.lap("iterate");
    let displacements = (condensed.par_iter().zip(bodies))
        .map(|(c, body)| recover(c, body, &rows, &p))
        .collect::<Result<Vec<_>, _>>()?;
    clock.lap("recover");
    let points = (rows.into_iter().zip(&p))
        .map(|(r, &p)| SolidContactPoint {
            pressure: p,
            ..r.point
        })
        .collect();
    Ok(SolidContactSolution {
        displacements,
        points,
        newton_steps: steps,
        timings: clock.laps,
    })
}

/// The phases' wall times.
struct Clock {
    last: std::time::Instant,
    laps: Vec<(&'static str, f64)>,
}

impl Default for Clock {
    fn default() -> Clock {
        Clock {
            last: std::time::Instant::now(),
            laps: Vec::new(),
        }
    }
}

impl Clock {
    fn lap(&mut self, phase: &'static str) {
        let now = std::time::Instant::now();
        self.laps.push((phase, (now - self.last).as_secs_f64()));
        self.last = now;
    }
}

/// Factorises body `b` (its DOFs from `at` in the coupled numbering) with the DOFs the rows
/// read ordered last, and condenses it: its part of G and of s⁰.
fn condense(
    b: usize,
    body: &SolidBodySpec<'_>,
    at: usize,
    rows: &[Row],
) -> Result<Condensed, SolidContactError> {
    let range = at..at + 3 * body.mesh.num_nodes();
    let mut interface: Vec<usize> = (rows.iter())
        .flat_map(|r| r.a.iter().map(|&(i, _)| i))
        .filter(|i| range.contains(i))
        .map(|i| i - at)
        .collect();
    interface.sort_unstable();
    interface.dedup();
    let fail = |e: contactdd_core::BodyError| SolidContactError::Factor {
        step: 0,
        message: format!("body {b}: {e}"),
    };
    let mut constraints = Constraints::for_dofs(range.len());
    body.prescribed
        .iter()
        .for_each(|&(d, v)| constraints.prescribe(d, v));
    let k = stiffness(body.mesh, &body.elasticity);
    let started = std::time::Instant::now();
    let mut factor =
        FactoredBody::new(&format!("body {b}"), k, &constraints, &interface).map_err(fail)?;
    factor.factorize(&[]).map_err(fail)?;
    let factorising = started.elapsed().as_secs_f64();
    let u0 = factor.solve(&body.load).map_err(fail)?;
    let l = factor.schur_factor().map_err(fail)?;
    let index = factor.interface_index(&interface);
    let mut x = Mat::<f64>::zeros(l.nrows(), rows.len());
    let mut s0 = vec![0.0; rows.len()];
    for (j, r) in rows.iter().enumerate() {
        for &(i, v) in r.a.iter().filter(|(i, _)| range.contains(i)) {
            s0[j] += v * u0[i - at];
            let pos = interface.binary_search(&(i - at)).ok();
            if let Some((k, c)) = pos.and_then(|q| index[q]) {
                x[(k, j)] += c * v;
            }
        }
    }
    solve_lower_triangular_in_place(l.as_ref(), x.as_mut(), Par::Seq);
    // Sequential: the same bits on any number of threads.
    let mut g = Mat::<f64>::zeros(rows.len(), rows.len());
    matmul(
        g.as_mut(),
        Accum::Replace,
        x.transpose(),
        x.as_ref(),
        1.0,
        Par::Seq,
    );
    Ok(Condensed {
        factor,
        range,
        g,
        s0,
        factorising,
    })
}

/// The semismooth Newton iteration on the pressures from the points whose gap is closed: the
/// pressures and the steps taken (the last one confirms the closed set).
fn newton(rows: &[Row], g: &Mat<f64>, s0: &[f64]) -> Result<(Vec<f64>, usize), SolidContactError> {
    let m = rows.len();
    let mut closed: Vec<bool> = rows.iter().map(|r| r.point.gap <= 0.0).collect();
    for step in 1..=MAX_STEPS {
        let set: Vec<usize> = (0..m).filter(|&j| closed[j]).collect();
        let mut p = vec![0.0; m];
        if !set.is_empty() {
            let mut a = Mat::<f64>::from_fn(set.len(), set.len(), |x, y| g[(set[x], set[y])]);
            let mut rhs =
                Mat::<f64>::from_fn(set.len(), 1, |x, _| s0[set[x]] - rows[set[x]].point.gap);
            for (x, &j) in set.iter().enumerate() {
                a[(x, x)] += rows[j].theta;
            }
            lu_solve_in_place(a, &mut rhs).ok_or(SolidContactError::Factor {
                step,
                message: "no memory for the Newton system".into(),
            })?;
            set.iter()
                .enumerate()
                .for_each(|(x, &j)| p[j] = rhs[(x, 0)]);
        }
        let s: Vec<f64> = (0..m)
            .map(|j| s0[j] - (0..m).map(|l| g[(j, l)] * p[l]).sum::<f64>())
            .collect();
        let next: Vec<bool> = (0..m).map(|j| s[j] > rows[j].point.gap).collect();
        if next == closed {
            let p = (0..m)
                .map(|j| ((s[j] - rows[j].point.gap) / rows[j].theta).max(0.0))
                .collect();
            return Ok((p, step));
        }
        closed = next;
    }
    Err(SolidContactError::NotSettled { steps: MAX_STEPS })
}

/// Body `c`'s displacement under its loads and the contact forces of the pressures `p`.
fn recover(
    c: &Condensed,
    body: &SolidBodySpec<'_>,
    rows: &[Row],
    p: &[f64],
) -> Result<Vec<f64>, SolidContactError> {
    let mut f = body.load.clone();
    for (r, &p) in rows.iter().zip(p) {
        for &(i, v) in r.a.iter().filter(|(i, _)| c.range.contains(i)) {
            f[i - c.range.start] -= r.point.weight * p * v;
        }
    }
    c.factor.solve(&f).map_err(|e| SolidContactError::Factor {
        step: 0,
        message: e.to_string(),
    })
}
