//! The text of `summary.json`: [`summary_json`] for a DD solve, [`monolithic_summary_json`] for
//! the monolithic reference.
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
//! | `iteration` | the iteration that ran: `interface-newton` or `robin-sweeps`               |
//! | `solver`    | the settings in words, as the console, `contactdd check` and Python say them |
//! | `stop_measure` | what the stopping test compares with `tol` (history's `measure`)        |
//! | `method`    | the sweeps' method name (`newton-kurchatov`, …; unused by the Newton method) |
//! | `gamma`     | the constant γ, or `"auto"`                                                |
//! | `theta`     | penalty θ per contact pair                                                 |
//! | `message`   | `null` when converged, else why not                                        |
//! | `equilibrium` | per body, the equilibrium residual (contact forces of the fields against those of the pressures, relative to the total contact force) |
//! | `accelerator`, `coarse` | the accelerator and coarse mode used                           |
//! | `history`   | per iteration `{k, gamma, measure, rel_change, active, normal_force}`; `gamma` is the Newton method's step length |
//! | `bodies`    | per body `{name, nodes, elements, dofs, order, applied_load, condensation}` |
//! | `contact`   | per pair `{name, bodies, body, node, x, y, gap, pressure, nodal_traction, status, weight, normal, force}`: `pressure` is p ≥ 0, `nodal_traction` as in `contact.csv`; a pair with friction also `{friction, tangential_force, stick_length, slip_length}` and per point `{tangential_traction, slip, total_slip, friction_status}` |
//! | `reactions` | per body `{body, supports: [{boundary, force}], total}` ([`reactions_json`]) |
//! | `timing_s`  | wall time per phase, seconds                                               |
//! | `version`   | contactdd version                                                          |
//! | `files`     | the manifest: the other files of the result set (written last, [`crate::result_set`]) |
//!
//! `dofs` counts the unknowns (2 per node minus the prescribed ones); `applied_load` is the total
//! applied force `[fx, fy]` at the result's load factor (the last step's with load steps); `condensation` is the path the body took, `dense` or `sparse`
//! (docs/sparse-path.md). In `contact`, the arrays have one entry per contact point of both
//! sides; `status` is `closed` (d − s < 0, the point carries pressure), `open`, or `no-partner`
//! (the normal ray misses the other body: infinite gap, written as `null`); `force` holds the total
//! contact force `[fx, fy]` on each of the two bodies: the resultant Σ w σ_n n. `normal_force`
//! in `history` is a different quantity, the sum of magnitudes Σ w |σ_n| over a body's contact
//! points. docs/outputs.md defines every quantity and says what is on disk after each exit code.

use serde_json::{json, Value};

use contactdd_core::{num_dofs, Order};
use contactdd_ddm::solution::{BodyResult, PairResult, Solution};
use contactdd_ddm::{Condensation, Friction, Gamma, Model, MonolithicSolution, Stop};

use crate::fields::{contact_pressures, friction_point, FrictionPoint};
use crate::reactions::{reactions, BodyReactions};

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
                "measure": json_number(r.measure),
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
        "iteration": sol.settings.iteration(),
        "solver": sol.settings.to_string(),
        "stop_measure": sol.settings.measure_name(),
        "tol": json_number(sol.tol),
        "method": sol.method.name(),
        "gamma": gamma_json(sol.gamma),
        "theta": json_numbers(&sol.theta),
        "message": sol.message,
        "equilibrium": json_numbers(&sol.equilibrium),
        "balance": balance_json(&sol.balance),
        "accelerator": sol.accelerator.to_string(),
        "coarse": sol.coarse.to_string(),
        "history": history,
        "bodies": with_paths(bodies_json(model, sol.load_factor), &sol.condensation),
        "contact": contact_json(model, &sol.contact, &sol.bodies),
        "enforcement": model.pairs.iter().map(|p| p.enforcement.to_string()).collect::<Vec<_>>(),
        "updates": sol.updates,
        "gap_tol": sol.gap_tol.map(json_number),
        "reactions": reactions_value(reactions),
        "timing_s": timing,
        "version": env!("CARGO_PKG_VERSION"),
    })
}

/// The force balance: per body `{imbalance, floor}`, and the problem's `loads` against its
/// reactions.
fn balance_json(balance: &contactdd_ddm::force_balance::Balance) -> Value {
    let bodies: Vec<Value> = (balance.bodies.iter())
        .map(|b| {
            json!({
                "imbalance": json_number(b.imbalance),
                "floor": json_number(b.floor),
                "motion": json_number(b.motion),
            })
        })
        .collect();
    json!({"bodies": bodies, "loads": json_number(balance.loads)})
}

/// `summary.json` of a monolithic reference solve: `solver = "monolithic"`, `converged`,
/// `message` (why not, or null), `newton_steps`, `enforcement` and `updates` and `gap_tol` (the
/// augmented Lagrangian's gap tolerance, a length; null without augmented pairs) as in
/// [`summary_json`], `history` (per step: `step`, `active`,
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
        "gap_tol": sol.gap_tol.map(json_number),
        "history": history,
        "rigid_modes": sol.rigid_modes,
        "equilibrium": json_numbers(&sol.equilibrium),
        "balance": balance_json(&sol.balance),
        "imbalance": json_numbers(&sol.imbalance),
        "bodies": bodies_json(model, 1.0),
        "contact": contact_json(model, &sol.contact, &sol.bodies),
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
        Stop::Unbalanced { .. } => "unbalanced",
        Stop::Unenforced { .. } => "unenforced",
    }
}

fn gamma_json(gamma: Gamma) -> Value {
    match gamma {
        Gamma::Constant(g) => json_number(g),
        Gamma::Auto => Value::from("auto"),
    }
}

/// The bodies' sizes, orders and applied loads (at the load `factor` the result used).
fn bodies_json(model: &Model, factor: f64) -> Value {
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
                "applied_load": json_numbers(&f.applied_load.map(|x| x * factor)),
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

/// The `friction` of a pair in `summary.json`: `{law, mu}` or `{law, bound}`.
pub fn friction_json(friction: Friction) -> Value {
    match friction {
        Friction::None => json!({ "law": "none" }),
        Friction::Coulomb { mu } => json!({ "law": "coulomb", "mu": json_number(mu) }),
        Friction::Tresca { bound } => json!({ "law": "tresca", "bound": json_number(bound) }),
    }
}

/// Adds the friction keys of pair `pair` (of model pair `friction`) to its entry: the law, the
/// resultant tangential force, the stick and slip lengths, and per point the columns of
/// `contact.csv` (`tangential_traction`, `slip`, `total_slip`, `friction_status`).
fn add_friction(entry: &mut Value, pair: &PairResult, friction: Friction) {
    let (stick, slip) = pair.stick_slip_lengths();
    let points: Vec<FrictionPoint> = (0..pair.gap.len())
        .map(|i| friction_point(pair, i))
        .collect();
    let column =
        |f: fn(&FrictionPoint) -> f64| json_numbers(&points.iter().map(f).collect::<Vec<_>>());
    entry["tangential_traction"] = column(|f| f.tangential);
    entry["slip"] = column(|f| f.slip);
    entry["total_slip"] = column(|f| f.total_slip);
    entry["friction_status"] = points.iter().map(|f| f.status.name()).collect();
    entry["friction"] = friction_json(friction);
    entry["tangential_force"] = json_number(pair.tangential_force());
    entry["stick_length"] = json_number(stick);
    entry["slip_length"] = json_number(slip);
}

/// The `contact` of `summary.json`; a pair with friction also has `friction`,
/// `tangential_force`, `stick_length` and `slip_length`, and per point `tangential_traction`,
/// `slip`, `total_slip` and `friction_status`.
fn contact_json(model: &Model, pairs: &[PairResult], bodies: &[BodyResult]) -> Value {
    let pressures = contact_pressures(pairs, bodies);
    pairs
        .iter()
        .zip(&pressures)
        .enumerate()
        .map(|(k, (p, pressure))| {
            let status: Vec<&str> = (0..p.gap.len()).map(|i| point_status(p, i)).collect();
            let body: Vec<&str> = p.side.iter().map(|&s| p.bodies[s].as_str()).collect();
            let mut entry = json!({
                "name": p.name,
                "bodies": p.bodies,
                "body": body,
                "node": p.node,
                "x": json_numbers(&p.x),
                "y": json_numbers(&p.y),
                "gap": json_numbers(&p.gap),
                "pressure": json_numbers(pressure),
                "nodal_traction": json_numbers(&p.pressure),
                "status": status,
                "weight": json_numbers(&p.weight),
                "normal": p.nx.iter().zip(&p.ny).map(|(&x, &y)| json_numbers(&[x, y])).collect::<Vec<_>>(),
                "nodal_force": p.fx.iter().zip(&p.fy).map(|(&x, &y)| json_numbers(&[x, y])).collect::<Vec<_>>(),
                "force": [json_numbers(&p.force_on(0)), json_numbers(&p.force_on(1))],
                "max_penetration": json_number(p.max_penetration()),
                "complementarity": json_number(p.complementarity()),
            });
            match model.pairs.get(k).map(|m| m.friction) {
                Some(f) if f.is_active() => add_friction(&mut entry, p, f),
                _ => {}
            }
            entry
        })
        .collect()
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
}
