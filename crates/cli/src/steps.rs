//! `contactdd solve` with `[solver] load-steps`: one solve per load factor on the one prepared
//! model, a line per step, and the step result folder (`contactdd_io::steps`); with a
//! `[[steps]]` load history, one solve per increment, the same folder with the rows labelled.

use std::path::Path;

use anyhow::{Context, Result};

use contactdd_ddm::history::{solve_history, Increment, LoadHistory};
use contactdd_ddm::steps::solve_steps;
use contactdd_ddm::{Hooks, Model, Prepared, Settings, Solution};
use contactdd_io::setup::Monitor;
use contactdd_io::steps::HistoryLabels;

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
            let label = format!("factor {}", sig(factor));
            say!("{}", step_line(k, count, &label, sol, monitored));
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
        .write_step_results(out, model, &steps, (monitor, units), None)
        .with_context(|| format!("cannot write the results to '{}'", out.display()))?;
    finish(&steps, count, "load steps", out, ranks)
}

/// The exit code and the final line of a run of `count` solves of which `steps` were done.
fn finish(
    steps: &[(f64, Solution)],
    count: usize,
    what: &str,
    out: &Path,
    ranks: &Ranks,
) -> Result<Exit> {
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
        say!("all {count} {what} converged; results in {}", out.display());
        Ok(Exit::Success)
    } else {
        let message = steps
            .last()
            .and_then(|(_, s)| s.message.clone())
            .unwrap_or_else(|| "unknown reason".into());
        say!(
            "NOT converged at {} {} of {count}: {message}; results in {}",
            what.trim_end_matches('s'),
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

/// Solves every increment of a load history, prints a line per increment, writes the results
/// (the applied loads and reactions of `summary.json` are those of the last increment's
/// combination); the exit code is that of the last increment.
pub fn run_history(
    run: StepRun<'_>,
    history: &LoadHistory,
    prepared: &mut Prepared,
) -> Result<Exit> {
    let StepRun {
        model,
        settings,
        monitor,
        units,
        out,
        quiet,
        ranks,
        ..
    } = run;
    let count = history.len();
    if !quiet {
        say!(
            "solving {} in {} steps, {count} increments: {settings}",
            model.name,
            history.steps.len(),
        );
    }
    let groups = history.group_names();
    let mut k = 0;
    let mut line = |inc: &Increment, sol: &Solution| {
        k += 1;
        let monitored = monitor.map(|m| ranks.monitored(sol, m));
        if !quiet {
            let name = history.steps.get(inc.step).map_or("", |s| s.name.as_str());
            let factors: Vec<String> = (groups.iter().zip(&inc.factors))
                .map(|(g, f)| format!("{g} {}", sig(*f)))
                .collect();
            let label = format!("{name} {}, {}", inc.increment, factors.join(", "));
            say!("{}", step_line(k, count, &label, sol, monitored));
        }
    };
    let done = solve_history(
        model,
        prepared,
        settings,
        history,
        Hooks::default(),
        &mut line,
    )
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    let increments: Vec<Increment> = done.iter().map(|(i, _)| i.clone()).collect();
    let labels = HistoryLabels::new(history, &increments);
    let times = HistoryLabels::times(history, &increments);
    let last = increments.last().map_or(vec![1.0], |i| i.factors.clone());
    let at_end = history.model_at(model, &last);
    let mut steps: Vec<(f64, Solution)> = times
        .into_iter()
        .zip(done.into_iter().map(|(_, s)| s))
        .collect();
    if let Some((_, sol)) = steps.last_mut() {
        // The last solve is the model at its combination (`at_end`) at factor 1.
        sol.load_factor = 1.0;
    }
    ranks
        .write_step_results(out, &at_end, &steps, (monitor, units), Some(&labels))
        .with_context(|| format!("cannot write the results to '{}'", out.display()))?;
    finish(&steps, count, "increments", out, ranks)
}

/// `step 2/4, factor 0.5: converged in 3 iterations (relative residual 2.1e-12); pair: force
/// (0, 4200), max p 2647[; monitor (ux, uy)]` with the monitored displacement.
fn step_line(
    k: usize,
    count: usize,
    label: &str,
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
    let mut line = format!("step {k}/{count}, {label}: {state}");
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
