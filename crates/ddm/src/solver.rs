//! The top-level solve: prepare every body once (assembly, symbolic and numeric factorisation,
//! condensation on the contact points; nothing here depends on the method or γ), then iterate and
//! recover the full fields.

use std::time::Instant;

use rayon::prelude::*;

use crate::coarse::Coarse;
use crate::condensed::CondensedBody;
use crate::contact::Interface;
use crate::error::SetupError;
use crate::iteration::{iterate, Hooks, Settings, Stop};
use crate::model::Model;
use crate::solution::{body_results, pair_results, stop_message, Solution};

/// Everything about a model that does not depend on the method or γ: reuse it across solves
/// (a γ sweep prepares once).
pub struct Prepared {
    /// Contact points.
    pub interface: Interface,
    /// Condensed bodies.
    pub bodies: Vec<CondensedBody>,
    /// Per body, the displacement size beyond which an iteration counts as blown up.
    pub scale: Vec<f64>,
    /// The rigid modes of the bodies that only contacts hold.
    pub coarse: Coarse,
    /// Setup wall times, seconds.
    pub timing: Vec<(String, f64)>,
}

/// Builds the contact geometry and factorises and condenses every body (in parallel).
pub fn prepare(model: &Model) -> Result<Prepared, SetupError> {
    let t = Instant::now();
    let interface = Interface::new(model)?;
    let t_contact = t.elapsed().as_secs_f64();
    let t = Instant::now();
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
        .map(|(b, body)| CondensedBody::new(body, interface.of_body(b), par))
        .collect::<Result<Vec<_>, _>>()?;
    let t_factor = t.elapsed().as_secs_f64();
    let scale = model
        .bodies
        .iter()
        .map(|b| 10.0 * b.mesh.bounding_box_diameter())
        .collect();
    let coarse = Coarse::new(model, &interface);
    Ok(Prepared {
        interface,
        bodies,
        scale,
        coarse,
        timing: vec![
            ("contact_setup".into(), t_contact),
            ("assemble_factor_condense".into(), t_factor),
        ],
    })
}

/// Iterates and recovers the full fields. A solve that did not converge still returns its last
/// iterate, marked by `converged = false`, `stop` and `message`.
pub fn solve(
    model: &Model,
    prepared: &Prepared,
    settings: &Settings,
    hooks: Hooks<'_>,
) -> Result<Solution, SetupError> {
    if !(settings.tol > 0.0 && settings.tol.is_finite()) {
        return Err(SetupError::Solver(format!(
            "tolerance must be positive, got {}",
            settings.tol
        )));
    }
    if let crate::relaxation::Gamma::Constant(g) = settings.gamma {
        if !(g > 0.0 && g.is_finite()) {
            return Err(SetupError::Solver(format!(
                "gamma must be positive, got {g}"
            )));
        }
    }
    let outcome = iterate(prepared, settings, hooks);
    let t = Instant::now();
    let displacements = prepared
        .bodies
        .par_iter()
        .enumerate()
        .map(|(b, body)| body.recover(&outcome.t_load[prepared.interface.body_range[b].clone()]))
        .collect::<Result<Vec<_>, _>>()?;
    let t_recover = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let bodies = body_results(model, &prepared.interface, &outcome.un, displacements);
    let contact = pair_results(model, &prepared.interface, &outcome.un);
    let t_post = t.elapsed().as_secs_f64();
    let mut timing: std::collections::BTreeMap<String, f64> =
        prepared.timing.iter().cloned().collect();
    timing.insert("iterate".into(), outcome.seconds);
    timing.insert("recover".into(), t_recover);
    timing.insert("post".into(), t_post);
    let theta = model.thetas();
    Ok(Solution {
        converged: outcome.stop == Stop::Converged,
        message: stop_message(
            &outcome.stop,
            model,
            settings.method,
            &outcome.history,
            settings.tol,
        ),
        stop: outcome.stop,
        iterations: outcome.iterations,
        method: settings.method,
        gamma: settings.gamma,
        theta,
        history: outcome.history,
        bodies,
        contact,
        timing,
    })
}
