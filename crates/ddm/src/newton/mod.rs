//! The interface Newton iteration: the penalty problem on the condensed interface, solved for all
//! contact points at once by a semismooth Newton (primal–dual active set) method. The algorithm
//! and its sources are in `docs/interface-newton.md`.
//!
//! Every body is condensed onto its contact points ([`crate::condensed::CondensedBody`]): with τ = D₀⁻¹T the
//! interface load in displacement units, its normal displacements are U_b = f₀ + B_b τ_b with
//! B_b = C₀D₀. Point j carries the penetration-like q_j = U_j − τ_j = θ_j p_j (p the contact
//! pressure), and the penalty law q = max(0, s − d) is the complementarity problem
//!   q ≥ 0,  s − d − q ≤ 0,  q (s − d − q) = 0,
//! written as q_j = max(0, q_j + ρ_j (s_j − d_j − q_j)) for any ρ_j > 0. Point j counts as closed
//! when the argument of the max is positive. ρ = 1 would be the penalty's own rule (closed where
//! s > d); ρ_j = 1 − B_jj, the body's share in the stiffness of the point with its spring, is the
//! primal–dual active set rule with the body's own stiffness as scale, which decides on the
//! pressure rather than on a penetration of the size of θ·p and so does not flip points at the
//! edge of the contact zone back and forth when θ is small. For a fixed closed set χ the
//! equations are linear:
//!   R_j = τ_j − U_j − χ_j (d_j − s_j) = 0,
//! and the Jacobian J = I − (I − χA) B (s = A U) has row e_j − B_j· for an open point and
//! e_j + Σ_k c_jk B_k· for a closed one (the point's own B row cancels). J is sparse by bodies:
//! dense blocks of the size of one body's contact zone, coupled only across closed pairs.
//!
//! Each step solves J δ = −R (by LU, or on sparse bodies by the symmetric form of `primal`)
//! and takes the full step. A watchdog keeps the last state whose ‖R̂‖ (R with closed rows
//! scaled by ρ: the complementarity residual) a step decreased enough; when a few full steps in a row do not decrease it below that state's, the run returns
//! there and backtracks along that state's step. Two safeguards keep J regular:
//! - rigid motions that no closed contact resists (two floating bodies moving together) are in
//!   the kernel of J; they are found from the bodies' free rigid modes, and the step is kept
//!   orthogonal to them by a bordered system (their residual is left to the bodies' balance,
//!   which the solver checks);
//! - a floating body with no closed point uses all its partnered points as closed in J and in
//!   the step's residual, which moves it towards its partners; so do the points that would
//!   resist a free rigid motion along which the loads do work (a body held sideways but pushed
//!   down). Such "stranded" states never count as progress or as converged.
//!
//! The bodies' responses B_b τ_b are evaluated in parallel; the factorisation is sequential, so
//! the result does not depend on the number of threads. A process evaluates only the bodies it
//! owns; the [`crate::exchange::Exchange`] shares their blocks B_b and responses, and every process then solves
//! the same Newton system (`crate::exchange`).

mod algebra;
mod blocks;
pub(crate) mod linear;
mod null_space;
mod primal;
mod rigid;
mod run;
mod step;
mod system;

use std::time::Instant;

use crate::contact::Interface;
use crate::iteration::Iteration;
use crate::outcome::{Hooks, Outcome};
use crate::prepared::Prepared;
use crate::settings::Settings;
use run::Run;
use system::System;

/// The interface Newton method with the tolerance and cap of the settings (their method and γ
/// are unused).
pub struct InterfaceNewton<'s>(pub &'s Settings);

impl Iteration for InterfaceNewton<'_> {
    fn run(
        &self,
        prepared: &Prepared,
        interface: &Interface,
        warm: Option<&[f64]>,
        hooks: Hooks<'_>,
    ) -> Outcome {
        iterate(prepared, interface, warm, self.0, hooks)
    }
}

/// Runs the interface Newton iteration on a prepared model with the contact points `interface`,
/// from the interface loads `warm` if given, else from the paper's initial value u⁰.
pub fn iterate(
    prepared: &Prepared,
    interface: &Interface,
    warm: Option<&[f64]>,
    settings: &Settings,
    hooks: Hooks<'_>,
) -> Outcome {
    let start = Instant::now();
    let system = System::new(prepared, interface);
    let mut run = Run::new(&system, prepared, warm, settings);
    let (stop, iterations) = run.solve(settings, hooks);
    let t_load = system.loads(&run.tau);
    Outcome {
        stop,
        iterations,
        un: run.state.u,
        t_load,
        history: run.history,
        seconds: start.elapsed().as_secs_f64(),
    }
}
