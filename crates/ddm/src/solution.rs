//! Results of a solve: per-body fields, per-pair contact quantities, history and timings.

use std::collections::BTreeMap;

use contactdd_core::post::stresses;
use contactdd_core::{dof, ElasticBody, Mesh, Vector, DIM};

use crate::coarse::CoarseMode;
use crate::contact::formulation::Forces;
use crate::contact::{Friction, Interface, Status};
use crate::force_balance::Balance;
use crate::method::Method;
use crate::model::Model;
use crate::outcome::{Breakdown, Record, Stop};
use crate::relaxation::Gamma;
use crate::settings::{Accelerator, Settings};

/// Fields of one body.
#[derive(Clone, Debug)]
pub struct BodyResult {
    /// Body name.
    pub name: String,
    /// The mesh (nodes, triangles, boundaries).
    pub mesh: Mesh,
    /// Displacement, 2 per node.
    pub displacement: Vec<f64>,
    /// Nodal (averaged) stress `[σ_xx, σ_yy, σ_xy, σ_zz]`.
    pub stress: Vec<[f64; 4]>,
    /// Nodal von Mises stress.
    pub von_mises: Vec<f64>,
    /// Contact pressure σ_n at the body's contact nodes (≤ 0, compressive), 0 elsewhere.
    pub contact_pressure: Vec<f64>,
    /// Where `mesh` is the skin of a body that another process meshes: the body's own number of
    /// each skin node (the numbering of the contact results); empty when `mesh` is the body's.
    pub node_ids: Vec<usize>,
}

impl BodyResult {
    /// The entry of a body whose fields another process holds (a distributed solve): its name
    /// and skin, no fields.
    pub fn elsewhere(body: &ElasticBody, node_ids: &[usize]) -> BodyResult {
        BodyResult {
            name: body.name.clone(),
            mesh: body.mesh.clone(),
            displacement: Vec::new(),
            stress: Vec::new(),
            von_mises: Vec::new(),
            contact_pressure: Vec::new(),
            node_ids: node_ids.to_vec(),
        }
    }

    /// The body's own number of node `n` of `mesh`.
    pub fn body_node(&self, n: usize) -> usize {
        self.node_ids.get(n).copied().unwrap_or(n)
    }

    /// Whether this process holds the body's fields.
    pub fn has_fields(&self) -> bool {
        !self.displacement.is_empty()
    }
}

/// Contact quantities of one pair, one entry per contact point (both sides).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PairResult {
    /// Pair name.
    pub name: String,
    /// The two body names.
    pub bodies: [String; 2],
    /// Which side (0 or 1) each point belongs to.
    pub side: Vec<usize>,
    /// Node index in its body.
    pub node: Vec<usize>,
    /// Coordinates (undeformed).
    pub x: Vec<f64>,
    /// Coordinates (undeformed).
    pub y: Vec<f64>,
    /// Gap after deformation d − s (negative = penetration of the penalty solution).
    pub gap: Vec<f64>,
    /// Normal contact stress σ_n = (d − s)⁻/θ (≤ 0); on the following side of a balanced pair the
    /// traction of the nodal contact force, F/w.
    pub pressure: Vec<f64>,
    /// True where closed: the gap d − s is negative (where the penalty formulation has pressure;
    /// on the following side of a balanced pair, its own gap).
    pub closed: Vec<bool>,
    /// Nodal quadrature weight of each point.
    pub weight: Vec<f64>,
    /// Outward normal of each point (x component).
    pub nx: Vec<f64>,
    /// Outward normal of each point (y component).
    pub ny: Vec<f64>,
    /// The contact force on each point's node (x component): w σ_n n for an own-side pair; for a
    /// balanced pair the node's share of the reference side's pressures (docs/method.md §4).
    pub fx: Vec<f64>,
    /// The contact force on each point's node (y component).
    pub fy: Vec<f64>,
    /// True where the point's gap is one the contact enforces (an own-side point, or the
    /// reference side of a balanced pair); false where it is a reading of the following side.
    pub enforced: Vec<bool>,
    /// Tangential traction σ_t along t = n turned by +90° (the reference side's points of a
    /// frictional pair; 0 elsewhere). Its force also enters `fx`, `fy` on both sides.
    pub tangential: Vec<f64>,
    /// The slip of this solve (load step): g − g₀, the change of the tangential relative
    /// displacement g = (u_own − u_partner)·t since the last step (0 without friction).
    pub slip: Vec<f64>,
    /// The accumulated tangential relative displacement g since the unloaded state.
    pub total_slip: Vec<f64>,
    /// Where each point is on its friction disc (open without friction).
    pub status: Vec<Status>,
    /// The pair's tangential law.
    pub friction: Friction,
}

impl PairResult {
    /// The largest contact pressure p = −σ_n ≥ 0 over the points whose own pressure acts (a
    /// following point's pressure is read from them, so it is never larger); 0 if none presses.
    pub fn max_pressure(&self) -> f64 {
        (0..self.pressure.len())
            .filter(|&i| self.is_enforced(i) && self.pressure[i].is_finite())
            .fold(0.0, |m: f64, i| m.max(-self.pressure[i]))
    }

    /// The largest penetration max (s − d)⁺ over the points with a partner whose gap the contact
    /// enforces (a length; 0 if none).
    pub fn max_penetration(&self) -> f64 {
        (0..self.gap.len())
            .filter(|&i| self.is_enforced(i) && self.gap[i].is_finite())
            .fold(0.0, |m, i| m.max(-self.gap[i]))
    }

    /// The complementarity residual: the largest |d − s| where the pressure is not zero, over the
    /// points whose gap the contact enforces (a length). The exact unilateral contact has zero gap
    /// wherever it presses; the penalty formulation leaves the penetration θ·p there.
    pub fn complementarity(&self) -> f64 {
        (0..self.gap.len())
            .filter(|&i| self.is_enforced(i) && self.pressure[i] < 0.0 && self.gap[i].is_finite())
            .fold(0.0, |m, i| m.max(self.gap[i].abs()))
    }

    /// Point i's gap is enforced (true where `enforced` is not filled in).
    fn is_enforced(&self, i: usize) -> bool {
        self.enforced.get(i).copied().unwrap_or(true)
    }

    /// The resultant tangential force Σ w σ_t of the pair's frictional points (a force per unit
    /// thickness along their tangents; 0 without friction).
    pub fn tangential_force(&self) -> f64 {
        (0..self.tangential.len())
            .map(|i| self.weight[i] * self.tangential[i])
            .sum()
    }

    /// How far the tractions leave the friction disc: the largest (|σ_t| − b)⁺ / b over the
    /// pressed points, b the slip bound at the point's pressure (0 without friction).
    pub fn traction_excess(&self) -> f64 {
        (0..self.tangential.len())
            .filter_map(|i| {
                let b = self.friction.bound(-self.pressure[i]);
                (b > 0.0).then(|| (self.tangential[i].abs() - b).max(0.0) / b)
            })
            .fold(0.0, f64::max)
    }

    /// How far the slips are from Coulomb's (or Tresca's) law (a length): the largest slip of a
    /// point that sticks (the penalty's elastic slip; 0 for the exact law), and of a slipping
    /// point its slip along its traction (the law has it against the traction).
    pub fn slip_violation(&self) -> f64 {
        (0..self.status.len())
            .map(|i| match self.status[i] {
                Status::Stick => self.slip[i].abs(),
                Status::Slip => (self.slip[i] * self.tangential[i].signum()).max(0.0),
                Status::Open => 0.0,
            })
            .fold(0.0, f64::max)
    }

    /// The lengths Σ w of the points that stick and of those that slip.
    pub fn stick_slip_lengths(&self) -> (f64, f64) {
        let length = |want: Status| {
            (0..self.status.len())
                .filter(|&i| self.status[i] == want)
                .map(|i| self.weight[i])
                .sum()
        };
        (length(Status::Stick), length(Status::Slip))
    }

    /// Total contact force on side `side` (the force the other body exerts): the sum of its
    /// nodal forces, Σ w σ_n n for an own-side pair.
    pub fn force_on(&self, side: usize) -> Vector {
        let mut f = [0.0; DIM];
        for i in (0..self.side.len()).filter(|&i| self.side[i] == side) {
            f[0] += self.fx[i];
            f[1] += self.fy[i];
        }
        f
    }
}

/// Per body, the nodal contact forces of the reported pressures (2 per node; w σ_n n for an
/// own-side pair, the dual mortar shares for a balanced one).
pub fn nodal_contact_force(model: &Model, b: usize, contact: &[PairResult]) -> Vec<f64> {
    let mut f = vec![0.0; model.bodies[b].load.len()];
    for (pair, p) in model.pairs.iter().zip(contact) {
        if !pair.bodies.contains(&b) {
            continue;
        }
        for i in (0..p.side.len()).filter(|&i| pair.bodies[p.side[i]] == b) {
            // A point without a partner has no force.
            if p.fx[i].is_finite() && p.fy[i].is_finite() {
                f[dof(p.node[i], 0)] += p.fx[i];
                f[dof(p.node[i], 1)] += p.fy[i];
            }
        }
    }
    f
}

/// A solve's result (also the partial result of a failed solve).
#[derive(Clone, Debug)]
pub struct Solution {
    /// True if every body met the tolerance.
    pub converged: bool,
    /// How the iteration ended.
    pub stop: Stop,
    /// Human-readable outcome (`None` when converged).
    pub message: Option<String>,
    /// Iterations taken.
    pub iterations: usize,
    /// Method used.
    pub method: Method,
    /// γ rule used.
    pub gamma: Gamma,
    /// Penalty θ per pair.
    pub theta: Vec<f64>,
    /// Per-iteration history.
    pub history: Vec<Record>,
    /// Per-body fields.
    pub bodies: Vec<BodyResult>,
    /// Per-pair contact results.
    pub contact: Vec<PairResult>,
    /// Accelerator used.
    pub accelerator: Accelerator,
    /// Coarse mode used.
    pub coarse: CoarseMode,
    /// Per body, the equilibrium residual: the contact forces the fields carry against those of
    /// the reported pressures, relative to the total contact force ([`crate::equilibrium::equilibrium`]).
    pub equilibrium: Vec<f64>,
    /// Per body, the independent force balance of the result: applied loads, contact forces and
    /// support reactions of the field ([`crate::force_balance`]).
    pub balance: Balance,
    /// Multiplier updates (inner solves) of the augmented Lagrangian pairs; 0 if every pair
    /// uses the penalty formulation.
    pub updates: usize,
    /// The gap tolerance of the augmented Lagrangian pairs (a length; `None` without such pairs).
    pub gap_tol: Option<f64>,
    /// The stopping tolerance the solve used (`Settings::tol`).
    pub tol: f64,
    /// The factor of every load and prescribed displacement of the model that this solve used
    /// (1 unless it is a load step).
    pub load_factor: f64,
    /// The settings of the solve; their `Display` is the description of the solver that the
    /// console, `check`, `summary.json` and Python print.
    pub settings: Settings,
    /// The final interface loads T of the contact points (a warm start for another solve of the
    /// same prepared model: [`crate::solver::solve_from`]).
    pub interface_loads: Vec<f64>,
    /// The friction state at the end of this solve, the start of the next load step: per
    /// frictional contact point (j, σ_t, g, λ), its index, tangential traction, tangential
    /// displacement and normal multiplier (0 for the penalty formulation)
    /// ([`crate::solver::Prepared::set_friction_state`]); empty without friction.
    pub friction_state: Vec<(usize, f64, f64, f64)>,
    /// The condensation path every body took (dense or sparse; `docs/sparse-path.md`).
    pub condensation: Vec<crate::condensed::Condensation>,
    /// Wall time per phase, seconds.
    pub timing: BTreeMap<String, f64>,
}

// The two texts of how an iteration ended: the full message of a solve (`stop_message`) and the
// short reason of a sweep cell (`short_reason`). Keep them together so that they stay in step.

/// The message for a non-converged outcome.
pub fn stop_message(
    stop: &Stop,
    model: &Model,
    settings: &Settings,
    history: &[Record],
) -> Option<String> {
    if settings.accelerator == Accelerator::Newton {
        return newton_message(stop, model, history, settings.tol);
    }
    let (method, tol) = (settings.method, settings.tol);
    let body = |b: usize| body_name(model, b);
    match stop {
        Stop::Converged => None,
        Stop::MaxIterations => {
            let worst = largest_change(history);
            Some(format!(
                "not converged after {} iterations (largest relative change {worst:.3e} > tolerance {tol:.1e}); raise max-iter, try a smaller gamma, gamma = \"auto\", another method, or the interface Newton method (accelerator = \"newton\"), whose count does not grow with the penalty's stiffness",
                history.len()
            ))
        }
        Stop::Interrupted => Some(format!("interrupted after {} iterations", history.len())),
        Stop::Unenforced { .. } => unenforced_message(stop),
        Stop::Unbalanced { .. } => unbalanced_message(stop, model, "tighten tol"),
        Stop::Stalled { residual, limit } => Some(format!(
            "stalled: after {} iterations the change is below the tolerance {tol:.1e}, but the contact forces that the fields carry differ from those of the contact pressures by {residual:.2e} of the total contact force (more than equilibrium-tol = {limit:.1e}); the iteration was still far from its fixed point: use a tighter tol, a larger gamma or gamma = \"auto\"",
            history.len()
        )),
        Stop::Diverged {
            body: b,
            iteration,
            reason,
        } => Some(match reason {
            Breakdown::LostContact if method == Method::Neumann => format!(
                "diverged: body '{}' is singular at iteration {iteration}: the neumann method (φ = 0) cannot hold a body that only its contact zone supports; use robin, active-set or a two-point method",
                body(*b)
            ),
            Breakdown::LostContact => format!(
                "diverged: body '{}' lost all contact at iteration {iteration} (its Robin problem became singular); try a smaller gamma, gamma = \"auto\", another method or the interface Newton method (accelerator = \"newton\")",
                body(*b)
            ),
            Breakdown::Slides => format!(
                "no equilibrium: body '{}' slides at iteration {iteration}: its loads push it harder than friction can hold it",
                body(*b)
            ),
            Breakdown::Singular => format!(
                "diverged: the Robin problem of body '{}' became singular at iteration {iteration}; try a smaller gamma, another method or the interface Newton method (accelerator = \"newton\")",
                body(*b)
            ),
            Breakdown::NonFinite => format!(
                "diverged: non-finite values in body '{}' at iteration {iteration}; try a smaller gamma or the interface Newton method (accelerator = \"newton\")",
                body(*b)
            ),
            Breakdown::Growth => format!(
                "diverged: the displacements of body '{}' grew without bound at iteration {iteration}; try a smaller gamma or the interface Newton method (accelerator = \"newton\")",
                body(*b)
            ),
            Breakdown::NoDescent => format!(
                "diverged: the iteration stopped making progress at iteration {iteration} (body '{}')",
                body(*b)
            ),
        }),
    }
}

/// The message of [`Stop::Unenforced`] (the same for every iteration).
fn unenforced_message(stop: &Stop) -> Option<String> {
    let Stop::Unenforced {
        updates,
        violation,
        limit,
    } = stop
    else {
        return None;
    };
    if violation <= limit {
        // The gaps met gap-tol; the pressures of the points with a stiffer inner penalty did not
        // settle to tol (`docs/augmented-lagrangian.md`, "Stopping rule").
        return Some(format!(
            "not enforced: after {updates} multiplier updates the gaps meet gap-tol ({violation:.3e} ≤ {limit:.3e}, a length) but the contact pressures still change by more than tol of the peak from one update to the next (the result is the closest update's); raise tol to accept it, or raise max-updates"
        ));
    }
    Some(format!(
        "not enforced: after {updates} multiplier updates the contact still violates the Signorini conditions by {violation:.3e} at best (gap-tol {limit:.3e}, a length; the result is that best update's); a tolerance near the rounding of the displacements cannot be reached, and with forces = \"own-side\" on curved non-matching meshes the violation can stop decreasing above it (balanced pairs, the default, do not): raise gap-tol to accept it; otherwise raise max-updates or use a smaller penalty θ, which makes the updates contract faster"
    ))
}

/// The message of a result whose forces do not balance, with its likeliest cause: rounding where
/// the reactions cannot resolve it (a displacement far beyond the strains), own-side pairs, a
/// stiffness contrast beyond what double precision resolves, else `remedy`.
pub(crate) fn unbalanced_message(stop: &Stop, model: &Model, remedy: &str) -> Option<String> {
    let Stop::Unbalanced {
        body: b,
        imbalance,
        floor,
        motion,
        limit,
    } = *stop
    else {
        return None;
    };
    let head = match b {
        Some(b) => format!(
            "not a solution: the iteration met its tolerance, but on body '{}' the applied loads, contact forces and support reactions leave a net force {imbalance:.2e} of the largest force total of a body (more than balance-tol = {limit:.1e})",
            body_name(model, b)
        ),
        None => format!(
            "not a solution: the iteration met its tolerance, but the applied loads and the support reactions of the whole problem leave a net force {imbalance:.2e} of their magnitudes (more than balance-tol = {limit:.1e})"
        ),
    };
    let young = |b: usize| model.bodies[b].material.young();
    let (soft, stiff) = (0..model.bodies.len())
        .map(young)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), e| {
            (lo.min(e), hi.max(e))
        });
    let cause = if stiff / soft >= 1e6 {
        format!("the Young's moduli span {:.1e} (from {soft:.3e} to {stiff:.3e}): a floating body that much stiffer than its contact springs loses its rigid motion to rounding in double precision. Lower the stiff bodies' modulus: 1e4 to 1e6 times their partners' already makes them rigid for them", stiff / soft)
    } else if motion > 1.0 || floor >= 0.1 * imbalance.max(limit) {
        format!("its displacements reach {motion:.1e} times its size (the rounding of its reactions alone {floor:.1e}): far beyond the small displacements of linear elasticity, so double precision loses the strains beside them: prescribe displacements of the size the linear theory assumes")
    } else if model.pairs.iter().any(|p| p.forces == Forces::OwnSide) {
        "own-side pairs on non-matching meshes let each side integrate its own pressures, so action and reaction differ: use forces = \"balanced\" (the default), or raise balance-tol to accept the difference".to_string()
    } else {
        remedy.to_string()
    };
    Some(format!("{head}; {cause}"))
}

/// Why the Newton steps can stall with own-side pairs, if the model has any.
fn own_side_hint(model: &Model) -> &'static str {
    if model.pairs.iter().any(|p| p.forces == Forces::OwnSide) {
        "; own-side pairs on non-matching meshes derive from no energy, and their residual can stop decreasing short of a solution: balanced pairs (forces = \"balanced\", the default) minimise an energy"
    } else {
        ""
    }
}

/// Why the contact forces of converged Newton steps can miss the fields' own.
fn stall_cause(model: &Model) -> &'static str {
    if model.pairs.iter().any(|p| p.forces == Forces::OwnSide) {
        "with own-side pairs on non-matching meshes each body integrates its own pressures, so a body held only by contact may not balance: refine the coarser contact mesh or use forces = \"balanced\""
    } else {
        "the rounding of the fields is then as large as the contact forces, which happens when the loads are so small that the rounding of the node coordinates (about 1e-16 of the model's size) exceeds the displacements they cause: scale the loads up (where the contact points start touching, the answer scales with them)"
    }
}

/// The largest relative change of a body in the last record (NaN without records).
fn largest_change(history: &[Record]) -> f64 {
    history
        .last()
        .map(|r| r.rel_change.iter().cloned().fold(0.0, f64::max))
        .unwrap_or(f64::NAN)
}

/// The message for a non-converged outcome of the interface Newton method.
fn newton_message(stop: &Stop, model: &Model, history: &[Record], tol: f64) -> Option<String> {
    let body = |b: usize| body_name(model, b);
    let steps = history.len();
    match stop {
        Stop::Converged => None,
        Stop::MaxIterations => {
            let worst = largest_change(history);
            Some(format!(
                "not converged after {steps} Newton steps (largest relative change {worst:.3e} > tolerance {tol:.1e}); raise max-iter, or try the Robin sweeps (accelerator = \"none\")"
            ))
        }
        Stop::Interrupted => Some(format!("interrupted after {steps} Newton steps")),
        Stop::Unenforced { .. } => unenforced_message(stop),
        Stop::Unbalanced { .. } => unbalanced_message(stop, model, "tighten tol"),
        Stop::Stalled { residual, limit } => Some(format!(
            "stalled: the Newton steps converged, but the contact forces that the fields carry differ from those of the contact pressures by {residual:.2e} of the total contact force (more than equilibrium-tol = {limit:.1e}); {}",
            stall_cause(model)
        )),
        Stop::Diverged {
            body: b,
            iteration,
            reason,
        } => Some(match reason {
            Breakdown::LostContact => format!(
                "diverged: nothing holds body '{}' at Newton step {iteration}: no closed contact point resists the rigid motion its loads push it in: check that its loads press it against its partners",
                body(*b)
            ),
            Breakdown::NoDescent => format!(
                "diverged: the Newton steps stopped reducing the residual at step {iteration}; try the Robin sweeps (accelerator = \"none\"){}",
                own_side_hint(model)
            ),
            Breakdown::Slides => format!(
                "no equilibrium: body '{}' slides: its loads push it along its contact zones harder than friction can hold it (found at Newton step {iteration}); lower the tangential load, raise the friction, or support the body",
                body(*b)
            ),
            Breakdown::Singular => format!(
                "diverged: the interface Newton system became singular at step {iteration}; try the Robin sweeps (accelerator = \"none\")"
            ),
            Breakdown::NonFinite => format!(
                "diverged: non-finite values in body '{}' at Newton step {iteration}",
                body(*b)
            ),
            Breakdown::Growth => format!(
                "diverged: the displacements of body '{}' grew without bound at Newton step {iteration}: is it held?",
                body(*b)
            ),
        }),
    }
}

/// A one-line reason for a table cell or CSV field.
pub fn short_reason(model: &Model, stop: &Stop) -> String {
    match stop {
        Stop::Converged => String::new(),
        Stop::MaxIterations => "max iterations".into(),
        Stop::Interrupted => "interrupted".into(),
        Stop::Stalled { .. } => "stalled (out of equilibrium)".into(),
        Stop::Unbalanced { .. } => "out of balance".into(),
        Stop::Unenforced { .. } => "max multiplier updates".into(),
        Stop::Diverged {
            body,
            iteration,
            reason,
        } => {
            let what = match reason {
                Breakdown::LostContact => "lost all contact",
                Breakdown::Singular => "singular Robin problem",
                Breakdown::NonFinite => "non-finite values",
                Breakdown::Growth => "growth",
                Breakdown::NoDescent => "no progress",
                Breakdown::Slides => "slides",
            };
            format!(
                "{}: {what} at iteration {iteration}",
                body_name(model, *body)
            )
        }
    }
}

/// The name of body `b` in messages (`?` for an index out of range).
fn body_name(model: &Model, b: usize) -> &str {
    model.bodies.get(b).map_or("?", |x| x.name.as_str())
}

/// Per-pair contact results from the final normal displacements.
pub fn pair_results(model: &Model, interface: &Interface, un: &[f64]) -> Vec<PairResult> {
    let mut s = vec![0.0; un.len()];
    interface.sum_normal(un, &mut s);
    let g = interface.slip_sums(un);
    let mut out: Vec<PairResult> = model
        .pairs
        .iter()
        .map(|p| PairResult {
            name: p.name.clone(),
            bodies: p.bodies.map(|b| model.bodies[b].name.clone()),
            friction: p.friction.resolved(),
            ..Default::default()
        })
        .collect();
    // The tangential unknown of each (pair, body, node), where a balanced pair has one.
    let tangent: std::collections::HashMap<(usize, usize, usize), usize> = interface
        .points
        .iter()
        .enumerate()
        .filter(|(_, p)| !p.is_contact())
        .map(|(j, p)| ((p.pair, p.body, p.node), j))
        .collect();
    for (j, p) in interface.points.iter().enumerate() {
        if !p.is_contact() {
            continue;
        }
        let mut force = [0.0; DIM];
        let fj = interface.total_force(j, &s, &g);
        for c in 0..DIM {
            force[c] = fj * p.normal[c];
        }
        if let Some(&t) = tangent.get(&(p.pair, p.body, p.node)) {
            let ft = interface.total_force(t, &s, &g);
            let dir = interface.points[t].normal;
            for c in 0..DIM {
                force[c] += ft * dir[c];
            }
        }
        let r = &mut out[p.pair];
        let side = usize::from(model.pairs[p.pair].bodies[0] != p.body);
        let x = model.position(p.body, p.node);
        let gap = if p.has_partner() {
            p.gap - s[j]
        } else {
            f64::INFINITY
        };
        r.side.push(side);
        r.node.push(p.node);
        r.x.push(x[0]);
        r.y.push(x[1]);
        r.gap.push(gap);
        r.pressure.push(interface.pressure(j, &s));
        r.closed.push(p.overlap(s[j]) < 0.0);
        r.weight.push(p.weight);
        r.nx.push(p.normal[0]);
        r.ny.push(p.normal[1]);
        r.fx.push(force[0]);
        r.fy.push(force[1]);
        r.enforced.push(p.carries());
        let (traction, status) = interface.traction(j, &s, &g);
        let reference = p.friction.as_ref().map_or(0.0, |f| f.reference);
        r.tangential.push(traction);
        r.slip.push(g[j] - reference);
        r.total_slip.push(g[j]);
        r.status.push(status);
    }
    out
}

/// Fields of every body from their displacements.
pub fn body_results(
    model: &Model,
    interface: &Interface,
    un: &[f64],
    displacements: Vec<Vec<f64>>,
) -> Vec<BodyResult> {
    let mut s = vec![0.0; un.len()];
    interface.sum_normal(un, &mut s);
    model
        .bodies
        .iter()
        .zip(displacements)
        .enumerate()
        .map(|(b, (body, u))| {
            // Another process recovered this body's field.
            if u.is_empty() {
                let remote = model.remote.get(b).and_then(Option::as_ref);
                return BodyResult::elsewhere(body, remote.map_or(&[], |r| r.ids.as_slice()));
            }
            let st = stresses(&body.mesh, &body.material, body.plane, &u);
            let mut pressure = vec![0.0; body.mesh.num_nodes()];
            for (j, p) in interface.points.iter().enumerate() {
                if p.body == b && p.has_partner() {
                    let sn = interface.pressure(j, &s);
                    pressure[p.node] = f64::min(pressure[p.node], sn);
                }
            }
            BodyResult {
                name: body.name.clone(),
                mesh: body.mesh.clone(),
                displacement: u,
                stress: st.nodal,
                von_mises: st.von_mises,
                contact_pressure: pressure,
                node_ids: Vec::new(),
            }
        })
        .collect()
}
