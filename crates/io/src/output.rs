//! Result files of a solve: `summary.json`, `contact.csv`, `history.csv` and one `.vtu` per body,
//! plus the CSV table of a γ sweep.
//!
//! The text builders ([`summary_json`], [`contact_csv`], [`history_csv`], [`sweep_csv`]) only
//! format; [`write_results`] writes a whole result folder. Every file is written by
//! [`write_atomic`] (re-exported from [`crate::atomic`]): to a temporary file in the target
//! folder, then renamed, so a reader (or a crash mid-write) never leaves a half-written file
//! behind.
//!
//! Non-finite numbers: JSON has no NaN or infinity, so every non-finite value in `summary.json`
//! becomes `null` (e.g. the gap of a contact point whose normal ray misses the partner body, or the
//! relative change of an iteration that broke down). The CSV files write such values as `inf`,
//! `-inf` or `NaN`, which Python's `float()`, numpy and pandas read back.
//!
//! `summary.json` keys:
//!
//! | key         | value                                                                      |
//! |-------------|----------------------------------------------------------------------------|
//! | `converged` | true if every body met the tolerance and the result is in equilibrium      |
//! | `stop`      | how the iteration ended ([`stop_name`]: `converged`, `max-iterations`, …)  |
//! | `iterations`| iterations taken (m)                                                       |
//! | `method`    | method name (`newton-kurchatov`, …)                                         |
//! | `gamma`     | the constant γ, or `"auto"`                                                |
//! | `theta`     | penalty θ per contact pair                                                 |
//! | `message`   | `null` when converged, else why not                                        |
//! | `equilibrium` | per body, the equilibrium residual (contact forces of the fields against those of the pressures, relative to the total contact force) |
//! | `accelerator`, `coarse` | the accelerator and coarse mode used                           |
//! | `history`   | per iteration `{k, gamma, rel_change, active, normal_force}` (per body)    |
//! | `bodies`    | per body `{name, nodes, elements, dofs, order, applied_load, condensation}` |
//! | `contact`   | per pair `{name, bodies, body, node, x, y, gap, pressure, status, weight, normal, force}` |
//! | `reactions` | per body `{body, supports: [{boundary, force}], total}` ([`reactions_json`]) |
//! | `timing_s`  | wall time per phase, seconds                                               |
//! | `version`   | contactdd version                                                          |
//! | `files`     | the manifest: the other files of the result set (written last, see below)  |
//!
//! `dofs` counts the unknowns (2 per node minus the prescribed ones); `applied_load` is the total
//! applied force `[fx, fy]`; `condensation` is the path the body took, `dense` or `sparse`
//! (docs/sparse-path.md). In `contact`, the arrays have one entry per contact point of both
//! sides; `status` is `closed` (d − s < 0, the point carries pressure), `open`, or `no-partner`
//! (the normal ray misses the other body: infinite gap, written as `null`); `force` holds the total
//! contact force `[fx, fy]` on each of the two bodies: the resultant Σ w σ_n n. `normal_force`
//! in `history` is a different quantity, the sum of magnitudes Σ w |σ_n| over a body's contact
//! points. docs/outputs.md defines every quantity and says what is on disk after each exit code.
//!
//! [`write_results`] writes the folder as a set ([`crate::result_set`]): the data files first,
//! `summary.json` last, so a folder without `summary.json` holds no complete result.

use std::collections::HashSet;
use std::io::{Error, ErrorKind};
use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use contactdd_core::{num_dofs, Order};
use contactdd_ddm::solution::{BodyResult, PairResult, Solution};
use contactdd_ddm::sweep::SweepRun;
use contactdd_ddm::{Condensation, Gamma, Model, MonolithicSolution, Stop};

pub use crate::atomic::write_atomic;
use crate::fields::{contact_point_data, element_von_mises, principal, tensor, ContactPointData};
use crate::number::format_f64 as num;
use crate::reactions::{reactions, BodyReactions};
use crate::result_set::{write_set, ResultSet};
use crate::shared_results::{write_results_shared, Part};
use crate::vtu::{write_vtu, Field, VtuData};

/// A JSON number, or `null` for NaN and ±infinity (which JSON cannot represent).
pub fn json_number(x: f64) -> Value {
    // `From<f64>` maps non-finite values to `Value::Null`; spelled out here because the file
    // format depends on it.
    if x.is_finite() {
        Value::from(x)
    } else {
        Value::Null
    }
}

fn json_numbers(xs: &[f64]) -> Value {
    Value::Array(xs.iter().map(|&x| json_number(x)).collect())
}

/// The status of a contact point: `closed`, `open`, or `no-partner` (infinite gap).
pub fn point_status(pair: &PairResult, i: usize) -> &'static str {
    if !pair.gap[i].is_finite() {
        "no-partner"
    } else if pair.closed[i] {
        "closed"
    } else {
        "open"
    }
}

/// `summary.json` of a DD solve (keys in the module docs).
pub fn summary_json(model: &Model, sol: &Solution) -> Value {
    summary_json_with(model, sol, &reactions(model, &sol.bodies, &sol.contact))
}

/// [`summary_json`] with the bodies' reactions given (a distributed solve gathers them from
/// the processes that hold the fields).
pub fn summary_json_with(model: &Model, sol: &Solution, reactions: &[BodyReactions]) -> Value {
    let history: Vec<Value> = sol
        .history
        .iter()
        .map(|r| {
            json!({
                "k": r.k,
                "gamma": json_number(r.gamma),
                "rel_change": json_numbers(&r.rel_change),
                "active": r.active,
                "normal_force": json_numbers(&r.contact_force),
            })
        })
        .collect();
    let timing: serde_json::Map<String, Value> = sol
        .timing
        .iter()
        .map(|(phase, &s)| (phase.clone(), json_number(s)))
        .collect();
    json!({
        "converged": sol.converged,
        "stop": stop_name(&sol.stop),
        "iterations": sol.iterations,
        "tol": json_number(sol.tol),
        "method": sol.method.name(),
        "gamma": gamma_json(sol.gamma),
        "theta": json_numbers(&sol.theta),
        "message": sol.message,
        "equilibrium": json_numbers(&sol.equilibrium),
        "accelerator": sol.accelerator.to_string(),
        "coarse": sol.coarse.to_string(),
        "history": history,
        "bodies": with_paths(bodies_json(model), &sol.condensation),
        "contact": contact_json(&sol.contact),
        "enforcement": model.pairs.iter().map(|p| p.enforcement.to_string()).collect::<Vec<_>>(),
        "updates": sol.updates,
        "gap_tol": sol.gap_tol.map(json_number),
        "reactions": reactions_value(reactions),
        "timing_s": timing,
        "version": env!("CARGO_PKG_VERSION"),
    })
}

/// `summary.json` of a monolithic reference solve: `solver = "monolithic"`, `converged`,
/// `message` (why not, or null), `newton_steps`, `history` (per step: `step`, `active`,
/// `residual`, `step_length`), `rigid_modes` (the rigid motions no contact resists, as text),
/// `equilibrium` (per body, the residual of the assembled equations relative to the forces),
/// `imbalance` (per rigid mode, the net force along it, relative), `bodies`, `contact` and
/// `timing_s` as in [`summary_json`], and `version`.
pub fn monolithic_summary_json(model: &Model, sol: &MonolithicSolution) -> Value {
    let history: Vec<Value> = sol
        .history
        .iter()
        .map(|r| {
            json!({
                "step": r.step,
                "active": r.active,
                "residual": json_number(r.residual),
                "step_length": json_number(r.step_length),
            })
        })
        .collect();
    json!({
        "solver": "monolithic",
        "converged": sol.converged,
        "message": sol.message,
        "newton_steps": sol.newton_steps,
        "enforcement": model.pairs.iter().map(|p| p.enforcement.to_string()).collect::<Vec<_>>(),
        "updates": sol.updates,
        "history": history,
        "rigid_modes": sol.rigid_modes,
        "equilibrium": json_numbers(&sol.equilibrium),
        "imbalance": json_numbers(&sol.imbalance),
        "bodies": bodies_json(model),
        "contact": contact_json(&sol.contact),
        "timing_s": { "total": json_number(sol.seconds) },
        "version": env!("CARGO_PKG_VERSION"),
    })
}

/// The name of how an iteration ended (`stop` in `summary.json`).
pub fn stop_name(stop: &Stop) -> &'static str {
    match stop {
        Stop::Converged => "converged",
        Stop::MaxIterations => "max-iterations",
        Stop::Diverged { .. } => "diverged",
        Stop::Interrupted => "interrupted",
        Stop::Stalled { .. } => "stalled",
        Stop::Unenforced { .. } => "unenforced",
    }
}

fn gamma_json(gamma: Gamma) -> Value {
    match gamma {
        Gamma::Constant(g) => json_number(g),
        Gamma::Auto => Value::from("auto"),
    }
}

pub use contactdd_core::loads::applied_load;

fn bodies_json(model: &Model) -> Value {
    model
        .bodies
        .iter()
        .enumerate()
        .map(|(b, body)| {
            let f = model.facts(b);
            json!({
                "name": body.name,
                "nodes": f.nodes,
                "elements": f.cells,
                "dofs": num_dofs(f.nodes).saturating_sub(f.prescribed),
                "order": match f.order {
                    Order::P1 => "p1",
                    Order::P2 => "p2",
                },
                "applied_load": json_numbers(&f.applied_load),
            })
        })
        .collect()
}

/// `bodies` with each body's condensation path.
fn with_paths(mut bodies: Value, paths: &[Condensation]) -> Value {
    if let Value::Array(list) = &mut bodies {
        for (body, path) in list.iter_mut().zip(paths) {
            body["condensation"] = Value::from(path.to_string());
        }
    }
    bodies
}

/// The `reactions` of `summary.json`: per body `{body, supports: [{boundary, force}], total}`
/// ([`reactions`]).
pub fn reactions_json(model: &Model, bodies: &[BodyResult], contact: &[PairResult]) -> Value {
    reactions_value(&reactions(model, bodies, contact))
}

fn reactions_value(reactions: &[BodyReactions]) -> Value {
    reactions
        .iter()
        .map(|r| {
            let supports: Vec<Value> = r
                .supports
                .iter()
                .map(|s| json!({ "boundary": s.boundary, "force": json_numbers(&s.force) }))
                .collect();
            json!({ "body": r.body, "supports": supports, "total": json_numbers(&r.total) })
        })
        .collect()
}

fn contact_json(pairs: &[PairResult]) -> Value {
    pairs
        .iter()
        .map(|p| {
            let status: Vec<&str> = (0..p.gap.len()).map(|i| point_status(p, i)).collect();
            let body: Vec<&str> = p.side.iter().map(|&s| p.bodies[s].as_str()).collect();
            json!({
                "name": p.name,
                "bodies": p.bodies,
                "body": body,
                "node": p.node,
                "x": json_numbers(&p.x),
                "y": json_numbers(&p.y),
                "gap": json_numbers(&p.gap),
                "pressure": json_numbers(&p.pressure),
                "status": status,
                "weight": json_numbers(&p.weight),
                "normal": p.nx.iter().zip(&p.ny).map(|(&x, &y)| json_numbers(&[x, y])).collect::<Vec<_>>(),
                "nodal_force": p.fx.iter().zip(&p.fy).map(|(&x, &y)| json_numbers(&[x, y])).collect::<Vec<_>>(),
                "force": [json_numbers(&p.force_on(0)), json_numbers(&p.force_on(1))],
                "max_penetration": json_number(p.max_penetration()),
                "complementarity": json_number(p.complementarity()),
            })
        })
        .collect()
}

/// `contact.csv` of a solve: one row per contact point.
pub fn contact_csv(sol: &Solution) -> String {
    pairs_csv(&sol.contact)
}

/// The contact CSV of any list of pair results, with header `pair,body,x,y,gap,pressure,status`.
pub fn pairs_csv(pairs: &[PairResult]) -> String {
    let header = ["pair", "body", "x", "y", "gap", "pressure", "status"];
    let rows = pairs.iter().flat_map(|p| {
        (0..p.gap.len()).map(move |i| {
            vec![
                p.name.clone(),
                p.bodies[p.side[i]].clone(),
                num(p.x[i]),
                num(p.y[i]),
                num(p.gap[i]),
                num(p.pressure[i]),
                point_status(p, i).to_string(),
            ]
        })
    });
    csv_text(header.map(String::from), rows)
}

/// `history.csv`: one row per iteration, header
/// `k,gamma,rel_change_<body>…,active_<body>…,normal_force_<body>…` (`normal_force` is
/// Σ w |σ_n| over the body's contact points, see docs/outputs.md).
pub fn history_csv(sol: &Solution) -> String {
    let mut header = vec!["k".to_string(), "gamma".into()];
    for prefix in ["rel_change", "active", "normal_force"] {
        header.extend(sol.bodies.iter().map(|b| format!("{prefix}_{}", b.name)));
    }
    let rows = sol.history.iter().map(|r| {
        let mut row = vec![r.k.to_string(), num(r.gamma)];
        row.extend(r.rel_change.iter().map(|&x| num(x)));
        row.extend(r.active.iter().map(|a| a.to_string()));
        row.extend(r.contact_force.iter().map(|&f| num(f)));
        row
    });
    csv_text(header, rows)
}

/// The table of a γ sweep, header `method,gamma,iterations,converged,reason` (γ `auto` for the
/// Aitken rule, reason empty when converged).
pub fn sweep_csv(runs: &[SweepRun]) -> String {
    let header = ["method", "gamma", "iterations", "converged", "reason"];
    let rows = runs.iter().map(|r| {
        vec![
            r.method.name().to_string(),
            r.gamma.map_or_else(|| "auto".to_string(), num),
            r.iterations.to_string(),
            r.converged.to_string(),
            r.reason.clone(),
        ]
    });
    csv_text(header.map(String::from), rows)
}

/// The text of a CSV table (the `csv` crate's writer: fields quoted where they hold a comma, a
/// quote or a line break; every record ends in `\n`).
pub(crate) fn csv_text(
    header: impl IntoIterator<Item = String>,
    rows: impl IntoIterator<Item = Vec<String>>,
) -> String {
    let mut writer = csv::WriterBuilder::new()
        .flexible(true)
        .from_writer(Vec::new());
    // Writing into memory cannot fail.
    let _ = writer.write_record(header.into_iter().collect::<Vec<_>>());
    for row in rows {
        let _ = writer.write_record(&row);
    }
    let bytes = writer.into_inner().unwrap_or_default();
    String::from_utf8(bytes).unwrap_or_default()
}

/// Writes a solve's result folder (created if needed) as a set ([`write_set`]): `contact.csv`,
/// `history.csv`, `<body>.vtu` per body and `results.pvd` (the ParaView collection of the bodies),
/// then `summary.json` with the manifest of those files.
/// The previous set in `dir` is removed first. Returns the paths written, `summary.json` last.
pub fn write_results(dir: &Path, model: &Model, sol: &Solution) -> std::io::Result<Vec<PathBuf>> {
    write_results_noted(dir, model, sol, None)
}

/// [`write_results`] with the problem's units note (`units` of the problem file) in
/// `summary.json`, for the axes of `contactdd plot`.
pub fn write_results_noted(
    dir: &Path,
    model: &Model,
    sol: &Solution,
    units: Option<&str>,
) -> std::io::Result<Vec<PathBuf>> {
    let reactions = reactions(model, &sol.bodies, &sol.contact);
    write_results_shared(dir, model, sol, &reactions, units, &Part::alone())
}

/// Writes a monolithic solve's result folder as a set, like [`write_results`]: `contact.csv` and
/// `<body>.vtu` per body, then `summary.json` ([`monolithic_summary_json`] with the reactions and
/// the manifest) last. Returns the paths written, `summary.json` last.
pub fn write_monolithic_results(
    dir: &Path,
    model: &Model,
    sol: &MonolithicSolution,
) -> std::io::Result<Vec<PathBuf>> {
    let mut summary = monolithic_summary_json(model, sol);
    summary["reactions"] = reactions_json(model, &sol.bodies, &sol.contact);
    write_set(dir, summary, |set| {
        set.write("contact.csv", pairs_csv(&sol.contact).as_bytes())?;
        write_solution_vtus(set, model, &sol.bodies, &sol.contact)
    })
}

/// Writes `<body>.vtu` per body into `dir` with the nodal fields of the results alone:
/// `displacement` (vector), `stress` (3×3 tensor), `principal_stress_1` ≥ `_2` ≥ `_3`,
/// `sigma_xx`, `sigma_yy`, `sigma_xy`, `sigma_zz`, `von_mises` and `contact_pressure` (scalars,
/// which ParaView colours by directly). File names are [`safe_file_name`]s of the body names,
/// made unique. [`write_solution_vtus`] adds the contact point data and the element von Mises.
pub fn write_body_vtus(dir: &Path, bodies: &[BodyResult]) -> std::io::Result<Vec<PathBuf>> {
    let mut written = Vec::with_capacity(bodies.len());
    let all = |_| true;
    write_vtus(
        dir,
        "",
        bodies,
        &all,
        |_, _| Ok(Extra::default()),
        &mut written,
    )?;
    Ok(written)
}

/// [`write_body_vtus`] into a result set, plus, from the model and the pairs' results, the point
/// data `gap` and `contact_status` (1 closed, 0 open, −1 no partner; both NaN off the contact
/// points) and the cell data `element_von_mises` (at each element's centroid). `bodies` are in the
/// order of `model.bodies`. Each file joins the set as soon as it is written, so that a failure
/// part way removes it with the set ([`ResultSet::abandon`]).
pub fn write_solution_vtus(
    set: &mut ResultSet,
    model: &Model,
    bodies: &[BodyResult],
    contact: &[PairResult],
) -> std::io::Result<()> {
    write_solution_vtus_as(set, model, bodies, contact, "")
}

/// [`write_solution_vtus`] with `suffix` after each body's file name (`<body><suffix>.vtu`, e.g.
/// the `-step3` of a load step).
pub fn write_solution_vtus_as(
    set: &mut ResultSet,
    model: &Model,
    bodies: &[BodyResult],
    contact: &[PairResult],
    suffix: &str,
) -> std::io::Result<()> {
    let mut written = Vec::with_capacity(bodies.len());
    let dir = set.dir().to_path_buf();
    let result = write_solution_vtus_of(
        &dir,
        model,
        bodies,
        contact,
        suffix,
        &|_| true,
        &mut written,
    );
    set.record(written);
    result
}

/// [`write_solution_vtus_as`] into `dir` for the bodies `owns` selects only (a process of a
/// distributed solve writes its own); each path joins `written` once its file is there. The
/// file names are those of all bodies: the same as when one process writes them all.
pub(crate) fn write_solution_vtus_of(
    dir: &Path,
    model: &Model,
    bodies: &[BodyResult],
    contact: &[PairResult],
    suffix: &str,
    owns: &dyn Fn(usize) -> bool,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<()> {
    write_vtus(
        dir,
        suffix,
        bodies,
        owns,
        |b, body| {
            let elastic = model.bodies.get(b).ok_or_else(|| {
                Error::new(
                    ErrorKind::InvalidInput,
                    "more body results than model bodies",
                )
            })?;
            Ok(Extra {
                contact: Some(contact_point_data(
                    &body.name,
                    body.mesh.num_nodes(),
                    contact,
                )),
                element_von_mises: Some(element_von_mises(elastic, &body.displacement)),
            })
        },
        written,
    )
}

/// The fields of a body's `.vtu` that need more than its [`BodyResult`].
#[derive(Default)]
struct Extra {
    contact: Option<ContactPointData>,
    element_von_mises: Option<Vec<f64>>,
}

/// The `.vtu` path of each body: `<name><suffix>.vtu`, or `<name>-<b><suffix>.vtu` when an
/// earlier body's name gives the same file name.
pub(crate) fn vtu_paths(dir: &Path, suffix: &str, bodies: &[BodyResult]) -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = Vec::with_capacity(bodies.len());
    // The names taken so far (a set: thousands of bodies are compared in linear time).
    let mut taken: HashSet<PathBuf> = HashSet::with_capacity(bodies.len());
    for (b, body) in bodies.iter().enumerate() {
        let name = safe_file_name(&body.name);
        let mut path = dir.join(format!("{name}{suffix}.vtu"));
        if taken.contains(&path) {
            path = dir.join(format!("{name}-{b}{suffix}.vtu"));
        }
        taken.insert(path.clone());
        paths.push(path);
    }
    paths
}

/// Writes the `.vtu` of each body that `owns` selects, pushing each path to `written` once the
/// file is there.
fn write_vtus(
    dir: &Path,
    suffix: &str,
    bodies: &[BodyResult],
    owns: &dyn Fn(usize) -> bool,
    extra: impl Fn(usize, &BodyResult) -> std::io::Result<Extra>,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<()> {
    let paths = vtu_paths(dir, suffix, bodies);
    for ((b, body), path) in bodies.iter().enumerate().zip(paths) {
        if !owns(b) {
            continue;
        }
        let extra = extra(b, body)?;
        let component = |k: usize| body.stress.iter().map(|s| s[k]).collect::<Vec<f64>>();
        let (sxx, syy, sxy, szz) = (component(0), component(1), component(2), component(3));
        let tensors: Vec<f64> = body.stress.iter().flat_map(tensor).collect();
        let principals: Vec<[f64; 3]> = body.stress.iter().map(principal).collect();
        let principal_k = |k: usize| principals.iter().map(|p| p[k]).collect::<Vec<f64>>();
        let (p1, p2, p3) = (principal_k(0), principal_k(1), principal_k(2));
        let field = |name, components, values| Field {
            name,
            components,
            values,
        };
        let mut points = vec![
            field("stress", 9, &tensors),
            field("principal_stress_1", 1, &p1),
            field("principal_stress_2", 1, &p2),
            field("principal_stress_3", 1, &p3),
            field("sigma_xx", 1, &sxx),
            field("sigma_yy", 1, &syy),
            field("sigma_xy", 1, &sxy),
            field("sigma_zz", 1, &szz),
            field("von_mises", 1, &body.von_mises),
            field("contact_pressure", 1, &body.contact_pressure),
        ];
        if let Some(c) = &extra.contact {
            points.push(field("gap", 1, &c.gap));
            points.push(field("contact_status", 1, &c.status));
        }
        let cells: Vec<Field<'_>> = extra
            .element_von_mises
            .as_deref()
            .map(|v| field("element_von_mises", 1, v))
            .into_iter()
            .collect();
        let data = VtuData {
            displacement: Some(&body.displacement),
            points: &points,
            cells: &cells,
        };
        write_vtu(&path, &body.mesh, data)?;
        written.push(path);
    }
    Ok(())
}

/// A name usable as a file name on every platform: letters, digits, `-`, `_` and `.` are kept,
/// anything else becomes `_` (an empty name becomes `_`).
pub fn safe_file_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.chars().all(|c| c == '.') {
        "_".into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_numbers_become_json_null() {
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(json_number(x), Value::Null);
            assert_eq!(json!({ "v": json_number(x) }).to_string(), r#"{"v":null}"#);
        }
        assert_eq!(json_number(1.5), json!(1.5));
    }

    #[test]
    fn csv_fields_are_quoted_where_needed() {
        let rows = [vec!["a,b".to_string(), "say \"x\"".into(), "plain".into()]];
        assert_eq!(
            csv_text(["h1", "h2", "h3"].map(String::from), rows),
            "h1,h2,h3\n\"a,b\",\"say \"\"x\"\"\",plain\n"
        );
    }

    /// Bodies whose names give the same file name get the body's index appended, in order.
    #[test]
    fn vtu_names_that_collide_get_the_body_index() {
        let mesh = contactdd_core::Mesh::new(
            vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            Order::P1,
            vec![0, 1, 2],
            Default::default(),
            Default::default(),
        )
        .unwrap();
        let body = |name: &str| BodyResult {
            name: name.to_string(),
            mesh: mesh.clone(),
            displacement: Vec::new(),
            stress: Vec::new(),
            von_mises: Vec::new(),
            contact_pressure: Vec::new(),
        };
        let bodies = ["a b", "c", "a_b", "a/b"].map(body);
        let names: Vec<String> = vtu_paths(Path::new("out"), "", &bodies)
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["a_b.vtu", "c.vtu", "a_b-2.vtu", "a_b-3.vtu"]);
    }

    #[test]
    fn file_names_are_sanitised() {
        assert_eq!(safe_file_name("lower"), "lower");
        assert_eq!(safe_file_name("a/b c"), "a_b_c");
        assert_eq!(safe_file_name(".."), "_");
        assert_eq!(safe_file_name(""), "_");
    }
}
