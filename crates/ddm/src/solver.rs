//! The top-level solve: the iteration the settings name on a prepared model ([`crate::prepared`]),
//! inside the augmented Lagrangian loop where pairs ask for exact contact, then the full fields,
//! the results and the equilibrium check that decides whether a converged iteration is a
//! solution.

use std::borrow::Cow;
use std::time::Instant;

use rayon::prelude::*;

use crate::coarse::CoarseMode;
use crate::contact::Interface;
use crate::equilibrium::equilibrium;
use crate::error::SetupError;
use crate::force_balance::{balance, Balance, BodyForces};
use crate::iteration::Iteration;
use crate::model::Model;
use crate::newton::InterfaceNewton;
use crate::outcome::{Hooks, Outcome, Stop};
pub use crate::prepared::{prepare, prepare_on, prepare_with, Preparation, Prepared};
use crate::settings::{Accelerator, Settings};
use crate::solution::{
    body_results, nodal_contact_force, pair_results, stop_message, BodyResult, PairResult, Solution,
};
use crate::sweeps::Sweeps;

/// The iteration `settings` name: the interface Newton method, or the Robin sweeps.
pub fn iteration_for(settings: &Settings) -> Box<dyn Iteration + '_> {
    match settings.accelerator {
        Accelerator::Newton => Box::new(InterfaceNewton(settings)),
        Accelerator::None | Accelerator::Anderson { .. } => Box::new(Sweeps(settings)),
    }
}

/// Runs the iteration of `settings` on a prepared model.
pub fn iterate(prepared: &Prepared, settings: &Settings, hooks: Hooks<'_>) -> Outcome {
    iteration_for(settings).run(prepared, &prepared.interface, None, hooks)
}

/// Iterates and recovers the full fields. A solve that did not converge still returns its last
/// iterate, marked by `converged = false`, `stop` and `message`.
pub fn solve(
    model: &Model,
    prepared: &Prepared,
    settings: &Settings,
    hooks: Hooks<'_>,
) -> Result<Solution, SetupError> {
    solve_from(model, prepared, settings, hooks, None)
}

/// [`solve`], with the interface Newton method starting from the interface loads `warm` of an
/// earlier solve of the same prepared model ([`Solution::interface_loads`]) when given.
pub fn solve_from(
    model: &Model,
    prepared: &Prepared,
    settings: &Settings,
    hooks: Hooks<'_>,
    warm: Option<&[f64]>,
) -> Result<Solution, SetupError> {
    settings.validate()?;
    check_friction(&prepared.interface, settings)?;
    let iteration = iteration_for(settings);
    let (outcome, interface, updates, gap_tol) = if model.is_augmented() {
        let a = crate::augmented::solve(model, prepared, &*iteration, settings, hooks, warm);
        (
            a.outcome,
            Cow::Owned(a.interface),
            a.updates,
            Some(a.gap_tol),
        )
    } else {
        let outcome = iteration.run(prepared, &prepared.interface, warm, hooks);
        (outcome, Cow::Borrowed(&prepared.interface), 0, None)
    };
    let (outcome, end) = match ending(model, prepared, &interface, &outcome, settings)? {
        end if !model.is_augmented() && polishable(&end.stop, &interface, settings) => {
            polish(model, prepared, &interface, (outcome, end), settings, hooks)?
        }
        end => (outcome, end),
    };
    let mut timing: std::collections::BTreeMap<String, f64> =
        prepared.timing.iter().cloned().collect();
    timing.insert("iterate".into(), outcome.seconds);
    timing.insert("recover".into(), end.t_recover);
    timing.insert("post".into(), end.t_post);
    let theta = model.thetas();
    let (stop, equilibrium, balance) = (end.stop, end.equilibrium, end.balance);
    let (bodies, contact, friction_state) = (end.bodies, end.contact, end.friction_state);
    Ok(Solution {
        converged: stop == Stop::Converged,
        message: stop_message(&stop, model, settings, &outcome.history),
        stop,
        iterations: outcome.iterations,
        method: settings.method,
        gamma: settings.gamma,
        accelerator: settings.accelerator,
        coarse: settings.coarse,
        theta,
        history: outcome.history,
        bodies,
        contact,
        equilibrium,
        balance,
        updates,
        gap_tol,
        tol: settings.tol,
        settings: settings.clone(),
        load_factor: prepared.load_factor,
        interface_loads: outcome.t_load,
        friction_state,
        condensation: prepared.paths.clone(),
        timing,
    })
}

/// What a solve makes of an iteration's outcome: the full fields, the contact results, the
/// equilibrium and balance checks and the verdict ([`verdict`]).
struct Ending {
    bodies: Vec<BodyResult>,
    contact: Vec<PairResult>,
    friction_state: Vec<(usize, f64, f64, f64)>,
    equilibrium: Vec<f64>,
    balance: Balance,
    stop: Stop,
    t_recover: f64,
    t_post: f64,
}

/// The [`Ending`] of `outcome` on the contact points `interface`.
fn ending(
    model: &Model,
    prepared: &Prepared,
    interface: &Interface,
    outcome: &Outcome,
    settings: &Settings,
) -> Result<Ending, SetupError> {
    let t = Instant::now();
    let displacements = recover(prepared, interface, &outcome.t_load)?;
    let t_recover = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let bodies = body_results(model, interface, &outcome.un, displacements);
    let contact = pair_results(model, interface, &outcome.un);
    let friction_state = friction_state(interface, &outcome.un);
    let balance = forces_balance(model, prepared, &bodies, &contact);
    let t_post = t.elapsed().as_secs_f64();
    let equilibrium = equilibrium(interface, &outcome.un, &outcome.t_load);
    let stop = verdict(outcome.stop.clone(), &equilibrium, &balance, settings);
    Ok(Ending {
        bodies,
        contact,
        friction_state,
        equilibrium,
        balance,
        stop,
        t_recover,
        t_post,
    })
}

/// The tolerance of the Newton steps that [`polish`] adds, relative to `tol`.
const POLISH: f64 = 1e-3;

/// Whether more Newton steps can turn the verdict `stop` into a solution: the interface Newton
/// method met its tolerance on a frictionless problem (penalty pairs: the caller asks), but a body is out of balance by
/// more than the rounding its reactions carry. The stopping test bounds the residual relative to
/// the displacements U; a pair whose penalty θ is far stiffer than its bodies carries contact
/// forces q/θ with q = θp ≪ U, so the same residual is a far larger error in the forces
/// (`docs/interface-newton.md`, "Stopping where the penalty is stiff").
fn polishable(stop: &Stop, interface: &Interface, settings: &Settings) -> bool {
    let above_rounding = matches!(*stop, Stop::Unbalanced { body: Some(_), imbalance, floor, .. }
        if imbalance > floor);
    above_rounding && settings.accelerator == Accelerator::Newton && !interface.has_friction()
}

/// Continues the Newton run of `outcome` from its interface loads to the tolerance
/// [`POLISH`]·tol, and keeps the continuation when it is a solution (its records follow the
/// first run's, its iterations and time add up); otherwise the first run's ending stands.
fn polish(
    model: &Model,
    prepared: &Prepared,
    interface: &Interface,
    (outcome, end): (Outcome, Ending),
    settings: &Settings,
    hooks: Hooks<'_>,
) -> Result<(Outcome, Ending), SetupError> {
    let tighter = Settings {
        tol: settings.tol * POLISH,
        ..settings.clone()
    };
    let more = InterfaceNewton(&tighter).run(prepared, interface, Some(&outcome.t_load), hooks);
    let polished = ending(model, prepared, interface, &more, settings)?;
    if polished.stop != Stop::Converged {
        return Ok((outcome, end));
    }
    let mut history = outcome.history;
    history.extend(more.history.into_iter().map(|mut record| {
        record.k += outcome.iterations;
        record
    }));
    let merged = Outcome {
        stop: more.stop,
        iterations: outcome.iterations + more.iterations,
        history,
        seconds: outcome.seconds + more.seconds,
        ..more
    };
    Ok((merged, polished))
}

/// The force balance of every body ([`crate::force_balance`]) at the loads of `prepared`.
fn forces_balance(
    model: &Model,
    prepared: &Prepared,
    bodies: &[BodyResult],
    contact: &[PairResult],
) -> Balance {
    let load = |b: usize| prepared.bodies[b].as_ref().map(|body| body.applied_load());
    balance_of(model, &load, bodies, contact, &*prepared.exchange)
}

/// The force balance of every body whose field this process holds, under the applied loads
/// `load(b)` (`None`: another process holds the body).
pub(crate) fn balance_of(
    model: &Model,
    load: &dyn Fn(usize) -> Option<Vec<f64>>,
    bodies: &[BodyResult],
    contact: &[PairResult],
    exchange: &dyn crate::exchange::Exchange,
) -> Balance {
    let fields: Vec<_> = (bodies.iter().enumerate())
        .map(|(b, r)| {
            let load = load(b).filter(|_| r.has_fields())?;
            let pair_forces = (model.pairs.iter().zip(contact))
                .flat_map(|(pair, result)| {
                    (0..2)
                        .filter(move |&side| pair.bodies[side] == b)
                        .map(move |side| result.force_on(side))
                })
                .collect();
            Some(BodyForces {
                displacement: &r.displacement,
                load,
                contact: nodal_contact_force(model, b, contact),
                pair_forces,
            })
        })
        .collect();
    balance(model, &fields, exchange)
}

/// How a solve ends: an iteration that met its tolerance is a solution only if its contact forces
/// are those its fields carry (`equilibrium`) and every body balances (`balance`).
fn verdict(stop: Stop, equilibrium: &[f64], balance: &Balance, settings: &Settings) -> Stop {
    // A NaN residual wins the fold: a non-finite result is out of equilibrium too.
    let worst = equilibrium.iter().fold(0.0f64, |m, &e| {
        if e.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(e)
        }
    });
    match stop {
        Stop::Converged if worst.is_nan() || worst > settings.equilibrium_tol => Stop::Stalled {
            residual: worst,
            limit: settings.equilibrium_tol,
        },
        Stop::Converged => unbalanced(balance, settings.balance_limit()).unwrap_or(Stop::Converged),
        stop => stop,
    }
}

/// The verdict of the independent balance check: the worst body, if one is out of balance by more
/// than `limit` (a NaN imbalance counts as the worst), else the whole problem's loads against its
/// reactions.
pub(crate) fn unbalanced(balance: &Balance, limit: f64) -> Option<Stop> {
    let key = |x: f64| if x.is_nan() { f64::INFINITY } else { x };
    let worst = (balance.bodies.iter().enumerate())
        .max_by(|(_, a), (_, b)| key(a.imbalance).total_cmp(&key(b.imbalance)));
    if let Some((body, worst)) = worst.filter(|(_, w)| key(w.imbalance) > limit) {
        return Some(Stop::Unbalanced {
            body: Some(body),
            imbalance: worst.imbalance,
            floor: worst.floor,
            motion: worst.motion,
            limit,
        });
    }
    let loads = Some(balance.loads).filter(|&l| key(l) > limit)?;
    let floor = balance.bodies.iter().map(|b| b.floor).fold(0.0, f64::max);
    let motion = balance.bodies.iter().map(|b| b.motion).fold(0.0, f64::max);
    Some(Stop::Unbalanced {
        body: None,
        imbalance: loads,
        floor,
        motion,
        limit,
    })
}

/// Refuses the settings that cannot solve the friction of `interface`: the Robin sweeps with
/// friction run one-level, since the coarse correction balances floating bodies by their normal
/// contact forces only and would move a body that friction holds. `contactdd check` asks it too.
pub fn check_friction(interface: &Interface, settings: &Settings) -> Result<(), SetupError> {
    let sweeps = settings.accelerator != Accelerator::Newton;
    if interface.has_friction() && sweeps && settings.coarse != CoarseMode::Off {
        return Err(SetupError::Solver(format!(
            "friction with the Robin sweeps needs coarse = \"off\": their coarse correction \
             (here \"{}\", the sweeps' default unless told otherwise) balances floating bodies by \
             their normal contact forces only; set coarse = \"off\" (--coarse off), or use the \
             interface Newton method (accelerator = \"newton\", the default)",
            settings.coarse
        )));
    }
    Ok(())
}

/// Per frictional point of `interface`, (j, σ_t, g, λ) at the interface displacements `un`, λ
/// its normal multiplier (0 for the penalty formulation).
fn friction_state(interface: &Interface, un: &[f64]) -> Vec<(usize, f64, f64, f64)> {
    if !interface.has_friction() {
        return Vec::new();
    }
    let mut s = vec![0.0; un.len()];
    interface.sum_normal(un, &mut s);
    let g = interface.slip_sums(un);
    (0..un.len())
        .filter(|&j| interface.points[j].friction.is_some())
        .map(|j| {
            let p = &interface.points[j];
            (j, interface.traction(j, &s, &g).0, g[j], p.multiplier)
        })
        .collect()
}

/// The displacement fields for the interface loads `t_load` of the bodies this process owns
/// (empty for the others, whose processes hold them). A failure on any process fails every
/// process.
fn recover(
    prepared: &Prepared,
    interface: &Interface,
    t_load: &[f64],
) -> Result<Vec<Vec<f64>>, SetupError> {
    let exchange = &*prepared.exchange;
    let own = prepared
        .bodies
        .par_iter()
        .enumerate()
        .map(|(b, body)| match body {
            Some(body) => body.recover(&t_load[interface.body_range[b].clone()]),
            None => Ok(Vec::new()),
        })
        .collect::<Result<Vec<_>, _>>();
    if exchange.is_local() {
        return Ok(own?);
    }
    let error = exchange.agree(own.as_ref().err().map(|e| e.to_string()));
    match (own, error) {
        (Ok(own), None) => Ok(own),
        (_, Some(message)) => Err(SetupError::Distributed(message)),
        (Err(e), None) => Err(e.into()),
    }
}
