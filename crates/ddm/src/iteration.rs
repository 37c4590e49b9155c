//! The Robin domain decomposition iteration (method.md §3) on the condensed bodies.
//!
//! The iterate lives on the interface: the normal displacements U of all contact points (plus the
//! interface loads T that reproduce the full fields at the end). Each iteration every body reads
//! U^k and U^{k−1} from shared buffers, computes its Robin coefficients φ^k and right-hand side,
//! solves its condensed Robin problem and writes its own slice of U^{k+1} (double buffering). The
//! bodies run in parallel with rayon; each body's arithmetic is sequential and independent of the
//! others, so the result does not depend on the number of threads.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use crate::condensed::{CondensedBody, RobinCache};
use crate::contact::Interface;
use crate::method::Method;
use crate::relaxation::{Gamma, Relaxation};

/// Settings of one DD solve.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Robin coefficient rule.
    pub method: Method,
    /// Relaxation parameter γ.
    pub gamma: Gamma,
    /// Stopping tolerance ε_u on the relative change of every body's normal displacements.
    pub tol: f64,
    /// Iteration cap.
    pub max_iter: usize,
    /// Initial normal displacement u^0_n on all contact points.
    pub u0: f64,
    /// Initial u^{−1}_n (two-point methods).
    pub u_prev: f64,
}

impl Default for Settings {
    /// The paper's values: u^0 = 1e−4, u^{−1} = 2e−4, ε = 1e−3 would be loose for general use, so
    /// the default tolerance is 1e−6.
    fn default() -> Settings {
        Settings {
            method: Method::NewtonKurchatov,
            gamma: Gamma::Auto,
            tol: 1e-6,
            max_iter: 500,
            u0: 1e-4,
            u_prev: 2e-4,
        }
    }
}

/// What happened in one iteration.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Record {
    /// Iteration number k (1-based: the record of the k-th solve).
    pub k: usize,
    /// γ^k used.
    pub gamma: f64,
    /// ‖u^{k}_n − u^{k−1}_n‖ / ‖u^{k}_n‖ per body.
    pub rel_change: Vec<f64>,
    /// Number of penetrating (closed) contact points per body after the update.
    pub active: Vec<usize>,
    /// Total normal contact force Σ w |σ_n| per body after the update.
    pub contact_force: Vec<f64>,
}

/// Why a body's iteration failed.
#[derive(Clone, Debug, PartialEq)]
pub enum Breakdown {
    /// The body's Robin problem became singular with no closed point left.
    LostContact,
    /// The Robin problem became singular although some points are closed.
    Singular,
    /// NaN or infinity appeared.
    NonFinite,
    /// The displacements grew beyond any physical size.
    Growth,
}

/// How the iteration ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Stop {
    /// All bodies met the tolerance.
    Converged,
    /// The iteration cap was reached.
    MaxIterations,
    /// A body broke down at an iteration.
    Diverged {
        /// Body index.
        body: usize,
        /// Iteration at which it happened.
        iteration: usize,
        /// What happened.
        reason: Breakdown,
    },
    /// Cancelled by the caller.
    Interrupted,
}

/// Interface state and history at the end of an iteration.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// How it ended.
    pub stop: Stop,
    /// Number of iterations taken.
    pub iterations: usize,
    /// Final normal displacements of all contact points.
    pub un: Vec<f64>,
    /// Final interface loads (full fields are K₀⁻¹(f + N T)).
    pub t_load: Vec<f64>,
    /// Per-iteration records.
    pub history: Vec<Record>,
    /// Wall time of the iteration.
    pub seconds: f64,
}

/// Optional callbacks of a solve.
#[derive(Clone, Copy, Default)]
pub struct Hooks<'a> {
    /// Called after every iteration.
    pub on_iteration: Option<&'a (dyn Fn(&Record) + Sync)>,
    /// Checked every iteration; set it to stop early.
    pub cancel: Option<&'a AtomicBool>,
}

/// Per-body buffers, allocated once per solve.
#[derive(Default)]
struct Scratch {
    cache: RobinCache,
    phi: Vec<f64>,
    r: Vec<f64>,
    tilde: Vec<f64>,
    t_new: Vec<f64>,
}

/// One body's share of an iteration: its buffers and its slices of the shared outputs.
struct BodyWork<'a> {
    scratch: &'a mut Scratch,
    next: &'a mut [f64],
    t_load: &'a mut [f64],
}

/// Runs the iteration. `bodies[b]` is body b condensed on `interface.of_body(b)`; `scale[b]` is a
/// length beyond which displacements count as blown up.
pub fn iterate(
    interface: &Interface,
    bodies: &[CondensedBody],
    scale: &[f64],
    settings: &Settings,
    hooks: Hooks<'_>,
) -> Outcome {
    let start = Instant::now();
    let m = interface.len();
    let nb = bodies.len();
    let mut u_prev = vec![settings.u_prev; m];
    let mut u_cur = vec![settings.u0; m];
    let mut u_next = vec![0.0; m];
    let mut t_load = vec![0.0; m];
    for (b, body) in bodies.iter().enumerate() {
        let range = interface.body_range[b].clone();
        let t0 = body.initial_load(&u_cur[range.clone()]);
        t_load[range].copy_from_slice(&t0);
    }
    let t_start = t_load.clone();
    let mut scratch: Vec<Scratch> = (0..nb)
        .map(|b| {
            let len = interface.body_range[b].len();
            Scratch {
                phi: vec![0.0; len],
                r: vec![0.0; len],
                tilde: vec![0.0; len],
                t_new: vec![0.0; len],
                ..Scratch::default()
            }
        })
        .collect();
    let mut t_backup = t_load.clone();
    let (mut s_prev, mut s_cur, mut s_next) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    interface.sum_normal(&u_prev, &mut s_prev);
    interface.sum_normal(&u_cur, &mut s_cur);
    let mut relax = Relaxation::new(settings.gamma);
    let mut history = Vec::new();
    let mut stop = Stop::MaxIterations;
    let mut iterations = 0;

    for k in 1..=settings.max_iter {
        if hooks.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            stop = Stop::Interrupted;
            break;
        }
        let gamma = relax.gamma();
        t_backup.copy_from_slice(&t_load);
        // Split the shared output buffers into per-body slices.
        let mut work = Vec::with_capacity(nb);
        {
            let (mut next_rest, mut t_rest) = (u_next.as_mut_slice(), t_load.as_mut_slice());
            for (b, scratch) in scratch.iter_mut().enumerate() {
                let len = interface.body_range[b].len();
                let (next, nr) = next_rest.split_at_mut(len);
                let (tl, tr) = t_rest.split_at_mut(len);
                next_rest = nr;
                t_rest = tr;
                work.push(BodyWork {
                    scratch,
                    next,
                    t_load: tl,
                });
            }
        }
        let (u_cur_ref, s_cur_ref, s_prev_ref) = (&u_cur, &s_cur, &s_prev);
        let results: Vec<Result<f64, Breakdown>> = work
            .par_iter_mut()
            .enumerate()
            .map(|(b, w)| {
                let range = interface.body_range[b].clone();
                let points = &interface.points[range.clone()];
                let u_own = &u_cur_ref[range.clone()];
                let Scratch {
                    cache,
                    phi,
                    r,
                    tilde,
                    t_new,
                } = &mut *w.scratch;
                for (j, p) in points.iter().enumerate() {
                    let g = range.start + j;
                    if !p.has_partner() {
                        // Never closes: φ = 0, no contact force.
                        (phi[j], r[j]) = (0.0, 0.0);
                        continue;
                    }
                    let (s, sp) = (s_cur_ref[g], s_prev_ref[g]);
                    phi[j] = settings.method.phi(p.gap, s, sp);
                    let kw = p.weight / p.theta;
                    r[j] = kw * (phi[j] * u_own[j] + (p.gap - s).min(0.0));
                }
                bodies[b]
                    .robin_solve(phi, r, cache, tilde, t_new)
                    .map_err(|_| {
                        if phi.iter().all(|&f| f == 0.0) {
                            Breakdown::LostContact
                        } else {
                            Breakdown::Singular
                        }
                    })?;
                let (mut diff, mut norm) = (0.0, 0.0);
                for j in 0..points.len() {
                    let new = gamma * tilde[j] + (1.0 - gamma) * u_own[j];
                    w.next[j] = new;
                    w.t_load[j] = gamma * t_new[j] + (1.0 - gamma) * w.t_load[j];
                    diff += (new - u_own[j]).powi(2);
                    norm += new * new;
                }
                if !w.next.iter().all(|v| v.is_finite()) {
                    return Err(Breakdown::NonFinite);
                }
                if w.next.iter().any(|v| v.abs() > scale[b]) {
                    return Err(Breakdown::Growth);
                }
                Ok(if norm > 0.0 {
                    (diff / norm).sqrt()
                } else {
                    diff.sqrt()
                })
            })
            .collect();
        drop(work);
        iterations = k;
        let mut rel_change = Vec::with_capacity(nb);
        let mut failed = None;
        for (b, res) in results.into_iter().enumerate() {
            match res {
                Ok(rc) => rel_change.push(rc),
                Err(reason) => {
                    failed.get_or_insert(Stop::Diverged {
                        body: b,
                        iteration: k,
                        reason,
                    });
                    rel_change.push(f64::NAN);
                }
            }
        }
        if let Some(s) = failed {
            // Keep the last good iterate consistent: U^k with its T^k.
            t_load.copy_from_slice(&t_backup);
            if relax.restart() {
                // Start over from the initial values with a smaller γ cap.
                u_prev.fill(settings.u_prev);
                u_cur.fill(settings.u0);
                t_load.copy_from_slice(&t_start);
                interface.sum_normal(&u_prev, &mut s_prev);
                interface.sum_normal(&u_cur, &mut s_cur);
                continue;
            }
            stop = s;
            break;
        }
        interface.sum_normal(&u_next, &mut s_next);
        let (mut active, mut force) = (vec![0usize; nb], vec![0.0; nb]);
        for (j, p) in interface.points.iter().enumerate() {
            if p.has_partner() && p.gap - s_next[j] < 0.0 {
                active[p.body] += 1;
                force[p.body] += p.weight * (s_next[j] - p.gap) / p.theta;
            }
        }
        let record = Record {
            k,
            gamma,
            rel_change,
            active,
            contact_force: force,
        };
        if let Some(f) = hooks.on_iteration {
            f(&record);
        }
        // With an adaptive γ a tiny step must not pass for convergence: the change is judged as
        // if γ were at least the starting value (for a constant γ this is the paper's criterion).
        let scale = relax.convergence_scale();
        let converged = record.rel_change.iter().all(|&r| r * scale <= settings.tol);
        relax.update(&u_cur, &u_next);
        history.push(record);
        // Rotate the double buffers: k−1 ← k ← k+1.
        std::mem::swap(&mut u_prev, &mut u_cur);
        std::mem::swap(&mut u_cur, &mut u_next);
        std::mem::swap(&mut s_prev, &mut s_cur);
        std::mem::swap(&mut s_cur, &mut s_next);
        if converged {
            stop = Stop::Converged;
            break;
        }
    }
    Outcome {
        stop,
        iterations,
        un: u_cur,
        t_load,
        history,
        seconds: start.elapsed().as_secs_f64(),
    }
}
