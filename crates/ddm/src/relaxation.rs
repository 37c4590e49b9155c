//! The relaxation parameter γ^k: constant, or chosen per iteration (`auto`).
//!
//! `auto` is Aitken's Δ² dynamic relaxation on the interface iterate, as used in partitioned
//! fluid–structure interaction (Irons–Tuck; Küttler & Wall 2008). With the unrelaxed update
//! r^k = ũ^k − u^k of the normal contact displacements,
//!   γ^{k+1} = −γ^k · (r^{k−1} · (r^k − r^{k−1})) / ‖r^k − r^{k−1}‖².
//! Safeguards, because the contact map is only piecewise linear:
//! - γ starts at γ₀ = 0.5 and stays in [γ_min, γ_max] = [0.1, 1];
//! - γ may at most double from one iteration to the next (Aitken overshoots after an active-set
//!   change);
//! - when the update grows (‖r^k‖ > 2‖r^{k−1}‖) γ is halved instead;
//! - when a body breaks down (its contact zone opens completely, or values blow up) the iteration
//!   restarts from the initial values with γ_max lowered by a factor 0.7 (down to γ_min); the iterations before the
//!   restart still count;
//! - convergence is judged as if γ were at least γ₀ (see [`Relaxation::convergence_scale`]), so a
//!   small step cannot pass for convergence.

use std::fmt;
use std::ops::Range;

/// Sums per-body partial sums over every body in body order, given this process's bodies' ones.
pub type Total<'a> = dyn Fn(Vec<[f64; 4]>) -> [f64; 4] + 'a;

/// A relaxation parameter choice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Gamma {
    /// The same γ every iteration (0 < γ ≤ 1 typically; docs/method.md allows any γ > 0).
    Constant(f64),
    /// Safeguarded Aitken Δ² relaxation.
    Auto,
}

impl fmt::Display for Gamma {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Gamma::Constant(g) => write!(f, "{g}"),
            Gamma::Auto => f.write_str("auto"),
        }
    }
}

/// Smallest γ the `auto` rule uses.
pub const GAMMA_MIN: f64 = 0.1;
/// Largest γ the `auto` rule uses.
pub const GAMMA_MAX: f64 = 1.0;
/// Starting γ of the `auto` rule.
pub const GAMMA_START: f64 = 0.5;
/// Growth of the unrelaxed update ‖r^k‖/‖r^{k−1}‖ above which a step counts as too long: the
/// `auto` rule halves γ, and the two-level sweeps check their coarse correction
/// (`crate::sweeps`). A contraction shrinks the update; a factor 2 leaves room for the
/// non-monotone steps of a piecewise-linear map (an active-set change).
pub const GROWTH: f64 = 2.0;

/// The state of the γ rule during one solve.
pub struct Relaxation {
    rule: Gamma,
    gamma: f64,
    last_update: Option<Vec<f64>>,
    /// Largest γ allowed (γ_max, times 0.7 at every restart).
    cap: f64,
}

impl Relaxation {
    /// Starts the rule.
    pub fn new(rule: Gamma) -> Relaxation {
        let gamma = match rule {
            Gamma::Constant(g) => g,
            Gamma::Auto => GAMMA_START,
        };
        Relaxation {
            rule,
            gamma,
            last_update: None,
            cap: GAMMA_MAX,
        }
    }

    /// γ for the next iteration.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }

    /// Factor applied to the relative change before comparing it with the tolerance: 1 for a
    /// constant γ, `max(1, γ₀/γ)` for `auto`, so that shrinking γ cannot fake convergence.
    pub fn convergence_scale(&self) -> f64 {
        match self.rule {
            Gamma::Constant(_) => 1.0,
            Gamma::Auto => (GAMMA_START / self.gamma).max(1.0),
        }
    }

    /// After a breakdown: for `auto`, lowers (×0.7) the largest γ the rule may use from now on and
    /// restarts it below that cap; returns true if the caller should restart the iteration from
    /// the initial values (false for a constant γ, or when the cap is already γ_min).
    pub fn restart(&mut self) -> bool {
        match self.rule {
            Gamma::Auto if self.cap > GAMMA_MIN => {
                self.cap = (0.7 * self.cap).max(GAMMA_MIN);
                self.gamma = GAMMA_START.min(self.cap);
                self.last_update = None;
                true
            }
            _ => false,
        }
    }

    /// Learns from an iteration that went from `u` to `u_next` with the current γ. `own` are the
    /// points of this process's bodies, body by body in increasing order, the only values it
    /// reads; `total` sums the per-body partial sums of every body (its own first computed from
    /// them) in body order, so that any number of processes adds the same numbers in the same
    /// order.
    pub fn update(&mut self, u: &[f64], u_next: &[f64], own: &[Range<usize>], total: &Total) {
        if let Gamma::Constant(_) = self.rule {
            return;
        }
        let g = self.gamma;
        let r: Vec<f64> = u.iter().zip(u_next).map(|(a, b)| (b - a) / g).collect();
        if let Some(prev) = &self.last_update {
            // Per body: ‖r‖², ‖r_prev‖², ‖Δr‖², r_prev · Δr.
            let partial = own
                .iter()
                .map(|range| {
                    let mut sums = [0.0; 4];
                    for j in range.clone() {
                        let dr = r[j] - prev[j];
                        sums[0] += r[j] * r[j];
                        sums[1] += prev[j] * prev[j];
                        sums[2] += dr * dr;
                        sums[3] += prev[j] * dr;
                    }
                    sums
                })
                .collect();
            let [rr, pp, dd, pd] = total(partial);
            let next = if rr.sqrt() > GROWTH * pp.sqrt() {
                0.5 * g
            } else if dd > 0.0 {
                -g * pd / dd
            } else {
                GAMMA_START
            };
            self.gamma = if next.is_finite() {
                next.min(2.0 * g).clamp(GAMMA_MIN, self.cap)
            } else {
                GAMMA_START
            };
        }
        self.last_update = Some(r);
    }
}
