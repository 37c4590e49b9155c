//! `contactdd plot`: figures from a result folder (contact pressure, gap and status, convergence
//! history, load steps, the deformed bodies coloured by von Mises stress) or from the CSV of a sweep (iterations against γ), as SVG and PNG.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use crate::args::PlotArgs;
use crate::plot_data::{Summary, Table, Units};
use crate::{load, plot_contact, plot_history, plot_mesh, plot_steps, plot_sweep, Exit};

/// `contactdd plot`.
pub fn plot(args: PlotArgs) -> Result<Exit> {
    let written = if args.results.is_file() {
        sweep(&args)?
    } else {
        folder(&args)?
    };
    for path in &written {
        say!("wrote {}", path.display());
    }
    Ok(Exit::Success)
}

/// The figures of a result folder, into `--out` (default `RESULTS/plots`).
fn folder(args: &PlotArgs) -> Result<Vec<PathBuf>> {
    let dir = &args.results;
    let mut summary = Summary::read(dir)?;
    if let Some(file) = &args.problem {
        let loaded = load(file)?;
        // What the result records wins: a solve may have overridden the file's tol.
        summary.tol = summary.tol.or(Some(loaded.settings.tol));
        summary.units = summary.units.or(loaded.problem.units);
    }
    let units = Units::parse(args.units.as_deref().or(summary.units.as_deref()));
    let out = args.out.clone().unwrap_or_else(|| dir.join("plots"));
    create(&out)?;
    let mut written = Vec::new();
    if summary.has("contact.csv") {
        let table = Table::read(&dir.join("contact.csv"))?;
        written.extend(plot_contact::figures(&table, &units, &out, &args.format)?);
    }
    if summary.has("history.csv") {
        let table = Table::read(&dir.join("history.csv"))?;
        let tol = args.tol.or(summary.tol);
        written.extend(plot_history::figures(&table, tol, &out, &args.format)?);
    }
    if summary.has("steps.csv") {
        let table = Table::read(&dir.join("steps.csv"))?;
        written.extend(plot_steps::figures(&table, &units, &out, &args.format)?);
    }
    written.extend(plot_mesh::figures(
        dir,
        &summary.files,
        &units,
        &out,
        &args.format,
    )?);
    Ok(written)
}

/// The figure of a sweep CSV, into `--out` (default: the CSV's folder), named after the CSV.
fn sweep(args: &PlotArgs) -> Result<Vec<PathBuf>> {
    let path = &args.results;
    let table = Table::read(path)?;
    let out = match &args.out {
        Some(out) => out.clone(),
        None => path.parent().map(Path::to_path_buf).unwrap_or_default(),
    };
    create(&out)?;
    let stem = path
        .file_stem()
        .map_or_else(|| "sweep".into(), |s| s.to_string_lossy().into_owned());
    plot_sweep::figures(&table, &out, &stem, &args.format)
}

fn create(dir: &Path) -> Result<()> {
    if dir.as_os_str().is_empty() {
        return Ok(());
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create '{}'", dir.display()))
}
