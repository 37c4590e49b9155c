//! `contactdd plot`: figures from a result folder (contact pressure, gap and status, friction,
//! convergence history, load steps, the deformed bodies coloured by von Mises stress; in space, the
//! pressure map and radial profile of `plot_space`) or from the CSV of a
//! sweep (iterations against γ), as SVG and PNG. Only the files that `summary.json` lists are
//! read, each a plain name in the folder, a regular file itself (no link followed, no FIFO or
//! device opened) and of bounded size ([`crate::plot_data::read_text`]); figures are written only
//! into the output folder, which must be a folder itself (not a link to one), each atomically,
//! never over anything but a regular file. A run that draws no figure is an error.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use crate::args::PlotArgs;
use crate::plot_data::{monitor_name, Summary, Table, Units};
use crate::plot_history::History;
use crate::{
    load, plot_contact, plot_friction, plot_history, plot_mesh, plot_space, plot_steps, plot_sweep,
    Exit,
};

/// `contactdd plot`.
pub fn plot(args: PlotArgs) -> Result<Exit> {
    let (written, out) = match folder_of(&args.results) {
        Some(dir) => folder(&args, &dir)?,
        None => sweep(&args)?,
    };
    if args.quiet {
        say!("wrote {} figure files to {}", written.len(), shown(&out));
    } else {
        for path in &written {
            say!("wrote {}", path.display());
        }
    }
    Ok(Exit::Success)
}

/// The result folder that `results` names: a folder, or the folder of a `summary.json` given
/// as a file; `None` for any other file (the CSV of a sweep).
fn folder_of(results: &Path) -> Option<PathBuf> {
    if !results.is_file() {
        return Some(results.to_path_buf());
    }
    if results.file_name()? != "summary.json" {
        return None;
    }
    Some(
        results
            .parent()
            .map_or_else(PathBuf::new, Path::to_path_buf),
    )
}

/// A folder for a message: `.` for the current one.
fn shown(dir: &Path) -> String {
    if dir.as_os_str().is_empty() {
        ".".into()
    } else {
        dir.display().to_string()
    }
}

/// The figures of the result folder `dir`, into `--out` (default `dir/plots`); returns the
/// files written and the folder.
fn folder(args: &PlotArgs, dir: &Path) -> Result<(Vec<PathBuf>, PathBuf)> {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let mut summary = Summary::read(dir)?;
    let space = summary.dimension == 3;
    if space {
        plot_space::notes(args);
    } else if let Some(file) = &args.problem {
        let loaded = load(file)?;
        // What the result records wins: a solve may have overridden the file's tol.
        summary.tol = summary.tol.or(Some(loaded.settings.tol));
        summary.units = summary.units.or(loaded.problem.units);
        let monitor = loaded.problem.solver.monitor;
        let named = monitor.map(|m| monitor_name(&m.body, &m.boundary));
        summary.monitor = summary.monitor.or(named);
    }
    let units = Units::parse(args.units.as_deref().or(summary.units.as_deref()));
    let out = args.out.clone().unwrap_or_else(|| dir.join("plots"));
    let created = output_folder(&out)?;
    let written = if space {
        plot_space::figures(dir, &summary, &units, &out, &args.format)
    } else {
        draw(args, dir, &summary, &units, &out)
    };
    if created && !written.as_ref().is_ok_and(|w| !w.is_empty()) {
        // Leave no empty folder behind (`remove_dir` removes only an empty one).
        let _ = std::fs::remove_dir(&out);
    }
    let written = written?;
    if written.is_empty() {
        bail!(
            "'{}': no figure to draw: its summary.json lists none of contact.csv, history.csv, \
             steps.csv or a body's .vtu file with ASCII arrays (see docs/plots.md)",
            dir.join("summary.json").display()
        );
    }
    Ok((written, out))
}

/// The figures of the result folder `dir` with `summary` into the folder `out`.
fn draw(
    args: &PlotArgs,
    dir: &Path,
    summary: &Summary,
    units: &Units,
    out: &Path,
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let table = |name: &str| Table::read(&dir.join(name));
    if summary.has("contact.csv") {
        let table = table("contact.csv")?;
        written.extend(plot_contact::figures(&table, units, out, &args.format)?);
        let laws = &summary.friction;
        let file = dir.join("summary.json");
        let fig = plot_friction::figures(&table, laws, &file, units, out, &args.format)?;
        written.extend(fig);
    }
    if summary.has("history.csv") {
        let history = History {
            table: table("history.csv")?,
            bodies: &summary.bodies,
            tol: args.tol.or(summary.tol),
            measure: summary.stop_measure.as_deref(),
            steps: summary.steps,
        };
        written.extend(plot_history::figures(&history, out, &args.format)?);
    }
    if summary.has("steps.csv") {
        let table = table("steps.csv")?;
        let monitor = summary.monitor.as_deref();
        let fig = plot_steps::figures(&table, units, monitor, out, &args.format)?;
        written.extend(fig);
    }
    let vtu = summary.listed(".vtu");
    written.extend(plot_mesh::figures(dir, &vtu, units, out, &args.format)?);
    Ok(written)
}

/// The figure of a sweep CSV, into `--out` (default: the CSV's folder), named after the CSV.
fn sweep(args: &PlotArgs) -> Result<(Vec<PathBuf>, PathBuf)> {
    let path = &args.results;
    let table = Table::read(path)?;
    let out = match &args.out {
        Some(out) => out.clone(),
        None => path.parent().map(Path::to_path_buf).unwrap_or_default(),
    };
    let created = output_folder(&out)?;
    let stem = path
        .file_stem()
        .map_or_else(|| "sweep".into(), |s| s.to_string_lossy().into_owned());
    let written = plot_sweep::figures(&table, &out, &stem, &args.format);
    if created && !written.as_ref().is_ok_and(|w| !w.is_empty()) {
        let _ = std::fs::remove_dir(&out);
    }
    let written = written?;
    if written.is_empty() {
        bail!("'{}': no figure to draw", path.display());
    }
    Ok((written, out))
}

/// Makes `dir` ready for the figures: created if missing; refused if it is a symbolic link (even
/// to a folder: the figures would land outside the folder named, such as a results folder's
/// `plots` pointing elsewhere) or anything but a folder. Returns whether it was created.
fn output_folder(dir: &Path) -> Result<bool> {
    if dir.as_os_str().is_empty() {
        return Ok(false);
    }
    let mut created = false;
    let meta = match std::fs::symlink_metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create '{}'", dir.display()))?;
            created = true;
            std::fs::symlink_metadata(dir)
        }
        other => other,
    }
    .with_context(|| format!("cannot use '{}' for the figures", dir.display()))?;
    if meta.file_type().is_symlink() {
        bail!(
            "'{}' is a symbolic link; figures are written only into a real folder \
             (name the folder it points to with --out if that is where they belong)",
            dir.display()
        );
    }
    if !meta.is_dir() {
        bail!(
            "'{}' is not a folder; cannot write the figures into it",
            dir.display()
        );
    }
    Ok(created)
}
