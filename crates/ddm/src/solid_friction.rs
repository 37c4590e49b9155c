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
//! motion now counts the work of the tractions too. It stops when the closed set and the
//! stick/slip statuses repeat and the tractions meet the law to `LAW_TOL`.

use faer::Mat;

use crate::contact3d::disc::{derivative, project, DiscStatus};
use crate::newton::linear::lu_solve_in_place;
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

/// An iterate: pressures, tractions, amplitudes, and the lines' values they give.
struct Iterate {
    p: Vec<f64>,
    tau: Vec<[f64; 2]>,
    alpha: Vec<f64>,
    v: Vec<f64>,
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
        tau: vec![[0.0; 2]; m],
        alpha: vec![0.0; inc.motions.work.len()],
        v: inc.v0.clone(),
    };
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
        let next;
        (it, next, merit) = damped(inc, &it, full, merit);
        let (law, residual, scale) = law_state(inc, &next, &it);
        let settled = next == closed && law == used && !held;
        if settled && residual <= LAW_TOL * scale {
            return Ok(finish(inc, it, &next, step));
        }
        (closed, status) = (next, law);
    }
    Err(slides(inc, &closed, &it).unwrap_or(SolidContactError::NotSettled { steps: MAX_STEPS }))
}

/// The most halvings of a step that does not lower the merit.
const HALVINGS: usize = 10;

/// The step from `it` towards the Newton iterate `full`, halved until the merit (the squared
/// violations of the laws) falls below `merit`, or taken whole when no halving lowers it: the
/// iterate with its pressures read from the law, its closed set, and its merit. Semismooth
/// Newton steps for friction converge only near the solution; far from it, a whole step can
/// land where the slip directions point the iteration back.
fn damped(
    inc: &Increment<'_>,
    it: &Iterate,
    full: Iterate,
    merit: f64,
) -> (Iterate, Vec<bool>, f64) {
    let mut omega = 1.0;
    let whole = settle(inc, full);
    if whole.2 < merit {
        return whole;
    }
    for _ in 0..HALVINGS {
        omega /= 2.0;
        let mix = |a: f64, b: f64| a + omega * (b - a);
        let trial = Iterate {
            p: (it.p.iter().zip(&whole.0.p))
                .map(|(&a, &b)| mix(a, b))
                .collect(),
            tau: (it.tau.iter().zip(&whole.0.tau))
                .map(|(a, b)| [mix(a[0], b[0]), mix(a[1], b[1])])
                .collect(),
            alpha: (it.alpha.iter().zip(&whole.0.alpha))
                .map(|(&a, &b)| mix(a, b))
                .collect(),
            v: Vec::new(),
        };
        let next = settle(inc, trial);
        if next.2 < merit {
            return next;
        }
    }
    whole
}

/// The iterate `it` with its lines' values, its pressures read from the law (the closed set it
/// gives), and its merit: Σ |τ − P_b(t)|² over the closed frictional points.
fn settle(inc: &Increment<'_>, mut it: Iterate) -> (Iterate, Vec<bool>, f64) {
    it.v = values(inc, &it);
    let m = inc.rows.len();
    let closed: Vec<bool> = (0..m)
        .map(|j| closes(&inc.rows[j], it.p[j], it.v[j]))
        .collect();
    it.p = (0..m)
        .map(|j| match closed[j] {
            true => pressure(&inc.rows[j], it.p[j], it.v[j]),
            false => 0.0,
        })
        .collect();
    let mut merit = 0.0;
    for j in (0..m).filter(|&j| closed[j]) {
        let Some(t) = inc.lines.tangent[j] else {
            continue;
        };
        let (tau, _) = project(trial(inc, j, &it, t), bound(&inc.rows[j], it.p[j]));
        merit += (tau[0] - it.tau[j][0]).powi(2) + (tau[1] - it.tau[j][1]).powi(2);
    }
    (it, closed, merit)
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

/// The statuses of the closed frictional points at the iterate, the largest difference between
/// their tractions and the law, and the scale it is measured on (the largest bound or traction).
fn law_state(
    inc: &Increment<'_>,
    closed: &[bool],
    it: &Iterate,
) -> (Vec<Option<DiscStatus>>, f64, f64) {
    let (mut residual, mut scale) = (0.0f64, f64::MIN_POSITIVE);
    let status = (0..closed.len())
        .map(|j| {
            let t = inc.lines.tangent[j].filter(|_| closed[j])?;
            let b = bound(&inc.rows[j], it.p[j]);
            let (tau, s) = project(trial(inc, j, it, t), b);
            let d = [tau[0] - it.tau[j][0], tau[1] - it.tau[j][1]];
            residual = residual.max(d[0].hypot(d[1]));
            scale = scale.max(b).max(it.tau[j][0].hypot(it.tau[j][1]));
            Some(s)
        })
        .collect();
    (status, residual, scale)
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
                let b = bound(&inc.rows[j], it.p[j]).max(f64::MIN_POSITIVE);
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
                _ if bound(&inc.rows[j], it.p[j]) > 0.0 => {
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
            let (traction, s) = project(trial(inc, j, &it, t), bound(&inc.rows[j], it.p[j]));
            (tau[j], status[j]) = (traction, Some(s));
        }
    }
    Frictional {
        p: it.p,
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
        tau: (0..m)
            .map(|j| tc[j].map_or([0.0; 2], |y| [rhs[(y, 0)], rhs[(y + 1, 0)]]))
            .collect(),
        alpha: (0..k).map(|q| rhs[(c + q, 0)]).collect(),
        v: Vec::new(),
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
    let b = bound(row, it.p[j]);
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
    lu_solve_in_place(a, rhs).ok_or(SolidContactError::Factor {
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

/// The lines' values v = v⁰ + G W z + E α at pressures, tractions and amplitudes `it`.
fn values(inc: &Increment<'_>, it: &Iterate) -> Vec<f64> {
    let mut z = vec![0.0; inc.lines.rows.len()];
    for (j, t) in inc.lines.tangent.iter().enumerate() {
        z[j] = -it.p[j];
        if let Some(t) = t {
            (z[*t], z[t + 1]) = (it.tau[j][0], it.tau[j][1]);
        }
    }
    (0..z.len())
        .map(|l| {
            let contact: f64 = (0..z.len()).map(|y| inc.g[(l, y)] * z[y]).sum();
            let rigid: f64 = (0..it.alpha.len())
                .map(|q| inc.motions.e[(l, q)] * it.alpha[q])
                .sum();
            inc.v0[l] + contact + rigid
        })
        .collect()
}

/// Whether a floating body slides: the loads do more work along one of its free motions than
/// friction can oppose there, Σ_j w_j b_j |Δg_j|, at a motion that changes no closed point's
/// approach (so that only friction resists it).
fn slides(inc: &Increment<'_>, closed: &[bool], it: &Iterate) -> Option<SolidContactError> {
    let e = &inc.motions.e;
    (0..inc.motions.work.len()).find_map(|q| {
        let mut resistance = 0.0;
        let mut reach = 0.0f64;
        for (j, t) in inc.lines.tangent.iter().enumerate() {
            let Some(t) = t.filter(|_| closed[j]) else {
                continue;
            };
            let dg = e[(t, q)].hypot(e[(t + 1, q)]);
            resistance += inc.rows[j].point.weight * bound(&inc.rows[j], it.p[j]) * dg;
            reach = reach.max(dg);
        }
        let pressed = (0..closed.len())
            .filter(|&j| closed[j])
            .any(|j| e[(j, q)].abs() > 1e-12 * reach);
        let work = inc.motions.work[q].abs();
        (!pressed && reach > 0.0 && work > resistance).then_some(SolidContactError::Slides {
            body: inc.motions.body[q],
            work,
            resistance,
        })
    })
}
