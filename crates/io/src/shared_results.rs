//! A solve's result folder written by the processes of a distributed solve together: each writes
//! the `.vtu` files of its own bodies, the first (the root) everything else — `contact.csv`,
//! `history.csv`, `results.pvd` over every body's file, and `summary.json` last with the manifest
//! of all of them. The folder is the one [`crate::output::write_results_noted`] writes in one
//! process, file for file.
//!
//! The processes take turns through `agree`, a collective that hands every process the first
//! error of any (the command line's MPI exchange): the root removes the previous set before
//! anyone writes, and writes the summary only once every process has written its files.

use std::io::Error;
use std::path::{Path, PathBuf};

use serde_json::json;

use contactdd_ddm::{Model, Solution};

use crate::output::{contact_csv, history_csv, summary_json, vtu_paths, write_solution_vtus_of};
use crate::result_set::ResultSet;

/// How this process takes part in writing a shared result folder.
pub struct Part<'a> {
    /// Whether this process writes the shared files and the summary.
    pub root: bool,
    /// The bodies whose `.vtu` this process writes.
    pub owns: &'a dyn Fn(usize) -> bool,
    /// The collective that returns the first error of any process (the same on every process).
    pub agree: &'a dyn Fn(Option<String>) -> Option<String>,
}

/// Writes this process's part of the result folder `dir` of `sol` (every process holds the whole
/// solution). Returns the paths this process wrote (the root's list ends with `summary.json`);
/// every process returns the same error if any failed.
pub fn write_results_shared(
    dir: &Path,
    model: &Model,
    sol: &Solution,
    units: Option<&str>,
    part: &Part<'_>,
) -> std::io::Result<Vec<PathBuf>> {
    let begun = if part.root {
        ResultSet::begin(dir).map(Some)
    } else {
        Ok(None)
    };
    agreed(part, begun.as_ref().err())?;
    let set = begun?;
    let mut own = Vec::new();
    let written = write_solution_vtus_of(
        dir,
        model,
        &sol.bodies,
        &sol.contact,
        "",
        part.owns,
        &mut own,
    );
    if let Err(e) = agreed(part, written.as_ref().err()) {
        own.iter().for_each(|p| drop(std::fs::remove_file(p)));
        if let Some(set) = set {
            set.abandon();
        }
        return Err(e);
    }
    let Some(mut set) = set else {
        return Ok(own);
    };
    let mut summary = summary_json(model, sol);
    summary["units"] = json!(units);
    let shared = (|| {
        set.write("contact.csv", contact_csv(sol).as_bytes())?;
        set.write("history.csv", history_csv(sol).as_bytes())?;
        let before = set.len();
        set.record(vtu_paths(dir, "", &sol.bodies));
        let entries: Vec<(f64, usize, String)> = set
            .names_since(before)
            .into_iter()
            .enumerate()
            .map(|(part, name)| (1.0, part, name))
            .collect();
        set.write("results.pvd", crate::steps::pvd(&entries).as_bytes())
    })();
    match shared {
        Ok(()) => set.finish(summary),
        Err(e) => {
            set.abandon();
            Err(e)
        }
    }
}

/// The first error of any process, as an error of this one.
fn agreed(part: &Part<'_>, error: Option<&Error>) -> std::io::Result<()> {
    match (part.agree)(error.map(|e| e.to_string())) {
        Some(message) => Err(Error::other(message)),
        None => Ok(()),
    }
}
