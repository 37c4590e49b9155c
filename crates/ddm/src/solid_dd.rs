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
//! recovers its field by one solve with its contact forces. A body its supports leave free to
//! move rigidly is pinned where its free motions are best seen, and their amplitudes join the
//! Newton system (`solid_newton`; docs/three-d.md, "Floating bodies").

use contactdd_core::factor::FactoredBody;
use contactdd_core::solid::assembly::stiffness;
use contactdd_core::solid::rigid::pin_dofs;
use contactdd_core::supports::Constraints;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Accum, Mat, Par};
use rayon::prelude::*;

use crate::solid_contact::{
    contact_rows, offsets, Lines, Row, SolidBodySpec, SolidContactError, SolidContactPoint,
    SolidContactSolution, SolidFrictionPoint, SolidPairSpec, SolidProgress,
};
use crate::solid_friction::{newton_friction, Frictional, Increment};
use crate::solid_newton::{newton, Motions};

/// One body after its factorisation: the factor, its DOF range in the coupled numbering, and
/// its part of G and of s⁰.
struct Condensed {
    factor: FactoredBody,
    range: std::ops::Range<usize>,
    g: Mat<f64>,
    s0: Vec<f64>,
    /// The seconds of the symbolic analysis and numeric factorisation.
    factorising: f64,
    /// The rigid motions its supports leave free (DOF vectors; empty for a held body).
    motions: Vec<Vec<f64>>,
}

/// Solves the contact of `bodies` (held by their supports or by the contact) through `pairs`: every body is
/// factorised once and the Newton iteration runs on the contact points.
pub fn solve_solid_dd(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
) -> Result<SolidContactSolution, SolidContactError> {
    solve_solid_dd_reported(bodies, pairs, &|_| {})
}

/// [`solve_solid_dd`], telling `report` of each phase as it ends (the same result).
pub fn solve_solid_dd_reported(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
    report: &(dyn Fn(SolidProgress) + Sync),
) -> Result<SolidContactSolution, SolidContactError> {
    let mut steps = solve_solid_dd_steps(bodies, pairs, &[1.0], report)?;
    steps
        .pop()
        .ok_or(SolidContactError::NotSettled { steps: 0 })
}

/// The solutions at the load factors `factors`: every load and prescribed displacement times
/// the factor, the gaps as they are. The bodies are factorised and condensed once; each factor
/// costs a Newton iteration on the contact points and one solve per body. Each solution's
/// timings are the phases' totals so far (the setup's included).
pub fn solve_solid_dd_steps(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
    factors: &[f64],
    report: &(dyn Fn(SolidProgress) + Sync),
) -> Result<Vec<SolidContactSolution>, SolidContactError> {
    let mut clock = Clock::default();
    let (offsets, _) = offsets(bodies);
    let rows = contact_rows(bodies, &offsets, pairs)?;
    clock.lap("contact geometry");
    report(SolidProgress::Geometry { points: rows.len() });
    let lines = Lines::new(&rows);
    let motions = Motions::new(bodies, &offsets, &lines.rows);
    let condensed: Vec<Condensed> = (bodies.par_iter().zip(&offsets).enumerate())
        .map(|(b, (body, &at))| {
            let c = condense(b, (body, &motions.of_body[b]), at, &lines.rows)?;
            report(SolidProgress::Condensed {
                body: b,
                seconds: c.factorising,
            });
            Ok(c)
        })
        .collect::<Result<_, SolidContactError>>()?;
    let (g, s0) = coupled(&condensed, &lines.weight);
    let slowest = condensed.iter().map(|c| c.factorising).fold(0.0, f64::max);
    clock.lap("assemble, factorise and condense");
    clock
        .laps
        .push(("of which the slowest body's factorisation", slowest));
    let mut solutions = Vec::with_capacity(factors.len());
    // Per point, the traction and slip each increment starts from: friction remembers the path.
    let mut carried = vec![[[0.0; 2]; 2]; rows.len()];
    for (k, &factor) in factors.iter().enumerate() {
        if factors.len() > 1 {
            report(SolidProgress::LoadStep {
                step: k + 1,
                of: factors.len(),
                factor,
            });
        }
        let f = match lines.frictional() {
            false => frictionless(newton(&rows, &g, (&s0, factor), &motions, report)?),
            true => newton_friction(
                &Increment {
                    rows: &rows,
                    lines: &lines,
                    g: &g,
                    v0: s0.iter().map(|s| factor * s).collect(),
                    work: motions.work.iter().map(|w| factor * w).collect(),
                    motions: &motions,
                    carried: &carried,
                },
                report,
            )?,
        };
        clock.lap("iterate");
        let displacements = (condensed.par_iter().zip(bodies).zip(&motions.first))
            .map(|((c, body), &first)| {
                let alpha = &f.alpha[first..first + c.motions.len()];
                recover(c, (body, factor), &rows, (&f.p, &f.tau), alpha)
            })
            .collect::<Result<Vec<_>, _>>()?;
        clock.lap("recover");
        let points = (0..rows.len())
            .map(|j| point(&rows[j], &f, j, carried[j]))
            .collect();
        for (j, c) in carried.iter_mut().enumerate() {
            *c = [f.tau[j], f.slip[j]];
        }
        let steps = f.steps;
        solutions.push(SolidContactSolution {
            displacements,
            points,
            newton_steps: steps,
            timings: clock.laps.clone(),
        });
    }
    Ok(solutions)
}

/// The frictionless iteration's result in the form of the frictional one.
fn frictionless((p, alpha, steps): (Vec<f64>, Vec<f64>, usize)) -> Frictional {
    let m = p.len();
    Frictional {
        p,
        tau: vec![[0.0; 2]; m],
        slip: vec![[0.0; 2]; m],
        status: vec![None; m],
        alpha,
        steps,
    }
}

/// Point j of the solution `f`, which started from the traction and slip `carried`.
fn point(row: &Row, f: &Frictional, j: usize, carried: [[f64; 2]; 2]) -> SolidContactPoint {
    let friction = row.friction.is_active().then(|| SolidFrictionPoint {
        tangents: row.frame,
        traction: f.tau[j],
        slip: f.slip[j],
        carried,
        status: f.status[j],
    });
    SolidContactPoint {
        pressure: f.p[j],
        friction,
        ..row.point.clone()
    }
}

/// G (over the lines, its columns weighted by `weight`) and s⁰ of all bodies.
fn coupled(condensed: &[Condensed], weight: &[f64]) -> (Mat<f64>, Vec<f64>) {
    let m = weight.len();
    let (mut g, mut s0) = (Mat::<f64>::zeros(m, m), vec![0.0; m]);
    for c in condensed {
        g += &c.g;
        s0.iter_mut().zip(&c.s0).for_each(|(s, x)| *s += x);
    }
    for (l, &w) in weight.iter().enumerate() {
        g.col_mut(l).iter_mut().for_each(|x| *x *= w);
    }
    (g, s0)
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
    /// Adds the time since the last lap to `phase` (summed over the load steps).
    fn lap(&mut self, phase: &'static str) {
        let now = std::time::Instant::now();
        let seconds = (now - self.last).as_secs_f64();
        match self.laps.iter_mut().find(|(p, _)| *p == phase) {
            Some(lap) => lap.1 += seconds,
            None => self.laps.push((phase, seconds)),
        }
        self.last = now;
    }
}

/// Factorises body `b` (its DOFs from `at` in the coupled numbering) with the DOFs the lines
/// read ordered last, and condenses it: its part of G and of s⁰.
fn condense(
    b: usize,
    (body, motions): (&SolidBodySpec<'_>, &[Vec<f64>]),
    at: usize,
    rows: &[&[(usize, f64)]],
) -> Result<Condensed, SolidContactError> {
    let range = at..at + 3 * body.mesh.num_nodes();
    let mut interface: Vec<usize> = (rows.iter())
        .flat_map(|r| r.iter().map(|&(i, _)| i))
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
    // A body its supports leave free: pinned where its free motions are best seen, which keeps
    // the factor a generalised inverse for loads that do no work along them.
    let prescribed: Vec<usize> = body.prescribed.iter().map(|&(d, _)| d).collect();
    pin_dofs(motions, &prescribed)
        .into_iter()
        .for_each(|d| constraints.prescribe(d, 0.0));
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
        for &(i, v) in r.iter().filter(|(i, _)| range.contains(i)) {
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
        motions: motions.to_vec(),
    })
}

/// Body `c`'s displacement under its loads and prescribed displacements times `factor` and the
/// contact forces of the pressures `p` and tractions `tau`.
fn recover(
    c: &Condensed,
    (body, factor): (&SolidBodySpec<'_>, f64),
    rows: &[Row],
    (p, tau): (&[f64], &[[f64; 2]]),
    alpha: &[f64],
) -> Result<Vec<f64>, SolidContactError> {
    let fail = |e: contactdd_core::BodyError| SolidContactError::Factor {
        step: 0,
        message: e.to_string(),
    };
    let mut f: Vec<f64> = body.load.iter().map(|v| factor * v).collect();
    for (r, &p) in rows.iter().zip(p) {
        for &(i, v) in r.a.iter().filter(|(i, _)| c.range.contains(i)) {
            f[i - c.range.start] -= r.point.weight * p * v;
        }
    }
    for (r, tau) in rows.iter().zip(tau).filter(|(r, _)| r.friction.is_active()) {
        for (t, &tc) in r.tangents.iter().zip(tau) {
            for &(i, v) in t.iter().filter(|(i, _)| c.range.contains(i)) {
                f[i - c.range.start] += r.point.weight * tc * v;
            }
        }
    }
    let mut u = c.factor.solve(&f).map_err(fail)?;
    if factor != 1.0 {
        // The solve imposes the prescribed values themselves; the field they cause alone
        // scales the rest of the way.
        let g = c.factor.solve(&vec![0.0; f.len()]).map_err(fail)?;
        u.iter_mut()
            .zip(&g)
            .for_each(|(u, g)| *u += (factor - 1.0) * g);
    }
    for (z, &a) in c.motions.iter().zip(alpha) {
        u.iter_mut().zip(z).for_each(|(x, v)| *x += a * v);
    }
    Ok(u)
}
