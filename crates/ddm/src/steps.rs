//! Load steps: the problem solved at a sequence of load factors (every load and prescribed
//! displacement times the factor), each step starting from the interface loads of the one
//! before. The bodies are factorised once: a load factor only scales their condensed loads.
//!
//! Contact is nonlinear, so the steps give the load–displacement curve of the problem, and reach
//! a full load gradually where the contact zone changes much.

use crate::error::SetupError;
use crate::history::{solve_history, HistoryStep, Increment, LoadHistory};
use crate::model::Model;
use crate::outcome::Hooks;
use crate::settings::Settings;
use crate::solution::Solution;
use crate::solver::Prepared;

/// The load factors of `count` equal steps up to the full load: 1/count, 2/count, …, 1.
pub fn equal_steps(count: usize) -> Vec<f64> {
    (1..=count).map(|k| k as f64 / count as f64).collect()
}

/// Checks a list of load factors: at least one, each finite and positive, increasing.
pub fn check_factors(factors: &[f64]) -> Result<(), String> {
    if factors.is_empty() {
        return Err("needs at least one load factor".into());
    }
    if let Some(f) = factors.iter().find(|f| !(f.is_finite() && **f > 0.0)) {
        return Err(format!("load factors must be positive and finite, got {f}"));
    }
    match factors.windows(2).find(|w| w[1] <= w[0]) {
        Some(w) => Err(format!(
            "load factors must increase from step to step, got {} after {}",
            w[1], w[0]
        )),
        None => Ok(()),
    }
}

/// Solves the model at every load factor in turn, calling `on_step(step, factor, solution)`
/// after each: the load history of one step per factor on the default group
/// ([`solve_history`], which also carries the friction state from step to step). Stops after
/// the first step that does not converge (its solution is the last one returned). The prepared
/// model is left at load factor 1 and the unloaded state.
pub fn solve_steps(
    model: &Model,
    prepared: &mut Prepared,
    settings: &Settings,
    factors: &[f64],
    hooks: Hooks<'_>,
    on_step: &mut dyn FnMut(usize, f64, &Solution),
) -> Result<Vec<(f64, Solution)>, SetupError> {
    check_factors(factors).map_err(SetupError::Solver)?;
    let history = LoadHistory {
        groups: Vec::new(),
        steps: (factors.iter().enumerate())
            .map(|(k, &f)| HistoryStep {
                name: format!("step{}", k + 1),
                factors: vec![(0, f)],
                increments: 1,
            })
            .collect(),
    };
    let mut each = |increment: &Increment, solution: &Solution| {
        on_step(increment.step + 1, increment.factors[0], solution)
    };
    let done = solve_history(model, prepared, settings, &history, hooks, &mut each)?;
    Ok(done.into_iter().map(|(i, s)| (i.factors[0], s)).collect())
}
