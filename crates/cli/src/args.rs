//! The command line grammar (clap derive) and the parsers of its values: a method, γ, and the
//! comma-separated lists of a sweep (γ also as `start:stop:step`).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use contactdd_ddm::settings::ANDERSON_DEPTH;
use contactdd_ddm::{Accelerator, CoarseMode, Enforcement, Friction, Gamma, Method};
use contactdd_io::setup::MAX_THREADS;
use contactdd_io::vtu::{VtuFormat, VtuLayout};

const EXIT_CODES: &str = "\
Exit codes:
  0  success (solve: converged; sweep: ran; check: the file is valid; plot: figures written)
  1  bad input (command line, problem file) or I/O error
  2  the solve ran but did not converge or diverged; the results of the last iterate
     are still written and summary.json says \"converged\": false with the reason";

/// Contact of elastic bodies, frictionless or with Coulomb or Tresca friction, by penalty Robin
/// domain decomposition.
#[derive(Debug, Parser)]
#[command(name = "contactdd", version, after_help = EXIT_CODES)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve a problem file and write summary.json, contact.csv, history.csv and one .vtu per body.
    #[command(after_help = EXIT_CODES)]
    Solve(SolveArgs),
    /// Run every method with every γ and tabulate the iteration counts (the paper's study).
    #[command(after_help = EXIT_CODES)]
    Sweep(SweepArgs),
    /// Validate a problem file and describe it, without solving.
    #[command(after_help = EXIT_CODES)]
    Check(CheckArgs),
    /// Solve all bodies at once by semismooth Newton (the reference the DD methods converge to).
    #[command(after_help = EXIT_CODES)]
    Monolithic(MonolithicArgs),
    /// Draw figures (SVG, PNG) from a result folder or a sweep CSV, without ParaView or Python.
    #[command(after_help = EXIT_CODES)]
    Plot(PlotArgs),
}

/// Options shared by the solving commands; they override the file's `[solver]` table.
#[derive(Debug, Args)]
pub struct Common {
    /// Stopping tolerance ε_u on every body's relative change (overrides solver.tol).
    #[arg(long, value_name = "T", value_parser = parse_positive)]
    pub tol: Option<f64>,
    /// Iteration cap (overrides solver.max-iter).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_iter: Option<u64>,
    /// Worker threads (overrides solver.threads; default: all cores).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=MAX_THREADS as u64))]
    pub threads: Option<u64>,
}

/// `contactdd solve`.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Problem file (TOML).
    pub file: PathBuf,
    /// Output folder [default: ./<problem name>-out].
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Method: neumann, robin, active-set, newton-chord or newton-kurchatov.
    #[arg(long, value_name = "M", value_parser = parse_method)]
    pub method: Option<Method>,
    /// Relaxation parameter γ > 0, or "auto" (Aitken). A constant γ alone runs the paper's
    /// one-level iteration (no accelerator, no coarse correction).
    #[arg(long, value_name = "G", value_parser = parse_gamma)]
    pub gamma: Option<Gamma>,
    /// Iteration: newton (the interface Newton method, the default unless --method or --gamma is
    /// given), none (Robin sweeps relaxed with γ) or anderson (sweeps with Anderson acceleration).
    #[arg(long, value_name = "A", value_parser = parse_accelerator)]
    pub accelerator: Option<Accelerator>,
    /// Rigid-body coarse correction: off, chains (floating bodies touching each other) or all.
    #[arg(long, value_name = "C", value_parser = parse_coarse)]
    pub coarse: Option<CoarseMode>,
    /// Contact enforcement of every pair (overrides each pair's `enforcement`): penalty or
    /// augmented (augmented Lagrangian: the exact unilateral contact for any θ).
    #[arg(long, value_name = "E", value_parser = parse_enforcement)]
    pub enforcement: Option<Enforcement>,
    /// Friction of every pair (overrides each pair's `friction`): coulomb:MU (|σ_t| ≤ MU·p),
    /// tresca:BOUND (|σ_t| ≤ BOUND) or none.
    #[arg(long, value_name = "F", value_parser = parse_friction)]
    pub friction: Option<Friction>,
    /// Augmented Lagrangian: the largest violation of the Signorini conditions, a length
    /// (overrides solver.gap-tol).
    #[arg(long, value_name = "L", value_parser = parse_positive)]
    pub gap_tol: Option<f64>,
    /// The largest net force and moment of a body of a converged result, relative to the largest
    /// force total of a body (overrides solver.balance-tol).
    #[arg(long, value_name = "B", value_parser = parse_positive)]
    pub balance_tol: Option<f64>,
    /// Encoding of the .vtu files: zlib (appended binary in zlib blocks, the default), binary
    /// (appended raw binary) or ascii (text, to read or diff); overrides output.vtu.
    #[arg(long, value_name = "E", value_parser = parse_vtu_format)]
    pub vtu_format: Option<VtuFormat>,
    /// Layout of the .vtu files: per-body (one file per body, the default) or collection (one
    /// file per result, bodies.vtu, with each body as its own piece); overrides output.vtu-layout.
    #[arg(long, value_name = "L", value_parser = parse_vtu_layout)]
    pub vtu_layout: Option<VtuLayout>,
    /// Solver options.
    #[command(flatten)]
    pub common: Common,
    /// Print only the final result line (no per-iteration lines).
    #[arg(long, short)]
    pub quiet: bool,
}

/// `contactdd sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Problem file (TOML).
    pub file: PathBuf,
    /// Comma-separated methods.
    #[arg(
        long,
        value_name = "LIST",
        default_value = "active-set,newton-chord,newton-kurchatov",
        value_parser = parse_method_list
    )]
    pub method: MethodList,
    /// Comma-separated γ values, "auto", or ranges start:stop:step (stop included), e.g.
    /// 0.05:0.85:0.05,auto.
    #[arg(long, value_name = "LIST", default_value = "0.1:1:0.1", value_parser = parse_gamma_list)]
    pub gamma: GammaList,
    /// CSV file to write; an existing path must be a regular file (never a link, FIFO or device)
    /// [default: ./<problem name>-sweep.csv].
    #[arg(long, short, value_name = "PATH")]
    pub out: Option<PathBuf>,
    /// Solver options.
    #[command(flatten)]
    pub common: Common,
    /// Print only the line naming the CSV written (no progress, no table).
    #[arg(long, short)]
    pub quiet: bool,
}

/// `contactdd check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Problem file (TOML).
    pub file: PathBuf,
    /// Friction of every pair (overrides each pair's `friction`): coulomb:MU (|σ_t| ≤ MU·p),
    /// tresca:BOUND (|σ_t| ≤ BOUND) or none.
    #[arg(long, value_name = "F", value_parser = parse_friction)]
    pub friction: Option<Friction>,
}

/// `contactdd monolithic`.
#[derive(Debug, Args)]
pub struct MonolithicArgs {
    /// Problem file (TOML).
    pub file: PathBuf,
    /// Output folder [default: ./<problem name>-monolithic-out].
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=MAX_THREADS as u64))]
    pub threads: Option<u64>,
    /// Newton steps at most [default: 50].
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_steps: Option<u64>,
    /// Contact enforcement of every pair (overrides each pair's `enforcement`): penalty or
    /// augmented (Uzawa updates of the multipliers around the Newton solves).
    #[arg(long, value_name = "E", value_parser = parse_enforcement)]
    pub enforcement: Option<Enforcement>,
    /// Friction of every pair (overrides each pair's `friction`): coulomb:MU (|σ_t| ≤ MU·p),
    /// tresca:BOUND (|σ_t| ≤ BOUND) or none.
    #[arg(long, value_name = "F", value_parser = parse_friction)]
    pub friction: Option<Friction>,
    /// Augmented Lagrangian: the largest violation of the Signorini conditions, a length
    /// (overrides solver.gap-tol).
    #[arg(long, value_name = "L", value_parser = parse_positive)]
    pub gap_tol: Option<f64>,
    /// Encoding of the .vtu files: zlib (appended binary in zlib blocks, the default), binary
    /// (appended raw binary) or ascii (text, to read or diff); overrides output.vtu.
    #[arg(long, value_name = "E", value_parser = parse_vtu_format)]
    pub vtu_format: Option<VtuFormat>,
    /// Layout of the .vtu files: per-body (one file per body, the default) or collection (one
    /// file per result, bodies.vtu, with each body as its own piece); overrides output.vtu-layout.
    #[arg(long, value_name = "L", value_parser = parse_vtu_layout)]
    pub vtu_layout: Option<VtuLayout>,
    /// Print only the final result line (no per-step lines).
    #[arg(long, short)]
    pub quiet: bool,
}

/// `contactdd plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// A result folder (of `solve` or `monolithic`: summary.json, contact.csv, …), its
    /// summary.json, or the CSV of a sweep.
    pub results: PathBuf,
    /// Output folder [default: RESULTS/plots for a folder, the CSV's own folder for a sweep].
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Image formats, comma-separated.
    #[arg(
        long,
        value_name = "F",
        value_delimiter = ',',
        default_value = "svg,png"
    )]
    pub format: Vec<Format>,
    /// The problem file that was solved: its `units` note labels the axes and its `tol` draws
    /// the tolerance line, when summary.json does not record them (and unless --units or --tol
    /// say otherwise).
    #[arg(long, value_name = "FILE")]
    pub problem: Option<PathBuf>,
    /// Tolerance line of the convergence history [default: summary.json's `tol`].
    #[arg(long, value_name = "T", value_parser = parse_positive)]
    pub tol: Option<f64>,
    /// Units note "length, stress" for the axes, e.g. "cm, N/cm^2" [default: summary.json's
    /// `units`].
    #[arg(long, value_name = "U")]
    pub units: Option<String>,
    /// Print only one final line (not one line per file written).
    #[arg(long, short)]
    pub quiet: bool,
}

/// An image format of `contactdd plot`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Scalable vector graphics (text as text: no font needed).
    Svg,
    /// A bitmap, its text drawn with the embedded DejaVu Sans font.
    Png,
}

/// A list of methods.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodList(pub Vec<Method>);

/// A list of γ rules.
#[derive(Clone, Debug, PartialEq)]
pub struct GammaList(pub Vec<Gamma>);

/// Most γ values one range may produce.
const MAX_RANGE_VALUES: usize = 10_000;

fn parse_positive(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("expected a positive number, got '{s}'")),
    }
}

fn parse_method(s: &str) -> Result<Method, String> {
    s.trim().parse::<Method>().map_err(|e| e.to_string())
}

fn parse_accelerator(s: &str) -> Result<Accelerator, String> {
    match s {
        "none" => Ok(Accelerator::None),
        "anderson" => Ok(Accelerator::Anderson {
            depth: ANDERSON_DEPTH,
        }),
        "newton" => Ok(Accelerator::Newton),
        _ => Err(format!(
            "unknown accelerator '{s}' (expected none, anderson or newton)"
        )),
    }
}

fn parse_vtu_format(s: &str) -> Result<VtuFormat, String> {
    s.parse::<VtuFormat>().map_err(|e| e.to_string())
}

fn parse_vtu_layout(s: &str) -> Result<VtuLayout, String> {
    s.parse::<VtuLayout>().map_err(|e| e.to_string())
}

fn parse_coarse(s: &str) -> Result<CoarseMode, String> {
    match s {
        "off" => Ok(CoarseMode::Off),
        "chains" => Ok(CoarseMode::Chains),
        "all" => Ok(CoarseMode::All),
        _ => Err(format!(
            "unknown coarse mode '{s}' (expected off, chains or all)"
        )),
    }
}

fn parse_enforcement(s: &str) -> Result<Enforcement, String> {
    match s {
        "penalty" => Ok(Enforcement::Penalty),
        "augmented" => Ok(Enforcement::Augmented),
        _ => Err(format!(
            "unknown enforcement '{s}' (expected penalty or augmented)"
        )),
    }
}

fn parse_friction(s: &str) -> Result<Friction, String> {
    contactdd_io::pairs::parse_friction(s)
}

fn parse_gamma(s: &str) -> Result<Gamma, String> {
    let s = s.trim();
    if s == "auto" {
        return Ok(Gamma::Auto);
    }
    parse_positive(s)
        .map(Gamma::Constant)
        .map_err(|_| format!("expected a positive number or \"auto\", got '{s}'"))
}

fn parse_method_list(s: &str) -> Result<MethodList, String> {
    let methods = s
        .split(',')
        .map(parse_method)
        .collect::<Result<Vec<_>, _>>()?;
    Ok(MethodList(methods))
}

fn parse_gamma_list(s: &str) -> Result<GammaList, String> {
    let mut out = Vec::new();
    for item in s.split(',') {
        let parts: Vec<&str> = item.split(':').collect();
        match parts.as_slice() {
            [one] => out.push(parse_gamma(one)?),
            [start, stop, step] => out.extend(gamma_range(start, stop, step)?),
            _ => {
                return Err(format!(
                    "'{item}': expected a number, \"auto\" or start:stop:step"
                ))
            }
        }
    }
    Ok(GammaList(out))
}

/// start, start + step, … up to and including `stop` (within a small tolerance, so that
/// 0.05:0.85:0.05 ends at 0.85 despite rounding); values are rounded to 12 significant digits.
fn gamma_range(start: &str, stop: &str, step: &str) -> Result<Vec<Gamma>, String> {
    let range = format!("{start}:{stop}:{step}");
    let (start, stop, step) = (
        parse_positive(start),
        parse_positive(stop),
        parse_positive(step),
    );
    let (Ok(start), Ok(stop), Ok(step)) = (start, stop, step) else {
        return Err(format!(
            "'{range}': start, stop and step must be positive numbers"
        ));
    };
    if stop < start {
        return Err(format!("'{range}': stop is smaller than start"));
    }
    let steps = ((stop - start) / step + 1e-9).floor();
    if steps >= MAX_RANGE_VALUES as f64 {
        return Err(format!(
            "'{range}': more than {MAX_RANGE_VALUES} values; use a larger step"
        ));
    }
    let round = |x: f64| {
        let scale = 10f64.powi(11 - x.abs().log10().floor() as i32);
        (x * scale).round() / scale
    };
    Ok((0..=steps as usize)
        .map(|i| Gamma::Constant(round(start + i as f64 * step)))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn constants(list: &GammaList) -> Vec<f64> {
        list.0
            .iter()
            .map(|g| match g {
                Gamma::Constant(v) => *v,
                Gamma::Auto => f64::NAN,
            })
            .collect()
    }

    #[test]
    fn gamma_ranges_include_the_stop_value() {
        let list = parse_gamma_list("0.05:0.85:0.05").unwrap();
        let v = constants(&list);
        assert_eq!(v.len(), 17);
        assert_eq!(v[0], 0.05);
        assert_eq!(v[2], 0.15);
        assert_eq!(v[16], 0.85);
        let list = parse_gamma_list("0.5,auto,0.1:0.3:0.1").unwrap();
        assert_eq!(list.0[1], Gamma::Auto);
        assert_eq!(constants(&list)[2..], [0.1, 0.2, 0.3]);
    }

    #[test]
    fn bad_gamma_lists_are_rejected() {
        for bad in [
            "",
            "0",
            "-1",
            "x",
            "0.1:0.05:0.01",
            "0.1:1",
            "0.1:1:0",
            "1e-9:1:1e-9",
            "nan",
        ] {
            assert!(parse_gamma_list(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn friction_values() {
        assert_eq!(
            parse_friction("coulomb:0.3"),
            Ok(Friction::Coulomb { mu: 0.3 })
        );
        assert_eq!(
            parse_friction("tresca:5"),
            Ok(Friction::Tresca { bound: 5.0 })
        );
        assert_eq!(parse_friction("none"), Ok(Friction::None));
        for (bad, says) in [
            ("coulomb", "coulomb:VALUE"),
            ("coulomb:x", "must be a number"),
            ("coulomb:-0.1", "at least 0"),
            ("coulomb:nan", "finite"),
            ("tresca:-1", "at least 0"),
            ("none:1", "takes no value"),
            ("stick", "unknown friction"),
        ] {
            let err = parse_friction(bad).unwrap_err();
            assert!(err.contains(says), "{bad}: {err}");
        }
    }

    #[test]
    fn method_lists() {
        let m = parse_method_list("robin,active-set").unwrap();
        assert_eq!(m.0, [Method::Robin, Method::ActiveSet]);
        let err = parse_method_list("robin,nope").unwrap_err();
        assert!(err.contains("unknown method 'nope'"), "{err}");
    }
}
