//! The tables of a load-step run (`[solver] load-steps`, or a `[[steps]]` load history: one row
//! per increment, labelled by [`HistoryLabels`]): one row per step in `steps.csv`
//! ([`steps_csv`]) and in `summary.json`'s `steps` ([`steps_json`]), and `results.pvd`
//! ([`pvd`]), the ParaView collection of every body at every step (the load factor is its time).
//! The run's folder (written by [`crate::output::write_step_results`]) also holds one
//! `<body>-step<k>.vtu` per body and step; its `summary.json`, `contact.csv` and `history.csv`
//! describe the last step.

use serde_json::{json, Value};

use contactdd_core::dof;
use contactdd_ddm::history::{Increment, LoadHistory};
use contactdd_ddm::solution::{BodyResult, PairResult};
use contactdd_ddm::{Model, Solution};

use crate::body_vtus::safe_file_name;
use crate::csv_tables::csv_text;
use crate::load_steps::Monitor;
use crate::number::format_f64 as num;
use crate::summary::json_number;

/// What one step reports per pair: the resultant contact force on the pair's first body, the
/// length of its closed contact zone (the quadrature weights of its closed points) and the
/// largest contact pressure p ≥ 0 ([`PairResult::max_pressure`]).
struct PairStep {
    force: [f64; 2],
    contact_length: f64,
    max_pressure: f64,
}

impl PairStep {
    fn new(pair: &PairResult) -> PairStep {
        let side0 = (0..pair.side.len()).filter(|&i| pair.side[i] == 0);
        PairStep {
            force: pair.force_on(0),
            contact_length: side0
                .filter(|&i| pair.closed[i])
                .map(|i| pair.weight[i])
                .sum(),
            max_pressure: pair.max_pressure(),
        }
    }
}

/// The mean displacement of the monitored boundary (NaN if it has no nodes, or if another
/// process holds the body's field).
pub fn monitored_displacement(bodies: &[BodyResult], monitor: &Monitor) -> [f64; 2] {
    let Some(body) = bodies.get(monitor.body).filter(|b| b.has_fields()) else {
        return [f64::NAN; 2];
    };
    let nodes = body
        .mesh
        .boundary_nodes(&monitor.boundary)
        .unwrap_or_default();
    let n = nodes.len() as f64;
    let mean = |c: usize| {
        nodes
            .iter()
            .map(|&v| body.displacement[dof(v, c)])
            .sum::<f64>()
            / n
    };
    [mean(0), mean(1)]
}

/// What the rows of a load history's tables add to those of load steps: the group names and,
/// per increment, its step's name, its number within the step and every group's factor.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HistoryLabels {
    /// The load groups, `default` first.
    pub groups: Vec<String>,
    /// Per increment: (step name, increment within the step from 1, factor of every group).
    pub rows: Vec<(String, usize, Vec<f64>)>,
}

impl HistoryLabels {
    /// The labels of the increments `increments` of `history`.
    pub fn new<'a>(
        history: &LoadHistory,
        increments: impl IntoIterator<Item = &'a Increment>,
    ) -> HistoryLabels {
        HistoryLabels {
            groups: history
                .group_names()
                .into_iter()
                .map(String::from)
                .collect(),
            rows: increments
                .into_iter()
                .map(|i| {
                    let name = history.steps.get(i.step).map(|s| s.name.clone());
                    (name.unwrap_or_default(), i.increment, i.factors.clone())
                })
                .collect(),
        }
    }

    /// The time of each increment, ParaView's: the step's number (from 0) plus the fraction of
    /// the step done.
    pub fn times(history: &LoadHistory, increments: &[Increment]) -> Vec<f64> {
        increments
            .iter()
            .map(|i| {
                let n = history.steps.get(i.step).map_or(1, |s| s.increments.max(1));
                i.step as f64 + i.increment as f64 / n as f64
            })
            .collect()
    }
}

/// `steps.csv`: `step,factor,converged,iterations`, then per pair `<pair>_force_x`,
/// `<pair>_force_y` (on its first body), `<pair>_contact_length`, `<pair>_max_pressure`, and with a
/// monitor `monitor_ux,monitor_uy` (`monitored`: the monitored displacement of every step).
/// With a load history (`labels`) the `factor` column is `time` (see [`HistoryLabels::times`])
/// and `name,increment,factor_<group>…` follow `step`.
pub fn steps_csv(
    model: &Model,
    steps: &[(f64, Solution)],
    monitored: Option<&[[f64; 2]]>,
    labels: Option<&HistoryLabels>,
) -> String {
    let mut head = vec!["step".to_string()];
    if let Some(l) = labels {
        head.extend(["name".to_string(), "increment".into(), "time".into()]);
        head.extend(
            l.groups
                .iter()
                .map(|g| format!("factor_{}", safe_file_name(g))),
        );
    } else {
        head.push("factor".into());
    }
    head.extend(["converged".to_string(), "iterations".into()]);
    for pair in &model.pairs {
        let name = safe_file_name(&pair.name);
        for what in ["force_x", "force_y", "contact_length", "max_pressure"] {
            head.push(format!("{name}_{what}"));
        }
    }
    if monitored.is_some() {
        head.extend(["monitor_ux".to_string(), "monitor_uy".into()]);
    }
    let mut rows = Vec::with_capacity(steps.len());
    for (k, (factor, sol)) in steps.iter().enumerate() {
        let mut row = vec![(k + 1).to_string()];
        if let Some((name, increment, factors)) = labels.and_then(|l| l.rows.get(k)) {
            row.extend([name.clone(), increment.to_string()]);
            row.push(num(*factor));
            row.extend(factors.iter().map(|f| num(*f)));
        } else {
            row.push(num(*factor));
        }
        row.extend([sol.converged.to_string(), sol.iterations.to_string()]);
        for pair in &sol.contact {
            let s = PairStep::new(pair);
            row.extend([s.force[0], s.force[1], s.contact_length, s.max_pressure].map(num));
        }
        if let Some(u) = monitored.and_then(|m| m.get(k)) {
            row.extend(u.map(num));
        }
        rows.push(row);
    }
    csv_text(head, rows)
}

/// The `steps` array of `summary.json`: per step its number, factor, convergence, iterations,
/// per pair the same values as `steps.csv`, and the monitored displacement (`monitored`, per
/// step). With a load history (`labels`) each step also has its `name`, `increment`, `time` (as
/// `factor`) and `factors` (by group).
pub fn steps_json(
    steps: &[(f64, Solution)],
    monitored: Option<&[[f64; 2]]>,
    labels: Option<&HistoryLabels>,
) -> Value {
    steps
        .iter()
        .enumerate()
        .map(|(k, (factor, sol))| {
            let pairs: Vec<Value> = sol
                .contact
                .iter()
                .map(|pair| {
                    let s = PairStep::new(pair);
                    json!({
                        "name": pair.name,
                        "force": s.force.map(json_number),
                        "contact_length": json_number(s.contact_length),
                        "max_pressure": json_number(s.max_pressure),
                    })
                })
                .collect();
            let mut step = json!({
                "step": k + 1,
                "factor": json_number(*factor),
                "converged": sol.converged,
                "iterations": sol.iterations,
                "pairs": pairs,
                "monitor": monitored.and_then(|m| m.get(k)).map(|u| u.map(json_number)),
            });
            if let Some((l, (name, increment, factors))) =
                labels.and_then(|l| Some((l, l.rows.get(k)?)))
            {
                step["name"] = json!(name);
                step["increment"] = json!(increment);
                step["time"] = json_number(*factor);
                let by_group: serde_json::Map<String, Value> = (l.groups.iter())
                    .zip(factors)
                    .map(|(g, f)| (g.clone(), json_number(*f)))
                    .collect();
                step["factors"] = Value::Object(by_group);
            }
            step
        })
        .collect()
}

/// A ParaView collection (`.pvd`) of `(time, part, file)` entries.
pub fn pvd(entries: &[(f64, usize, String)]) -> String {
    let mut out = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n",
    );
    for (time, part, file) in entries {
        out += &format!(
            "    <DataSet timestep=\"{}\" part=\"{part}\" file=\"{}\"/>\n",
            num(*time),
            xml_escape(file)
        );
    }
    out + "  </Collection>\n</VTKFile>\n"
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
