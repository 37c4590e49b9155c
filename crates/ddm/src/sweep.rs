//! The γ sweep: methods × γ values → iterations, converged or why not (the paper's Fig. 3 /
//! Table 1). Everything that does not depend on γ (assembly, factorisation, condensation) is
//! prepared once; each run only iterates on the interface, and runs execute in parallel.

use rayon::prelude::*;

use crate::iteration::{iterate, Breakdown, Hooks, Settings, Stop};
use crate::method::Method;
use crate::model::Model;
use crate::relaxation::Gamma;
use crate::solver::Prepared;

/// One run of a sweep.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SweepRun {
    /// Method.
    pub method: Method,
    /// γ (`None` for `auto`).
    pub gamma: Option<f64>,
    /// Iterations taken (m).
    pub iterations: usize,
    /// True if converged.
    pub converged: bool,
    /// Why not ("" when converged).
    pub reason: String,
}

/// Runs every method with every γ; `base` supplies the tolerance, cap and initial values.
pub fn sweep(
    model: &Model,
    prepared: &Prepared,
    methods: &[Method],
    gammas: &[Gamma],
    base: &Settings,
) -> Vec<SweepRun> {
    let jobs: Vec<(Method, Gamma)> = gammas
        .iter()
        .flat_map(|&g| methods.iter().map(move |&m| (m, g)))
        .collect();
    jobs.par_iter()
        .map(|&(method, gamma)| {
            let settings = Settings {
                method,
                gamma,
                ..base.clone()
            };
            let out = iterate(
                &prepared.interface,
                &prepared.bodies,
                &prepared.scale,
                &settings,
                Hooks::default(),
            );
            SweepRun {
                method,
                gamma: match gamma {
                    Gamma::Constant(g) => Some(g),
                    Gamma::Auto => None,
                },
                iterations: out.iterations,
                converged: out.stop == Stop::Converged,
                reason: short_reason(model, &out.stop),
            }
        })
        .collect()
}

/// A one-line reason for a table cell or CSV field.
pub fn short_reason(model: &Model, stop: &Stop) -> String {
    let name = |b: usize| {
        model
            .bodies
            .get(b)
            .map_or("?", |x| x.name.as_str())
            .to_string()
    };
    match stop {
        Stop::Converged => String::new(),
        Stop::MaxIterations => "max iterations".into(),
        Stop::Interrupted => "interrupted".into(),
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
            };
            format!("{}: {what} at iteration {iteration}", name(*body))
        }
    }
}
