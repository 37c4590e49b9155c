//! The `[[steps]]` tables: a load history ([`contactdd_ddm::history::LoadHistory`]) from the
//! problem's steps and the `group` of its loads.
//!
//! The groups are the names the loads give, in the order they first appear (bodies in order, then
//! their loads); the loads without a group and the prescribed displacements are the group
//! `default`. Every group with a load must be named by some step (else its loads would never
//! apply), and a step may name only known groups. A load with a group needs a history.

use std::collections::{BTreeSet, HashMap};

use contactdd_core::names::{listed, shown};

use contactdd_ddm::history::{HistoryStep, LoadGroup, LoadHistory, DEFAULT_GROUP};
use contactdd_ddm::{Model, SetupError};

use crate::bodies::group_load;
use crate::body_vtus::safe_file_name;
use crate::error::solver_error;
use crate::load_steps::MAX_LOAD_STEPS;
use crate::number::format_f64 as num;
use crate::problem::{Problem, StepSpec};

fn steps_error(message: impl std::fmt::Display) -> SetupError {
    solver_error("steps", message)
}

/// The load history of `problem` on its built `model` (`None` without `[[steps]]`), checked:
/// the errors name the step and the key.
pub fn history(problem: &Problem, model: &Model) -> Result<Option<LoadHistory>, SetupError> {
    let names = group_names(problem);
    if problem.steps.is_empty() {
        return match names.iter().find(|n| *n != DEFAULT_GROUP) {
            Some(name) => Err(steps_error(format!(
                "loads of group '{}' need a [[steps]] history that sets the group's factor",
                shown(name)
            ))),
            None => Ok(None),
        };
    }
    if problem.solver.load_steps.is_some() {
        return Err(steps_error(
            "[solver] load-steps and [[steps]] exclude each other: give the history's steps only",
        ));
    }
    check_columns(&names)?;
    let steps = problem
        .steps
        .iter()
        .enumerate()
        .map(|(k, spec)| step(k, spec, &names))
        .collect::<Result<Vec<_>, _>>()?;
    let total = steps
        .iter()
        .fold(0usize, |n, s| n.saturating_add(s.increments));
    if total > MAX_LOAD_STEPS {
        return Err(steps_error(format!(
            "at most {MAX_LOAD_STEPS} increments in all, got {total}"
        )));
    }
    for (g, name) in names.iter().enumerate() {
        let named = steps.iter().any(|s| s.factors.iter().any(|&(i, _)| i == g));
        let loaded = g > 0 || default_loads(problem);
        if loaded && !named {
            return Err(steps_error(format!(
                "no step sets the factor of load group '{}', so its loads would never apply",
                shown(name)
            )));
        }
    }
    let groups = names[1..]
        .iter()
        .map(|name| group(problem, model, name))
        .collect::<Result<Vec<_>, _>>()?;
    let history = LoadHistory { groups, steps };
    history.check(model.bodies.len()).map_err(steps_error)?;
    Ok(Some(history))
}

/// Refuses two groups whose `steps.csv` columns (`factor_<group>`, the group's
/// [`safe_file_name`]) would be the same.
fn check_columns(names: &[String]) -> Result<(), SetupError> {
    let mut columns: HashMap<String, &str> = HashMap::with_capacity(names.len());
    for name in names {
        if let Some(other) = columns.insert(safe_file_name(name), name) {
            return Err(steps_error(format!(
                "load groups '{}' and '{}' give the same steps.csv column 'factor_{}'; name \
                 groups so that they differ in letters, digits, '-', '_' or '.'",
                shown(other),
                shown(name),
                shown(&safe_file_name(name))
            )));
        }
    }
    Ok(())
}

/// The group names: `default` first, then the loads' groups in order of appearance.
fn group_names(problem: &Problem) -> Vec<String> {
    let mut names = vec![DEFAULT_GROUP.to_string()];
    for load in problem.bodies.iter().flat_map(|b| &b.loads) {
        let name = load.group_name();
        if !names.iter().any(|n| n == name) {
            names.push(name.to_string());
        }
    }
    names
}

/// True if the default group applies anything: a load without a group, or a prescribed
/// displacement other than 0.
fn default_loads(problem: &Problem) -> bool {
    problem.bodies.iter().any(|b| {
        b.loads.iter().any(|l| l.group_name() == DEFAULT_GROUP)
            || b.supports.iter().any(|s| s.value != 0.0)
    })
}

/// Step `k` of the history, its factors by group number of `names`.
fn step(k: usize, spec: &StepSpec, names: &[String]) -> Result<HistoryStep, SetupError> {
    let name = spec.step_name(k);
    let error = |m: String| steps_error(format!("[{k}] '{}': {m}", shown(&name)));
    let increments = spec.increments.unwrap_or(1);
    let increments = usize::try_from(increments)
        .ok()
        .filter(|&n| n >= 1)
        .ok_or_else(|| error(format!("increments must be at least 1, got {increments}")))?;
    if increments > MAX_LOAD_STEPS {
        return Err(error(format!(
            "at most {MAX_LOAD_STEPS} increments, got {increments}"
        )));
    }
    if spec.factors.is_empty() {
        return Err(error(
            "factors: give the factor of at least one load group".into(),
        ));
    }
    let mut factors = Vec::with_capacity(spec.factors.len());
    for (group, &f) in &spec.factors {
        let Some(g) = names.iter().position(|n| n == group) else {
            let known: BTreeSet<&str> = names.iter().map(String::as_str).collect();
            let known: Vec<&str> = known.into_iter().collect();
            return Err(error(format!(
                "factors: no load group named '{}' (known: {})",
                shown(group),
                listed(known).join(", ")
            )));
        };
        if !f.is_finite() {
            return Err(error(format!(
                "factors.{}: must be finite, got {}",
                shown(group),
                num(f)
            )));
        }
        factors.push((g, f));
    }
    Ok(HistoryStep {
        name,
        factors,
        increments,
    })
}

/// Group `name`'s load vector on every body this process meshes (empty elsewhere, and on the
/// bodies without a load of the group).
fn group(problem: &Problem, model: &Model, name: &str) -> Result<LoadGroup, SetupError> {
    let loads = problem
        .bodies
        .iter()
        .zip(&model.bodies)
        .enumerate()
        .map(|(b, (spec, body))| {
            let has = spec.loads.iter().any(|l| l.group_name() == name);
            match has && model.remote(b).is_none() {
                true => group_load(&spec.name, &body.mesh, &spec.loads, name),
                false => Ok(Vec::new()),
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(LoadGroup {
        name: name.to_string(),
        loads,
    })
}
