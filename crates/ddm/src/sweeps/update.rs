//! How the Robin sweeps' outputs become the next state: relaxation with γ (the paper's
//! iteration) or Anderson acceleration.

use super::ranks::BodySums;
use crate::anderson::Anderson;
use crate::measures::largest;
use crate::outcome::Record;
use crate::relaxation::{Gamma, Relaxation};
use crate::settings::{Accelerator, Settings};

/// How the sweeps' outputs become the next state.
pub(super) enum Update {
    Relax(Relaxation),
    Anderson {
        memory: Anderson,
        /// γ of the first step (and of steps without secant pairs).
        first_gamma: f64,
    },
}

/// Interface-sized work buffers of one solve.
pub(super) struct Buffers {
    /// The sweep's outputs Ũ and T̃.
    pub(super) tilde: Vec<f64>,
    pub(super) t_tilde: Vec<f64>,
    /// The proposed next state and its pair sums.
    pub(super) next: Vec<f64>,
    pub(super) s_next: Vec<f64>,
    /// The state before the coarse correction.
    pub(super) input: Vec<f64>,
    pub(super) input_t: Vec<f64>,
}

impl Buffers {
    /// Buffers for an interface of `m` unknowns.
    pub(super) fn new(m: usize) -> Buffers {
        Buffers {
            tilde: vec![0.0; m],
            t_tilde: vec![0.0; m],
            next: vec![0.0; m],
            s_next: vec![0.0; m],
            input: vec![0.0; m],
            input_t: vec![0.0; m],
        }
    }
}

impl Update {
    pub(super) fn new(settings: &Settings) -> Update {
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
    pub(super) fn propose(&self, u: &[f64], buf: &mut Buffers) -> f64 {
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
    pub(super) fn converged(&self, record: &Record, tol: f64) -> bool {
        let scale = self.change_scale();
        record.rel_change.iter().all(|&r| r * scale <= tol)
    }

    /// What [`Update::converged`] compares with the tolerance: the largest scaled change.
    pub(super) fn measure(&self, rel_change: &[f64]) -> f64 {
        let scale = self.change_scale();
        largest(rel_change.iter().map(|&r| r * scale))
    }

    /// With an adaptive γ a tiny step must not pass for convergence: the change is judged as if
    /// γ were at least the starting value (for a constant γ this is the paper's criterion).
    fn change_scale(&self) -> f64 {
        match self {
            Update::Relax(relax) => relax.convergence_scale(),
            Update::Anderson { .. } => 1.0,
        }
    }

    /// Makes `buf.next` and `t` the next state (Anderson: from the accelerated combination unless
    /// the iteration has converged, when the sweep's output is the result). Returns false if
    /// `buf.next` is no longer the proposed state.
    pub(super) fn commit(
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
