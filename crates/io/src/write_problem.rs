//! Writes a problem back out as the text of a problem file: the inverse of
//! [`crate::setup::resolve`] for what a problem holds after it was read or built in code.
//!
//! The solver settings are written in full ([`solver_spec`]: every key explicit, the resolved
//! values), so the text reads back to the same [`Settings`] whatever defaults the reader would
//! otherwise fill in (`u0` from the model's size, the accelerator from a constant γ). Floats are
//! written by the `toml` crate in the shortest text that reads back to the same value, so a
//! problem written and read again gives the same model bit for bit.

use contactdd_ddm::{Accelerator, CoarseMode, Gamma, Settings};

use crate::problem::{AcceleratorSpec, CoarseSpec, GammaSpec, Problem, SolverSpec};

/// The `[solver]` table of `settings` with every key given, plus `threads` and the load steps
/// and monitor of `keep` (which [`Settings`] does not hold).
pub fn solver_spec(settings: &Settings, threads: Option<usize>, keep: &SolverSpec) -> SolverSpec {
    SolverSpec {
        method: Some(settings.method),
        gamma: Some(match settings.gamma {
            Gamma::Constant(g) => GammaSpec::Value(g),
            Gamma::Auto => GammaSpec::Auto,
        }),
        accelerator: Some(match settings.accelerator {
            Accelerator::None => AcceleratorSpec::None,
            Accelerator::Anderson { .. } => AcceleratorSpec::Anderson,
            Accelerator::Newton => AcceleratorSpec::Newton,
        }),
        coarse: Some(match settings.coarse {
            CoarseMode::Off => CoarseSpec::Off,
            CoarseMode::Chains => CoarseSpec::Chains,
            CoarseMode::All => CoarseSpec::All,
        }),
        tol: Some(settings.tol),
        equilibrium_tol: Some(settings.equilibrium_tol),
        balance_tol: settings.balance_tol,
        max_iter: Some(settings.max_iter),
        gap_tol: settings.gap_tol,
        max_updates: Some(settings.max_updates),
        u0: Some(settings.u0),
        u_prev: Some(settings.u_prev),
        condensation: Some(settings.condensation),
        threads,
        ..keep.clone()
    }
}

/// The text of a problem file holding `problem`.
pub fn to_toml(problem: &Problem) -> Result<String, toml::ser::Error> {
    toml::to_string(problem)
}
