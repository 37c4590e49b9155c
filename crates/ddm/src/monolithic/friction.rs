//! Friction and the rigid motions of the monolithic reference: the statuses the Newton step
//! assumes where the closed set it uses goes beyond the state's, and the verdict on a frictional
//! model whose loads push a floating body along a rigid motion harder than friction can hold it.
//! No state balances such loads (the discrete problem has no solution), so the run cannot
//! converge; the verdict names the body and the motion instead of the residual or imbalance that
//! the run ends with.

use crate::contact::Status;
use crate::model::Model;

use super::modes::{changed_by, describe_motion, kernel, Mode, Modes};
use super::system::{Evaluation, ReducedSystem};

/// Work of the loads along a free rigid motion, relative to their work along all free modes,
/// above which the motion is loaded (far above the rounding of loads that balance).
const WORK_TOL: f64 = 1e-8;

/// Why the state `eval` slides, if it does: with every frictional point on the edge of its disc,
/// the closed points leave a rigid motion v free that moves some closed frictional point
/// tangentially and along which the loads do more work |W| than friction can oppose,
/// Σ_j w_j b_j |Δg_j(v)| (b_j the slip bound at the point's pressure, Δg_j the change of its
/// tangential displacement along v). The body named is the one that moves most along v. `None`
/// without friction.
pub(super) fn sliding(
    model: &Model,
    system: &ReducedSystem,
    modes: &Modes,
    eval: &Evaluation,
) -> Option<String> {
    let total = modes.iter().map(|m| m.work * m.work).sum::<f64>().sqrt();
    if !system.friction || total == 0.0 {
        return None;
    }
    let points = &system.interface.points;
    let frictional: Vec<usize> = (0..points.len())
        .filter(|&j| eval.closed[j] && points[j].friction.is_some())
        .collect();
    kernel(modes, &eval.closed, &[])
        .weights
        .iter()
        .find_map(|w| {
            let change: Vec<f64> = frictional.iter().map(|&j| modes.g_along(j, w)).collect();
            let largest = change.iter().fold(0.0f64, |a, c| a.max(c.abs()));
            let held = (frictional.iter())
                .flat_map(|&j| modes.on_g[j].iter().map(|&(_, v)| v.abs()))
                .fold(0.0f64, f64::max);
            if largest <= 1e-8 * held {
                return None;
            }
            let capacity: f64 = frictional
                .iter()
                .zip(&change)
                .filter_map(|(&j, dg)| {
                    let (p, f) = (&points[j], points[j].friction.as_ref()?);
                    Some(p.weight * f.law.bound(-p.pressure(eval.s[j])) * dg.abs())
                })
                .sum();
            let work: f64 = w.iter().zip(modes.iter()).map(|(c, m)| c * m.work).sum();
            (work.abs() > WORK_TOL * total && work.abs() > capacity).then(|| {
                format!(
                    "no equilibrium: body '{}' slides: its loads push it along {} harder than \
                     friction can hold it (their work {:.3e} against at most {:.3e})",
                    model.bodies[moves_most(modes, w)].name,
                    describe_motion(model, modes, w),
                    work.abs(),
                    capacity
                )
            })
        })
}

/// The body that moves most along the motion with mode weights `w`.
fn moves_most(modes: &[Mode], w: &[f64]) -> usize {
    let mut share: Vec<f64> = Vec::new();
    for (m, c) in modes.iter().zip(w) {
        if share.len() <= m.body {
            share.resize(m.body + 1, 0.0);
        }
        share[m.body] += c * c;
    }
    (0..share.len())
        .max_by(|&a, &b| share[a].total_cmp(&share[b]))
        .unwrap_or(0)
}

/// The step's sets beyond [`super::jacobian_set`]'s, with friction: at the `first` step the
/// points that touch ([`touching_start`]); afterwards the slipping points whose direction
/// reversed since the state with the tangential displacements `previous` stick
/// ([`crate::contact::Interface::hold_reversals`]).
pub(super) fn step_sets(
    system: &ReducedSystem,
    eval: &Evaluation,
    (first, previous): (bool, &[f64]),
    chi: &mut [bool],
    status: &mut [Status],
) {
    if first {
        touching_start(system, eval, chi, status);
    }
    (system.interface).hold_reversals(status, previous, &eval.g);
}

/// With friction, the first step from the unloaded state also closes the points that touch there
/// (gap d − s ≤ 0), sticking: the statuses of a frictional solution depend on the whole contact
/// zone, and a first step that leaves a touching interface open loads its neighbours with
/// tractions far beyond their discs, from which the stick/slip sets take many steps to recover.
/// (The decomposition's start u⁰ closes them likewise.) Frictionless runs start as before.
fn touching_start(
    system: &ReducedSystem,
    eval: &Evaluation,
    chi: &mut [bool],
    status: &mut [Status],
) {
    if !system.friction {
        return;
    }
    let points = &system.interface.points;
    for (j, p) in points.iter().enumerate() {
        if p.carries() && p.has_partner() && system.spring(j) > 0.0 {
            chi[j] |= p.penalty_gap() - eval.s[j] <= 0.0;
        }
    }
    stick_where_closed(system, chi, status);
}

/// Whether the step from `eval` to `next` kept the closed set `chi` and the statuses `status` it
/// assumed, so that it solved their (linear) equations: with friction, also every slipping
/// point's direction (a reversed one changes its equations under the same status).
pub(super) fn kept_sets(
    system: &ReducedSystem,
    (eval, next): (&Evaluation, &Evaluation),
    chi: &[bool],
    status: &[Status],
) -> bool {
    let reversed = (system.interface).hold_reversals(&mut next.status.clone(), &eval.g, &next.g);
    next.closed == chi && next.status == status && !reversed
}

/// Frictional points closed in `chi` but open in `status` stick: J treats them as touching, and
/// a body that just touches does not slide (J then resists its tangential motions too).
pub(super) fn stick_where_closed(system: &ReducedSystem, chi: &[bool], status: &mut [Status]) {
    let points = &system.interface.points;
    for (j, st) in status.iter_mut().enumerate() {
        if chi[j] && *st == Status::Open && points[j].friction.is_some() {
            *st = Status::Stick;
        }
    }
}

/// The frictional points that can close whose tangential displacement one of the rigid motions
/// with mode weights `ws` changes: sticking, they would resist it.
pub(super) fn resisting_tangentially(
    system: &ReducedSystem,
    modes: &Modes,
    ws: &[Vec<f64>],
) -> Vec<usize> {
    if !system.friction {
        return Vec::new();
    }
    let points = &system.interface.points;
    let candidates: Vec<usize> = (0..points.len())
        .filter(|&j| points[j].has_partner() && points[j].friction.is_some())
        .collect();
    changed_by(&candidates, ws, |j, w| modes.g_along(j, w))
}
