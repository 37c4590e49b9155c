//! The γ sweep: methods × γ values → iterations, converged or why not (the paper's Fig. 3 /
//! Table 1). Everything that does not depend on γ (assembly, factorisation, condensation) is
//! prepared once; each run only iterates on the interface, and runs execute in parallel.
//! [`sweep_with`] takes a cancel flag (Ctrl-C in the Python module) and reports each run as it ends
//! (progress).

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use crate::coarse::CoarseMode;
use crate::method::Method;
use crate::model::Model;
use crate::outcome::{Hooks, Stop};
use crate::prepared::Prepared;
use crate::relaxation::Gamma;
use crate::settings::{Accelerator, Settings};
use crate::solution::short_reason;
use crate::solver::iterate;

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
    /// Why not ("" when converged): [`short_reason`] of `stop`.
    pub reason: String,
    /// How the run ended.
    #[serde(skip)]
    pub stop: Stop,
}

/// What a sweep reports and obeys while it runs.
#[derive(Clone, Copy, Default)]
pub struct SweepHooks<'a> {
    /// Once set, runs not yet started are skipped and running ones stop at their next iteration.
    pub cancel: Option<&'a AtomicBool>,
    /// Called with each run as soon as it ends (from the thread that ran it; runs end in any
    /// order).
    pub on_run: Option<&'a (dyn Fn(&SweepRun) + Sync)>,
}

/// Runs every method with every γ; `base` supplies the tolerance, cap and initial values.
/// Runs are returned γ by γ, method by method. See [`sweep_with`] for a sweep that reports its
/// progress and can be stopped.
pub fn sweep(
    model: &Model,
    prepared: &Prepared,
    methods: &[Method],
    gammas: &[Gamma],
    base: &Settings,
) -> Vec<SweepRun> {
    sweep_with(
        model,
        prepared,
        methods,
        gammas,
        base,
        SweepHooks::default(),
    )
}

/// [`sweep`] with hooks: a cancel flag (it is every run's [`Hooks::cancel`]) and a callback per
/// finished run. Every run is still returned; those that did not complete have reason
/// `"interrupted"` (`iterations` is 0 for a skipped run).
pub fn sweep_with(
    model: &Model,
    prepared: &Prepared,
    methods: &[Method],
    gammas: &[Gamma],
    base: &Settings,
    hooks: SweepHooks<'_>,
) -> Vec<SweepRun> {
    let cancel = hooks.cancel;
    let jobs: Vec<(Method, Gamma)> = gammas
        .iter()
        .flat_map(|&g| methods.iter().map(move |&m| (m, g)))
        .collect();
    jobs.par_iter()
        .map(|&(method, gamma)| {
            let (iterations, stop) = if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                (0, Stop::Interrupted)
            } else {
                // A sweep studies the paper's relaxed iteration: no accelerator, no coarse step.
                let settings = Settings {
                    method,
                    gamma,
                    accelerator: Accelerator::None,
                    coarse: CoarseMode::Off,
                    ..base.clone()
                };
                let hooks = Hooks {
                    on_iteration: None,
                    cancel,
                };
                let out = iterate(prepared, &settings, hooks);
                (out.iterations, out.stop)
            };
            let run = SweepRun {
                method,
                gamma: match gamma {
                    Gamma::Constant(g) => Some(g),
                    Gamma::Auto => None,
                },
                iterations,
                converged: stop == Stop::Converged,
                reason: short_reason(model, &stop),
                stop,
            };
            if let Some(report) = hooks.on_run {
                report(&run);
            }
            run
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::benchmark::Notch;
    use crate::solver::prepare;

    #[test]
    fn a_cancelled_sweep_reports_every_run_as_interrupted() {
        let notch = Notch {
            nx: 8,
            ny: 4,
            ..Notch::default()
        };
        let model = notch.model().unwrap();
        let prepared = prepare(&model).unwrap();
        let methods = [Method::ActiveSet, Method::NewtonKurchatov];
        let gammas = [Gamma::Constant(0.5), Gamma::Auto];
        let base = Settings {
            tol: 1e-3,
            ..Settings::default()
        };
        let reported = std::sync::Mutex::new(Vec::new());
        let on_run = |r: &SweepRun| reported.lock().unwrap().push(r.clone());
        let hooks = SweepHooks {
            cancel: None,
            on_run: Some(&on_run),
        };
        let free = sweep_with(&model, &prepared, &methods, &gammas, &base, hooks);
        assert_eq!(free, sweep(&model, &prepared, &methods, &gammas, &base));
        // Every run reported once, in whatever order the runs ended.
        let mut reported = reported.into_inner().unwrap();
        reported.sort_by_key(|r| free.iter().position(|f| f == r));
        assert_eq!(reported, free);
        assert!(free.iter().all(|r| r.converged), "{free:?}");
        let cancel = AtomicBool::new(true);
        let hooks = SweepHooks {
            cancel: Some(&cancel),
            on_run: None,
        };
        let stopped = sweep_with(&model, &prepared, &methods, &gammas, &base, hooks);
        assert_eq!(stopped.len(), methods.len() * gammas.len());
        for (s, f) in stopped.iter().zip(&free) {
            assert_eq!((s.method, s.gamma), (f.method, f.gamma));
            assert_eq!((s.iterations, s.converged), (0, false));
            assert_eq!(s.reason, "interrupted");
        }
    }
}
