//! A monolithic reference: the same discrete penalty problem as the domain decomposition, solved
//! for all bodies at once by a globalised semismooth Newton method on the assembled equations
//!   K u − f − Σ_j (w_j/θ_j) min(0, d_j − s_j(u)) n_j = 0
//! (docs/monolithic.md), with the tangential forces w_j σ_t,j of Coulomb's or Tresca's law on
//! the carriers of frictional pairs. It shares no solver code with the decomposition: only the
//! model, the contact geometry and the finite element core.
//!
//! - `reduced`: the contact terms touch only the contact DOFs, so the interior DOFs of every
//!   body are eliminated once, exactly, by a sparse Cholesky factorisation with the contact DOFs
//!   ordered last; every Newton step then refactorises only the contact block.
//! - `system`: the reduced equations F(x) = 0 on the contact DOFs x, their generalised Jacobian
//!   for a closed set and the frictional points' stick/slip/open statuses, and the step.
//! - `modes`: rigid motions that no closed contact (nor sticking point) resists, kept out of the
//!   step.
//! - `friction`: the statuses the step assumes beyond the state's, and a body that slides.
//! - `balance`: the equilibrium check on the assembled system.
//!
//! The iteration starts from u = 0 and stops when a full step leaves the closed set and the
//! statuses unchanged (then the step solved the linear equations of the final sets); the result
//! counts as converged only if it is also in equilibrium.

mod balance;
mod friction;
mod modes;
mod reduced;
mod system;

use std::time::Instant;

use rayon::prelude::*;

use crate::augmented::{
    augmented_points, default_gap_tol, distance, friction_update, uzawa_update, FrictionUpdate,
    Update,
};
use crate::contact::formulation::InnerPenalty;
use crate::contact::{Interface, Status};
use crate::error::SetupError;
use crate::model::Model;
use crate::settings::Settings;
use crate::solution::{body_results, pair_results, BodyResult, PairResult};

use modes::{dot, project_out, Modes};
use reduced::ReducedBody;
use system::{Evaluation, ReducedSystem, Sparse};

/// Accepted states whose worst merit the line search compares with (Grippo, Lampariello &
/// Lucidi's non-monotone rule).
const WINDOW: usize = 10;
/// Halvings of the step at most in the line search.
const MAX_HALVINGS: usize = 12;
/// Sufficient decrease of the merit per unit step length (Armijo).
const ARMIJO: f64 = 1e-4;
/// A relative residual at the level of round-off: no refinement step needed.
const ROUND_OFF: f64 = 1e-14;

/// Limits of the monolithic solve.
#[derive(Clone, Debug, PartialEq)]
pub struct MonolithicSettings {
    /// Newton steps at most.
    pub max_steps: usize,
    /// Largest accepted equilibrium residual of a body, relative to the applied and contact
    /// forces (round-off reaches about 1e-7 with a 1e8 stiffness contrast between bodies).
    pub equilibrium_tol: f64,
    /// Largest accepted net force, relative to the same, along a rigid motion that no contact
    /// resists (own-side pairs on non-matching meshes leave a small one: each side integrates its
    /// own pressures).
    pub imbalance_tol: f64,
    /// Largest net force and moment of a body, and of the problem's loads against its reactions,
    /// relative to the largest force total of a body ([`crate::force_balance`], the
    /// decomposition's check and default).
    pub balance_tol: f64,
    /// Augmented Lagrangian pairs: the largest violation of the Signorini conditions (a length;
    /// `None`: `GAP_TOL` times the largest normal displacement of the contact points in the first
    /// solve, the decomposition's rule).
    pub gap_tol: Option<f64>,
    /// Augmented Lagrangian pairs: where a point's inner penalty is stiffer than its pair's θ,
    /// the largest change of its pressure from one update to the next, relative to the peak
    /// pressure, at which the pressures count as settled (`docs/augmented-lagrangian.md`,
    /// "Stopping rule"); the decomposition's default `tol`.
    pub tol: f64,
    /// Augmented Lagrangian pairs: multiplier updates at most (plain Uzawa updates, each a
    /// Newton solve).
    pub max_updates: usize,
}

impl Default for MonolithicSettings {
    fn default() -> Self {
        MonolithicSettings {
            max_steps: 50,
            equilibrium_tol: 1e-6,
            balance_tol: crate::settings::BALANCE_TOL,
            imbalance_tol: 1e-2,
            gap_tol: None,
            tol: Settings::default().tol,
            max_updates: 200,
        }
    }
}

/// One Newton step.
#[derive(Clone, Debug, PartialEq)]
pub struct MonolithicStep {
    /// Step number, from 1.
    pub step: usize,
    /// Closed contact points after the step.
    pub active: usize,
    /// ‖F‖ after the step relative to the condensed load.
    pub residual: f64,
    /// Step length taken by the line search (1: the full Newton step).
    pub step_length: f64,
}

/// The monolithic reference solution.
#[derive(Clone, Debug)]
pub struct MonolithicSolution {
    /// True if the closed set settled and the result is in equilibrium.
    pub converged: bool,
    /// Why it did not converge.
    pub message: Option<String>,
    /// Newton steps taken (of the last multiplier update).
    pub newton_steps: usize,
    /// Augmented Lagrangian multiplier updates (Newton solves); 0 for the penalty formulation.
    pub updates: usize,
    /// The gap tolerance of the augmented Lagrangian pairs (a length); `None` without them.
    pub gap_tol: Option<f64>,
    /// The steps.
    pub history: Vec<MonolithicStep>,
    /// Rigid motions of the final closed set that no contact resists, kept out of the steps.
    pub rigid_modes: Vec<String>,
    /// Per body, the equilibrium residual off those motions (relative).
    pub equilibrium: Vec<f64>,
    /// The force balance of the bodies and of the problem ([`crate::force_balance`]), checked
    /// against `equilibrium_tol` as the decomposition checks its own.
    pub balance: crate::force_balance::Balance,
    /// Per entry of `rigid_modes`, the net force along it (relative).
    pub imbalance: Vec<f64>,
    /// Per-body fields.
    pub bodies: Vec<BodyResult>,
    /// Per-pair contact results.
    pub contact: Vec<PairResult>,
    /// Normal displacements of all contact points.
    pub un: Vec<f64>,
    /// Wall time, seconds.
    pub seconds: f64,
}

/// Errors for a contact node on an inclined `normal` support: the reduced system here keeps
/// contact DOFs in x/y components, which such a node does not have (the domain decomposition
/// solves it).
fn check_inclined_corners(model: &Model, interface: &Interface) -> Result<(), SetupError> {
    for p in &interface.points {
        let body = &model.bodies[p.body];
        if body.constraints.inclined_normal(p.node).is_some() {
            let pair = &model.pairs[p.pair];
            let side = usize::from(pair.bodies[1] == p.body);
            return Err(SetupError::Body {
                body: body.name.clone(),
                message: format!(
                    "node {} of contact boundary '{}' (pair '{}') lies on an inclined 'normal' \
                     support; the monolithic reference cannot solve that corner (the domain \
                     decomposition can)",
                    p.node, pair.boundaries[side], pair.name
                ),
            });
        }
    }
    Ok(())
}

/// Solves the penalty contact problem monolithically with the default limits.
pub fn solve_monolithic(model: &Model) -> Result<MonolithicSolution, SetupError> {
    solve_monolithic_with(model, &MonolithicSettings::default(), None)
}

/// Solves the penalty contact problem monolithically, calling `on_step` after every Newton step.
/// Errors only for a model that cannot be solved (a body that is not held, invalid contact
/// geometry or limits); a run that does not converge returns its last state with
/// `converged = false`.
pub fn solve_monolithic_with(
    model: &Model,
    settings: &MonolithicSettings,
    on_step: Option<&(dyn Fn(&MonolithicStep) + Sync)>,
) -> Result<MonolithicSolution, SetupError> {
    check_settings(settings)?;
    let start = Instant::now();
    // The inner penalty of the decomposition's interface Newton method (its default): the
    // augmented balanced pairs' points take a θ no softer than the rod model's with c =
    // AUGMENTED_C, so that each update contracts by about the same factor and the default gap
    // tolerance, taken from the first solve, does not depend on the pair's θ. The tangential
    // penalty of a frictional point is its θ, so an augmented frictional pair needs it too: the
    // decomposition's only method with friction uses it (docs/monolithic.md).
    let mut interface = Interface::with_inner(model, InnerPenalty::Stiffened)?;
    check_inclined_corners(model, &interface)?;
    // One level of parallelism: over bodies when there are several, inside faer otherwise.
    let par = if model.bodies.len() > 1 {
        faer::Par::Seq
    } else {
        faer::Par::rayon(0)
    };
    let bodies = model
        .bodies
        .par_iter()
        .enumerate()
        .map(|(b, body)| ReducedBody::new(body, interface.of_body(b), par))
        .collect::<Result<Vec<_>, _>>()?;
    let augmented = augmented_points(model, &interface);
    let mut gap_tol = settings.gap_tol;
    let mut updates = 0;
    loop {
        updates += 1;
        let (next, slip) = {
            let system = ReducedSystem::new(model, &interface, &bodies);
            let modes = modes::free_rigid_modes(model, &system);
            let run = newton(&system, &modes, settings, on_step);
            let un: Vec<f64> = system.un.iter().map(|a| a.at(&run.x)).collect();
            let limit = *gap_tol.get_or_insert_with(|| default_gap_tol(&un));
            // The normal multipliers, and the frictional points' tangential ones (the exact
            // Coulomb law); done as the decomposition's loop is.
            let update = uzawa_update(&interface, &un, &augmented);
            let slip = friction_update(&interface, &un, &augmented);
            let enforced =
                !model.is_augmented() || distance(&update, &slip, limit, settings.tol) <= 1.0;
            if run.stop.is_some() || enforced || updates >= settings.max_updates {
                let end = End {
                    run,
                    un,
                    unenforced: (!enforced)
                        .then(|| unenforced(updates, &update, &slip, (limit, settings.tol))),
                    updates: if model.is_augmented() { updates } else { 0 },
                    gap_tol: model.is_augmented().then_some(limit),
                };
                return finish(model, &system, &bodies, &modes, settings, end, start);
            }
            (update.multipliers, slip)
        };
        slip.apply(&mut interface);
        // Uzawa's update: the multipliers become the pressures just found.
        for (j, p) in interface.points.iter_mut().enumerate() {
            if augmented[j].is_some() {
                p.multiplier = next[j];
            }
        }
    }
}

/// Why the multiplier updates stopped short of done after `updates` updates: the violation of
/// the last `update` (and `slip`) above the gap tolerance, or the pressures not settled to `tol`
/// of the peak; `(gap_tol, tol)`.
fn unenforced(
    updates: usize,
    update: &Update,
    slip: &FrictionUpdate,
    (gap_tol, tol): (f64, f64),
) -> String {
    let violation = update.violation.max(slip.violation);
    if violation > gap_tol {
        return format!(
            "not enforced: after {updates} multiplier updates the contact violates the \
             Signorini conditions by {violation:.3e} (gap-tol {gap_tol:.3e}, a length)"
        );
    }
    let change = update.settle.max(slip.settle) / update.peak;
    format!(
        "not enforced: after {updates} multiplier updates the gaps meet gap-tol \
         ({violation:.3e} <= {gap_tol:.3e}, a length) but the contact pressures still change by \
         {change:.1e} of the peak from one update to the next (tol {tol:.0e})"
    )
}

/// How the Newton iteration (and the multiplier updates) ended.
struct End {
    run: Run,
    un: Vec<f64>,
    /// Why the multiplier updates stopped short of the gap tolerance.
    unenforced: Option<String>,
    updates: usize,
    /// The gap tolerance of the augmented pairs (`None` without them).
    gap_tol: Option<f64>,
}

/// The fields, forces, equilibrium check and verdict of a finished run.
fn finish(
    model: &Model,
    system: &ReducedSystem,
    bodies: &[ReducedBody],
    modes: &Modes,
    settings: &MonolithicSettings,
    end: End,
    start: Instant,
) -> Result<MonolithicSolution, SetupError> {
    let End {
        run,
        un,
        unenforced,
        updates,
        gap_tol,
    } = end;
    let contact = system.contact_forces(model, &run.eval);
    let displacements = bodies
        .par_iter()
        .enumerate()
        .map(|(b, body)| {
            let mut x = run.x[system.offset[b]..system.offset[b] + body.dofs.len()].to_vec();
            let rigid = system.rigid[b].split(&mut x);
            body.recover(&model.bodies[b], &contact[b], &x, &rigid)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let kernel = modes::kernel(modes, &run.eval.closed, &run.eval.sticking());
    let check = balance::balance(model, system, &displacements, &contact, modes, &kernel);
    let rigid_modes: Vec<String> = kernel
        .weights
        .iter()
        .map(|w| modes::describe_motion(model, modes, w))
        .collect();
    // A body that slides is named first: no state balances its loads.
    let message = run
        .stop
        .or(unenforced)
        .or_else(|| verdict(model, settings, &check, &rigid_modes, run.steps))
        .map(|m| friction::sliding(model, system, modes, &run.eval).unwrap_or(m));
    let interface = system.interface;
    let bodies = body_results(model, interface, &un, displacements);
    let contact = pair_results(model, interface, &un);
    let exchange = crate::exchange::Local::new(model.bodies.len());
    let load = |b: usize| Some(model.bodies[b].load.clone());
    let forces = crate::solver::balance_of(model, &load, &bodies, &contact, &exchange);
    let message = message.or_else(|| {
        let stop = crate::solver::unbalanced(&forces, settings.balance_tol)?;
        crate::solution::unbalanced_message(&stop, model, "raise max-steps")
    });
    Ok(MonolithicSolution {
        converged: message.is_none(),
        message,
        newton_steps: run.steps,
        updates,
        gap_tol,
        history: run.history,
        rigid_modes,
        equilibrium: check.bodies,
        imbalance: check.motions,
        bodies,
        contact,
        balance: forces,
        un,
        seconds: start.elapsed().as_secs_f64(),
    })
}

fn check_settings(settings: &MonolithicSettings) -> Result<(), SetupError> {
    let positive = |v: f64| v > 0.0 && v.is_finite();
    if settings.max_steps == 0 {
        return Err(SetupError::Solver("max-steps must be at least 1".into()));
    }
    if !positive(settings.equilibrium_tol) || !positive(settings.imbalance_tol) {
        return Err(SetupError::Solver(format!(
            "the equilibrium tolerances must be positive, got {} and {}",
            settings.equilibrium_tol, settings.imbalance_tol
        )));
    }
    if let Some(g) = settings.gap_tol.filter(|&g| !positive(g)) {
        return Err(SetupError::Solver(format!(
            "gap-tol must be positive and finite, got {g}"
        )));
    }
    if !positive(settings.tol) || settings.max_updates == 0 {
        return Err(SetupError::Solver(format!(
            "tol must be positive and finite and max-updates at least 1, got {} and {}",
            settings.tol, settings.max_updates
        )));
    }
    Ok(())
}

/// None if a settled result is in equilibrium; otherwise why not.
fn verdict(
    model: &Model,
    settings: &MonolithicSettings,
    check: &balance::Balance,
    rigid_modes: &[String],
    steps: usize,
) -> Option<String> {
    let worst =
        (0..check.bodies.len()).max_by(|&a, &b| check.bodies[a].total_cmp(&check.bodies[b]));
    if let Some(b) = worst {
        let r = check.bodies[b];
        if r.is_nan() || r > settings.equilibrium_tol {
            return Some(format!(
                "the closed set settled in {steps} steps but body '{}' is out of equilibrium: \
                 residual {r:.1e} of the forces (limit {:.0e})",
                model.bodies[b].name, settings.equilibrium_tol
            ));
        }
    }
    check
        .motions
        .iter()
        .zip(rigid_modes)
        .find(|(f, _)| f.is_nan() || **f > settings.imbalance_tol)
        .map(|(f, name)| {
            format!(
                "net force {f:.1e} of the forces along {name}, which no contact resists \
                 (limit {:.0e}): the loads do not balance",
                settings.imbalance_tol
            )
        })
}

/// The end state of the Newton iteration.
struct Run {
    x: Vec<f64>,
    eval: Evaluation,
    steps: usize,
    history: Vec<MonolithicStep>,
    /// Why it stopped without settling (None: settled).
    stop: Option<String>,
}

/// The globalised semismooth Newton iteration from x = 0, λ = 0.
fn newton(
    system: &ReducedSystem,
    modes: &Modes,
    settings: &MonolithicSettings,
    on_step: Option<&(dyn Fn(&MonolithicStep) + Sync)>,
) -> Run {
    let mut x = vec![0.0; system.n];
    let mut lam = vec![0.0; system.interface.len()];
    let mut eval = system.evaluate(&x, &lam);
    let scale = load_scale(system);
    let mut merits: Vec<f64> = Vec::new();
    let mut history = Vec::new();
    // Consecutive steps whose line search found no decrease.
    let mut failures = 0;
    let mut seen = std::collections::HashSet::new();
    let end = |x, eval, steps, history, stop| Run {
        x,
        eval,
        steps,
        history,
        stop,
    };
    let mut previous_g = Vec::new(); // g of the state the last step started from
    for k in 1..=settings.max_steps {
        let (mut chi, mut status) = jacobian_set(system, modes, &eval);
        friction::step_sets(system, &eval, (k == 1, &previous_g), &mut chi, &mut status);
        let stick: Vec<bool> = status.iter().map(|&s| s == Status::Stick).collect();
        let z = modes::kernel(modes, &chi, &stick).on_x;
        let Some((dx, dlam)) = system.direction((&chi, &status), &z, &eval, &lam) else {
            let stop = format!("step {k}: the Newton system is singular");
            return end(x, eval, k - 1, history, Some(stop));
        };
        merits.push(merit(&z, &eval));
        let reference = merits
            .iter()
            .rev()
            .take(WINDOW)
            .fold(0.0, |a: f64, &b| a.max(b));
        let statuses: Vec<u8> = status.iter().map(|&s| s as u8).collect();
        let new_set = seen.insert((chi.clone(), statuses));
        let (alpha, next, decreased) =
            step_length(system, &z, new_set, (&x, &lam), (&dx, &dlam), reference);
        failures = if decreased { 0 } else { failures + 1 };
        x.iter_mut().zip(&dx).for_each(|(v, d)| *v += alpha * d);
        lam.iter_mut().zip(&dlam).for_each(|(v, d)| *v += alpha * d);
        let record = MonolithicStep {
            step: k,
            active: next.closed.iter().filter(|&&c| c).count(),
            residual: merit(&z, &next) / scale,
            step_length: alpha,
        };
        // A full step that keeps the closed set solved its linear equations; on an
        // ill-conditioned system (a stiffness contrast, a very soft penalty) one more step with
        // the same set refines the round-off, until the residual stops falling.
        let before = merits.last().copied().unwrap_or(0.0) / scale;
        let settled = alpha == 1.0
            && friction::kept_sets(system, (&eval, &next), &chi, &status)
            && (record.residual <= ROUND_OFF || record.residual > 0.1 * before);
        if let Some(f) = on_step {
            f(&record);
        }
        history.push(record);
        previous_g = std::mem::replace(&mut eval, next).g;
        if settled {
            return end(x, eval, k, history, None);
        }
        if failures >= WINDOW {
            let stop = format!(
                "the line search found no decrease in {WINDOW} consecutive steps (step {k})"
            );
            return end(x, eval, k, history, Some(stop));
        }
    }
    let stop = format!(
        "the closed set did not settle in {} Newton steps",
        settings.max_steps
    );
    end(x, eval, settings.max_steps, history, Some(stop))
}

/// The size of the condensed loads, ‖g‖₂ over all bodies: the scale of the reported residuals.
fn load_scale(system: &ReducedSystem) -> f64 {
    system
        .bodies
        .iter()
        .map(|b| dot(&b.g, &b.g))
        .sum::<f64>()
        .sqrt()
        .max(f64::MIN_POSITIVE)
}

/// The step length along (δx, δλ), the evaluation there and whether the merit decreased.
/// Full active-set steps while they visit new closed sets (`new_set`) and the merit stays within
/// the non-monotone window's worst `reference` (the rule the line search applies); the line
/// search once a set comes back (the plain iteration would cycle) or the merit would grow past it.
fn step_length(
    system: &ReducedSystem,
    z: &[Sparse],
    new_set: bool,
    at: (&[f64], &[f64]),
    dir: (&[f64], &[f64]),
    reference: f64,
) -> (f64, Evaluation, bool) {
    let full = new_set
        .then(|| full_step(system, at, dir))
        .filter(|e| merit(z, e) <= reference);
    match full {
        Some(next) => (1.0, next, true),
        None => line_search(system, z, at, dir, reference),
    }
}

/// The points treated as closed in J and the frictional points' statuses there: the closed
/// points, and for a body with free rigid modes that no closed point loads, the partnered points
/// loading it of smallest gap d − s (it moves until they touch, instead of being held still;
/// closing every partnered point would glue it on across gaps of any size and cost the line
/// search many short steps). Frictional points that J treats as closed but are open stick.
fn jacobian_set(
    system: &ReducedSystem,
    modes: &Modes,
    eval: &Evaluation,
) -> (Vec<bool>, Vec<Status>) {
    let points = &system.interface.points;
    let mut chi = eval.closed.clone();
    for (b, range) in system.interface.body_range.iter().enumerate() {
        // The points whose pressure loads the body: its own, or the carriers facing it.
        let mut loaders: Vec<usize> = range
            .clone()
            .flat_map(|q| system.interface.carried[q].iter().map(|&(j, _)| j))
            .collect();
        loaders.dedup();
        let floating = modes.iter().any(|m| m.body == b);
        if !floating || loaders.iter().any(|&j| chi[j]) {
            continue;
        }
        let gap = |j: usize| points[j].penalty_gap() - eval.s[j];
        let partnered = loaders.iter().copied().filter(|&j| points[j].has_partner());
        let Some(least) = partnered.clone().map(gap).min_by(f64::total_cmp) else {
            continue;
        };
        let tie = 1e-9 * (least.abs() + system.size[b]);
        for j in partnered.filter(|&j| gap(j) <= least + tie) {
            chi[j] = true;
        }
    }
    let mut status = eval.status.clone();
    friction::stick_where_closed(system, &chi, &mut status);
    hold_loaded_motions(system, modes, eval, &mut chi, &mut status);
    (chi, status)
}

/// A body held by closed points, but not along a motion its loads push it in (a column of
/// blocks held sideways by its neighbours, open below; a block whose frictional points all
/// slip): the points that would resist the free motions, of smallest gap over all of them, count
/// as closed in `chi`, or if none is open, the frictional points that would resist them stick in
/// `status`, until no loaded motion is left free. All free motions at once, not one group of
/// bodies after the other: the sets then do not depend on how the free motions are split.
fn hold_loaded_motions(
    system: &ReducedSystem,
    modes: &Modes,
    eval: &Evaluation,
    chi: &mut [bool],
    status: &mut [Status],
) {
    let points = &system.interface.points;
    for _ in 0..modes.len() {
        let stick: Vec<bool> = status.iter().map(|&s| s == Status::Stick).collect();
        let Some(w) = loaded_motions(modes, chi, &stick) else {
            break;
        };
        let open: Vec<usize> = resisting(system, modes, &w)
            .into_iter()
            .filter(|&j| !chi[j])
            .collect();
        let gap = |j: usize| points[j].penalty_gap() - eval.s[j];
        let Some(least) = open.iter().map(|&j| gap(j)).min_by(f64::total_cmp) else {
            let slipping: Vec<usize> = friction::resisting_tangentially(system, modes, &w)
                .into_iter()
                .filter(|&j| status[j] != Status::Stick)
                .collect();
            if slipping.is_empty() {
                break;
            }
            for j in slipping {
                chi[j] = true;
                status[j] = Status::Stick;
            }
            continue;
        };
        let size = system.size.iter().fold(0.0f64, |a, &b| a.max(b));
        let tie = 1e-9 * (least.abs() + size);
        for j in open.into_iter().filter(|&j| gap(j) <= least + tie) {
            chi[j] = true;
        }
        friction::stick_where_closed(system, chi, status);
    }
}

/// Work of the loads along a free motion, relative to their work along all free modes, above
/// which the motion is loaded (far above the rounding of loads that balance).
const WORK_TOL: f64 = 1e-8;

/// The weights of the rigid motions that the closed points `chi` and the sticking points `stick`
/// leave free, if the applied loads do work along one of them.
fn loaded_motions(modes: &Modes, chi: &[bool], stick: &[bool]) -> Option<Vec<Vec<f64>>> {
    let total = modes.iter().map(|m| m.work * m.work).sum::<f64>().sqrt();
    if total == 0.0 {
        return None;
    }
    let free = modes::kernel(modes, chi, stick).weights;
    free.iter()
        .any(|w| {
            let work: f64 = w.iter().zip(modes.iter()).map(|(c, m)| c * m.work).sum();
            work.abs() > WORK_TOL * total
        })
        .then_some(free)
}

/// The points that can carry a force (partnered, own-side or carriers) and whose pair sum one of
/// the motions with mode weights `ws` changes.
fn resisting(system: &ReducedSystem, modes: &Modes, ws: &[Vec<f64>]) -> Vec<usize> {
    let points = &system.interface.points;
    let candidates: Vec<usize> = (0..points.len())
        .filter(|&j| points[j].has_partner() && points[j].carries())
        .collect();
    modes::changed_by(&candidates, ws, |j, w| modes.s_along(j, w))
}

/// ‖(F, Φ)‖ with F's part along the unresisted motions `z` removed (no step changes that part;
/// the balance check judges it).
fn merit(z: &[Sparse], eval: &Evaluation) -> f64 {
    let mut r = eval.f.clone();
    project_out(z, &mut r);
    (dot(&r, &r) + dot(&eval.phi, &eval.phi)).sqrt()
}

/// The state after the full step.
fn full_step(
    system: &ReducedSystem,
    (x, lam): (&[f64], &[f64]),
    (dx, dlam): (&[f64], &[f64]),
) -> Evaluation {
    let add = |v: &[f64], d: &[f64]| -> Vec<f64> { v.iter().zip(d).map(|(a, b)| a + b).collect() };
    system.evaluate(&add(x, dx), &add(lam, dlam))
}

/// Backtracks along the direction from the state until the merit decreases enough against
/// `reference`; returns the step length, the state there and whether it decreased enough (if
/// not, the shortest step).
fn line_search(
    system: &ReducedSystem,
    z: &[Sparse],
    (x, lam): (&[f64], &[f64]),
    (dx, dlam): (&[f64], &[f64]),
    reference: f64,
) -> (f64, Evaluation, bool) {
    let mut alpha = 1.0;
    let mut halvings = 0;
    loop {
        let along = |v: &[f64], d: &[f64]| -> Vec<f64> {
            v.iter().zip(d).map(|(a, b)| a + alpha * b).collect()
        };
        let eval = system.evaluate(&along(x, dx), &along(lam, dlam));
        let f = merit(z, &eval);
        let decreased = f <= (1.0 - ARMIJO * alpha) * reference;
        if decreased || halvings >= MAX_HALVINGS || f.is_nan() {
            return (alpha, eval, decreased);
        }
        alpha *= 0.5;
        halvings += 1;
    }
}
