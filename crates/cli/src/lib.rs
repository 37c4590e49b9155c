//! # contactdd-cli
//!
//! The `contactdd` command line: read a TOML problem file, solve it by penalty Robin domain
//! decomposition and write the results; or sweep methods × γ, check a file, or run the monolithic
//! reference. The binary's `main` only calls [`run`], which tests call in-process too.
//!
//! ```text
//! contactdd solve FILE [--out DIR] [--method M] [--gamma G|auto] [--tol T] [--max-iter K]
//!                      [--threads N] [--quiet]
//! contactdd sweep FILE [--method LIST] [--gamma LIST] [--out PATH] [--tol T] [--max-iter K]
//!                      [--threads N]
//! contactdd check FILE
//! contactdd monolithic FILE [--out DIR] [--threads N] [--max-steps K] [--quiet]
//! contactdd plot RESULTS [--out DIR] [--format svg,png] [--tol T] [--units U] [--quiet]
//! ```
//!
//! Exit codes ([`Exit`]):
//!
//! | code | meaning                                                                            |
//! |------|------------------------------------------------------------------------------------|
//! | 0    | success: solved and converged (`solve`), ran (`sweep`), valid (`check`),            |
//! |      | figures written (`plot`)                                                           |
//! | 1    | bad input or I/O error: invalid command line, unreadable or invalid problem file,  |
//! |      | a body that cannot be factorised, results that cannot be written                   |
//! | 2    | ran but did not converge or diverged; the last iterate's results are still written |
//! |      | and `summary.json` says `"converged": false` with the message                      |
//!
//! A write error on stdout other than a closed pipe turns 0 into 1. What is on disk after each
//! exit code: docs/outputs.md.
//!
//! Errors print one line `error: <context>: <cause>` on stderr.

/// `println!` that ignores a closed stdout (`contactdd sweep … | head` must not fail) but
/// remembers any other write error ([`console`]), which turns exit 0 into exit 1.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::console::line(format_args!($($arg)*))
    };
}

mod args;
mod check;
mod console;
#[cfg(feature = "mpi")]
pub mod mpi_exchange;
mod plot;
mod plot_contact;
mod plot_data;
mod plot_draw;
mod plot_friction;
mod plot_history;
mod plot_mesh;
mod plot_space;
mod plot_steps;
mod plot_sweep;
mod rank_use;
pub mod ranks;
mod report;
mod solid;
mod solve;
mod steps;
mod sweep;

use std::ffi::OsString;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::error::ErrorKind;
use clap::Parser;

use args::{Cli, Command};

/// The process outcome, one exit code each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exit {
    /// 0: solved and converged, or the command ran successfully.
    Success = 0,
    /// 1: bad input (command line or problem file) or an I/O error.
    Error = 1,
    /// 2: the solve ran but did not converge (or diverged); results were still written.
    NotConverged = 2,
}

impl From<Exit> for ExitCode {
    fn from(e: Exit) -> ExitCode {
        ExitCode::from(e as u8)
    }
}

/// The exit code of a command's result, with its error said once (every rank of a distributed
/// solve meets the same error; rank 0 says it).
fn reported(result: Result<Exit>) -> Exit {
    match result {
        Ok(exit) => exit,
        Err(e) => {
            if ranks::is_root() {
                eprintln!("error: {e:#}");
            }
            Exit::Error
        }
    }
}

/// Runs the command line `args` (the first item is the program name) and returns the outcome.
/// Output goes to stdout, errors to stderr as `error: …`.
pub fn run<I, T>(args: I) -> Exit
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            // --help and --version are "errors" to clap; print them and succeed.
            let _ = e.print();
            return match e.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => Exit::Success,
                _ => Exit::Error,
            };
        }
    };
    // Only `solve` distributes: under `mpirun` rank 0 runs the other commands alone, and every
    // rank ends with its exit code.
    let exit = match cli.command {
        // A problem in space runs on rank 0 alone (its decomposition has no MPI yet).
        Command::Solve(a) if solid::is_solid_file(&a.file) => {
            ranks::on_root(|| reported(solid::solve(a)))
        }
        Command::Solve(a) => reported(solve::solve(a)),
        Command::Sweep(a) => ranks::on_root(|| reported(sweep::sweep(a))),
        Command::Check(a) if solid::is_solid_file(&a.file) => {
            ranks::on_root(|| reported(solid::check(a)))
        }
        Command::Check(a) => ranks::on_root(|| reported(check::check(a))),
        Command::Monolithic(a) if solid::is_solid_file(&a.file) => {
            ranks::on_root(|| reported(solid::monolithic(a)))
        }
        Command::Monolithic(a) => ranks::on_root(|| reported(solve::monolithic(a))),
        Command::Plot(a) => ranks::on_root(|| reported(plot::plot(a))),
    };
    match console::take_failure() {
        // The report was lost: never claim success.
        Some(e) if exit == Exit::Success => {
            eprintln!("error: cannot write to standard output: {e}");
            Exit::Error
        }
        _ => exit,
    }
}

/// Runs `f` on a rayon pool of `threads` workers, or on the global pool when `None`.
fn with_threads<R>(threads: Option<usize>, f: impl FnOnce() -> Result<R> + Send) -> Result<R>
where
    R: Send,
{
    match threads {
        None => f(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .with_context(|| format!("cannot start {n} worker threads"))?
            .install(f),
    }
}

/// Loads a problem file; the setup error's message already names the file, body and key. A
/// `monitor` that no step would report is warned about on stderr.
fn load(path: &std::path::Path) -> Result<contactdd_io::Loaded> {
    // `to_string` rather than `?`: the message already contains the cause, so a `{:#}` chain
    // would repeat it.
    let loaded = contactdd_io::load_file(path).map_err(|e| anyhow::anyhow!("{e}"))?;
    warn_loaded(path, &loaded);
    Ok(loaded)
}

/// Prints the warnings of a loaded problem file on stderr (a `monitor` that no step reports).
fn warn_loaded(path: &std::path::Path, loaded: &contactdd_io::Loaded) {
    if let Some(warning) = loaded.unreported_monitor() {
        eprintln!("warning: {}: {warning}", path.display());
    }
}
