//! Measures of an interface state shared by the iterations: starting values, relative changes,
//! breakdowns and the per-body contact summary.

use std::ops::Range;

use crate::contact::{Interface, Role};
use crate::exchange::share_vectors;
use crate::outcome::Breakdown;
use crate::prepared::Prepared;
use crate::settings::Settings;

/// The starting value `value` of the normal displacements of the points in `range`, and 0 for the
/// tangential unknowns of balanced pairs (the paper's u⁰ is a normal approach).
pub(crate) fn starting_values(interface: &Interface, range: Range<usize>, value: f64) -> Vec<f64> {
    interface.points[range]
        .iter()
        .map(|p| if p.is_contact() { value } else { 0.0 })
        .collect()
}

/// The largest normal displacement that the bodies' loads and prescribed displacements produce
/// on their own, max |f₀| over every body (NaN if any is NaN), the same on every process.
pub(crate) fn free_response_scale(prepared: &Prepared) -> f64 {
    let own = (prepared.bodies.iter())
        .map(|body| {
            let f0 = body.as_ref().map_or(&[][..], |b| b.free_response());
            vec![largest(f0.iter().map(|v| v.abs()))]
        })
        .collect();
    largest(
        share_vectors(&*prepared.exchange, own)
            .into_iter()
            .flatten(),
    )
}

/// The factor on the starting values u⁰ and u⁻¹: 1, unless a start of that size would bury the
/// problem's own data in rounding. The data's displacement scale D is the largest normal
/// displacement the loads produce on their own (`response`, [`free_response_scale`]) or that an
/// initial overlap asks for. An iteration that starts a distance u⁰ away carries rounding errors
/// of about ε u⁰ into its iterates; when ε u⁰ exceeds tol·D (loads of 1e-30 against a u⁰ of
/// 1e-4, say) no iterate can meet the tolerance, and the start moves to the data's scale: the
/// factor D / u⁰, 0 when there is no data.
pub(crate) fn start_factor(response: f64, interface: &Interface, settings: &Settings) -> f64 {
    let overlap = largest(
        (interface.points.iter())
            .filter(|p| p.is_contact() && p.has_partner())
            .map(|p| (-p.penalty_gap()).max(0.0)),
    );
    let data = response.max(overlap);
    let start = settings.u0.abs().max(settings.u_prev.abs());
    if start * f64::EPSILON > settings.tol * data {
        data / start
    } else {
        1.0
    }
}

/// Whether the problem has no data: no body's loads or prescribed displacements move its
/// contact points (`response`, [`free_response_scale`], is 0), no load does work along a free
/// rigid motion, no pair starts overlapping (d ≥ 0), and no friction state or multiplier carries
/// over from an earlier solve. Then zero interface loads solve the interface problem exactly.
pub(crate) fn unloaded(response: f64, prepared: &Prepared, interface: &Interface) -> bool {
    let loaded = |p: &crate::contact::ContactPoint| {
        let carried = p
            .friction
            .as_ref()
            .is_some_and(|f| f.multiplier != 0.0 || f.reference != 0.0);
        carried
            || p.multiplier != 0.0
            || (p.is_contact() && p.has_partner() && p.penalty_gap() < 0.0)
    };
    response == 0.0
        && !interface.points.iter().any(loaded)
        && prepared.coarse.floating_loads().iter().all(|&w| w == 0.0)
}

/// Per body: ‖a − b‖/‖a‖ over its points (‖a − b‖ if a = 0).
pub(crate) fn relative_change(interface: &Interface, a: &[f64], b: &[f64]) -> Vec<f64> {
    interface
        .body_range
        .iter()
        .map(|range| body_change(range.clone(), a, b))
        .collect()
}

/// The largest of `values`; NaN if any is NaN (a non-finite state never passes a test).
pub(crate) fn largest(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0f64, |m, v| {
        if v.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(v)
        }
    })
}

/// ‖a − b‖/‖a‖ over the points `range` (‖a − b‖ if a = 0).
pub(crate) fn body_change(range: Range<usize>, a: &[f64], b: &[f64]) -> f64 {
    let (mut diff, mut norm) = (0.0, 0.0);
    for j in range {
        diff += (a[j] - b[j]).powi(2);
        norm += a[j] * a[j];
    }
    if norm > 0.0 {
        (diff / norm).sqrt()
    } else {
        diff.sqrt()
    }
}

/// Why a body's sweep, with its new values `v`, broke down: its own failure, non-finite values,
/// or values beyond the body's `scale`.
pub(crate) fn body_breakdown(
    swept: Result<(), Breakdown>,
    v: &[f64],
    scale: f64,
) -> Option<Breakdown> {
    match swept {
        Err(reason) => Some(reason),
        Ok(()) if !v.iter().all(|x| x.is_finite()) => Some(Breakdown::NonFinite),
        Ok(()) if v.iter().any(|x| x.abs() > scale) => Some(Breakdown::Growth),
        Ok(()) => None,
    }
}

/// Closed points and total normal contact force Σ w |σ_n| per body for the pair sums `s` (on the
/// following side of a balanced pair, Σ |F| of its nodal forces).
pub(crate) fn contact_summary(
    interface: &Interface,
    s: &[f64],
    nb: usize,
) -> (Vec<usize>, Vec<f64>) {
    (0..nb).map(|b| body_contact(interface, s, b)).unzip()
}

/// Closed points and total normal contact force of body `b` (see [`contact_summary`]).
pub(crate) fn body_contact(interface: &Interface, s: &[f64], b: usize) -> (usize, f64) {
    let (mut active, mut force) = (0usize, 0.0);
    for j in interface.body_range[b].clone() {
        let p = &interface.points[j];
        if p.overlap(s[j]) < 0.0 {
            active += 1;
        }
        if p.carries() && p.overlap(s[j]) < 0.0 {
            force -= p.weight * p.pressure(s[j]);
        } else if p.role == Role::Follower {
            force += interface.force(j, s).abs();
        }
    }
    (active, force)
}
