//! `contactdd solve` (domain decomposition) and `contactdd monolithic` (the reference): load the
//! file, apply the command-line overrides, prepare, solve while printing one line per iteration,
//! write the result folder, print the summary.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

use contactdd_ddm::contact::check as contact_check;
use contactdd_ddm::contact::Interface;
use contactdd_ddm::monolithic::{solve_monolithic_with, MonolithicSettings, MonolithicStep};
use contactdd_ddm::{
    prepare_on, solve as dd_solve, Accelerator, CoarseMode, Condensation, Gamma, Hooks, Model,
    MonolithicSolution, Prepared, Record,
};
use contactdd_io::output::{safe_file_name, write_monolithic_results};
use contactdd_io::reactions::BodyReactions;
use contactdd_io::setup::Loaded;
use contactdd_io::vtu::VtuOptions;

use crate::args::{Common, MonolithicArgs, SolveArgs};
use crate::console::Status;
use crate::rank_use::RankUse;
use crate::ranks::Ranks;
use crate::report::{
    applied_loads, pair_report, progress, reaction_report, sig, status_text, timing, IterationTable,
};
use crate::steps::{run_history, run_steps, StepRun};
use crate::{load, with_threads, Exit};

/// Applies `--tol`, `--max-iter` and `--threads` to the file's settings; returns the thread count.
pub fn apply_common(
    common: &Common,
    settings: &mut contactdd_ddm::Settings,
    file_threads: Option<usize>,
) -> Option<usize> {
    if let Some(t) = common.tol {
        settings.tol = t;
    }
    if let Some(k) = common.max_iter {
        settings.max_iter = usize::try_from(k).unwrap_or(usize::MAX);
    }
    common
        .threads
        .map(|n| usize::try_from(n).unwrap_or(usize::MAX))
        .or(file_threads)
}

/// Whether iteration `k` gets a line: every one up to 10, then every 10th up to 100, every 100th
/// up to 1000 and so on (the last iteration always does), so a long run prints a few dozen lines.
fn shown(k: usize) -> bool {
    let mut step = 1;
    while k >= 10 * step {
        step *= 10;
    }
    k % step == 0
}

/// Paces the iteration table: the lines of [`shown`], plus one whenever [`Pacer::QUIET_FOR`] has
/// passed since the last, so that a slow run in a log file never looks dead.
struct Pacer {
    /// When the last line was printed, and its iteration.
    last: Mutex<(Instant, usize)>,
}

impl Pacer {
    const QUIET_FOR: Duration = Duration::from_secs(10);

    fn new() -> Pacer {
        Pacer {
            last: Mutex::new((Instant::now(), 0)),
        }
    }

    /// Whether iteration `k` gets a line (and remembers it if so).
    fn take(&self, k: usize) -> bool {
        let Ok(mut last) = self.last.lock() else {
            return shown(k);
        };
        let due = shown(k) || last.0.elapsed() >= Self::QUIET_FOR;
        if due {
            *last = (Instant::now(), k);
        }
        due
    }

    /// The iteration of the last line printed (0: none).
    fn last(&self) -> usize {
        self.last.lock().map_or(0, |l| l.1)
    }
}

/// The file's settings with `solve`'s command-line overrides; returns them and the thread count.
fn cli_settings(args: &SolveArgs, loaded: &Loaded) -> (contactdd_ddm::Settings, Option<usize>) {
    let mut settings = loaded.settings.clone();
    if args.accelerator.is_none() && (args.method.is_some() || args.gamma.is_some()) {
        settings.use_sweeps();
    }
    if let Some(m) = args.method {
        settings.method = m;
    }
    if let Some(g) = args.gamma {
        settings.gamma = g;
        if let Gamma::Constant(_) = g {
            // The paper's iteration, unless asked otherwise below.
            (settings.accelerator, settings.coarse) = (Accelerator::None, CoarseMode::Off);
        }
    }
    if let Some(a) = args.accelerator {
        settings.accelerator = a;
        // Sweeps with relaxation get the coarse correction, except the paper's constant γ.
        let paper = matches!(settings.gamma, Gamma::Constant(_));
        settings.coarse = if a == Accelerator::None && !paper {
            CoarseMode::Chains
        } else {
            CoarseMode::Off
        };
    }
    if let Some(c) = args.coarse {
        settings.coarse = c;
    }
    if let Some(g) = args.gap_tol {
        settings.gap_tol = Some(g);
    }
    if let Some(b) = args.balance_tol {
        settings.balance_tol = Some(b);
    }
    let threads = apply_common(&args.common, &mut settings, loaded.threads);
    (settings, threads)
}

/// Solves with the iteration table on stdout and a live status on a terminal (unless `quiet`).
fn iterate_shown(
    model: &Model,
    prepared: &Prepared,
    settings: &contactdd_ddm::Settings,
    quiet: bool,
) -> Result<contactdd_ddm::Solution> {
    let table = IterationTable::new(model, settings);
    if !quiet {
        say!(
            "solving {}: {}, {}, {settings}",
            model.name,
            count(model.bodies.len(), "body", "bodies"),
            count(model.pairs.len(), "contact pair", "contact pairs"),
        );
        say!("{}", table.header());
    }
    let (pacer, status) = (Pacer::new(), Status::new(!quiet));
    let print_line = |r: &Record| {
        if pacer.take(r.k) {
            say!("{}", table.line(r))
        }
        status.update(|| status_text(r));
    };
    let hooks = Hooks {
        on_iteration: if quiet { None } else { Some(&print_line) },
        cancel: None,
    };
    let sol = dd_solve(model, prepared, settings, hooks).map_err(|e| anyhow::anyhow!("{e}"))?;
    status.finish();
    match sol.history.last() {
        Some(last) if !quiet && pacer.last() != last.k => say!("{}", table.line(last)),
        _ => {}
    }
    Ok(sol)
}

/// `contactdd solve`.
pub fn solve(args: SolveArgs) -> Result<Exit> {
    let start = Instant::now();
    let (loaded, ranks) = Ranks::load(&args.file, (args.vtu_format, args.vtu_layout))?;
    let t_load = start.elapsed().as_secs_f64();
    let (settings, threads) = cli_settings(&args, &loaded);
    let mut model = loaded.model;
    if let Some(e) = args.enforcement {
        model.pairs.iter_mut().for_each(|p| p.enforcement = e);
    }
    if let Some(f) = args.friction {
        model.pairs.iter_mut().for_each(|p| p.friction = f);
    }
    let model = &model;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| default_dir(model, "out"));
    // Only rank 0 of a distributed run speaks.
    let quiet = args.quiet || !ranks.is_root();

    with_threads(threads, || {
        let mut prepared = prepare_shown(&args.file, model, &settings, &ranks, quiet)?;
        let run = StepRun {
            model,
            settings: &settings,
            factors: loaded.steps.as_deref().unwrap_or_default(),
            monitor: loaded.monitor.as_ref(),
            units: loaded.problem.units.as_deref(),
            out: &out,
            quiet,
            ranks: &ranks,
        };
        if let Some(history) = &loaded.history {
            return run_history(run, history, &mut prepared);
        }
        if loaded.steps.is_some() {
            return run_steps(run, &mut prepared);
        }
        let mut sol = iterate_shown(model, &prepared, &settings, quiet)?;
        drop(prepared); // the factorisations' memory goes back before the output's arrives
        let usage = ranks.usage();
        if ranks.size() > 1 {
            for (r, u) in usage.iter().enumerate() {
                sol.timing
                    .insert(format!("communication_rank{r}"), u.communication);
            }
        }
        let t_reactions = Instant::now();
        let reactions = ranks.reactions(model, &sol);
        sol.timing.insert("load".into(), t_load);
        (sol.timing).insert("reactions".into(), t_reactions.elapsed().as_secs_f64());
        let units = loaded.problem.units.as_deref();
        let t_write = Instant::now();
        let written = ranks
            .write_results(&out, model, &sol, &reactions, units)
            .with_context(|| format!("cannot write the results to '{}'", out.display()))?;
        let t_write = t_write.elapsed().as_secs_f64();
        if !ranks.is_root() {
            // Rank 0 reports; every rank ends with the same exit code.
            return Ok(if sol.converged {
                Exit::Success
            } else {
                Exit::NotConverged
            });
        }

        let outcome = solve_outcome(&sol, &settings);
        if quiet {
            say!("{outcome}; results in {}", out.display());
        } else {
            say!("");
            say!("{outcome}");
            let phases = phases(&sol, (t_load, t_write), start);
            let usage = (ranks.size() > 1).then_some(usage.as_slice());
            print_summary(model, &sol, &reactions, &phases, usage);
            say!("results: {}", files(&out, &written));
        }
        Ok(exit(sol.converged, &out))
    })
}

/// Assembles and factorises every body (with a progress line unless `quiet`); rank 0 prints the
/// contact warnings, before a setup error too.
fn prepare_shown(
    file: &Path,
    model: &Model,
    settings: &contactdd_ddm::Settings,
    ranks: &Ranks,
    quiet: bool,
) -> Result<Prepared> {
    if !quiet {
        progress(&format!(
            "assembling and factorising {}…",
            count(model.bodies.len(), "body", "bodies")
        ));
    }
    let prepared = prepare_on(model, settings, ranks.exchange());
    if let (Err(_), true) = (&prepared, ranks.is_root()) {
        // The contact warnings often explain a failed setup (a body that only a pair facing
        // nowhere would hold is singular): print them before the error.
        if let Ok(interface) = Interface::new(model) {
            warn_contact(file, model, &interface);
        }
    }
    let prepared = prepared.map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))?;
    if ranks.is_root() {
        warn_contact(file, model, &prepared.interface);
    }
    Ok(prepared)
}

/// The result line of a domain decomposition solve.
fn solve_outcome(sol: &contactdd_ddm::Solution, settings: &contactdd_ddm::Settings) -> String {
    let updates = match sol.gap_tol {
        Some(tol) => format!(
            "; augmented Lagrangian: {} multiplier updates, gap-tol {}",
            sol.updates,
            sig(tol)
        ),
        None => String::new(),
    };
    let last = sol.history.last().map_or(String::new(), |r| {
        format!(
            ": {} {:.1e} ≤ tol {:e}",
            settings.measure_name(),
            r.measure,
            settings.tol
        )
    });
    let done = format!(
        "converged in {} iterations ({}{updates}){last}",
        sol.iterations,
        settings.scheme()
    );
    outcome(sol.converged, done, sol.message.as_deref())
}

/// The console's phases of a solve from its `start`: `load`, the solver's phases, `write`, and
/// `other` (start-up, thread pools, this report), so that they add up to the `total`.
fn phases(
    sol: &contactdd_ddm::Solution,
    (load, write): (f64, f64),
    start: Instant,
) -> Vec<(&'static str, f64)> {
    let mut phases = vec![("load", load)];
    phases.extend(
        SOLVE_PHASES
            .iter()
            .filter_map(|&k| Some((k, *sol.timing.get(k)?))),
    );
    phases.push(("write", write));
    let total = start.elapsed().as_secs_f64();
    let timed: f64 = phases.iter().map(|p| p.1).sum();
    phases.push(("other", (total - timed).max(0.0)));
    phases.push(("total", total));
    phases
}

/// The timed phases of a solve, in the order the console reports them.
const SOLVE_PHASES: [&str; 6] = [
    "contact_setup",
    "assemble_factor_condense",
    "iterate",
    "recover",
    "post",
    "reactions",
];

/// The console summary after the outcome line: every pair, the loads, the reactions, the timings
/// and, on several ranks, each rank's use.
fn print_summary(
    model: &Model,
    sol: &contactdd_ddm::Solution,
    reactions: &[BodyReactions],
    phases: &[(&str, f64)],
    usage: Option<&[RankUse]>,
) {
    for line in pair_report(model, &sol.contact, &sol.theta) {
        say!("{line}");
    }
    say!("{}", applied_loads(model, sol.load_factor));
    let sparse: Vec<&str> = (model.bodies.iter().zip(&sol.condensation))
        .filter(|(_, &path)| path == Condensation::Sparse)
        .map(|(b, _)| b.name.as_str())
        .collect();
    if !sparse.is_empty() {
        say!("sparse condensation: {}", sparse.join(", "));
    }
    for line in reaction_report(reactions) {
        say!("{line}");
    }
    say!("{}", timing(phases.to_vec()));
    if let Some(usage) = usage {
        say!("{}", rank_report(usage));
    }
}

/// The result line: `done`, or why not.
fn outcome(converged: bool, done: String, message: Option<&str>) -> String {
    if converged {
        done
    } else {
        format!("NOT converged: {}", message.unwrap_or("unknown reason"))
    }
}

/// One line on the ranks of a distributed run: communication time, values received (gathered,
/// point to point) and peak memory of each.
fn rank_report(usage: &[RankUse]) -> String {
    let ranks: Vec<String> = usage
        .iter()
        .enumerate()
        .map(|(r, u)| {
            format!(
                "rank {r} communication {:.3} s (received {} values gathered, {} point to point), \
                 peak memory {:.0} MiB",
                u.communication, u.gathered, u.point_to_point, u.peak_mib
            )
        })
        .collect();
    format!("ranks: {}", ranks.join("; "))
}

/// The exit code, with a warning where the last iterate of a run that did not converge went.
fn exit(converged: bool, out: &Path) -> Exit {
    if converged {
        Exit::Success
    } else {
        eprintln!(
            "warning: not converged; the last iterate was written to '{}'",
            out.display()
        );
        Exit::NotConverged
    }
}

/// The model of `contactdd monolithic`: the command line's enforcement and friction on every
/// pair.
fn monolithic_model(args: &MonolithicArgs, mut model: Model) -> Result<Model> {
    if let Some(e) = args.enforcement {
        model.pairs.iter_mut().for_each(|p| p.enforcement = e);
    }
    if let Some(f) = args.friction {
        model.pairs.iter_mut().for_each(|p| p.friction = f);
    }
    Ok(model)
}

/// `contactdd monolithic`.
pub fn monolithic(args: MonolithicArgs) -> Result<Exit> {
    let start = Instant::now();
    let loaded = load(&args.file)?;
    let output = loaded.problem.output;
    let vtu = VtuOptions {
        format: args.vtu_format.or(output.vtu).unwrap_or_default(),
        layout: args.vtu_layout.or(output.vtu_layout).unwrap_or_default(),
    };
    let (settings, threads) = monolithic_settings(&args, &loaded);
    let model = &monolithic_model(&args, loaded.model)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| default_dir(model, "monolithic-out"));
    let quiet = args.quiet;
    with_threads(threads, || {
        // Contact geometry errors are input errors (exit 1).
        let interface = Interface::new(model).map_err(|e| anyhow::anyhow!("{e}"))?;
        contact_check::refuse(&warn_contact(&args.file, model, &interface))
            .map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?;
        if !quiet {
            progress(&format!(
                "assembling, factorising and reducing {}…",
                count(model.bodies.len(), "body", "bodies")
            ));
        }
        let print_step = |r: &MonolithicStep| {
            say!(
                "{:>5}  {:>8}  {:>10.2e}  {:>7.4}",
                r.step,
                r.active,
                r.residual,
                r.step_length
            )
        };
        if !quiet {
            say!(
                "solving {} monolithically by semismooth Newton: {}, {}, max-steps {}",
                model.name,
                count(model.bodies.len(), "body", "bodies"),
                count(model.pairs.len(), "contact pair", "contact pairs"),
                settings.max_steps
            );
            say!(" step    closed    residual   length");
        }
        let hook: Option<&(dyn Fn(&MonolithicStep) + Sync)> =
            if quiet { None } else { Some(&print_step) };
        // A model that cannot be solved is an input error (exit 1), with the message of `solve`.
        let sol =
            solve_monolithic_with(model, &settings, hook).map_err(|e| anyhow::anyhow!("{e}"))?;
        let written = write_monolithic_results(&out, model, &sol, vtu)
            .with_context(|| format!("cannot write the results to '{}'", out.display()))?;
        let outcome = monolithic_outcome(&sol);
        if quiet {
            say!("{outcome}; results in {}", out.display());
        } else {
            say!("");
            say!("monolithic reference for {}: {outcome}", model.name);
            report_monolithic(model, &sol);
            say!(
                "{}",
                timing([
                    ("solve", sol.seconds),
                    ("total", start.elapsed().as_secs_f64())
                ])
            );
            say!("results: {}", files(&out, &written));
        }
        Ok(exit(sol.converged, &out))
    })
}

/// The file's settings with `monolithic`'s command-line overrides; returns them and the thread
/// count.
fn monolithic_settings(
    args: &MonolithicArgs,
    loaded: &Loaded,
) -> (MonolithicSettings, Option<usize>) {
    let threads = args
        .threads
        .map(|n| usize::try_from(n).unwrap_or(usize::MAX))
        .or(loaded.threads);
    let mut settings = MonolithicSettings {
        gap_tol: args.gap_tol.or(loaded.settings.gap_tol),
        ..MonolithicSettings::default()
    };
    if let Some(b) = loaded.settings.balance_tol {
        settings.balance_tol = b;
    }
    if let Some(k) = args.max_steps {
        settings.max_steps = usize::try_from(k).unwrap_or(usize::MAX);
    }
    (settings, threads)
}

/// The result line of a monolithic solve.
fn monolithic_outcome(sol: &MonolithicSolution) -> String {
    let done = if sol.updates > 0 {
        format!(
            "converged in {} semismooth Newton solves (augmented Lagrangian multiplier updates), the last {} steps",
            sol.updates, sol.newton_steps
        )
    } else {
        format!("converged in {} semismooth Newton steps", sol.newton_steps)
    };
    outcome(sol.converged, done, sol.message.as_deref())
}

/// Prints the warnings about the contact geometry on stderr; returns all findings.
fn warn_contact(file: &Path, model: &Model, interface: &Interface) -> Vec<contact_check::Finding> {
    let findings = contact_check::check(model, interface);
    for f in findings.iter().filter(|f| !f.is_error()) {
        eprintln!("warning: {}: {f}", file.display());
    }
    findings
}

/// The rigid modes, the equilibrium residuals and the contact report of a monolithic solve.
fn report_monolithic(model: &Model, sol: &MonolithicSolution) {
    if sol.rigid_modes.is_empty() {
        say!("rigid modes fixed: none");
    } else {
        say!("rigid modes fixed (no contact resists them):");
        for (m, f) in sol.rigid_modes.iter().zip(&sol.imbalance) {
            say!("  {m}; net force along it {f:.1e} of the forces");
        }
    }
    let worst = sol.equilibrium.iter().fold(0.0f64, |a, &b| a.max(b));
    say!("equilibrium: largest residual {worst:.1e} of the forces");
    for line in pair_report(model, &sol.contact, &model.thetas()) {
        say!("{line}");
    }
    say!("{}", applied_loads(model, 1.0));
}

/// `./<problem name>-<suffix>`.
fn default_dir(model: &Model, suffix: &str) -> PathBuf {
    PathBuf::from(format!("{}-{suffix}", safe_file_name(&model.name)))
}

/// `dir/ (a, b, c)`.
fn files(dir: &Path, written: &[PathBuf]) -> String {
    let names: Vec<String> = written
        .iter()
        .filter_map(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .collect();
    format!("{}/ ({})", dir.display(), names.join(", "))
}

/// `1 body`, `2 bodies`.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

#[cfg(test)]
mod tests {
    use super::shown;

    #[test]
    fn long_runs_print_a_few_dozen_lines() {
        let lines: Vec<usize> = (1..=6631).filter(|&k| shown(k)).collect();
        assert_eq!(&lines[..12], &[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 20, 30]);
        assert!(lines.contains(&100) && lines.contains(&6000) && !lines.contains(&6100));
        assert_eq!(lines.len(), 33);
    }
}
