//! The relaxation parameter γ^k: constant, or chosen per iteration (`auto`).
//!
//! `auto` is Aitken's Δ² dynamic relaxation on the interface iterate, as used in partitioned
//! fluid–structure interaction (Irons–Tuck / Küttler–Wall): with the unrelaxed update
//! r^k = ũ^k − u^k,
//!   γ^{k+1} = −γ^k · (r^{k−1} · (r^k − r^{k−1})) / ‖r^k − r^{k−1}‖²,
//! safeguarded: γ is kept in [γ_min, γ_max]; when the update grows (‖r^k‖ > 2‖r^{k−1}‖) γ is halved
//! instead, and it restarts from γ₀ when the update is not defined (r^k = r^{k−1}).

use std::fmt;

use crate::iteration::Record;

/// A relaxation parameter choice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Gamma {
    /// The same γ every iteration (0 < γ ≤ 1 typically; method.md allows any γ > 0).
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
pub const GAMMA_MIN: f64 = 0.02;
/// Largest γ the `auto` rule uses.
pub const GAMMA_MAX: f64 = 1.0;
/// Starting γ of the `auto` rule.
pub const GAMMA_START: f64 = 0.5;

/// The state of the γ rule during one solve.
pub struct Relaxation {
    rule: Gamma,
    gamma: f64,
    last_update: Option<Vec<f64>>,
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
        }
    }

    /// γ for the next iteration.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }

    /// Learns from an iteration that went from `u` to `u_next` with the current γ.
    pub fn update(&mut self, u: &[f64], u_next: &[f64], _record: &Record) {
        if let Gamma::Constant(_) = self.rule {
            return;
        }
        let g = self.gamma;
        let r: Vec<f64> = u.iter().zip(u_next).map(|(a, b)| (b - a) / g).collect();
        if let Some(prev) = &self.last_update {
            let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
            let dr: Vec<f64> = r.iter().zip(prev).map(|(a, b)| a - b).collect();
            let dd: f64 = dr.iter().map(|x| x * x).sum();
            let next = if norm(&r) > 2.0 * norm(prev) {
                0.5 * g
            } else if dd > 0.0 {
                -g * prev.iter().zip(&dr).map(|(a, b)| a * b).sum::<f64>() / dd
            } else {
                GAMMA_START
            };
            self.gamma = if next.is_finite() {
                next.clamp(GAMMA_MIN, GAMMA_MAX)
            } else {
                GAMMA_START
            };
        }
        self.last_update = Some(r);
    }
}
