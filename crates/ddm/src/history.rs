//! Load histories: named load groups, each with its own factor, ramped step by step (press
//! first, then shear). Friction makes the answer depend on the load path, so a history is the
//! problem: each step ramps every group's factor linearly, in equal increments, from its value at
//! the end of the step before (0 at the start) to the step's target; a group a step does not name
//! keeps its factor.
//!
//! The default group is the bodies' own loads and prescribed displacements (`Model`'s bodies'
//! `load` and supports); the others are load vectors of their own ([`LoadGroup`]). The bodies are
//! factorised once: each group's condensed response is computed once, and an increment only
//! combines them ([`Prepared::set_load_combination`]).

use contactdd_core::geometry::dot;
use contactdd_core::node_vector;

use crate::error::SetupError;
use crate::exchange::share_vectors;
use crate::model::Model;
use crate::outcome::Hooks;
use crate::settings::Settings;
use crate::solution::Solution;
use crate::solver::{solve_from, Prepared};

/// The name of the group of the bodies' own loads and prescribed displacements.
pub const DEFAULT_GROUP: &str = "default";

/// A load group other than the default one: per body its load vector (2 entries per node; empty
/// where the group does not load the body, or another process meshes it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadGroup {
    /// The group's name.
    pub name: String,
    /// Per body, the load vector.
    pub loads: Vec<Vec<f64>>,
}

/// One step of a history: the factors it ramps the groups to, in equal increments.
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryStep {
    /// The step's name.
    pub name: String,
    /// The target factors: (group number, factor), group 0 the default group and group g ≥ 1
    /// [`LoadHistory::groups`]`[g − 1]`. Groups not named keep their factor.
    pub factors: Vec<(usize, f64)>,
    /// Equal increments of the step (≥ 1); each is one solve.
    pub increments: usize,
}

/// A load history: the load groups and the steps.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadHistory {
    /// The groups other than the default one.
    pub groups: Vec<LoadGroup>,
    /// The steps, in order.
    pub steps: Vec<HistoryStep>,
}

/// One increment of a history: a solve at one combination of the groups' factors.
#[derive(Clone, Debug, PartialEq)]
pub struct Increment {
    /// The step's number in [`LoadHistory::steps`] (from 0).
    pub step: usize,
    /// The increment's number within its step (from 1).
    pub increment: usize,
    /// Every group's factor, the default group first ([`LoadHistory::group_names`]).
    pub factors: Vec<f64>,
}

impl LoadHistory {
    /// The group names: the default group, then [`LoadHistory::groups`].
    pub fn group_names(&self) -> Vec<&str> {
        std::iter::once(DEFAULT_GROUP)
            .chain(self.groups.iter().map(|g| g.name.as_str()))
            .collect()
    }

    /// The number of solves: the steps' increments.
    pub fn len(&self) -> usize {
        self.steps
            .iter()
            .fold(0usize, |n, s| n.saturating_add(s.increments))
    }

    /// True if the history has no increment.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Checks the history for a model of `bodies` bodies: at least one step, every step with at
    /// least one increment and finite factors of known groups, every group with one load vector
    /// per body (or none) and distinct names.
    pub fn check(&self, bodies: usize) -> Result<(), String> {
        if self.steps.is_empty() {
            return Err("a load history needs at least one step".into());
        }
        let names = self.group_names();
        for (g, name) in names.iter().enumerate() {
            if names[..g].contains(name) {
                return Err(format!("load group '{name}' is defined twice"));
            }
        }
        for group in &self.groups {
            if !group.loads.is_empty() && group.loads.len() != bodies {
                return Err(format!(
                    "load group '{}' has load vectors for {} bodies, the model has {bodies}",
                    group.name,
                    group.loads.len()
                ));
            }
        }
        for step in &self.steps {
            if step.increments == 0 {
                return Err(format!("step '{}': needs at least 1 increment", step.name));
            }
            for &(g, f) in &step.factors {
                if g >= names.len() {
                    return Err(format!("step '{}': no load group number {g}", step.name));
                }
                if !f.is_finite() {
                    return Err(format!(
                        "step '{}': the factor of group '{}' must be finite, got {f}",
                        step.name, names[g]
                    ));
                }
            }
        }
        Ok(())
    }

    /// Every increment in order. Within a step the factors run linearly from the step's start
    /// to its targets, c = c₀ + (c₁ − c₀)·i/n; the last increment takes the targets exactly.
    pub fn increments(&self) -> Vec<Increment> {
        let mut current = vec![0.0; self.groups.len() + 1];
        let mut out = Vec::with_capacity(self.len());
        for (s, step) in self.steps.iter().enumerate() {
            let start = current.clone();
            for &(g, f) in &step.factors {
                if let Some(c) = current.get_mut(g) {
                    *c = f;
                }
            }
            let n = step.increments;
            for i in 1..=n {
                let factors = match i == n {
                    true => current.clone(),
                    false => (start.iter().zip(&current))
                        .map(|(a, b)| a + (b - a) * (i as f64 / n as f64))
                        .collect(),
                };
                out.push(Increment {
                    step: s,
                    increment: i,
                    factors,
                });
            }
        }
        out
    }

    /// The model with every body's load at the combination `factors` (the default group
    /// first): what a result at that combination reports as the applied loads and balances its
    /// reactions against. A body another process meshes keeps its load.
    pub fn model_at(&self, model: &Model, factors: &[f64]) -> Model {
        let mut out = model.clone();
        let default = factors.first().copied().unwrap_or(1.0);
        for (b, body) in out.bodies.iter_mut().enumerate() {
            if model.remote(b).is_some() {
                continue;
            }
            body.load.iter_mut().for_each(|f| *f *= default);
            for (group, &c) in self.groups.iter().zip(&factors[1.min(factors.len())..]) {
                if let Some(l) = group.loads.get(b).filter(|l| l.len() == body.load.len()) {
                    body.load.iter_mut().zip(l).for_each(|(f, v)| *f += c * v);
                }
            }
        }
        out
    }
}

/// Per body (those this process meshes), per group, the work of the group's load along each
/// free rigid mode of the body; shared with every process.
fn rigid_work(model: &Model, prepared: &Prepared, groups: &[LoadGroup]) -> Vec<Vec<Vec<f64>>> {
    let exchange = &*prepared.exchange;
    let own: Vec<Vec<f64>> = (0..model.bodies.len())
        .map(|b| {
            if model.remote(b).is_some() || !exchange.owns(b) {
                return Vec::new();
            }
            let facts = model.facts(b);
            let nodes = model.bodies[b].mesh.nodes();
            let mut flat = Vec::with_capacity(groups.len() * facts.free.len());
            for group in groups {
                let load = group.loads.get(b).filter(|l| !l.is_empty());
                flat.extend(facts.free.iter().map(|v| {
                    match load {
                        Some(l) => (nodes.iter().enumerate())
                            .map(|(i, &x)| dot(facts.basis.motion(x, v), node_vector(l, i)))
                            .sum(),
                        None => 0.0,
                    }
                }));
            }
            flat
        })
        .collect();
    share_vectors(exchange, own)
        .into_iter()
        .enumerate()
        .map(|(b, flat)| {
            let modes = model.facts(b).free.len();
            (0..groups.len())
                .map(|g| flat.get(g * modes..(g + 1) * modes).unwrap_or(&[]).to_vec())
                .collect()
        })
        .collect()
}

impl Prepared {
    /// Sets the load groups of a history (each at factor 0; the default group at factor 1):
    /// every body this process owns computes each group's response once (one solve per group),
    /// and the coarse space its work on the rigid modes. A collective under a distributed solve.
    /// An empty `groups` removes them.
    pub fn set_load_groups(
        &mut self,
        model: &Model,
        groups: &[LoadGroup],
    ) -> Result<(), SetupError> {
        for (b, body) in self.bodies.iter_mut().enumerate() {
            if let Some(body) = body.as_mut() {
                let loads: Vec<Vec<f64>> = groups
                    .iter()
                    .map(|g| g.loads.get(b).cloned().unwrap_or_default())
                    .collect();
                body.set_load_groups(&model.bodies[b].name, &loads)?;
            }
        }
        let work = rigid_work(model, self, groups);
        self.coarse.set_load_groups(&work);
        self.group_factors = vec![0.0; groups.len()];
        self.set_load_factor(1.0);
        Ok(())
    }

    /// Sets the load combination of a history: `factors[0]` on the bodies' own loads and
    /// prescribed displacements (the default group), `factors[g]` on group g of
    /// [`Prepared::set_load_groups`]. With one factor this is [`Prepared::set_load_factor`].
    pub fn set_load_combination(&mut self, factors: &[f64]) {
        let default = factors.first().copied().unwrap_or(1.0);
        let groups = &factors[1.min(factors.len())..];
        self.load_factor = default;
        self.group_factors = groups.to_vec();
        for body in self.bodies.iter_mut().flatten() {
            body.set_load_combination(default, groups);
        }
        self.coarse.set_load_combination(default, groups);
    }
}

/// Solves the model at every increment of `history` in turn, calling `on_increment(increment,
/// solution)` after each. Stops after the first increment that does not converge (its solution
/// is the last one returned). Each increment starts from the interface loads and the friction
/// state that the increment before ends in, the first from the unloaded state. The prepared
/// model is left as it was: at load factor 1, without the groups, in the unloaded state.
pub fn solve_history(
    model: &Model,
    prepared: &mut Prepared,
    settings: &Settings,
    history: &LoadHistory,
    hooks: Hooks<'_>,
    on_increment: &mut dyn FnMut(&Increment, &Solution),
) -> Result<Vec<(Increment, Solution)>, SetupError> {
    history
        .check(model.bodies.len())
        .map_err(SetupError::Solver)?;
    let result = prepared
        .set_load_groups(model, &history.groups)
        .and_then(|()| run_increments(model, prepared, settings, history, hooks, on_increment));
    // Restoring needs no solve: no group is left.
    let _ = prepared.set_load_groups(model, &[]);
    prepared.set_friction_state(&[]);
    result
}

/// The increments of [`solve_history`] on a prepared model holding the history's groups.
fn run_increments(
    model: &Model,
    prepared: &mut Prepared,
    settings: &Settings,
    history: &LoadHistory,
    hooks: Hooks<'_>,
    on_increment: &mut dyn FnMut(&Increment, &Solution),
) -> Result<Vec<(Increment, Solution)>, SetupError> {
    let mut done: Vec<(Increment, Solution)> = Vec::with_capacity(history.len());
    for increment in history.increments() {
        prepared.set_load_combination(&increment.factors);
        let warm = done.last().map(|(_, s)| s.interface_loads.as_slice());
        let solution = solve_from(model, prepared, settings, hooks, warm)?;
        on_increment(&increment, &solution);
        prepared.set_friction_state(&solution.friction_state);
        let converged = solution.converged;
        done.push((increment, solution));
        if !converged {
            break;
        }
    }
    Ok(done)
}
