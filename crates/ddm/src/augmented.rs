//! Augmented Lagrangian enforcement: the exact unilateral (Signorini) contact as the limit of
//! penalty solves with multipliers, for any fixed θ (`docs/augmented-lagrangian.md`).
//!
//! Every contact point of a pair with `enforcement = "augmented"` carries a multiplier estimate
//! λ ≥ 0 (a pressure), and the penalty acts on the shifted gap d − θλ, so the pressure is
//! p = (λ + (s − d)/θ)⁺. The inner problem is therefore the penalty problem with other gaps, and
//! any iteration of this crate solves it unchanged. After each inner solve, the Uzawa
//! (Powell–Hestenes) update sets λ to the pressure just found, and the next inner solve starts
//! from the last interface loads. At a fixed point the gap d − s vanishes wherever λ > 0 and is
//! non-negative elsewhere: the Signorini conditions.
//!
//! Stopping: after an inner solve with multipliers λ, every augmented point has the new pressure
//! p and the gap g = d − s. Where p > 0 the exact solution has g = 0, and where p = 0 it has
//! g ≥ 0; the loop stops when the largest violation of either, max(max_{p>0} |g|, max (−g)⁺),
//! is below the gap tolerance (a length: `gap-tol`, or by default `tol` times the largest
//! normal displacement of the contact points). The result is that inner solve: its pressures and
//! fields are consistent with each other, and its multipliers are the reported pressures.

use std::time::Instant;

use crate::anderson::Anderson;
use crate::contact::formulation::Enforcement;
use crate::contact::{Interface, Status};
use crate::iteration::Iteration;
use crate::model::Model;
use crate::outcome::{Hooks, Outcome, Record, Stop};
use crate::prepared::Prepared;
use crate::settings::{Settings, ANDERSON_DEPTH};

/// The default gap tolerance, relative to the largest normal displacement of the contact points.
pub const GAP_TOL: f64 = 1e-6;

/// Updates without coming closer to done (`Update::distance`: a new smallest violation, or
/// pressures that settle further) after which the loop stops: the Signorini conditions cannot be
/// met more closely (with non-matching meshes, both sides' nodes cannot all close exactly).
pub const STALL: usize = 5;

/// The outcome of the multiplier loop.
pub struct Augmented {
    /// The last inner solve; `iterations` and `history` count every inner iteration.
    pub outcome: Outcome,
    /// The contact points with the multipliers of the last inner solve.
    pub interface: Interface,
    /// Multiplier updates (inner solves) taken.
    pub updates: usize,
    /// The gap tolerance used (length).
    pub gap_tol: f64,
}

/// Solves the model's contact problem with augmented Lagrangian enforcement on the pairs that
/// ask for it (the others keep λ = 0, the penalty formulation), by `iteration` for every inner
/// solve; the first inner solve starts from the interface loads `warm` when given. `settings`
/// give the loop's tolerances and cap.
pub fn solve(
    model: &Model,
    prepared: &Prepared,
    iteration: &dyn Iteration,
    settings: &Settings,
    hooks: Hooks<'_>,
    warm: Option<&[f64]>,
) -> Augmented {
    let start = Instant::now();
    let inner = Inner {
        prepared,
        iteration,
        hooks,
    };
    let mut result = update_loop(model, &inner, settings, warm);
    // The iteration's time is the whole loop's, every inner solve included.
    result.outcome.seconds = start.elapsed().as_secs_f64();
    result
}

/// The multiplier updates of [`solve`].
fn update_loop(
    model: &Model,
    inner: &Inner<'_>,
    settings: &Settings,
    warm: Option<&[f64]>,
) -> Augmented {
    let mut interface = inner.prepared.interface.clone();
    let augmented = augmented_points(model, &interface);
    let mut history: Vec<Record> = Vec::new();
    let mut memory = Anderson::new(ANDERSON_DEPTH);
    // The multipliers the points start from: 0, or a load step's frictional points' last ones.
    let mut lambda: Vec<f64> = interface.points.iter().map(|p| p.multiplier).collect();
    let mut warm = warm.map(<[f64]>::to_vec);
    let mut gap_tol = settings.gap_tol.unwrap_or(f64::NAN);
    // The converged inner solve closest to the Signorini conditions so far: what the loop
    // returns when it cannot meet the tolerance.
    let mut best: Option<Best> = None;
    let mut since_best = 0;
    let mut last_distance = f64::INFINITY;
    let mut updates = 0;
    loop {
        updates += 1;
        let outcome = inner.solve(&interface, warm.as_deref(), &mut history);
        if outcome.stop != Stop::Converged {
            return match best {
                Some(b) => b.unenforced(history, updates, gap_tol),
                None => finish(outcome, history, interface, updates, gap_tol),
            };
        }
        if gap_tol.is_nan() {
            gap_tol = default_gap_tol(&outcome.un);
        }
        // G(λ): the pressures of this solve on the augmented points, and how far it is from exact.
        let update = uzawa_update(&interface, &outcome.un, &augmented);
        let slip = friction_update(&interface, &outcome.un, &augmented);
        let distance = distance(&update, &slip, gap_tol, settings.tol);
        if distance <= 1.0 {
            return finish(outcome, history, interface, updates, gap_tol);
        }
        let (next, violation) = (update.multipliers, update.violation);
        let t_load = outcome.t_load.clone();
        if best.as_ref().map_or(true, |b| distance < b.distance) {
            since_best = 0;
            best = Some(Best {
                outcome,
                interface: interface.clone(),
                violation,
                distance,
            });
        } else {
            since_best += 1;
        }
        if since_best >= STALL || updates >= settings.max_updates {
            if let Some(b) = best {
                return b.unenforced(history, updates, gap_tol);
            }
        }
        // Uzawa's λ ← G(λ), accelerated over the earlier updates; the warm start's loads are
        // combined with the same coefficients.
        let mut loads = warm.unwrap_or_else(|| t_load.clone());
        // An update that took the loop further from done spoils Anderson's secant model (an
        // extrapolation across a change of the closed set, or past the clamp λ ≥ 0): start it
        // again from this update.
        if distance > last_distance {
            memory.reset();
        }
        last_distance = distance;
        memory.advance(&mut lambda, &mut loads, &next, &t_load, 1.0);
        set_multipliers(&mut interface, &mut lambda, &augmented);
        slip.apply(&mut interface);
        warm = Some(loads);
    }
}

/// Clamps the multipliers `lambda` to λ ≥ 0 on the augmented points (0 elsewhere) and gives them
/// to the contact points.
fn set_multipliers(interface: &mut Interface, lambda: &mut [f64], augmented: &[Option<f64>]) {
    for (j, p) in interface.points.iter_mut().enumerate() {
        lambda[j] = if augmented[j].is_some() {
            lambda[j].max(0.0)
        } else {
            0.0
        };
        p.multiplier = lambda[j];
    }
}

/// The result of the loop: `outcome` with the whole history.
fn finish(
    mut outcome: Outcome,
    history: Vec<Record>,
    interface: Interface,
    updates: usize,
    gap_tol: f64,
) -> Augmented {
    outcome.iterations = history.len();
    outcome.history = history;
    Augmented {
        outcome,
        interface,
        updates,
        gap_tol,
    }
}

/// A converged inner solve and the contact points it used.
struct Best {
    outcome: Outcome,
    interface: Interface,
    /// Its violation of the Signorini conditions.
    violation: f64,
    /// Its [`Update::distance`] from done.
    distance: f64,
}

impl Best {
    /// The solve returned as [`Stop::Unenforced`] after `updates` updates in all.
    fn unenforced(mut self, history: Vec<Record>, updates: usize, gap_tol: f64) -> Augmented {
        self.outcome.stop = Stop::Unenforced {
            updates,
            violation: self.violation,
            limit: gap_tol,
        };
        finish(self.outcome, history, self.interface, updates, gap_tol)
    }
}

/// The inner solves: one iteration on one prepared model, with the caller's hooks.
struct Inner<'a> {
    prepared: &'a Prepared,
    iteration: &'a dyn Iteration,
    hooks: Hooks<'a>,
}

impl Inner<'_> {
    /// One inner solve, its records numbered on from `history` (and appended to it).
    fn solve(
        &self,
        interface: &Interface,
        warm: Option<&[f64]>,
        history: &mut Vec<Record>,
    ) -> Outcome {
        let (offset, hooks) = (history.len(), self.hooks);
        let renumber = |r: &Record| Record {
            k: r.k + offset,
            ..r.clone()
        };
        let report = |r: &Record| {
            if let Some(f) = hooks.on_iteration {
                f(&renumber(r));
            }
        };
        let inner = Hooks {
            on_iteration: Some(&report),
            cancel: hooks.cancel,
        };
        let mut outcome = self.iteration.run(self.prepared, interface, warm, inner);
        history.extend(outcome.history.drain(..).map(|r| renumber(&r)));
        outcome
    }
}

/// Per point of `interface`, the θ its pair gives, where the pair uses the augmented Lagrangian
/// (and the point has a partner and carries its pressure); `None` elsewhere.
pub(crate) fn augmented_points(model: &Model, interface: &Interface) -> Vec<Option<f64>> {
    interface
        .points
        .iter()
        .map(|p| {
            (p.carries()
                && p.has_partner()
                && model.pairs[p.pair].enforcement == Enforcement::Augmented)
                .then(|| model.theta(p.pair))
        })
        .collect()
}

/// The default gap tolerance for the normal displacements `un` of a first solve. The first
/// solve has λ = 0, so its displacements include the penetration θ·p of the inner penalty: with
/// the pair's own θ they grow without bound as θ softens, and so would the tolerance. The inner
/// penalty of [`crate::InnerPenalty::Stiffened`] is never softer than the rod model's with
/// c = [`crate::contact::AUGMENTED_C`], so with it (the interface Newton method and the
/// monolithic reference) the tolerance of a balanced pair does not depend on θ once θ is softer
/// than that.
pub(crate) fn default_gap_tol(un: &[f64]) -> f64 {
    GAP_TOL * un.iter().fold(0.0, |m: f64, u| m.max(u.abs()))
}

/// How far an inner solve is from done, 1 at the tolerances: the normal update's
/// [`Update::distance`] and the tangential one's [`FrictionUpdate::distance`], against the gap
/// tolerance `gap_tol` and the pressures' settling tolerance `tol` (relative to the peak).
pub(crate) fn distance(update: &Update, slip: &FrictionUpdate, gap_tol: f64, tol: f64) -> f64 {
    update
        .distance(gap_tol, tol)
        .max(slip.distance(gap_tol, tol, update.peak))
}

/// What one Uzawa update finds ([`uzawa_update`]).
pub(crate) struct Update {
    /// The new multipliers: the pressure magnitude p = −σ_n of every augmented point, 0
    /// elsewhere.
    pub multipliers: Vec<f64>,
    /// The largest violation of the Signorini conditions over the augmented points: the gap
    /// |d − s| where p > 0, the penetration (s − d)⁺ elsewhere (a length).
    pub violation: f64,
    /// The largest change |p − λ| of a pressed point whose inner θ is stiffer than its pair's
    /// (`crate::contact::AUGMENTED_C`): its gap θ|p − λ| is then small long before its pressure
    /// has settled, so the pressures are also asked to settle.
    pub settle: f64,
    /// The largest pressure of the augmented points.
    pub peak: f64,
}

impl Update {
    /// How far from done, 1 at the tolerances: the violation against `gap_tol`, and the
    /// pressures' last change against `tol` times the peak pressure.
    pub fn distance(&self, gap_tol: f64, tol: f64) -> f64 {
        let settle = if self.settle > 0.0 {
            self.settle / (tol * self.peak)
        } else {
            0.0
        };
        (self.violation / gap_tol).max(settle)
    }
}

/// What one Uzawa update of the tangential multipliers finds ([`friction_update`]): the exact
/// Coulomb (or Tresca) law is the fixed point λ_t = σ_t, where a sticking point keeps its
/// tangential displacement (g = g₀) and a slipping one slips against its traction.
pub(crate) struct FrictionUpdate {
    /// (point, σ_t): the new tangential multipliers of the augmented frictional points.
    pub tractions: Vec<(usize, f64)>,
    /// The largest violation of the law (a length): |g − g₀| where a point sticks, the slip
    /// along its traction (g − g₀)·sgn σ_t where it slips.
    pub violation: f64,
    /// The largest change |σ_t − λ_t|.
    pub settle: f64,
}

impl FrictionUpdate {
    /// How far from done, 1 at the tolerances: the violation against `gap_tol`, the
    /// tractions' last change against `tol` times the peak pressure `peak`.
    pub fn distance(&self, gap_tol: f64, tol: f64, peak: f64) -> f64 {
        let settle = if self.settle > 0.0 {
            self.settle / (tol * peak)
        } else {
            0.0
        };
        (self.violation / gap_tol).max(settle)
    }

    /// Gives the new tangential multipliers to the contact points.
    pub fn apply(&self, interface: &mut Interface) {
        for &(j, t) in &self.tractions {
            if let Some(f) = interface.points[j].friction.as_mut() {
                f.multiplier = t;
            }
        }
    }
}

/// One Uzawa update of the tangential multipliers from the displacements `un` of a solve, at
/// the frictional points of the augmented pairs (`augmented`); empty without friction.
pub(crate) fn friction_update(
    interface: &Interface,
    un: &[f64],
    augmented: &[Option<f64>],
) -> FrictionUpdate {
    let mut update = FrictionUpdate {
        tractions: Vec::new(),
        violation: 0.0,
        settle: 0.0,
    };
    if !interface.has_friction() {
        return update;
    }
    let mut s = vec![0.0; un.len()];
    interface.sum_normal(un, &mut s);
    let g = interface.slip_sums(un);
    for (j, p) in interface.points.iter().enumerate() {
        let (Some(f), Some(_)) = (&p.friction, augmented[j]) else {
            continue;
        };
        let (t, status) = interface.traction(j, &s, &g);
        let slip = g[j] - f.reference;
        let v = match status {
            Status::Stick => slip.abs(),
            Status::Slip => (slip * t.signum()).max(0.0),
            Status::Open => 0.0,
        };
        update.violation = update.violation.max(v);
        update.settle = update.settle.max((t - f.multiplier).abs());
        update.tractions.push((j, t));
    }
    update
}

/// One Uzawa update from the normal displacements `un` of a solve with the multipliers of
/// `interface`, at the points that `augmented` marks with their pair's θ.
pub(crate) fn uzawa_update(interface: &Interface, un: &[f64], augmented: &[Option<f64>]) -> Update {
    let mut s = vec![0.0; un.len()];
    interface.sum_normal(un, &mut s);
    let (mut violation, mut settle, mut peak) = (0.0f64, 0.0f64, 0.0f64);
    let multipliers = interface
        .points
        .iter()
        .enumerate()
        .map(|(j, p)| {
            let Some(theta) = augmented[j] else {
                return 0.0;
            };
            let (pressure, gap) = (-p.pressure(s[j]), p.gap - s[j]);
            let v = if pressure > 0.0 {
                if p.theta < theta {
                    settle = settle.max((pressure - p.multiplier).abs());
                }
                gap.abs()
            } else {
                (-gap).max(0.0)
            };
            violation = violation.max(v);
            peak = peak.max(pressure);
            pressure
        })
        .collect();
    Update {
        multipliers,
        violation,
        settle,
        peak,
    }
}
