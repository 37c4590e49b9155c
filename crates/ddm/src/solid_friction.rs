//! The semismooth Newton iteration of the decomposition in space with friction
//! (docs/three-d.md, "Friction in space").
//!
//! The lines of [`Lines`] (every point's normal row, then the two tangential rows of each
//! frictional point) read v = v⁰ + G W z + E α, with z = −p on a normal line and the traction τ
//! on a tangential one. A closed frictional point j carries the traction
//!
//!   τ_j = P_b(λ_j − (g_j − g₀_j)/θ),   g_j its two tangential lines' values,
//!
//! P_b the projection onto the disc of radius b (μ p_j or the Tresca bound), λ_j and g₀_j the
//! traction and slip the increment starts from, θ the pair's penalty (the tangential one too).
//! At an exact point λ_j is τ_j itself, so that a sticking point keeps g = g₀ exactly (Alart and
//! Curnier's fixed point). A step linearises P_b at the iterate: the identity where it sticks,
//! and where it slips τ = M t + μ p t̂ (Coulomb; + b t̂ for Tresca), with t the trial traction,
//! t̂ its direction and M = (b/|t|)(I − t̂ t̂ᵀ), so that the step is a linear system over the
//! closed points' pressures and tractions and the motions' amplitudes; the balance of each free
//! motion now counts the work of the tractions too. A step is halved where it does not lower
//! the merit (`settle`), and a floating body that friction cannot hold is named (`slides`).
//! It stops at a whole step after which the closed set and the stick/slip statuses repeat and
//! the tractions meet the law to `LAW_TOL`.

use faer::Mat;

use crate::contact3d::disc::{derivative, project, DiscStatus};
use crate::newton::linear::lu_solve_refined;
use crate::solid_contact::{Lines, Row, SolidContactError, SolidProgress, MAX_STEPS};
use crate::solid_newton::{closes, full_rank, pressure, start, Motions};
use crate::Friction;

/// The tractions meet the law when they differ from it by at most this much of the largest
/// bound or traction: far above rounding, far below any discretisation error.
const LAW_TOL: f64 = 1e-10;

/// The solution of an increment.
pub(crate) struct Frictional {
    /// Every point's pressure.
    pub(crate) p: Vec<f64>,
    /// Every point's traction (zero at a frictionless or open point).
    pub(crate) tau: Vec<[f64; 2]>,
    /// Every point's slip g (zero at a frictionless point).
    pub(crate) slip: Vec<[f64; 2]>,
    /// Stick or slip at a closed frictional point.
    pub(crate) status: Vec<Option<DiscStatus>>,
    /// The motions' amplitudes.
    pub(crate) alpha: Vec<f64>,
    /// The Newton steps taken.
    pub(crate) steps: usize,
}

/// The increment's data: the rows, their lines, G (columns weighted), v⁰ and the loads' work
/// along the free motions (both times the load factor), and per point the traction and slip it
/// starts from.
pub(crate) struct Increment<'a> {
    pub(crate) rows: &'a [Row],
    pub(crate) lines: &'a Lines<'a>,
    pub(crate) g: &'a Mat<f64>,
    pub(crate) v0: Vec<f64>,
    pub(crate) work: Vec<f64>,
    pub(crate) motions: &'a Motions,
    pub(crate) carried: &'a [[[f64; 2]; 2]],
}

/// An iterate: pressures, tractions, amplitudes, and the lines' values they give with the
/// magnitudes of their terms (|v⁰| + Σ|G W z| + Σ|E α|, for their rounding), and the pressures
/// the contact law reads from those values, which bound the tractions: a point the values close
/// carries its pressure's bound at once, rather than the step's zero.
#[derive(Clone)]
struct Iterate {
    p: Vec<f64>,
    law: Vec<f64>,
    tau: Vec<[f64; 2]>,
    alpha: Vec<f64>,
    v: Vec<f64>,
    size: Vec<f64>,
}

/// The semismooth Newton iteration of one increment.
pub(crate) fn newton_friction(
    inc: &Increment<'_>,
    report: &dyn Fn(SolidProgress),
) -> Result<Frictional, SolidContactError> {
    let m = inc.rows.len();
    let mut closed = start(inc.rows, &inc.lines.tangent, inc.motions);
    // A closed point sticks at first: at the start of an increment nothing slips yet.
    let mut status: Vec<Option<DiscStatus>> = (0..m)
        .map(|j| (closed[j] && inc.lines.tangent[j].is_some()).then_some(DiscStatus::Stick))
        .collect();
    let mut it = Iterate {
        p: vec![0.0; m],
        law: vec![0.0; m],
        tau: vec![[0.0; 2]; m],
        alpha: vec![0.0; inc.motions.work.len()],
        v: inc.v0.clone(),
        size: inc.v0.iter().map(|v| v.abs()).collect(),
    };
    // The merit of the iterate: a whole step is taken where it lowers it.
    let mut merit = f64::INFINITY;
    for step in 1..=MAX_STEPS {
        let (used, held) = hold(inc, &closed, &status, &it).map_err(|body| {
            slides(inc, &closed, &it).unwrap_or(SolidContactError::NotHeld { body, step })
        })?;
        let full = step_solve(inc, &closed, &used, &it, step)?;
        report(SolidProgress::NewtonStep {
            step,
            closed: closed.iter().filter(|&&c| c).count(),
        });
        // A whole step meets its linear equations (the balance of the free motions among them):
        // only a whole step whose sets repeat and whose tractions meet the law ends the run.
        let (whole, next, e) = settle(inc, full.clone());
        let (law, meets) = law_state(inc, &next, &whole);
        if meets && next == closed && law == used && !held {
            return Ok(finish(inc, whole, &next, step));
        }
        (it, closed, merit) = match e < merit {
            true => (whole, next, e),
            false => match halved(inc, &it, full, merit) {
                Some(h) => h,
                // No progress: a body that slides is the likeliest reason.
                None => match slides(inc, &closed, &it) {
                    Some(error) => return Err(error),
                    None => (whole, next, e),
                },
            },
        };
        status = law_state(inc, &closed, &it).0;
    }
    Err(slides(inc, &closed, &it).unwrap_or(SolidContactError::NotSettled { steps: MAX_STEPS }))
}

/// The most halvings of a step that does not lower the merit.
const HALVINGS: usize = 10;

/// The step from `it` towards the Newton iterate `full` halved until the merit (the squared
/// violations of the laws, `settle`) falls below `merit`, if some halving lowers it: the
/// iterate, its closed set and its merit. Semismooth Newton steps for
/// friction converge only near the solution; far from it, a whole step can overshoot the slip
/// directions.
fn halved(
    inc: &Increment<'_>,
    it: &Iterate,
    full: Iterate,
    merit: f64,
) -> Option<(Iterate, Vec<bool>, f64)> {
    let mut omega = 1.0;
    for _ in 0..HALVINGS {
        omega /= 2.0;
        let mix = |a: f64, b: f64| a + omega * (b - a);
        let trial = Iterate {
            p: (it.p.iter().zip(&full.p))
                .map(|(&a, &b)| mix(a, b))
                .collect(),
            law: Vec::new(),
            tau: (it.tau.iter().zip(&full.tau))
                .map(|(a, b)| [mix(a[0], b[0]), mix(a[1], b[1])])
                .collect(),
            alpha: (it.alpha.iter().zip(&full.alpha))
                .map(|(&a, &b)| mix(a, b))
                .collect(),
            v: Vec::new(),
            size: Vec::new(),
        };
        let next = settle(inc, trial);
        if next.2 < merit {
            return Some(next);
        }
    }
    None
}

/// The iterate `it` with its lines' values, the closed set they give (as the primal–dual
/// active set method closes points) and its merit: the squared violations of the contact law,
/// of the friction law at the closed frictional points and of the free motions' balance (per
/// unit contact area), so that no iterate looks solved while its pressures, tractions and values
/// disagree.
fn settle(inc: &Increment<'_>, mut it: Iterate) -> (Iterate, Vec<bool>, f64) {
    let m = inc.rows.len();
    (it.v, it.size) = values(inc, &it);
    let closed: Vec<bool> = (0..m)
        .map(|j| closes(&inc.rows[j], it.p[j], it.v[j]))
        .collect();
    it.law = (0..m)
        .map(|j| match closed[j] {
            true => pressure(&inc.rows[j], it.p[j], it.v[j]),
            false => 0.0,
        })
        .collect();
    let mut merit = unbalance(inc, &it);
    for j in 0..m {
        let row = &inc.rows[j];
        merit += (it.p[j] - it.law[j]).powi(2);
        let Some(t) = inc.lines.tangent[j].filter(|_| closed[j]) else {
            continue;
        };
        let (tau, _) = project(trial(inc, j, &it, t), bound(row, it.law[j]));
        merit += (tau[0] - it.tau[j][0]).powi(2) + (tau[1] - it.tau[j][1]).powi(2);
    }
    (it, closed, merit)
}

/// The squared violation of the free motions' balance at `it`, per unit contact area.
fn unbalance(inc: &Increment<'_>, it: &Iterate) -> f64 {
    let area: f64 = inc.rows.iter().map(|r| r.point.weight).sum();
    let e = &inc.motions.e;
    (inc.motions.work.iter().enumerate())
        .map(|(q, work)| {
            let mut r = -work;
            for (j, t) in inc.lines.tangent.iter().enumerate() {
                let w = inc.rows[j].point.weight;
                r += w * e[(j, q)] * it.p[j];
                if let Some(t) = t {
                    r -= w * (e[(*t, q)] * it.tau[j][0] + e[(t + 1, q)] * it.tau[j][1]);
                }
            }
            (r / area).powi(2)
        })
        .sum()
}

/// The bound of point `j` at pressure `p`: μ p (Coulomb) or the Tresca bound.
fn bound(row: &Row, p: f64) -> f64 {
    match row.friction {
        Friction::Coulomb { mu } => mu * p.max(0.0),
        Friction::Tresca { bound } => bound,
        Friction::None => 0.0,
    }
}

/// The trial traction of frictional point `j` at the iterate.
fn trial(inc: &Increment<'_>, j: usize, it: &Iterate, t: usize) -> [f64; 2] {
    let [lambda, g0] = inc.carried[j];
    let lambda = if inc.rows[j].exact { it.tau[j] } else { lambda };
    let theta = inc.rows[j].theta;
    [0, 1].map(|c| lambda[c] - (it.v[t + c] - g0[c]) / theta)
}

/// The statuses of the closed frictional points at the iterate, and whether their tractions
/// meet the law: each within `LAW_TOL` of the largest bound or traction, or within the rounding
/// of its trial traction where that is larger.
fn law_state(
    inc: &Increment<'_>,
    closed: &[bool],
    it: &Iterate,
) -> (Vec<Option<DiscStatus>>, bool) {
    let (mut scale, mut misses) = (f64::MIN_POSITIVE, Vec::new());
    let status = (0..closed.len())
        .map(|j| {
            let t = inc.lines.tangent[j].filter(|_| closed[j])?;
            let b = bound(&inc.rows[j], it.law[j]);
            let (tau, s) = project(trial(inc, j, it, t), b);
            let miss = (tau[0] - it.tau[j][0]).hypot(tau[1] - it.tau[j][1]);
            misses.push((miss, rounding(inc, it, j, t)));
            scale = scale.max(b).max(it.tau[j][0].hypot(it.tau[j][1]));
            Some(s)
        })
        .collect();
    let meets = (misses.iter()).all(|&(miss, floor)| miss <= floor.max(LAW_TOL * scale));
    (status, meets)
}

/// The rounding of point j's trial traction (tangential lines t, t + 1): the unit roundoff
/// times the terms of its lines' values v = v⁰ + G W z + E α, times their magnitudes, over θ.
fn rounding(inc: &Increment<'_>, it: &Iterate, j: usize, t: usize) -> f64 {
    let terms = (inc.lines.rows.len() + it.alpha.len() + 1) as f64;
    let size = (it.size[t]).max(it.size[t + 1]);
    f64::EPSILON / 2.0 * terms * size / inc.rows[j].theta
}

/// The statuses a step uses: where the step would leave some of a body's free motions
/// unresisted (by its closed points' normal lines, its sticking points, and the slipping points
/// across their slip directions), its slipping point nearest its disc (smallest |t|/b) sticks
/// for the step, one at a time, so that the step has a solution; whether any point was held
/// so. A body that nothing can hold is returned as the error.
fn hold(
    inc: &Increment<'_>,
    closed: &[bool],
    status: &[Option<DiscStatus>],
    it: &Iterate,
) -> Result<(Vec<Option<DiscStatus>>, bool), usize> {
    let mut used = status.to_vec();
    let mut held = false;
    while let Some(body) = unresisted(inc, closed, &used, it) {
        let sees = |l: usize| {
            (0..inc.motions.body.len())
                .any(|q| inc.motions.body[q] == body && inc.motions.e[(l, q)] != 0.0)
        };
        let nearest = (0..closed.len())
            .filter(|&j| used[j] == Some(DiscStatus::Slip))
            .filter_map(|j| inc.lines.tangent[j].map(|t| (j, t)))
            .filter(|&(_, t)| sees(t) || sees(t + 1))
            .map(|(j, t)| {
                let tr = trial(inc, j, it, t);
                let b = bound(&inc.rows[j], it.law[j]).max(f64::MIN_POSITIVE);
                (j, tr[0].hypot(tr[1]) / b)
            })
            .min_by(|x, y| x.1.total_cmp(&y.1));
        let Some((j, _)) = nearest else {
            return Err(body);
        };
        used[j] = Some(DiscStatus::Stick);
        held = true;
    }
    Ok((used, held))
}

/// A body some of whose free motions the step with statuses `used` would leave unresisted.
fn unresisted(
    inc: &Increment<'_>,
    closed: &[bool],
    used: &[Option<DiscStatus>],
    it: &Iterate,
) -> Option<usize> {
    let e = &inc.motions.e;
    (0..inc.motions.first.len()).find(|&b| {
        let cols: Vec<usize> = (0..inc.motions.body.len())
            .filter(|&q| inc.motions.body[q] == b)
            .collect();
        let read = |l: usize| cols.iter().map(|&q| e[(l, q)]).collect::<Vec<f64>>();
        let mut readings = Vec::new();
        for j in (0..closed.len()).filter(|&j| closed[j]) {
            readings.push(read(j));
            let Some(t) = inc.lines.tangent[j] else {
                continue;
            };
            match used[j] {
                Some(DiscStatus::Stick) => readings.extend([read(t), read(t + 1)]),
                // Slipping, it resists a slip across its direction (where its bound is not 0).
                _ if bound(&inc.rows[j], it.law[j]) > 0.0 => {
                    let tr = trial(inc, j, it, t);
                    let (x, y) = (read(t), read(t + 1));
                    readings.push(
                        x.iter()
                            .zip(&y)
                            .map(|(x, y)| tr[0] * y - tr[1] * x)
                            .collect(),
                    );
                }
                _ => {}
            }
        }
        !cols.is_empty() && !full_rank(&readings, cols.len())
    })
}

/// The accepted solution: pressures by the law, tractions projected onto their discs.
fn finish(inc: &Increment<'_>, it: Iterate, closed: &[bool], steps: usize) -> Frictional {
    let m = closed.len();
    let (mut tau, mut slip, mut status) = (vec![[0.0; 2]; m], vec![[0.0; 2]; m], vec![None; m]);
    for j in 0..m {
        let Some(t) = inc.lines.tangent[j] else {
            continue;
        };
        slip[j] = [it.v[t], it.v[t + 1]];
        if closed[j] {
            let (traction, s) = project(trial(inc, j, &it, t), bound(&inc.rows[j], it.law[j]));
            (tau[j], status[j]) = (traction, Some(s));
        }
    }
    Frictional {
        p: it.law,
        tau,
        slip,
        status,
        alpha: it.alpha,
        steps,
    }
}

/// Where the step's unknowns sit: per point its pressure's column (closed points) and its first
/// traction column (closed frictional points), and their number before the amplitudes.
fn columns(
    inc: &Increment<'_>,
    closed: &[bool],
) -> (Vec<Option<usize>>, Vec<Option<usize>>, usize) {
    let (mut pc, mut tc, mut n) = (vec![None; closed.len()], vec![None; closed.len()], 0);
    for j in (0..closed.len()).filter(|&j| closed[j]) {
        pc[j] = Some(n);
        n += 1;
    }
    for j in (0..closed.len()).filter(|&j| closed[j] && inc.lines.tangent[j].is_some()) {
        tc[j] = Some(n);
        n += 2;
    }
    (pc, tc, n)
}

/// One Newton step with the closed set `closed` and the statuses `used`, linearised at `it`.
fn step_solve(
    inc: &Increment<'_>,
    closed: &[bool],
    used: &[Option<DiscStatus>],
    it: &Iterate,
    step: usize,
) -> Result<Iterate, SolidContactError> {
    let (pc, tc, c) = columns(inc, closed);
    let k = inc.motions.work.len();
    let (mut a, mut rhs) = (Mat::<f64>::zeros(c + k, c + k), Mat::<f64>::zeros(c + k, 1));
    // Adds `scale` times the line l's value v_l = v⁰_l + Σ G z + E α to equation x's left side
    // (its constant to the right side).
    let add_line = |a: &mut Mat<f64>, rhs: &mut Mat<f64>, x: usize, l: usize, scale: f64| {
        for (j, col) in pc.iter().enumerate() {
            if let Some(y) = col {
                a[(x, *y)] -= scale * inc.g[(l, j)];
            }
        }
        for (j, col) in tc.iter().enumerate() {
            if let (Some(y), Some(t)) = (col, inc.lines.tangent[j]) {
                a[(x, *y)] += scale * inc.g[(l, t)];
                a[(x, y + 1)] += scale * inc.g[(l, t + 1)];
            }
        }
        for q in 0..k {
            a[(x, c + q)] += scale * inc.motions.e[(l, q)];
        }
        rhs[(x, 0)] -= scale * inc.v0[l];
    };
    for j in (0..closed.len()).filter(|&j| closed[j]) {
        let (row, x) = (&inc.rows[j], pc[j].unwrap_or(0));
        // θ p − s = −d (an exact point: s = d).
        a[(x, x)] += if row.exact { 0.0 } else { row.theta };
        add_line(&mut a, &mut rhs, x, j, -1.0);
        rhs[(x, 0)] -= row.point.gap;
        let (Some(y), Some(t)) = (tc[j], inc.lines.tangent[j]) else {
            continue;
        };
        tangential(inc, (j, x, y, t), used[j], it, &mut a, &mut rhs, &add_line);
    }
    for q in 0..k {
        for j in (0..closed.len()).filter(|&j| closed[j]) {
            let w = inc.rows[j].point.weight;
            a[(c + q, pc[j].unwrap_or(0))] += w * inc.motions.e[(j, q)];
            if let (Some(y), Some(t)) = (tc[j], inc.lines.tangent[j]) {
                a[(c + q, y)] -= w * inc.motions.e[(t, q)];
                a[(c + q, y + 1)] -= w * inc.motions.e[(t + 1, q)];
            }
        }
        rhs[(c + q, 0)] = inc.work[q];
    }
    solve(a, &mut rhs, step)?;
    let m = closed.len();
    let next = Iterate {
        p: (0..m).map(|j| pc[j].map_or(0.0, |x| rhs[(x, 0)])).collect(),
        law: Vec::new(),
        tau: (0..m)
            .map(|j| tc[j].map_or([0.0; 2], |y| [rhs[(y, 0)], rhs[(y + 1, 0)]]))
            .collect(),
        alpha: (0..k).map(|q| rhs[(c + q, 0)]).collect(),
        v: Vec::new(),
        size: Vec::new(),
    };
    Ok(next)
}

/// The two tangential equations of closed frictional point j (pressure column x, traction
/// columns y, y + 1, tangential lines t, t + 1) under its status.
#[allow(clippy::type_complexity)]
fn tangential(
    inc: &Increment<'_>,
    (j, x, y, t): (usize, usize, usize, usize),
    status: Option<DiscStatus>,
    it: &Iterate,
    a: &mut Mat<f64>,
    rhs: &mut Mat<f64>,
    add_line: &dyn Fn(&mut Mat<f64>, &mut Mat<f64>, usize, usize, f64),
) {
    let row = &inc.rows[j];
    let (theta, exact) = (row.theta, row.exact);
    let [lambda, g0] = inc.carried[j];
    let lambda = if exact { [0.0; 2] } else { lambda };
    if status != Some(DiscStatus::Slip) {
        // Stick: θ τ + g = θ λ + g₀ (an exact point: g = g₀).
        for c in 0..2 {
            a[(y + c, y + c)] += if exact { 0.0 } else { theta };
            add_line(a, rhs, y + c, t + c, 1.0);
            rhs[(y + c, 0)] += theta * lambda[c] + g0[c];
        }
        return;
    }
    // Slip: (I − [exact] M) τ + (M/θ) g − μ t̂ p = M (λ + g₀/θ) (+ b t̂ under Tresca).
    let tr = trial(inc, j, it, t);
    let b = bound(row, it.law[j]);
    let (m, dir) = derivative(tr, b);
    for c in 0..2 {
        for d in 0..2 {
            let identity = if c == d { 1.0 } else { 0.0 };
            a[(y + c, y + d)] += identity - if exact { m[c][d] } else { 0.0 };
            add_line(a, rhs, y + c, t + d, m[c][d] / theta);
            rhs[(y + c, 0)] += m[c][d] * (lambda[d] + g0[d] / theta);
        }
        match row.friction {
            Friction::Coulomb { mu } => a[(y + c, x)] -= mu * dir[c],
            _ => rhs[(y + c, 0)] += b * dir[c],
        }
    }
}

/// Solves the step's system in place of `rhs`.
fn solve(a: Mat<f64>, rhs: &mut Mat<f64>, step: usize) -> Result<(), SolidContactError> {
    if a.nrows() == 0 {
        return Ok(());
    }
    lu_solve_refined(a, rhs, 2).ok_or(SolidContactError::Factor {
        step,
        message: "no memory for the Newton system".into(),
    })?;
    match (0..rhs.nrows()).all(|x| rhs[(x, 0)].is_finite()) {
        true => Ok(()),
        false => Err(SolidContactError::Factor {
            step,
            message: "the Newton system is singular".into(),
        }),
    }
}

/// The lines' values v = v⁰ + G W z + E α at pressures, tractions and amplitudes `it`, and the
/// magnitudes of their terms.
fn values(inc: &Increment<'_>, it: &Iterate) -> (Vec<f64>, Vec<f64>) {
    let mut z = vec![0.0; inc.lines.rows.len()];
    for (j, t) in inc.lines.tangent.iter().enumerate() {
        z[j] = -it.p[j];
        if let Some(t) = t {
            (z[*t], z[t + 1]) = (it.tau[j][0], it.tau[j][1]);
        }
    }
    (0..z.len())
        .map(|l| {
            let (mut v, mut size) = (inc.v0[l], inc.v0[l].abs());
            for (y, zy) in z.iter().enumerate() {
                v += inc.g[(l, y)] * zy;
                size += (inc.g[(l, y)] * zy).abs();
            }
            for (q, a) in it.alpha.iter().enumerate() {
                v += inc.motions.e[(l, q)] * a;
                size += (inc.motions.e[(l, q)] * a).abs();
            }
            (v, size)
        })
        .unzip()
}

/// Whether a floating body slides: along the motion z that its loads drive hardest among those
/// that change no closed point's approach (so that only friction resists them), the loads do
/// more work than friction can oppose, Σ_j w_j b_j |Δg_j(z)|.
fn slides(inc: &Increment<'_>, closed: &[bool], it: &Iterate) -> Option<SolidContactError> {
    let e = &inc.motions.e;
    (0..inc.motions.first.len()).find_map(|body| {
        let cols: Vec<usize> = (0..inc.motions.body.len())
            .filter(|&q| inc.motions.body[q] == body)
            .collect();
        let z = driven(inc, closed, &cols)?;
        let along = |l: usize| {
            cols.iter()
                .zip(&z)
                .map(|(&q, c)| e[(l, q)] * c)
                .sum::<f64>()
        };
        let work: f64 = cols
            .iter()
            .zip(&z)
            .map(|(&q, c)| inc.motions.work[q] * c)
            .sum();
        let mut resistance = 0.0;
        for (j, t) in inc.lines.tangent.iter().enumerate() {
            let Some(t) = t.filter(|_| closed[j]) else {
                continue;
            };
            let dg = along(t).hypot(along(t + 1));
            resistance += inc.rows[j].point.weight * bound(&inc.rows[j], it.law[j]) * dg;
        }
        (work > resistance).then_some(SolidContactError::Slides {
            body,
            work,
            resistance,
        })
    })
}

/// A combination z of the motions `cols` that no closed point's approach sees and along which
/// the loads work: their work vector projected onto the null space of the closed normal lines'
/// readings (`None` if that is empty or the work has no part there). Any such z certifies a
/// slide when the loads' work along it exceeds what friction can oppose.
fn driven(inc: &Increment<'_>, closed: &[bool], cols: &[usize]) -> Option<Vec<f64>> {
    let n = cols.len();
    if n == 0 {
        return None;
    }
    let e = &inc.motions.e;
    let set: Vec<usize> = (0..closed.len()).filter(|&j| closed[j]).collect();
    let gram = nalgebra::DMatrix::<f64>::from_fn(n, n, |x, y| {
        set.iter().map(|&j| e[(j, cols[x])] * e[(j, cols[y])]).sum()
    });
    let eigen = gram.symmetric_eigen();
    let largest = eigen
        .eigenvalues
        .iter()
        .fold(0.0f64, |a, &l| a.max(l.abs()));
    let floor = f64::EPSILON * set.len().max(1) as f64 * largest;
    let work: Vec<f64> = cols.iter().map(|&q| inc.motions.work[q]).collect();
    let mut z = vec![0.0; n];
    for (k, &l) in eigen.eigenvalues.iter().enumerate() {
        if l <= floor {
            let v = eigen.eigenvectors.column(k);
            let c: f64 = (0..n).map(|x| v[x] * work[x]).sum();
            (0..n).for_each(|x| z[x] += c * v[x]);
        }
    }
    z.iter().any(|&c| c != 0.0).then_some(z)
}
