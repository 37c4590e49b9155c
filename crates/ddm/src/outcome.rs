//! What an interface iteration reports: a record per iteration, how it stopped, and its final
//! interface state; and the callbacks a caller hands it.

use std::sync::atomic::AtomicBool;

/// Why a body's Robin solve failed.
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
    /// The interface Newton steps no longer reduce the residual.
    NoDescent,
    /// The loads push the body along a motion harder than friction can hold it: it slides.
    Slides,
}

/// What happened in one iteration.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Record {
    /// Iteration number k (1-based: the record of the k-th solve).
    pub k: usize,
    /// The Robin sweeps: γ^k used. The interface Newton method: the step length α.
    pub gamma: f64,
    /// What the iteration's stopping test compares with the tolerance after this iteration
    /// ([`crate::settings::Settings::measure_name`]): the largest relative change of a body for
    /// the sweeps (scaled as the test scales it), the relative residual of the Newton method.
    pub measure: f64,
    /// ‖u^{k}_n − u^{k−1}_n‖ / ‖u^{k}_n‖ per body.
    pub rel_change: Vec<f64>,
    /// Number of penetrating (closed) contact points per body after the update.
    pub active: Vec<usize>,
    /// Total normal contact force Σ w |σ_n| per body after the update.
    pub contact_force: Vec<f64>,
}

impl Record {
    /// The one record of a problem without data, solved at once by zero interface loads: every
    /// change, closed count and force zero over `bodies` bodies.
    pub(crate) fn unloaded(bodies: usize) -> Record {
        Record {
            k: 1,
            gamma: 1.0,
            measure: 0.0,
            rel_change: vec![0.0; bodies],
            active: vec![0; bodies],
            contact_force: vec![0.0; bodies],
        }
    }
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
    /// The iteration met its tolerance, but a body's applied loads, contact forces and support
    /// reactions do not balance (set by [`crate::solver::solve`] from [`crate::force_balance`]).
    Unbalanced {
        /// The body out of balance (the worst one); `None`: every body balances, but the
        /// problem's loads and reactions do not.
        body: Option<usize>,
        /// Its net force and moment, relative to the largest force total of a body (for the
        /// problem: relative to the sum of the bodies' load and reaction magnitudes).
        imbalance: f64,
        /// The rounding its reactions can carry, on the same scale.
        floor: f64,
        /// Its largest displacement over its size.
        motion: f64,
        /// The tolerance the imbalance exceeds.
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
