//! The top-level solve: prepare every body once (assembly, symbolic and numeric factorisation,
//! condensation on the contact points; nothing here depends on the method or γ), then iterate and
//! recover the full fields.

use std::borrow::Cow;
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use crate::coarse::Coarse;
use crate::condensed::{analyse_all, Condensation, CondensedBody, SetupTimes};
use crate::contact::Interface;
use crate::error::SetupError;
use crate::exchange::{share_vectors, Exchange, Local};
use crate::iteration::{iterate_on, Accelerator, Hooks, Settings, Stop};
use crate::model::{InnerPenalty, Model};
use crate::solution::{body_results, pair_results, stop_message, Solution};

/// Everything about a model that does not depend on the method or γ: reuse it across solves
/// (a γ sweep prepares once).
pub struct Prepared {
    /// Contact points.
    pub interface: Interface,
    /// Condensed bodies, those this process owns (`None`: another process's body).
    pub bodies: Vec<Option<CondensedBody>>,
    /// The path every body took, dense or sparse (the cost model's choice under `auto`), the
    /// same on every process.
    pub paths: Vec<Condensation>,
    /// How the bodies' values reach the other processes ([`Local`]: there are none).
    pub exchange: Arc<dyn Exchange>,
    /// Per body, the displacement size beyond which an iteration counts as blown up.
    pub scale: Vec<f64>,
    /// The rigid modes of the bodies that only contacts hold.
    pub coarse: Coarse,
    /// Setup wall times, seconds.
    pub timing: Vec<(String, f64)>,
}

impl Prepared {
    /// Scales every body's loads and prescribed displacements by `factor` (1: the problem as
    /// given): the load steps of [`crate::steps`] reuse one factorisation.
    pub fn set_load_factor(&mut self, factor: f64) {
        for body in self.bodies.iter_mut().flatten() {
            body.set_load_factor(factor);
        }
        self.coarse.set_load_factor(factor);
    }
}

/// How [`prepare_with`] sets the bodies up: their condensation path, and the inner penalty of
/// the augmented balanced pairs, which suits one iteration and not the other. From a
/// [`Condensation`] alone: that path, for the default iteration (the interface Newton method);
/// from [`Settings`]: for the iteration they choose.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Preparation {
    /// The condensation path (`docs/sparse-path.md`).
    pub condensation: Condensation,
    /// The augmented balanced pairs' inner penalty.
    pub inner: InnerPenalty,
}

impl Preparation {
    /// For a γ sweep ([`mod@crate::sweep`]): the paper's iteration, so the pairs' own θ.
    pub fn for_sweeps(condensation: Condensation) -> Self {
        Preparation {
            condensation,
            inner: InnerPenalty::AsGiven,
        }
    }
}

impl From<Condensation> for Preparation {
    fn from(condensation: Condensation) -> Self {
        Preparation {
            condensation,
            ..Preparation::default()
        }
    }
}

impl From<&Settings> for Preparation {
    fn from(settings: &Settings) -> Self {
        Preparation {
            condensation: settings.condensation,
            inner: if settings.accelerator == Accelerator::Newton {
                InnerPenalty::Stiffened
            } else {
                InnerPenalty::AsGiven
            },
        }
    }
}

/// Builds the contact geometry and factorises and condenses every body (in parallel), each on
/// the path the cost model chooses ([`Condensation::Auto`]), for the default iteration.
pub fn prepare(model: &Model) -> Result<Prepared, SetupError> {
    prepare_with(model, Preparation::default())
}

/// [`prepare`] with the condensation path given (`docs/sparse-path.md`), or the settings of the
/// solve to come.
pub fn prepare_with(model: &Model, how: impl Into<Preparation>) -> Result<Prepared, SetupError> {
    prepare_on(model, how, Arc::new(Local::new(model.bodies.len())))
}

/// [`prepare_with`] for the bodies that `exchange` gives this process; the contact geometry and
/// the coarse space, cheap and needed by all, are built by every process. An error of any
/// process is every process's error.
pub fn prepare_on(
    model: &Model,
    how: impl Into<Preparation>,
    exchange: Arc<dyn Exchange>,
) -> Result<Prepared, SetupError> {
    let Preparation {
        condensation,
        inner,
    } = how.into();
    let t = Instant::now();
    let interface = Interface::with_inner(model, inner)?;
    crate::contact_check::refuse(&crate::contact_check::check(model, &interface))?;
    let t_contact = t.elapsed().as_secs_f64();
    let t = Instant::now();
    // One level of parallelism: over bodies when there are several, inside faer otherwise. A
    // process of a distributed solve chooses as one process would, so its factors are the same.
    let par = if model.bodies.len() > 1 {
        faer::Par::Seq
    } else {
        faer::Par::rayon(0)
    };
    let owned = condense_owned(model, &interface, condensation, &*exchange, par);
    let (bodies, times) = if exchange.is_local() {
        owned?
    } else {
        let error = exchange.agree(owned.as_ref().err().map(|e| e.to_string()));
        match (owned, error) {
            (Ok(owned), None) => owned,
            (_, Some(message)) => return Err(SetupError::Distributed(message)),
            (Err(e), None) => return Err(e),
        }
    };
    let t_factor = t.elapsed().as_secs_f64();
    let paths = taken_paths(&bodies, &*exchange);
    let sum = |f: fn(&SetupTimes) -> f64| times.iter().map(f).sum::<f64>();
    let scale = (0..model.bodies.len())
        .map(|b| {
            let (lo, hi) = model.bounds(b);
            10.0 * contactdd_core::mesh::dist(lo, hi)
        })
        .collect();
    let coarse = Coarse::new(model, &interface);
    Ok(Prepared {
        interface,
        bodies,
        paths,
        exchange,
        scale,
        coarse,
        timing: vec![
            ("contact_setup".into(), t_contact),
            ("assemble_factor_condense".into(), t_factor),
            // Per phase, summed over the bodies (which run in parallel).
            ("assembly".into(), sum(|t| t.assembly)),
            ("symbolic".into(), sum(|t| t.symbolic)),
            ("numeric".into(), sum(|t| t.numeric)),
            ("condensation".into(), sum(|t| t.condensation)),
        ],
    })
}

/// The path each body took, from the processes that own them.
fn taken_paths(bodies: &[Option<CondensedBody>], exchange: &dyn Exchange) -> Vec<Condensation> {
    let own = bodies
        .iter()
        .map(|b| match b.as_ref().and_then(CondensedBody::sparse) {
            Some(_) => vec![1.0],
            None => vec![0.0],
        })
        .collect();
    share_vectors(exchange, own)
        .iter()
        .map(|v| match v.first() == Some(&1.0) {
            true => Condensation::Sparse,
            false => Condensation::Dense,
        })
        .collect()
}

/// The bodies that `exchange` gives this process analysed, factorised and condensed, in
/// parallel, once their factors are known to fit in memory; the others `None`.
fn condense_owned(
    model: &Model,
    interface: &Interface,
    condensation: Condensation,
    exchange: &dyn Exchange,
    par: faer::Par,
) -> Result<(Vec<Option<CondensedBody>>, Vec<SetupTimes>), SetupError> {
    let analysed = analyse_all(model, interface, condensation, &|b| exchange.owns(b))?;
    Ok(analysed
        .into_par_iter()
        .map(|a| match a {
            Some(a) => a.condense(par).map(|(body, t)| (Some(body), t)),
            None => Ok((None, SetupTimes::default())),
        })
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip())
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
    if !(settings.tol > 0.0 && settings.tol.is_finite()) {
        return Err(SetupError::Solver(format!(
            "tolerance must be positive, got {}",
            settings.tol
        )));
    }
    if settings.equilibrium_tol.is_nan() || settings.equilibrium_tol <= 0.0 {
        return Err(SetupError::Solver(format!(
            "equilibrium-tol must be positive, got {}",
            settings.equilibrium_tol
        )));
    }
    if let crate::relaxation::Gamma::Constant(g) = settings.gamma {
        if !(g > 0.0 && g.is_finite()) {
            return Err(SetupError::Solver(format!(
                "gamma must be positive, got {g}"
            )));
        }
    }
    if settings.max_updates == 0 {
        return Err(SetupError::Solver("max-updates must be at least 1".into()));
    }
    if let Some(g) = settings.gap_tol {
        if !(g > 0.0 && g.is_finite()) {
            return Err(SetupError::Solver(format!(
                "gap-tol must be a positive length, got {g}"
            )));
        }
    }
    let (outcome, interface, updates, gap_tol) = if model.is_augmented() {
        let a = crate::augmented::solve(model, prepared, settings, hooks, warm);
        (
            a.outcome,
            Cow::Owned(a.interface),
            a.updates,
            Some(a.gap_tol),
        )
    } else {
        let outcome = iterate_on(prepared, &prepared.interface, warm, settings, hooks);
        (outcome, Cow::Borrowed(&prepared.interface), 0, None)
    };
    let t = Instant::now();
    let displacements = recover(prepared, &interface, &outcome.t_load)?;
    let t_recover = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let bodies = body_results(model, &interface, &outcome.un, displacements);
    let contact = pair_results(model, &interface, &outcome.un);
    let t_post = t.elapsed().as_secs_f64();
    let mut timing: std::collections::BTreeMap<String, f64> =
        prepared.timing.iter().cloned().collect();
    timing.insert("iterate".into(), outcome.seconds);
    timing.insert("recover".into(), t_recover);
    timing.insert("post".into(), t_post);
    let theta = model.thetas();
    let equilibrium = equilibrium(&interface, &outcome.un, &outcome.t_load);
    // A NaN residual wins the fold: a non-finite result is out of equilibrium too.
    let worst = equilibrium.iter().fold(0.0f64, |m, &e| {
        if e.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(e)
        }
    });
    let stop = match outcome.stop {
        Stop::Converged if worst.is_nan() || worst > settings.equilibrium_tol => Stop::Stalled {
            residual: worst,
            limit: settings.equilibrium_tol,
        },
        stop => stop,
    };
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
        updates,
        gap_tol,
        tol: settings.tol,
        interface_loads: outcome.t_load,
        condensation: prepared.paths.clone(),
        timing,
    })
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

/// Per body, the equilibrium residual of the result: the contact forces that the recovered field
/// carries (T − D₀U at every contact point, since K u = f + N (T − D₀ Nᵀu)) against the penalty
/// forces w σ_n(s) of the reported pressures, ‖·‖₂ over the body's points relative to ‖w σ_n‖₂
/// over all points. Zero at a fixed point of the iteration, whatever stopped it.
pub fn equilibrium(interface: &Interface, un: &[f64], t_load: &[f64]) -> Vec<f64> {
    let mut s = vec![0.0; un.len()];
    interface.sum_normal(un, &mut s);
    let force = |j: usize| interface.force(j, &s);
    let total = (0..un.len()).map(|j| force(j).powi(2)).sum::<f64>().sqrt();
    interface
        .body_range
        .iter()
        .map(|range| {
            let residual = range
                .clone()
                .map(|j| {
                    let p = &interface.points[j];
                    (t_load[j] - p.spring * un[j] - force(j)).powi(2)
                })
                .sum::<f64>()
                .sqrt();
            if residual == 0.0 {
                0.0
            } else {
                residual / total
            }
        })
        .collect()
}
