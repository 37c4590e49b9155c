//! Measures of an interface state shared by the iterations: starting values, relative changes,
//! breakdowns and the per-body contact summary.

use std::ops::Range;

use crate::contact::{Interface, Role};
use crate::outcome::Breakdown;

/// The starting value `value` of the normal displacements of the points in `range`, and 0 for the
/// tangential unknowns of balanced pairs (the paper's u⁰ is a normal approach).
pub(crate) fn starting_values(interface: &Interface, range: Range<usize>, value: f64) -> Vec<f64> {
    interface.points[range]
        .iter()
        .map(|p| if p.is_contact() { value } else { 0.0 })
        .collect()
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
