//! The domain decomposition iteration (docs/method.md §3) on the condensed bodies.
//!
//! The iterate lives on the interface: the normal displacements U of all contact points, plus the
//! interface loads T that reproduce the full fields at the end. One iteration is one parallel
//! [`RobinSweep`] (every body solves its Robin problem against its partners' last state),
//! optionally preceded by the rigid-body `Coarse` correction, followed by one of two updates:
//!
//! - **relaxation** (the paper's iteration): U^{k+1} = γ^k Ũ + (1 − γ^k) U^k, with a constant γ
//!   or Aitken's `auto` ([`Relaxation`]); it stops when every body's relative change
//!   ‖U^{k+1} − U^k‖/‖U^{k+1}‖ is below the tolerance;
//! - **Anderson acceleration** ([`Anderson`]) over the whole interface vector; it stops when every
//!   body's relative residual ‖Ũ − U^k‖/‖Ũ‖ of the map is below the tolerance, and the result is
//!   the map's output Ũ.
//!
//! `docs/two-level.md` describes the accelerated two-level iteration, the default.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use crate::anderson::Anderson;
pub use crate::coarse::CoarseMode;
use crate::contact::{Interface, Role};
use crate::exchange::share_slices;
use crate::method::Method;
use crate::relaxation::{Gamma, Relaxation};
pub use crate::robin_sweep::Breakdown;
use crate::robin_sweep::RobinSweep;
use crate::solver::Prepared;
use crate::sweep_sharing::{BodyChecks, BodySums, Sharing};

/// How the iterates of the Robin sweeps are combined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accelerator {
    /// Relaxation with γ only (the paper's iteration).
    None,
    /// Anderson acceleration (IQN-ILS) with at most `depth` secant pairs.
    Anderson {
        /// Memory: the number of secant pairs kept.
        depth: usize,
    },
    /// The interface semismooth Newton method of [`crate::newton`] (the method and γ are unused).
    Newton,
}

impl std::fmt::Display for Accelerator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Accelerator::None => f.write_str("none"),
            Accelerator::Anderson { depth } => write!(f, "anderson({depth})"),
            Accelerator::Newton => f.write_str("newton"),
        }
    }
}

/// Default Anderson memory: enough to act as GMRES over the few tens of iterations the two-level
/// iteration takes, small against any interface.
pub const ANDERSON_DEPTH: usize = 40;

/// Default largest equilibrium residual of a converged result: 1 % of the total contact force.
/// The relative-change test bounds the last step, not the remaining error; converged solves of
/// slowly contracting problems carry residuals up to about 1e−3 at tol = 1e−6, while an iteration
/// stopped far from its fixed point (a tiny γ) is off by tens of percent.
pub const EQUILIBRIUM_TOL: f64 = 1e-2;

/// Settings of one DD solve.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Robin coefficient rule.
    pub method: Method,
    /// Relaxation parameter γ (with Anderson: the relaxation of the first step).
    pub gamma: Gamma,
    /// How the sweeps' outputs are combined.
    pub accelerator: Accelerator,
    /// Which bodies the rigid-body coarse correction moves into balance before every sweep.
    pub coarse: CoarseMode,
    /// Stopping tolerance on every body's relative change (relaxation) or residual (Anderson).
    pub tol: f64,
    /// Largest equilibrium residual (relative to the total contact force) a converged result may
    /// have; above it the solve reports [`Stop::Stalled`].
    pub equilibrium_tol: f64,
    /// Iteration cap.
    pub max_iter: usize,
    /// Initial normal displacement u^0_n on all contact points.
    pub u0: f64,
    /// Initial u^{−1}_n (two-point methods).
    pub u_prev: f64,
    /// Augmented Lagrangian pairs: the largest violation of the Signorini conditions (a length)
    /// of a converged result; `None`: `tol` times the largest normal displacement of the contact
    /// points ([`crate::augmented`]).
    pub gap_tol: Option<f64>,
    /// Augmented Lagrangian pairs: the cap on multiplier updates (inner solves).
    pub max_updates: usize,
    /// How the bodies are condensed on their contact points; read by the callers of
    /// [`crate::solver::prepare_with`] (the iteration itself works on either path).
    pub condensation: crate::condensed::Condensation,
}

impl Settings {
    /// The paper's iteration: `method` with a relaxation rule `gamma`, no accelerator, no coarse
    /// correction, the other values as in [`Settings::default`].
    pub fn paper(method: Method, gamma: Gamma) -> Settings {
        Settings {
            method,
            gamma,
            accelerator: Accelerator::None,
            coarse: CoarseMode::Off,
            ..Settings::default()
        }
    }
}

impl Settings {
    /// Anderson acceleration of `active-set` sweeps (γ = 1 for the first step) without coarse
    /// correction; the other values as in [`Settings::default`].
    pub fn anderson() -> Settings {
        Settings {
            method: Method::ActiveSet,
            gamma: Gamma::Constant(1.0),
            accelerator: Accelerator::Anderson {
                depth: ANDERSON_DEPTH,
            },
            coarse: CoarseMode::Off,
            ..Settings::default()
        }
    }
}

impl Settings {
    /// The two-level sweeps: `newton-kurchatov` Robin sweeps with Aitken's `auto` relaxation and
    /// the rigid-body coarse correction of chains of floating bodies; the other values as in
    /// [`Settings::default`].
    pub fn two_level() -> Settings {
        Settings {
            method: Method::NewtonKurchatov,
            gamma: Gamma::Auto,
            accelerator: Accelerator::None,
            coarse: CoarseMode::Chains,
            ..Settings::default()
        }
    }

    /// Called when a Robin rule (a method or γ) is asked for without an accelerator: the
    /// interface Newton method uses neither, so it gives way to the two-level sweeps.
    pub fn use_sweeps(&mut self) {
        if self.accelerator == Accelerator::Newton {
            self.accelerator = Accelerator::None;
            self.coarse = CoarseMode::Chains;
        }
    }

    /// The iteration in words: `interface newton`, or the method and γ rule, with the accelerator
    /// and coarse mode when used.
    pub fn scheme(&self) -> String {
        if self.accelerator == Accelerator::Newton {
            return "interface newton".into();
        }
        let mut text = format!("{}, gamma {}", self.method, self.gamma);
        if self.accelerator != Accelerator::None {
            text += &format!(", accelerator {}", self.accelerator);
        }
        if self.coarse != CoarseMode::Off {
            text += &format!(", coarse {}", self.coarse);
        }
        text
    }
}

impl Default for Settings {
    /// The interface Newton method ([`crate::newton`]); tolerance 1e−6; the paper's initial
    /// values u^0 = 1e−4, u^{−1} = 2e−4. The method and γ (`newton-kurchatov`, `auto`) are those of
    /// the sweeps a caller switches to with [`Settings::use_sweeps`].
    fn default() -> Settings {
        Settings {
            method: Method::NewtonKurchatov,
            gamma: Gamma::Auto,
            accelerator: Accelerator::Newton,
            coarse: CoarseMode::Off,
            tol: 1e-6,
            equilibrium_tol: EQUILIBRIUM_TOL,
            max_iter: 500,
            u0: 1e-4,
            u_prev: 2e-4,
            gap_tol: None,
            max_updates: 100,
            condensation: crate::condensed::Condensation::Auto,
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
    /// The multiplier updates of an augmented Lagrangian pair ended (cap, no more progress, or a
    /// failed inner solve) before the Signorini conditions held to the gap tolerance; the
    /// result is the converged inner solve closest to them.
    Unenforced {
        /// Multiplier updates taken.
        updates: usize,
        /// The result's largest violation of the Signorini conditions (length).
        violation: f64,
        /// The gap tolerance it exceeds.
        limit: f64,
    },
    /// The change met the tolerance, but the result is out of equilibrium (set by
    /// [`crate::solver::solve`], never by the iteration itself).
    Stalled {
        /// The largest equilibrium residual of a body.
        residual: f64,
        /// The tolerance it exceeds.
        limit: f64,
    },
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

/// The interface state: U^{k−1}, U^k, their pair sums, and the loads T^k.
struct State {
    u_prev: Vec<f64>,
    u: Vec<f64>,
    s_prev: Vec<f64>,
    s: Vec<f64>,
    t: Vec<f64>,
}

impl State {
    /// The initial values u^0, u^{−1} and the loads T^0 that reproduce u^0.
    fn initial(prepared: &Prepared, interface: &Interface, settings: &Settings) -> State {
        let m = interface.len();
        let (mut t, mut u) = (vec![0.0; m], vec![0.0; m]);
        for (b, body) in prepared.bodies.iter().enumerate() {
            let Some(body) = body else { continue };
            let range = interface.body_range[b].clone();
            let u0 = starting_values(interface, range.clone(), settings.u0);
            let (u_b, t_b) = body.initial_state(&u0);
            t[range.clone()].copy_from_slice(&t_b);
            u[range].copy_from_slice(&u_b);
        }
        share_slices(&*prepared.exchange, &interface.body_range, &mut t);
        share_slices(&*prepared.exchange, &interface.body_range, &mut u);
        let mut state = State {
            u_prev: starting_values(interface, 0..m, settings.u_prev),
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

/// The starting value `value` of the normal displacements of the points in `range`, and 0 for the
/// tangential unknowns of balanced pairs (the paper's u⁰ is a normal approach).
pub(crate) fn starting_values(interface: &Interface, range: Range<usize>, value: f64) -> Vec<f64> {
    interface.points[range]
        .iter()
        .map(|p| if p.is_contact() { value } else { 0.0 })
        .collect()
}

/// Per body: ‖a − b‖/‖a‖ over its points (‖a − b‖ if a = 0).
pub(crate) fn relative_change(interface: &Interface, a: &[f64], b: &[f64]) -> Vec<f64> {
    interface
        .body_range
        .iter()
        .map(|range| body_change(range.clone(), a, b))
        .collect()
}

/// ‖a − b‖/‖a‖ over the points `range` (‖a − b‖ if a = 0).
pub(crate) fn body_change(range: Range<usize>, a: &[f64], b: &[f64]) -> f64 {
    let (mut diff, mut norm) = (0.0, 0.0);
    for j in range {
        diff += (a[j] - b[j]).powi(2);
        norm += a[j] * a[j];
    }
    if norm > 0.0 {
        (diff / norm).sqrt()
    } else {
        diff.sqrt()
    }
}

/// Why a body's sweep, with its new values `v`, broke down: its own failure, non-finite values,
/// or values beyond the body's `scale`.
pub(crate) fn body_breakdown(
    swept: Result<(), Breakdown>,
    v: &[f64],
    scale: f64,
) -> Option<Breakdown> {
    match swept {
        Err(reason) => Some(reason),
        Ok(()) if !v.iter().all(|x| x.is_finite()) => Some(Breakdown::NonFinite),
        Ok(()) if v.iter().any(|x| x.abs() > scale) => Some(Breakdown::Growth),
        Ok(()) => None,
    }
}

/// Closed points and total normal contact force Σ w |σ_n| per body for the pair sums `s` (on the
/// following side of a balanced pair, Σ |F| of its nodal forces).
pub(crate) fn contact_summary(
    interface: &Interface,
    s: &[f64],
    nb: usize,
) -> (Vec<usize>, Vec<f64>) {
    (0..nb).map(|b| body_contact(interface, s, b)).unzip()
}

/// Closed points and total normal contact force of body `b` (see [`contact_summary`]).
pub(crate) fn body_contact(interface: &Interface, s: &[f64], b: usize) -> (usize, f64) {
    let (mut active, mut force) = (0usize, 0.0);
    for j in interface.body_range[b].clone() {
        let p = &interface.points[j];
        if p.overlap(s[j]) < 0.0 {
            active += 1;
        }
        if p.carries() && p.overlap(s[j]) < 0.0 {
            force -= p.weight * p.pressure(s[j]);
        } else if p.role == Role::Follower {
            force += interface.force(j, s).abs();
        }
    }
    (active, force)
}

/// How the sweeps' outputs become the next state.
enum Update {
    Relax(Relaxation),
    Anderson {
        memory: Anderson,
        /// γ of the first step (and of steps without secant pairs).
        first_gamma: f64,
    },
}

/// Interface-sized work buffers of one solve.
struct Buffers {
    /// The sweep's outputs Ũ and T̃.
    tilde: Vec<f64>,
    t_tilde: Vec<f64>,
    /// The proposed next state and its pair sums.
    next: Vec<f64>,
    s_next: Vec<f64>,
    /// The state before the coarse correction.
    input: Vec<f64>,
    input_t: Vec<f64>,
}

impl Update {
    fn new(settings: &Settings) -> Update {
        match settings.accelerator {
            Accelerator::None | Accelerator::Newton => {
                Update::Relax(Relaxation::new(settings.gamma))
            }
            Accelerator::Anderson { depth } => Update::Anderson {
                memory: Anderson::new(depth),
                first_gamma: match settings.gamma {
                    Gamma::Constant(g) => g,
                    Gamma::Auto => 1.0,
                },
            },
        }
    }

    /// Proposes the next normal displacements in `buf.next` (relaxed, or the sweep's output for
    /// Anderson, whose stopping test is on the unrelaxed residual); returns the γ used.
    fn propose(&self, u: &[f64], buf: &mut Buffers) -> f64 {
        match self {
            Update::Relax(relax) => {
                let gamma = relax.gamma();
                for j in 0..u.len() {
                    buf.next[j] = gamma * buf.tilde[j] + (1.0 - gamma) * u[j];
                }
                gamma
            }
            Update::Anderson { .. } => {
                buf.next.copy_from_slice(&buf.tilde);
                1.0
            }
        }
    }

    /// The stopping test on the record's relative changes.
    fn converged(&self, record: &Record, tol: f64) -> bool {
        // With an adaptive γ a tiny step must not pass for convergence: the change is judged as
        // if γ were at least the starting value (for a constant γ this is the paper's criterion).
        let scale = match self {
            Update::Relax(relax) => relax.convergence_scale(),
            Update::Anderson { .. } => 1.0,
        };
        record.rel_change.iter().all(|&r| r * scale <= tol)
    }

    /// Makes `buf.next` and `t` the next state (Anderson: from the accelerated combination unless
    /// the iteration has converged, when the sweep's output is the result). Returns false if
    /// `buf.next` is no longer the proposed state.
    fn commit(
        &mut self,
        gamma: f64,
        converged: bool,
        u: &[f64],
        t: &mut [f64],
        buf: &mut Buffers,
        sums: &BodySums<'_>,
    ) -> bool {
        match self {
            Update::Relax(relax) => {
                relax.update(u, &buf.next, &sums.own, &|own| sums.total(own));
                for j in 0..t.len() {
                    t[j] = gamma * buf.t_tilde[j] + (1.0 - gamma) * t[j];
                }
                true
            }
            Update::Anderson { .. } if converged => {
                t.copy_from_slice(&buf.t_tilde);
                true
            }
            Update::Anderson {
                memory,
                first_gamma,
            } => {
                buf.next.copy_from_slice(&buf.input);
                t.copy_from_slice(&buf.input_t);
                memory.advance(&mut buf.next, t, &buf.tilde, &buf.t_tilde, *first_gamma);
                false
            }
        }
    }
}

/// Runs the iteration on a prepared model.
pub fn iterate(prepared: &Prepared, settings: &Settings, hooks: Hooks<'_>) -> Outcome {
    iterate_on(prepared, &prepared.interface, None, settings, hooks)
}

/// Runs the iteration on a prepared model with the contact points `interface` (the prepared
/// ones, or a copy with other multipliers: [`crate::augmented`]). The interface Newton method
/// starts from the interface loads `warm` when given (a previous outcome's `t_load`); the sweeps
/// always start from the paper's initial values.
pub fn iterate_on(
    prepared: &Prepared,
    interface: &Interface,
    warm: Option<&[f64]>,
    settings: &Settings,
    hooks: Hooks<'_>,
) -> Outcome {
    if settings.accelerator == Accelerator::Newton {
        return crate::newton::iterate(prepared, interface, warm, settings, hooks);
    }
    sweeps(prepared, interface, settings, hooks)
}

/// The Robin sweeps, relaxed or accelerated.
fn sweeps(
    prepared: &Prepared,
    interface: &Interface,
    settings: &Settings,
    hooks: Hooks<'_>,
) -> Outcome {
    let start = Instant::now();
    let (m, exchange) = (interface.len(), &*prepared.exchange);
    let ranges = &interface.body_range;
    let accelerated = settings.accelerator != Accelerator::None;
    let mut sweep = RobinSweep::new(interface, &prepared.bodies, settings.method, accelerated);
    let sharing = Sharing::new(settings, exchange, interface);
    let sums = BodySums::new(exchange, ranges);
    let mut update = Update::new(settings);
    let mut state = State::initial(prepared, interface, settings);
    let mut buf = Buffers {
        tilde: vec![0.0; m],
        t_tilde: vec![0.0; m],
        next: vec![0.0; m],
        s_next: vec![0.0; m],
        input: vec![0.0; m],
        input_t: vec![0.0; m],
    };
    let mut history = Vec::new();
    let mut stop = Stop::MaxIterations;
    let mut iterations = 0;

    for k in 1..=settings.max_iter {
        if hooks.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            stop = Stop::Interrupted;
            break;
        }
        iterations = k;
        buf.input.copy_from_slice(&state.u);
        buf.input_t.copy_from_slice(&state.t);
        if settings.coarse != CoarseMode::Off {
            let (u, t) = (&mut state.u, &mut state.t);
            prepared
                .coarse
                .correct(settings.coarse, interface, exchange, u, t);
            interface.sum_normal(&state.u, &mut state.s);
        }
        let swept = sweep.apply(
            &state.u,
            &state.s,
            &state.s_prev,
            &mut buf.tilde,
            &mut buf.t_tilde,
        );
        let swept = sharing.outputs(exchange, ranges, &mut buf.tilde, &mut buf.t_tilde, swept);
        let gamma = update.propose(&state.u, &mut buf);
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
            if let Update::Relax(relax) = &mut update {
                if relax.restart() {
                    // Start over from the initial values with a smaller γ cap.
                    state = State::initial(prepared, interface, settings);
                    continue;
                }
            }
            stop = Stop::Diverged {
                body,
                iteration: k,
                reason,
            };
            break;
        }
        let record = Record {
            k,
            gamma,
            rel_change: checks.rel_change,
            active: checks.active,
            contact_force: checks.contact_force,
        };
        if let Some(f) = hooks.on_iteration {
            f(&record);
        }
        let converged = update.converged(&record, settings.tol);
        if !update.commit(gamma, converged, &state.u, &mut state.t, &mut buf, &sums) {
            interface.sum_normal(&buf.next, &mut buf.s_next);
        }
        history.push(record);
        state.advance(&mut buf.next, &mut buf.s_next);
        if converged {
            stop = Stop::Converged;
            break;
        }
    }
    // The result holds every body's values on every process.
    sharing.everywhere(exchange, ranges, &mut state.u);
    sharing.everywhere(exchange, ranges, &mut state.t);
    Outcome {
        stop,
        iterations,
        un: state.u,
        t_load: state.t,
        history,
        seconds: start.elapsed().as_secs_f64(),
    }
}
