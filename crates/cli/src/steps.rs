//! `contactdd solve` with `[solver] load-steps`: one solve per load factor on the one prepared
//! model, a line per step, and the step result folder (`contactdd_io::steps`).

use std::path::Path;

use anyhow::{Context, Result};

use contactdd_ddm::steps::solve_steps;
use contactdd_ddm::{Hooks, Model, Prepared, Settings, Solution};
use contactdd_io::setup::Monitor;

use crate::ranks::Ranks;
use crate::report::{sig, vec2};
use crate::Exit;

/// What a load-step run needs besides the prepared model.
pub struct StepRun<'a> {
    /// The model.
    pub model: &'a Model,
    /// Iteration settings.
    pub settings: &'a Settings,
    /// The load factors.
    pub factors: &'a [f64],
    /// The boundary whose mean displacement each step reports.
    pub monitor: Option<&'a Monitor>,
    /// The problem's units note, for `summary.json`.
    pub units: Option<&'a str>,
    /// The result folder.
    pub out: &'a Path,
    /// Only the final line.
    pub quiet: bool,
    /// The processes of the run (rank 0 reports).
    pub ranks: &'a Ranks,
}

/// Solves at every load factor, prints a line per step, writes the results; the exit code is
/// that of the last step.
pub fn run_steps(run: StepRun<'_>, prepared: &mut Prepared) -> Result<Exit> {
    let StepRun {
        model,
        settings,
        factors,
        monitor,
        units,
        out,
        quiet,
        ranks,
    } = run;
    if !quiet {
        say!(
            "solving {} in {} load steps: {settings}",
            model.name,
            factors.len(),
        );
    }
    let count = factors.len();
    let mut line = |k: usize, factor: f64, sol: &Solution| {
        // Every rank takes part: the monitored body's rank holds its field.
        let monitored = monitor.map(|m| ranks.monitored(sol, m));
        if !quiet {
            say!("{}", step_line(k, count, factor, sol, monitored));
        }
    };
    let steps = solve_steps(
        model,
        prepared,
        settings,
        factors,
        Hooks::default(),
        &mut line,
    )
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    ranks
        .write_step_results(out, model, &steps, monitor, units)
        .with_context(|| format!("cannot write the results to '{}'", out.display()))?;
    let converged = steps.last().is_some_and(|(_, s)| s.converged);
    let done = steps.len() == count && converged;
    if !ranks.is_root() {
        // Rank 0 reports; every rank ends with the same exit code.
        return Ok(if done {
            Exit::Success
        } else {
            Exit::NotConverged
        });
    }
    if done {
        say!(
            "all {count} load steps converged; results in {}",
            out.display()
        );
        Ok(Exit::Success)
    } else {
        let message = steps
            .last()
            .and_then(|(_, s)| s.message.clone())
            .unwrap_or_else(|| "unknown reason".into());
        say!(
            "NOT converged at load step {} of {count}: {message}; results in {}",
            steps.len(),
            out.display()
        );
        eprintln!(
            "warning: not converged; the steps up to the failed one were written to '{}'",
            out.display()
        );
        Ok(Exit::NotConverged)
    }
}

/// `step 2/4, factor 0.5: converged in 3 iterations (relative residual 2.1e-12); pair: force
/// (0, 4200), max p 2647[; monitor (ux, uy)]` with the monitored displacement.
fn step_line(
    k: usize,
    count: usize,
    factor: f64,
    sol: &Solution,
    monitored: Option<[f64; 2]>,
) -> String {
    let state = if sol.converged {
        let last = sol.history.last().map_or(f64::NAN, |r| r.measure);
        format!(
            "converged in {} iterations ({} {last:.1e})",
            sol.iterations,
            sol.settings.measure_name()
        )
    } else {
        "NOT converged".into()
    };
    let mut line = format!("step {k}/{count}, factor {}: {state}", sig(factor));
    for pair in &sol.contact {
        line += &format!(
            "; {}: force on {} {}, max p {}",
            pair.name,
            pair.bodies[0],
            vec2(pair.force_on(0)),
            sig(pair.max_pressure())
        );
    }
    if let Some(u) = monitored {
        line += &format!("; monitor {}", vec2(u));
    }
    line
}
