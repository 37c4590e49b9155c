//! The Robin sweeps: the paper's domain decomposition iteration (docs/method.md §3) on the
//! condensed bodies.
//!
//! The iterate lives on the interface: the normal displacements U of all contact points, plus the
//! interface loads T that reproduce the full fields at the end. One iteration is one parallel
//! [`RobinSweep`] (every body solves its Robin problem against its partners' last state),
//! optionally preceded by the rigid-body `Coarse` correction, followed by one of two updates:
//!
//! - **relaxation** (the paper's iteration): U^{k+1} = γ^k Ũ + (1 − γ^k) U^k, with a
//!   constant γ or Aitken's `auto` ([`crate::relaxation::Relaxation`]); it stops when every
//!   body's relative change ‖U^{k+1} − U^k‖/‖U^{k+1}‖ is below the tolerance;
//! - **Anderson acceleration** (`crate::anderson`) over the whole interface vector; it stops
//!   when every body's relative residual ‖Ũ − U^k‖/‖Ũ‖ of the map is below the tolerance, and
//!   the result is the map's output Ũ.
//!
//! `docs/two-level.md` describes the accelerated two-level iteration.

mod guard;
mod ranks;
pub mod robin;
mod update;

use std::sync::atomic::Ordering;
use std::time::Instant;

use crate::coarse::CoarseMode;
use crate::contact::Interface;
use crate::exchange::share_slices;
use crate::iteration::Iteration;
use crate::measures::{free_response_scale, start_factor, starting_values, unloaded};
use crate::outcome::{Hooks, Outcome, Record, Stop};
use crate::prepared::Prepared;
use crate::settings::Settings;
use ranks::{BodyChecks, BodySums, Sharing};
pub use robin::RobinSweep;
use update::{Buffers, Update};

/// The Robin sweeps with the method, γ rule, accelerator (none: the paper's relaxation, or
/// Anderson) and coarse mode of the settings.
pub struct Sweeps<'s>(pub &'s Settings);

impl Iteration for Sweeps<'_> {
    /// The sweeps always start from the paper's initial values; `warm` is not used.
    fn run(
        &self,
        prepared: &Prepared,
        interface: &Interface,
        _warm: Option<&[f64]>,
        hooks: Hooks<'_>,
    ) -> Outcome {
        run(prepared, interface, self.0, hooks)
    }
}

/// The interface state: U^{k−1}, U^k, their pair sums, and the loads T^k.
struct State {
    u_prev: Vec<f64>,
    u: Vec<f64>,
    s_prev: Vec<f64>,
    s: Vec<f64>,
    t: Vec<f64>,
}

impl State {
    /// The initial values u^0, u^{−1} (the settings' times `factor`, [`start_factor`]) and the
    /// loads T^0 that reproduce u^0.
    fn initial(
        prepared: &Prepared,
        interface: &Interface,
        settings: &Settings,
        factor: f64,
    ) -> State {
        let m = interface.len();
        let (mut t, mut u) = (vec![0.0; m], vec![0.0; m]);
        for (b, body) in prepared.bodies.iter().enumerate() {
            let Some(body) = body else { continue };
            let range = interface.body_range[b].clone();
            let u0 = starting_values(interface, range.clone(), factor * settings.u0);
            let (u_b, t_b) = body.initial_state(&u0);
            t[range.clone()].copy_from_slice(&t_b);
            u[range].copy_from_slice(&u_b);
        }
        share_slices(&*prepared.exchange, &interface.body_range, &mut t);
        share_slices(&*prepared.exchange, &interface.body_range, &mut u);
        let mut state = State {
            u_prev: starting_values(interface, 0..m, factor * settings.u_prev),
            u,
            s_prev: vec![0.0; m],
            s: vec![0.0; m],
            t,
        };
        interface.sum_normal(&state.u_prev, &mut state.s_prev);
        interface.sum_normal(&state.u, &mut state.s);
        state
    }

    /// Makes `u`, with its pair sums `s`, the new current state: k−1 ← k ← new.
    fn advance(&mut self, u: &mut Vec<f64>, s: &mut Vec<f64>) {
        std::mem::swap(&mut self.u_prev, &mut self.u);
        std::mem::swap(&mut self.u, u);
        std::mem::swap(&mut self.s_prev, &mut self.s);
        std::mem::swap(&mut self.s, s);
    }
}

/// One solve's sweeps: the map, how its outputs travel, the update and the state.
struct Run<'a> {
    prepared: &'a Prepared,
    interface: &'a Interface,
    settings: &'a Settings,
    sweep: RobinSweep<'a>,
    sharing: Sharing,
    sums: BodySums<'a>,
    update: Update,
    state: State,
    /// The factor on the starting values, for a restart.
    start: f64,
    buf: Buffers,
    /// The coarse mode in use: the settings', until the guard switches it off.
    coarse: CoarseMode,
    /// The size of the last sweep's unrelaxed update ‖Ũ − U‖, while the guard watches.
    last_update: Option<f64>,
}

/// What one sweep and its update came to.
enum Swept {
    /// A body broke down and the relaxation starts over with a smaller γ cap.
    Restart,
    /// A body broke down for good.
    Stop(Stop),
    /// The iteration's record, and whether it met the tolerance.
    Done(Record, bool),
}

impl<'a> Run<'a> {
    /// `start`: the factor on the starting values ([`start_factor`]).
    fn new(
        prepared: &'a Prepared,
        interface: &'a Interface,
        settings: &'a Settings,
        start: f64,
    ) -> Self {
        let exchange = &*prepared.exchange;
        let accelerated = settings.accelerator != crate::settings::Accelerator::None;
        Run {
            prepared,
            interface,
            settings,
            sweep: RobinSweep::new(interface, &prepared.bodies, settings.method, accelerated),
            sharing: Sharing::new(settings, exchange, interface),
            sums: BodySums::new(exchange, &interface.body_range),
            update: Update::new(settings),
            state: State::initial(prepared, interface, settings, start),
            start,
            buf: Buffers::new(interface.len()),
            coarse: settings.coarse,
            last_update: None,
        }
    }

    /// Iteration k: the coarse correction, the sweep, the update and its checks.
    fn iteration(&mut self, k: usize) -> Swept {
        let (prepared, interface, settings) = (self.prepared, self.interface, self.settings);
        let exchange = &*prepared.exchange;
        let (state, buf) = (&mut self.state, &mut self.buf);
        buf.input.copy_from_slice(&state.u);
        buf.input_t.copy_from_slice(&state.t);
        let mut corrected = false;
        if self.coarse != CoarseMode::Off {
            let (u, t) = (&mut state.u, &mut state.t);
            corrected = prepared
                .coarse
                .correct(self.coarse, interface, exchange, u, t)
                > 0;
            interface.sum_normal(&state.u, &mut state.s);
        }
        let swept = self.sweep();
        let swept = match self.guarded() {
            true => self.guard(swept, corrected),
            false => swept,
        };
        let (state, buf) = (&mut self.state, &mut self.buf);
        let gamma = self.update.propose(&state.u, buf);
        interface.sum_normal(&buf.next, &mut buf.s_next);
        let (next, before) = (&buf.next, &buf.input);
        let checks = BodyChecks::new(
            interface,
            exchange,
            swept,
            &prepared.scale,
            next,
            before,
            &buf.s_next,
        );
        if let Some((body, reason)) = checks.breakdown {
            if let Update::Relax(relax) = &mut self.update {
                if relax.restart() {
                    // Start over from the initial values with a smaller γ cap.
                    self.state = State::initial(prepared, interface, settings, self.start);
                    self.last_update = None;
                    return Swept::Restart;
                }
            }
            let iteration = k;
            return Swept::Stop(Stop::Diverged {
                body,
                iteration,
                reason,
            });
        }
        let record = Record {
            k,
            gamma,
            measure: self.update.measure(&checks.rel_change),
            rel_change: checks.rel_change,
            active: checks.active,
            contact_force: checks.contact_force,
        };
        let converged = self.update.converged(&record, settings.tol);
        Swept::Done(record, converged)
    }

    /// Makes the proposed state the next one.
    fn commit(&mut self, gamma: f64, converged: bool) {
        let (state, buf) = (&mut self.state, &mut self.buf);
        if !(self.update).commit(gamma, converged, &state.u, &mut state.t, buf, &self.sums) {
            self.interface.sum_normal(&buf.next, &mut buf.s_next);
        }
        state.advance(&mut buf.next, &mut buf.s_next);
    }
}

/// The Robin sweeps, relaxed or accelerated as `settings` say.
fn run(
    prepared: &Prepared,
    interface: &Interface,
    settings: &Settings,
    hooks: Hooks<'_>,
) -> Outcome {
    let start = Instant::now();
    let response = free_response_scale(prepared);
    if unloaded(response, prepared, interface) {
        return unloaded_outcome(interface, hooks, start);
    }
    let factor = start_factor(response, interface, settings);
    let mut run = Run::new(prepared, interface, settings, factor);
    let mut history = Vec::new();
    let mut stop = Stop::MaxIterations;
    let mut iterations = 0;
    for k in 1..=settings.max_iter {
        if hooks.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            stop = Stop::Interrupted;
            break;
        }
        iterations = k;
        let (record, converged) = match run.iteration(k) {
            Swept::Restart => continue,
            Swept::Stop(s) => {
                stop = s;
                break;
            }
            Swept::Done(record, converged) => (record, converged),
        };
        if let Some(f) = hooks.on_iteration {
            f(&record);
        }
        run.commit(record.gamma, converged);
        history.push(record);
        if converged {
            stop = Stop::Converged;
            break;
        }
    }
    // The result holds every body's values on every process.
    let (exchange, ranges) = (&*prepared.exchange, &interface.body_range);
    run.sharing.everywhere(exchange, ranges, &mut run.state.u);
    run.sharing.everywhere(exchange, ranges, &mut run.state.t);
    Outcome {
        stop,
        iterations,
        un: run.state.u,
        t_load: run.state.t,
        history,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The outcome of a problem without data ([`unloaded`]): zero displacements and loads at every
/// point solve it exactly, in one recorded iteration. (A sweep from u⁰ = 0 would find no closed
/// point to hold a floating body, and report it lost.)
fn unloaded_outcome(interface: &Interface, hooks: Hooks<'_>, start: Instant) -> Outcome {
    let record = Record::unloaded(interface.body_range.len());
    if let Some(f) = hooks.on_iteration {
        f(&record);
    }
    Outcome {
        stop: Stop::Converged,
        iterations: 1,
        un: vec![0.0; interface.len()],
        t_load: vec![0.0; interface.len()],
        history: vec![record],
        seconds: start.elapsed().as_secs_f64(),
    }
}
