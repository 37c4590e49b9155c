//! Result files of a solve: `summary.json`, `contact.csv`, `history.csv` and one `.vtu` per body
//! (or one for all bodies, [`VtuLayout::Collection`]), plus the CSV table of a γ sweep.
//!
//! The text builders ([`summary_json`], [`contact_csv`], [`history_csv`], [`sweep_csv`]) only
//! format; [`write_results`] writes a whole result folder. Every file is written by
//! [`write_atomic`] (re-exported from [`crate::atomic`]): to a temporary file in the target
//! folder, then renamed, so a reader (or a crash mid-write) never leaves a half-written file
//! behind.
//!
//! The text of each file is built by its own module: [`crate::summary`] (`summary.json`, whose
//! keys it lists; JSON has no NaN or infinity, so every non-finite value becomes `null`),
//! [`crate::csv_tables`] (the CSV files, where such values are `inf`, `-inf` or `NaN`),
//! [`crate::body_vtus`] (the `.vtu` of each body) and [`crate::steps`] (the tables of a load-step
//! run); this module re-exports their public items. Every folder, of one process or of several,
//! is written by [`crate::distributed_results`].
//!
//! [`write_results`] writes the folder as a set ([`crate::result_set`]): the data files first,
//! `summary.json` last, so a folder without `summary.json` holds no complete result.

use std::path::{Path, PathBuf};

use contactdd_ddm::{Model, MonolithicSolution, Solution};

use crate::distributed_results::{write_results_shared, write_step_results_shared, Part};
use crate::load_steps::Monitor;
use crate::reactions::reactions;
use crate::result_set::write_set;
use crate::steps::HistoryLabels;

pub use crate::atomic::write_atomic;
pub use crate::body_vtus::{
    safe_file_name, write_body_vtus, write_solution_vtus, write_solution_vtus_as,
};
pub use crate::csv_tables::{contact_csv, history_csv, pairs_csv, sweep_csv};
pub use crate::summary::{
    json_number, monolithic_summary_json, point_status, reactions_json, stop_name, summary_json,
    summary_json_with,
};
pub use crate::vtu::{VtuFormat, VtuLayout, VtuOptions};
pub use contactdd_core::loads::applied_load;

/// Writes a solve's result folder (created if needed) as a set ([`write_set`]): `contact.csv`,
/// `history.csv`, `<body>.vtu` per body and `results.pvd` (the ParaView collection of the bodies),
/// then `summary.json` with the manifest of those files.
/// The previous set in `dir` is removed first. Returns the paths written, `summary.json` last.
pub fn write_results(dir: &Path, model: &Model, sol: &Solution) -> std::io::Result<Vec<PathBuf>> {
    write_results_noted(dir, model, sol, None, VtuFormat::default())
}

/// [`write_results`] with the problem's units note (`units` of the problem file) in
/// `summary.json`, for the axes of `contactdd plot`, and the `.vtu` files in `vtu` (a
/// [`VtuFormat`], one file per body, or [`VtuOptions`] with the layout).
pub fn write_results_noted(
    dir: &Path,
    model: &Model,
    sol: &Solution,
    units: Option<&str>,
    vtu: impl Into<VtuOptions>,
) -> std::io::Result<Vec<PathBuf>> {
    let reactions = reactions(model, &sol.bodies, &sol.contact);
    write_results_shared(dir, model, sol, &reactions, units, &Part::alone_as(vtu))
}

/// Writes a monolithic solve's result folder as a set, like [`write_results`]: `contact.csv`
/// (frictionless: the monolithic reference refuses friction) and
/// `<body>.vtu` per body, then `summary.json` ([`monolithic_summary_json`] with the reactions and
/// the manifest) last, the `.vtu` files in `vtu` (as [`write_results_noted`]). Returns the paths
/// written, `summary.json` last.
pub fn write_monolithic_results(
    dir: &Path,
    model: &Model,
    sol: &MonolithicSolution,
    vtu: impl Into<VtuOptions>,
) -> std::io::Result<Vec<PathBuf>> {
    let vtu = vtu.into();
    let mut summary = monolithic_summary_json(model, sol);
    summary["reactions"] = reactions_json(model, &sol.bodies, &sol.contact);
    write_set(dir, summary, |set| {
        set.write(
            "contact.csv",
            pairs_csv(&sol.contact, &sol.bodies, false).as_bytes(),
        )?;
        write_solution_vtus_as(set, model, &sol.bodies, &sol.contact, "", vtu)
    })
}

/// Writes the result folder of a load-step run as a set (see [`crate::steps`]), with the problem's
/// `units` note in `summary.json` and the `.vtu` files in `vtu` (as [`write_results_noted`]).
/// Returns the paths written, `summary.json` last.
pub fn write_step_results(
    dir: &Path,
    model: &Model,
    steps: &[(f64, Solution)],
    (monitor, units): (Option<&Monitor>, Option<&str>),
    vtu: impl Into<VtuOptions>,
) -> std::io::Result<Vec<PathBuf>> {
    let part = Part::alone_as(vtu);
    write_step_results_shared(dir, model, steps, monitor, units, None, &part)
}

/// [`write_step_results`] for a load history: `steps` are the increments (with their
/// [`HistoryLabels::times`]), labelled by `labels`.
pub fn write_history_results(
    dir: &Path,
    model: &Model,
    steps: &[(f64, Solution)],
    (monitor, units): (Option<&Monitor>, Option<&str>),
    labels: &HistoryLabels,
    vtu: impl Into<VtuOptions>,
) -> std::io::Result<Vec<PathBuf>> {
    let part = Part::alone_as(vtu);
    write_step_results_shared(dir, model, steps, monitor, units, Some(labels), &part)
}
