//! A solve's result folder written by the processes of a distributed solve together: each writes
//! the `.vtu` files of its own bodies, the first (the root) everything else — `contact.csv`,
//! `history.csv` (and for load steps `steps.csv`), `results.pvd` over every body's file, and
//! `summary.json` last with the manifest of all of them. The folder is the one
//! [`crate::output::write_results_noted`] (or [`crate::output::write_step_results`]) writes in one
//! process, file for file: a single process writes through the same code, as [`Part::alone`].
//!
//! The processes take turns through `agree`, a collective that hands every process the first
//! error of any (the command line's MPI exchange): the root removes the previous set before
//! anyone writes, and writes the summary only once every process has written its files.

use std::io::{Error, ErrorKind};
use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use contactdd_ddm::{Model, Solution};

use crate::body_vtus::{
    collection_path, vtu_paths, write_solution_collection, write_solution_vtus_of,
};
use crate::csv_tables::{contact_csv, history_csv};
use crate::load_steps::Monitor;
use crate::packed::{pack_reactions, unpack_reactions};
use crate::reactions::{body_reactions, BodyReactions};
use crate::result_set::{staging_dir, ResultSet};
use crate::steps::{monitored_displacement, pvd, steps_csv, steps_json, HistoryLabels};
use crate::summary::summary_json_with;
use crate::vtu::{CollectionOverRanks, VtuFormat, VtuLayout, VtuOptions};

/// How this process takes part in writing a shared result folder.
pub struct Part<'a> {
    /// Whether this process writes the shared files and the summary.
    pub root: bool,
    /// The bodies whose `.vtu` this process writes.
    pub owns: Box<dyn Fn(usize) -> bool + 'a>,
    /// The collective that returns the first error of any process (the same on every process).
    pub agree: Box<dyn Fn(Option<String>) -> Option<String> + 'a>,
    /// The collective that hands every process every body's values, given this process's own
    /// bodies' in body order (`contactdd_ddm::exchange::Exchange::gather`).
    pub gather: Box<dyn Fn(Vec<Vec<f64>>) -> Vec<Vec<f64>> + 'a>,
    /// The encoding and the layout of the `.vtu` files (the same on every process). The
    /// [`VtuLayout::Collection`] layout needs every body's fields in this process: a process
    /// that does not own every body refuses it ([`CollectionOverRanks`]).
    pub vtu: VtuOptions,
}

impl Part<'static> {
    /// A single process: it writes everything, the `.vtu` files in the default [`VtuFormat`].
    pub fn alone() -> Part<'static> {
        Part::alone_as(VtuFormat::default())
    }

    /// A single process writing the `.vtu` files in `vtu` (a [`VtuFormat`], one file per
    /// body, or [`VtuOptions`]).
    pub fn alone_as(vtu: impl Into<VtuOptions>) -> Part<'static> {
        Part {
            root: true,
            owns: Box::new(|_| true),
            agree: Box::new(|error| error),
            gather: Box::new(|own| own),
            vtu: vtu.into(),
        }
    }
}

/// The reactions of every body, each computed by the process that holds its field and handed to
/// every process (a collective). A body whose values arrive damaged (a bug, never an input) gets
/// NaN reactions rather than an error that would stop this process alone.
pub fn shared_reactions(model: &Model, sol: &Solution, part: &Part<'_>) -> Vec<BodyReactions> {
    let own = (sol.bodies.iter().enumerate())
        .filter(|(b, _)| (part.owns)(*b))
        .map(|(b, fields)| pack_reactions(&body_reactions(model, b, fields, &sol.contact)))
        .collect();
    let all = (part.gather)(own);
    (all.iter().zip(&model.bodies))
        .map(|(v, body)| {
            unpack_reactions(v).unwrap_or_else(|_| BodyReactions {
                body: body.name.clone(),
                supports: Vec::new(),
                total: [f64::NAN; 2],
            })
        })
        .collect()
}

/// The mean displacement of the monitored boundary in `sol`, computed by the process that holds
/// the body's field and handed to every process (a collective).
pub fn shared_monitor(sol: &Solution, monitor: &Monitor, part: &Part<'_>) -> [f64; 2] {
    let own = (0..sol.bodies.len())
        .filter(|&b| (part.owns)(b))
        .map(|b| match b == monitor.body {
            true => monitored_displacement(&sol.bodies, monitor).to_vec(),
            false => Vec::new(),
        })
        .collect();
    let all = (part.gather)(own);
    match all.get(monitor.body).map(Vec::as_slice) {
        Some(&[ux, uy]) => [ux, uy],
        _ => [f64::NAN; 2],
    }
}

/// Writes this process's part of the result folder `dir` of `sol`, whose bodies' `reactions`
/// every process holds ([`shared_reactions`]). Returns the paths this process wrote (the root's
/// list ends with `summary.json`); every process returns the same error if any failed.
pub fn write_results_shared(
    dir: &Path,
    model: &Model,
    sol: &Solution,
    reactions: &[BodyReactions],
    units: Option<&str>,
    part: &Part<'_>,
) -> std::io::Result<Vec<PathBuf>> {
    let contents = Contents {
        files: vec![
            ("contact.csv", contact_csv(model, sol)),
            ("history.csv", history_csv(sol)),
        ],
        vtus: vec![(1.0, String::new(), sol)],
        summary: summary_json_with(model, sol, reactions),
    };
    write_shared(dir, model, contents, units, part)
}

/// [`write_results_shared`] for a load-step run: the folder of
/// [`crate::output::write_step_results`], file for file; `labels` those of a load history's
/// increments.
pub fn write_step_results_shared(
    dir: &Path,
    model: &Model,
    steps: &[(f64, Solution)],
    monitor: Option<&Monitor>,
    units: Option<&str>,
    labels: Option<&HistoryLabels>,
    part: &Part<'_>,
) -> std::io::Result<Vec<PathBuf>> {
    let Some((_, last)) = steps.last() else {
        return Err(Error::new(ErrorKind::InvalidInput, "no load step to write"));
    };
    let reactions = shared_reactions(model, last, part);
    let monitored = monitor.map(|m| {
        (steps.iter())
            .map(|(_, sol)| shared_monitor(sol, m, part))
            .collect::<Vec<_>>()
    });
    let monitored = monitored.as_deref();
    let mut summary = summary_json_with(model, last, &reactions);
    summary["steps"] = steps_json(steps, monitored, labels);
    let contents = Contents {
        files: vec![
            ("contact.csv", contact_csv(model, last)),
            ("history.csv", history_csv(last)),
            ("steps.csv", steps_csv(model, steps, monitored, labels)),
        ],
        vtus: steps
            .iter()
            .enumerate()
            .map(|(k, (factor, sol))| (*factor, format!("-step{}", k + 1), sol))
            .collect(),
        summary,
    };
    write_shared(dir, model, contents, units, part)
}

/// What a shared folder holds: the root's files, in order; the VTU sets (time, file suffix,
/// solution), whose bodies every process writes its part of; and the summary.
struct Contents<'a> {
    files: Vec<(&'static str, String)>,
    vtus: Vec<(f64, String, &'a Solution)>,
    summary: Value,
}

/// Writes this process's part of `contents` into `dir`: its bodies' VTU files, and on the root
/// the files, `results.pvd` over every VTU set and the summary, last.
fn write_shared(
    dir: &Path,
    model: &Model,
    contents: Contents<'_>,
    units: Option<&str>,
    part: &Part<'_>,
) -> std::io::Result<Vec<PathBuf>> {
    let collection = part.vtu.layout == VtuLayout::Collection;
    if collection {
        // Every process takes this turn (the layout is the same on every one).
        let bodies = model.bodies.len();
        let refused = (!(0..bodies).all(|b| (part.owns)(b)))
            .then(|| Error::new(ErrorKind::Unsupported, CollectionOverRanks));
        agreed(part, refused.as_ref())?;
    }
    let begun = if part.root {
        ResultSet::begin(dir).map(Some)
    } else {
        Ok(None)
    };
    agreed(part, begun.as_ref().err())?;
    let set = begun?;
    // Every process writes into the set's staging folder, which the root created.
    let staging = staging_dir(dir);
    let mut own = Vec::new();
    let format = part.vtu.format;
    let written = contents.vtus.iter().try_for_each(|(_, suffix, sol)| {
        let to = (staging.as_path(), suffix.as_str(), format);
        let of = (sol.bodies.as_slice(), sol.contact.as_slice());
        match collection {
            false => write_solution_vtus_of(to, model, of, &*part.owns, &mut own),
            // Only one process writes the file (the check above leaves one).
            true => write_solution_collection(to, model, of, &mut own),
        }
    });
    if let Err(e) = agreed(part, written.as_ref().err()) {
        own.iter().for_each(|p| drop(std::fs::remove_file(p)));
        if let Some(set) = set {
            set.abandon();
        }
        return Err(e);
    }
    let Some(mut set) = set else {
        // Where the root's swap puts them.
        return Ok(own
            .iter()
            .filter_map(|p| Some(dir.join(p.file_name()?)))
            .collect());
    };
    let mut summary = contents.summary;
    summary["units"] = json!(units);
    let shared = (|| {
        for (name, text) in &contents.files {
            set.write(name, text.as_bytes())?;
        }
        let mut entries = Vec::new();
        for (time, suffix, sol) in &contents.vtus {
            let before = set.len();
            match collection {
                false => set.record(vtu_paths(&staging, suffix, &sol.bodies)),
                true => set.record([collection_path(&staging, suffix)]),
            }
            for (part, name) in set.names_since(before).into_iter().enumerate() {
                entries.push((*time, part, name));
            }
        }
        set.write("results.pvd", pvd(&entries).as_bytes())
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
