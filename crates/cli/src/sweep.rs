//! `contactdd sweep`: prepare once, run every method with every γ, print the table of iteration
//! counts (rows γ, columns methods) and write it as CSV.

use std::path::PathBuf;

use anyhow::{Context, Result};

use std::sync::atomic::{AtomicUsize, Ordering};

use contactdd_ddm::gamma_study::{SweepHooks, SweepRun};
use contactdd_ddm::{prepare_with, sweep_with, Gamma, Method, Preparation, Stop};
use contactdd_io::atomic::check_output_path;
use contactdd_io::output::{safe_file_name, sweep_csv, write_atomic};

use crate::args::SweepArgs;
use crate::console::Status;
use crate::report::progress;
use crate::solve::{apply_common, count};
use crate::{load, with_threads, Exit};

/// One run for the status line: method, γ and its outcome.
fn run_text(r: &SweepRun) -> String {
    let gamma = r.gamma.map_or("auto".to_string(), |g| g.to_string());
    let outcome = if r.converged {
        format!("{} iterations", r.iterations)
    } else {
        r.reason.clone()
    };
    format!("{} γ {gamma}: {outcome}", r.method.name())
}

/// `contactdd sweep`.
pub fn sweep(args: SweepArgs) -> Result<Exit> {
    let loaded = load(&args.file)?;
    let mut settings = loaded.settings.clone();
    let threads = apply_common(&args.common, &mut settings, loaded.threads);
    let model = &loaded.model;
    let (methods, gammas) = (&args.method.0, &args.gamma.0);
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{}-sweep.csv", safe_file_name(&model.name))));
    // Checked again when writing; checking first saves a whole sweep when the path is refused.
    check_output_path(&out).with_context(|| format!("cannot write '{}'", out.display()))?;
    let quiet = args.quiet;
    let runs = with_threads(threads, || {
        if !quiet {
            progress(&format!(
                "assembling and factorising {}…",
                count(model.bodies.len(), "body", "bodies")
            ));
        }
        let how = Preparation::for_sweeps(settings.condensation);
        let prepared = prepare_with(model, how).map_err(|e| anyhow::anyhow!("{e}"))?;
        if !quiet {
            progress(&format!(
                "running {} × {} = {} solves…",
                count(methods.len(), "method", "methods"),
                count(gammas.len(), "gamma", "gammas"),
                methods.len() * gammas.len()
            ));
        }
        let (status, done) = (Status::new(!quiet), AtomicUsize::new(0));
        let total = methods.len() * gammas.len();
        let on_run = |r: &SweepRun| {
            let k = done.fetch_add(1, Ordering::Relaxed) + 1;
            status.update(|| format!("{k} of {total} runs done; last: {}", run_text(r)));
        };
        let hooks = SweepHooks {
            cancel: None,
            on_run: Some(&on_run),
        };
        let runs = sweep_with(model, &prepared, methods, gammas, &settings, hooks);
        status.finish();
        Ok(runs)
    })?;
    write_atomic(&out, sweep_csv(&runs).as_bytes())
        .with_context(|| format!("cannot write '{}'", out.display()))?;
    if !quiet {
        say!(
            "sweep of {}: iterations m to reach tol {:e} (max-iter {}); div@k = diverged at \
             iteration k, max = not converged within max-iter",
            model.name,
            settings.tol,
            settings.max_iter
        );
        say!("{}", table(methods, gammas, &runs).trim_end());
    }
    say!("wrote {}", out.display());
    Ok(Exit::Success)
}

/// The table: one row per γ, one column per method.
fn table(methods: &[Method], gammas: &[Gamma], runs: &[SweepRun]) -> String {
    let widths: Vec<usize> = methods.iter().map(|m| m.name().len().max(7)).collect();
    let mut s = format!("{:>8}", "gamma");
    for (m, w) in methods.iter().zip(&widths) {
        s += &format!("  {:>w$}", m.name());
    }
    s.push('\n');
    for g in gammas {
        let key = match *g {
            Gamma::Constant(v) => Some(v),
            Gamma::Auto => None,
        };
        s += &format!("{:>8}", g.to_string());
        for (m, w) in methods.iter().zip(&widths) {
            let run = runs.iter().find(|r| r.method == *m && r.gamma == key);
            s += &format!("  {:>w$}", run.map_or("?".into(), cell));
        }
        s.push('\n');
    }
    s
}

/// `m` when converged, `max` at the iteration cap, `div@k` when it broke down at iteration k,
/// `int` when interrupted.
fn cell(run: &SweepRun) -> String {
    match run.stop {
        Stop::Converged => run.iterations.to_string(),
        Stop::MaxIterations => "max".into(),
        Stop::Interrupted => "int".into(),
        Stop::Stalled { .. } => "stall".into(),
        Stop::Unbalanced { .. } => "unbal".into(),
        Stop::Unenforced { .. } => "unenf".into(),
        Stop::Diverged { .. } => format!("div@{}", run.iterations),
    }
}
