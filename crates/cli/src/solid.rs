//! The commands on a problem file in space (`dimension = 3`): `solve` (the decomposition),
//! `monolithic` (the reference) and `check`. The options of the planar iterations that do not
//! exist in space yet are refused by name rather than ignored.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};

use contactdd_ddm::contact3d::DiscStatus;
use contactdd_ddm::solid_contact::SolidProgress;
use contactdd_io::body_vtus::safe_file_name;
use contactdd_io::solid_problem::is_solid_text;
use contactdd_io::solid_results::write_solid_results;
use contactdd_io::solid_run::{run_solid_reported, tangential_force, SolidOutcome, SolidSolver};
use contactdd_io::solid_setup::{load_solid_file, SolidModel};
use contactdd_io::vtu::VtuLayout;

use crate::args::{CheckArgs, MonolithicArgs, SolveArgs};
use crate::solve::count;
use crate::{with_threads, Exit};

/// Whether `path` holds a problem in space (a top-level `dimension` key). A file that cannot be
/// read counts as planar: the planar loader then reports why.
pub fn is_solid_file(path: &Path) -> bool {
    std::fs::read_to_string(path).is_ok_and(|t| is_solid_text(&t))
}

/// The options that have no meaning in space yet, named.
fn refuse(options: &[(&str, bool)]) -> Result<()> {
    let given: Vec<&str> = options.iter().filter(|o| o.1).map(|o| o.0).collect();
    if given.is_empty() {
        return Ok(());
    }
    bail!(
        "{} not available for problems in space (dimension = 3): they run the interface Newton \
         method of the decomposition, whose augmented pairs meet the Signorini conditions \
         exactly (no gap tolerance, no iteration tolerance)",
        given.join(", ")
    )
}

/// `contactdd solve` on a problem in space.
pub fn solve(args: SolveArgs) -> Result<Exit> {
    refuse(&[
        ("--method", args.method.is_some()),
        ("--gamma", args.gamma.is_some()),
        ("--accelerator", args.accelerator.is_some()),
        ("--coarse", args.coarse.is_some()),
        ("--gap-tol", args.gap_tol.is_some()),
        ("--tol", args.common.tol.is_some()),
        ("--max-iter", args.common.max_iter.is_some()),
    ])?;
    let mut model = load(&args.file)?;
    overrides(
        &mut model,
        args.balance_tol,
        args.vtu_format,
        args.vtu_layout,
    )?;
    enforce(&mut model, args.enforcement, args.friction);
    let threads = args.common.threads.map(|n| n as usize).or(model.threads);
    let out = (args.out.clone()).unwrap_or_else(|| default_dir(&model, "out"));
    run(
        &model,
        SolidSolver::Decomposition,
        threads,
        &out,
        args.quiet,
    )
}

/// `contactdd monolithic` on a problem in space.
pub fn monolithic(args: MonolithicArgs) -> Result<Exit> {
    refuse(&[
        ("--max-steps", args.max_steps.is_some()),
        ("--gap-tol", args.gap_tol.is_some()),
    ])?;
    let mut model = load(&args.file)?;
    overrides(&mut model, None, args.vtu_format, args.vtu_layout)?;
    enforce(&mut model, args.enforcement, args.friction);
    let threads = args.threads.map(|n| n as usize).or(model.threads);
    let out = (args.out.clone()).unwrap_or_else(|| default_dir(&model, "monolithic-out"));
    run(&model, SolidSolver::Monolithic, threads, &out, args.quiet)
}

/// `contactdd check` on a problem in space: the file loads, its bodies mesh and its pairs
/// resolve.
pub fn check(args: CheckArgs) -> Result<Exit> {
    let mut model = load(&args.file)?;
    enforce(&mut model, None, args.friction);
    say!("{}", describe(&model).trim_end());
    say!(
        "solver: {} (contactdd monolithic: the {})",
        SolidSolver::Decomposition.label(),
        SolidSolver::Monolithic.label()
    );
    say!("ok: '{}' is a valid problem", args.file.display());
    Ok(Exit::Success)
}

/// The command line's `--enforcement` and `--friction`, for every pair.
fn enforce(
    model: &mut SolidModel,
    enforcement: Option<contactdd_ddm::Enforcement>,
    friction: Option<contactdd_ddm::Friction>,
) {
    for p in &mut model.pairs {
        p.enforcement = enforcement.unwrap_or(p.enforcement);
        p.friction = friction.unwrap_or(p.friction);
    }
}

fn load(path: &Path) -> Result<SolidModel> {
    load_solid_file(path).map_err(|e| anyhow::anyhow!("{e}"))
}

/// The command line's `--balance-tol`, `--vtu-format` and `--vtu-layout`.
fn overrides(
    model: &mut SolidModel,
    balance_tol: Option<f64>,
    format: Option<contactdd_io::vtu::VtuFormat>,
    layout: Option<VtuLayout>,
) -> Result<()> {
    if let Some(b) = balance_tol {
        model.balance_tol = b;
    }
    if let Some(f) = format {
        model.output.vtu = Some(f);
    }
    if let Some(l) = layout {
        model.output.vtu_layout = Some(l);
    }
    Ok(())
}

/// Solves, writes the result folder and reports.
fn run(
    model: &SolidModel,
    solver: SolidSolver,
    threads: Option<usize>,
    out: &Path,
    quiet: bool,
) -> Result<Exit> {
    if !quiet {
        say!("{}", describe(model).trim_end());
        say!("solving by the {} …", solver.label());
    }
    let started = Instant::now();
    let report = |p: SolidProgress| {
        if !quiet {
            say!("  {}", progress(model, p));
        }
    };
    let outcome = with_threads(threads, || {
        run_solid_reported(model, solver, &report).map_err(|e| anyhow::anyhow!("{e}"))
    })?;
    let solve_time = started.elapsed().as_secs_f64();
    let written = write_solid_results(out, model, &outcome)
        .with_context(|| format!("cannot write the results to '{}'", out.display()))?;
    let verdict = verdict(model, &outcome);
    if quiet {
        say!("{verdict}; results in {}", out.display());
    } else {
        say!("{verdict}");
        for line in pair_lines(model, &outcome) {
            say!("{line}");
        }
        let phases: Vec<String> = (outcome.solution.timings.iter())
            .map(|(p, s)| format!("{p} {s:.3} s"))
            .collect();
        say!("phases: {} (solve {solve_time:.3} s)", phases.join(", "));
        let names: Vec<String> = (written.iter())
            .filter_map(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .collect();
        say!("results: {}/ ({})", out.display(), names.join(", "));
    }
    if outcome.converged {
        Ok(Exit::Success)
    } else {
        eprintln!(
            "warning: not converged; the result was written to '{}'",
            out.display()
        );
        Ok(Exit::NotConverged)
    }
}

/// One progress line of the decomposition.
fn progress(model: &SolidModel, p: SolidProgress) -> String {
    match p {
        SolidProgress::Geometry { points } => {
            format!("contact geometry: {}", count(points, "point", "points"))
        }
        SolidProgress::Condensed { body, seconds } => format!(
            "body {}: factorised and condensed ({seconds:.2} s to factorise)",
            model.bodies[body].name
        ),
        SolidProgress::LoadStep { step, of, factor } => {
            format!("load step {step} of {of}: load factor {factor}")
        }
        SolidProgress::NewtonStep { step, closed } => {
            format!("Newton step {step}: {closed} closed")
        }
    }
}

/// The verdict line: converged only with the check passed.
fn verdict(model: &SolidModel, o: &SolidOutcome) -> String {
    let steps = count(o.solution.newton_steps, "Newton step", "Newton steps");
    let worst = o.balance.worst();
    let floor = o.balance.bodies.iter().map(|b| b.floor).fold(0.0, f64::max);
    let bound = if worst <= model.balance_tol {
        format!("≤ balance-tol {:.0e}", model.balance_tol)
    } else {
        format!(
            "within the rounding floor {floor:.1e} (balance-tol {:.0e})",
            model.balance_tol
        )
    };
    match &o.reason {
        None => format!(
            "converged in {steps} ({}): force balance {worst:.1e} {bound}",
            o.solver.label()
        ),
        Some(why) => format!("not converged after {steps} ({}): {why}", o.solver.label()),
    }
}

/// One line per pair: points, closed points, normal force, peak pressure.
fn pair_lines(model: &SolidModel, o: &SolidOutcome) -> Vec<String> {
    (model.pairs.iter().enumerate())
        .map(|(k, p)| {
            let points: Vec<_> = o.solution.points.iter().filter(|q| q.pair == k).collect();
            let closed = points.iter().filter(|q| q.pressure > 0.0).count();
            let force: f64 = points.iter().map(|q| q.weight * q.pressure).sum();
            let peak = points.iter().map(|q| q.pressure).fold(0.0, f64::max);
            let mut line = format!(
                "pair {}: {} with a partner, {closed} closed; normal force {force:.6e}, peak pressure {peak:.6e}",
                p.name,
                count(points.len(), "point", "points")
            );
            if p.friction.is_active() {
                let slip = (points.iter())
                    .filter(|q| q.friction.as_ref().is_some_and(|f| f.status == Some(DiscStatus::Slip)))
                    .count();
                let [x, y, z] = tangential_force(&o.solution, k);
                line.push_str(&format!(
                    "; {slip} of {closed} slip; tangential force ({x:.6e}, {y:.6e}, {z:.6e})"
                ));
            }
            line
        })
        .collect()
}

/// The description `check` and `solve` print: the problem, each body, each pair.
fn describe(model: &SolidModel) -> String {
    let mut out = format!(
        "problem {} (space): {}, {}\n",
        model.name,
        count(model.bodies.len(), "body", "bodies"),
        count(model.pairs.len(), "contact pair", "contact pairs")
    );
    for b in &model.bodies {
        out.push_str(&format!(
            "  body {}: {} nodes, {} tetrahedra ({:?}), {} prescribed DOFs\n",
            b.name,
            b.mesh.num_nodes(),
            b.mesh.num_tets(),
            b.mesh.order(),
            b.prescribed.len()
        ));
    }
    for p in &model.pairs {
        out.push_str(&format!(
            "  pair {}: {}:{} against {}:{}, theta {:.3e}, search {:.3e}, {}\n",
            p.name,
            model.bodies[p.sides[0].0].name,
            p.sides[0].1,
            model.bodies[p.sides[1].0].name,
            p.sides[1].1,
            p.theta,
            p.search,
            p.enforcement
        ));
        if p.friction.is_active() {
            out.insert_str(out.len() - 1, &format!(", friction: {}", p.friction));
        }
    }
    if model.load_factors.len() > 1 {
        out.push_str(&format!(
            "  load steps: {} (load factors {:?})\n",
            model.load_factors.len(),
            model.load_factors
        ));
    }
    out
}

fn default_dir(model: &SolidModel, suffix: &str) -> PathBuf {
    PathBuf::from(format!("{}-{suffix}", safe_file_name(&model.name)))
}
