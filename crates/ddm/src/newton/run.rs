//! The driver of one Newton run: full steps watched by a non-monotone watchdog, a backtracking
//! line search from its checkpoint, and the stopping rule.

use std::sync::atomic::Ordering;

use super::algebra::norm;
use super::step::Caches;
use super::system::{Evaluation, System};
use crate::contact::Status;
use crate::exchange::share_slices;
use crate::measures::{
    contact_summary, free_response_scale, largest, relative_change, start_factor, starting_values,
    unloaded,
};
use crate::outcome::{Breakdown, Hooks, Record, Stop};
use crate::prepared::Prepared;
use crate::settings::Settings;

/// The forcing term of the inexact Newton step (Dembo, Eisenstat & Steihaug 1982) as a fraction
/// of the convergence tolerance: a step is refined until ‖Jδ + R‖ ≤ 10⁻³ tol ‖R‖, an error that
/// none of the iteration's decisions can see.
const FORCING: f64 = 1e-3;

/// Full steps the watchdog takes without a sufficient decrease of ‖R̂‖ before it returns to its
/// checkpoint (the window of Grippo, Lampariello & Lucidi's non-monotone rule, 10).
const WINDOW: usize = 10;

/// Halvings of the step at most in the line search.
const MAX_HALVINGS: usize = 12;

/// Sufficient decrease of ‖R‖ per unit step length (Armijo).
const ARMIJO: f64 = 1e-4;

/// The state of one Newton run.
pub(super) struct Run<'s, 'a> {
    system: &'s System<'a>,
    scale: &'s [f64],
    pub(super) tau: Vec<f64>,
    pub(super) state: Evaluation,
    pub(super) history: Vec<Record>,
    /// The last body that a step found pulled away from its partners (see [`Run::watch`]).
    pulled: Option<usize>,
    /// What the steps keep for the next.
    caches: Caches,
    /// The tangential displacements of the state the last step started from (empty before the
    /// first step): [`crate::contact::Interface::hold_reversals`] compares the slip directions
    /// with them.
    previous_g: Vec<f64>,
    /// Whether the problem has no data ([`unloaded`]).
    unloaded: bool,
}

/// The watchdog's reference: the last state whose ‖R̂‖ a step decreased enough, with the closed
/// set, kernel and Newton step taken from it.
struct Checkpoint {
    tau: Vec<f64>,
    state: Evaluation,
    /// ‖R̂‖ there, the value that full steps must fall below.
    merit: f64,
    chi: Vec<bool>,
    status: Vec<Status>,
    z: Vec<Vec<f64>>,
    delta: Vec<f64>,
    /// Full steps taken since without that decrease.
    steps: usize,
}

/// One iteration's move: the step length, the closed set and Newton step it went along, and the
/// state it reached.
struct Step {
    alpha: f64,
    chi: Vec<bool>,
    status: Vec<Status>,
    delta: Vec<f64>,
    next: Evaluation,
}

impl<'s, 'a> Run<'s, 'a> {
    /// Starts from the interface loads `warm`, or else from the paper's initial value u⁰ on
    /// every contact point.
    pub(super) fn new(
        system: &'s System<'a>,
        prepared: &'s Prepared,
        warm: Option<&[f64]>,
        settings: &Settings,
    ) -> Self {
        let mut t = vec![0.0; system.len()];
        let response = free_response_scale(prepared);
        let u0 = settings.u0 * start_factor(response, system.interface, settings);
        for (b, body) in system.bodies.iter().enumerate() {
            let range = system.range(b);
            match (warm, body) {
                (Some(warm), _) => t[range.clone()].copy_from_slice(&warm[range]),
                // Where the penalty problem has one solution, a sparse body starts unloaded:
                // its load for u⁰ takes conjugate gradients that cost more than a Newton step.
                (None, Some(body)) if body.sparse().is_some() && system.variational => {}
                (None, Some(body)) => {
                    let u0 = starting_values(system.interface, range.clone(), u0);
                    t[range].copy_from_slice(&body.initial_load(&u0))
                }
                (None, None) => {}
            }
        }
        if warm.is_none() {
            share_slices(system.exchange, &system.interface.body_range, &mut t);
        }
        let mut tau: Vec<f64> = t
            .iter()
            .zip(&system.d0)
            .map(|(t, &d)| if d > 0.0 { t / d } else { 0.0 })
            .collect();
        if warm.is_none() {
            unload_unbounded(system, &prepared.scale, &mut tau);
        }
        let state = system.evaluate(&tau);
        Run {
            system,
            scale: &prepared.scale,
            tau,
            state,
            history: Vec::new(),
            pulled: None,
            caches: Caches::default(),
            previous_g: Vec::new(),
            unloaded: unloaded(response, prepared, system.interface),
        }
    }

    pub(super) fn solve(&mut self, settings: &Settings, hooks: Hooks<'_>) -> (Stop, usize) {
        if self.unloaded {
            return self.zero(hooks);
        }
        let mut watchdog: Option<Checkpoint> = None;
        for k in 1..=settings.max_iter {
            if hooks.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return (Stop::Interrupted, k - 1);
            }
            if let Some(b) = self.system.unresisted(&self.state.free) {
                return (self.lost(b, k), k);
            }
            let (chi, mut status) = self.system.jacobian_set(&self.state);
            let held = (self.system.interface).hold_reversals(
                &mut status,
                &self.previous_g,
                &self.state.g,
            );
            let found;
            let free = if chi == self.state.closed && status == self.state.status {
                &self.state.free
            } else {
                found = self.system.free_motions(&chi, &status);
                &found
            };
            let z = self.system.kernel(free);
            let r = self.system.residual(&self.tau, &self.state, &chi, &status);
            let sets = (chi.as_slice(), status.as_slice(), self.state.g.as_slice());
            let forcing = FORCING * settings.tol;
            let Some(delta) = self.system.step(&mut self.caches, sets, &z, &r, forcing) else {
                return (self.failure(k, Breakdown::Singular), k);
            };
            let checkpoint = watchdog.take().unwrap_or_else(|| Checkpoint {
                tau: self.tau.clone(),
                state: self.state.clone(),
                merit: self.system.merit(&z, &self.state),
                chi: chi.clone(),
                status: status.clone(),
                z: z.clone(),
                delta: delta.clone(),
                steps: 0,
            });
            let step = match self.watch(k, checkpoint, (chi, status), &z, delta) {
                Ok((step, kept)) => {
                    watchdog = kept;
                    step
                }
                Err(stop) => return (stop, k),
            };
            let settled = self.settled(&step);
            let record = self.record(k, &step, settled);
            if let Some(f) = hooks.on_iteration {
                f(&record);
            }
            let converged = !held && self.converged(&step, &record, settled, settings.tol);
            self.history.push(record);
            self.tau = self.along(&step.delta, step.alpha);
            self.previous_g = std::mem::replace(&mut self.state, step.next).g;
            if converged {
                return (Stop::Converged, k);
            }
        }
        let k = settings.max_iter;
        match self.system.sliding(&self.state) {
            Some(b) => (diverged(b, k, Breakdown::Slides), k),
            None => (Stop::MaxIterations, k),
        }
    }

    /// The solution of a problem without data ([`unloaded`]): τ = 0 and U = 0 solve it exactly
    /// (every point open or just touching, every residual zero; a floating body that nothing
    /// holds has nothing to move it either). One iteration records it, with a zero residual.
    fn zero(&mut self, hooks: Hooks<'_>) -> (Stop, usize) {
        let n = self.system.len();
        self.tau = vec![0.0; n];
        self.state = self.system.evaluation(&self.tau, vec![0.0; n]);
        let record = Record::unloaded(self.system.bodies.len());
        if let Some(f) = hooks.on_iteration {
            f(&record);
        }
        self.history.push(record);
        (Stop::Converged, 1)
    }

    /// The watchdog's step `k` along `delta` (with closed set `chi` and kernel `z`): the full
    /// step while `checkpoint` allows it, else back to the checkpoint and along its step. Also
    /// returns the checkpoint to keep (`None` once a step decreased its ‖R̂‖ enough: the next
    /// state is the next checkpoint), or the stop when a body is pulled away or the step fails.
    fn watch(
        &mut self,
        k: usize,
        mut checkpoint: Checkpoint,
        (chi, status): (Vec<bool>, Vec<Status>),
        z: &[Vec<f64>],
        delta: Vec<f64>,
    ) -> Result<(Step, Option<Checkpoint>), Stop> {
        let mut full = (checkpoint.steps < WINDOW)
            .then(|| {
                let next = self.along(&delta, 1.0);
                self.system
                    .evaluate_step(&self.caches.applied, &next, &self.state, &delta)
            })
            .filter(|next| self.check(&next.u).is_none());
        // A body that nothing held, and that the step (which closed all its points) leaves held
        // by none again, is pulled away from its partners. Unless the checkpoint holds every
        // body: the glued step can also strand a pressed body while other bodies' closed sets are
        // still wrong (an own-side wall), so the watchdog goes back there; a failure later names
        // the body.
        let pulled = self
            .state
            .stranded
            .filter(|&b| full.as_ref().is_some_and(|next| next.stranded == Some(b)));
        if let Some(body) = pulled {
            if checkpoint.merit.is_infinite() {
                return Err(self.lost(body, k));
            }
            self.pulled = Some(body);
            full = None;
        }
        if let Some(next) = full {
            let kept =
                (!decreases(self.system.merit(z, &next), checkpoint.merit, 1.0)).then(|| {
                    checkpoint.steps += 1;
                    checkpoint
                });
            let step = Step {
                alpha: 1.0,
                chi,
                status,
                delta,
                next,
            };
            return Ok((step, kept));
        }
        // Back to the checkpoint, and along its step as far as its ‖R̂‖ decreases.
        self.tau = checkpoint.tau;
        self.state = checkpoint.state;
        let Some((alpha, next)) =
            self.line_search(&checkpoint.z, &checkpoint.delta, checkpoint.merit)
        else {
            return Err(self.failure(k, Breakdown::NoDescent));
        };
        if let Some((body, reason)) = self.check(&next.u) {
            return Err(diverged(body, k, reason));
        }
        let step = Step {
            alpha,
            chi: checkpoint.chi,
            status: checkpoint.status,
            delta: checkpoint.delta,
            next,
        };
        Ok((step, None))
    }

    /// Whether `step` ends the solve. A full step that leaves the closed set as it was solved the
    /// (then linear) equations: the primal–dual active set method's own stopping rule, confirmed
    /// by the residual (it keeps any part along the kernel). Otherwise the relative change
    /// decides. A floating body that nothing holds has no determined position: never a solution.
    /// `settled`: [`Run::settled`] of `step`.
    fn converged(
        &self,
        step: &Step,
        record: &Record,
        settled: Option<(f64, f64)>,
        tol: f64,
    ) -> bool {
        let exact = settled.is_some_and(|(residual, u)| residual <= tol * u);
        step.alpha == 1.0
            && (exact || record.rel_change.iter().all(|&r| r <= tol))
            && step.next.stranded.is_none()
    }

    /// ‖R̂‖ and ‖U‖ at the step's state where the step left the closed set (and the frictional
    /// points' statuses) as it was (the equations were then linear), `None` otherwise.
    fn settled(&self, step: &Step) -> Option<(f64, f64)> {
        let next = &step.next;
        let same = step.chi == self.state.closed
            && next.closed == step.chi
            && step.status == self.state.status
            && next.status == step.status;
        same.then(|| {
            let residual = norm(&next.scaled_residual(&self.system.rho));
            (residual, norm(&next.u))
        })
    }

    /// τ + α δ.
    fn along(&self, delta: &[f64], alpha: f64) -> Vec<f64> {
        self.tau
            .iter()
            .zip(delta)
            .map(|(t, d)| t + alpha * d)
            .collect()
    }

    /// Backtracks along δ from half a step until ‖R̂‖ falls enough below `merit` (the full step
    /// was tried by the watchdog); the step length and the state there, or `None` when no step
    /// length decreases it.
    fn line_search(&self, z: &[Vec<f64>], delta: &[f64], merit: f64) -> Option<(f64, Evaluation)> {
        let mut alpha = 0.5;
        for _ in 1..=MAX_HALVINGS {
            let eval = self.system.evaluate(&self.along(delta, alpha));
            let f = self.system.merit(z, &eval);
            if decreases(f, merit, alpha) {
                return Some((alpha, eval));
            }
            alpha *= 0.5;
        }
        None
    }

    /// The first body with non-finite normal displacements, or with displacements beyond its
    /// scale along a free rigid motion: only a body that supports do not hold can move without
    /// bound. A held body's displacements are bounded by what its loads, its supports and the
    /// interface loads produce; a large step there (a stiff penalty, an interference fit) is a
    /// step for the watchdog and the line search to judge, not a body that is not held.
    fn check(&self, u: &[f64]) -> Option<(usize, Breakdown)> {
        (0..self.system.bodies.len()).find_map(|b| {
            let v = &u[self.system.range(b)];
            if !v.iter().all(|x| x.is_finite()) {
                Some((b, Breakdown::NonFinite))
            } else if !self.system.mode_range[b].is_empty()
                && v.iter().any(|x| x.abs() > self.scale[b])
            {
                Some((b, Breakdown::Growth))
            } else {
                None
            }
        })
    }

    /// The body that nothing holds in the current state, if any.
    fn stranded(&self) -> Option<usize> {
        self.state.stranded
    }

    /// The stop when nothing holds body `b` at step `k`: with friction, a body that slides is
    /// named as such.
    fn lost(&self, b: usize, k: usize) -> Stop {
        match self.system.sliding(&self.state) {
            Some(s) => diverged(s, k, Breakdown::Slides),
            None => diverged(b, k, Breakdown::LostContact),
        }
    }

    /// The stop when the steps make no progress or J is singular: a body that lost its hold (now,
    /// or at a step the watchdog went back from), or `otherwise`.
    /// A body that slides under friction is named first.
    fn failure(&self, k: usize, otherwise: Breakdown) -> Stop {
        if let Some(b) = self.system.sliding(&self.state) {
            return diverged(b, k, Breakdown::Slides);
        }
        match self.stranded().or(self.pulled) {
            Some(b) => diverged(b, k, Breakdown::LostContact),
            None => diverged(0, k, otherwise),
        }
    }

    fn record(&self, k: usize, step: &Step, settled: Option<(f64, f64)>) -> Record {
        let (interface, next) = (self.system.interface, &step.next);
        let (active, contact_force) = contact_summary(interface, &next.s, self.system.bodies.len());
        let rel_change = relative_change(interface, &next.u, &self.state.u);
        Record {
            k,
            gamma: step.alpha,
            measure: Self::measure(settled, &rel_change),
            rel_change,
            active,
            contact_force,
        }
    }

    /// What [`Run::converged`] compares with the tolerance: the relative residual ‖R̂‖/‖U‖ where
    /// the step left the closed set as it was, or the largest relative change if that is smaller.
    fn measure(settled: Option<(f64, f64)>, rel_change: &[f64]) -> f64 {
        let change = largest(rel_change.iter().copied());
        match settled {
            None => change,
            Some((residual, u)) => {
                let relative = if residual == 0.0 { 0.0 } else { residual / u };
                relative.min(change)
            }
        }
    }
}

/// The stop of a solve that broke down at iteration `k` because of `body`.
fn diverged(body: usize, k: usize, reason: Breakdown) -> Stop {
    Stop::Diverged {
        body,
        iteration: k,
        reason,
    }
}

/// Whether ‖R̂‖ = `f` after a step of length `alpha` falls enough below `reference` (Armijo); a
/// state that nothing holds (infinite ‖R̂‖) never does.
fn decreases(f: f64, reference: f64, alpha: f64) -> bool {
    f.is_finite() && f <= (1.0 - ARMIJO * alpha) * reference
}

/// Starts every body whose starting interface loads `tau` (displacement units) exceed its
/// blow-up size `scale` unloaded. The paper's u⁰ gives each body the load that moves all its
/// contact points by u⁰; where a support holds a point's direction (the tangential unknown of a
/// point on a symmetry line) no load moves it, that solve is singular, and rounding leaves loads
/// of 1e17 and more along the held direction. They move nothing, but the first Newton step has
/// to cancel them, and the rounding of that cancellation is larger than the solution.
fn unload_unbounded(system: &System<'_>, scale: &[f64], tau: &mut [f64]) {
    for (b, &limit) in scale.iter().enumerate() {
        let range = system.range(b);
        if tau[range.clone()]
            .iter()
            .any(|t| !t.is_finite() || t.abs() > limit)
        {
            tau[range].iter_mut().for_each(|t| *t = 0.0);
        }
    }
}
