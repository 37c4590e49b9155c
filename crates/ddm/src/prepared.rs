//! The prepared model: everything about a model that does not depend on the iteration (the
//! contact geometry, every body assembled, factorised and condensed on its contact points, the
//! coarse space), built once and reused by every solve of it.

use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use crate::coarse::Coarse;
use crate::condensed::{analyse_all, Condensation, CondensedBody, SetupTimes};
use crate::contact::formulation::InnerPenalty;
use crate::contact::Interface;
use crate::error::SetupError;
use crate::exchange::{share_vectors, Exchange, Local};
use crate::model::Model;
use crate::settings::{Accelerator, Settings};

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
    /// The factor of every load and prescribed displacement ([`Prepared::set_load_factor`]);
    /// under a load history, of the default group's ([`crate::history`]).
    pub load_factor: f64,
    /// The factors of a load history's other groups ([`Prepared::set_load_groups`]; empty
    /// without a history).
    pub group_factors: Vec<f64>,
}

impl Prepared {
    /// Scales every body's loads and prescribed displacements by `factor` (1: the problem as
    /// given): the load steps of [`crate::steps`] reuse one factorisation. A load history's other
    /// groups ([`Prepared::set_load_groups`]) go to factor 0.
    pub fn set_load_factor(&mut self, factor: f64) {
        self.load_factor = factor;
        self.group_factors.iter_mut().for_each(|c| *c = 0.0);
        for body in self.bodies.iter_mut().flatten() {
            body.set_load_factor(factor);
        }
        self.coarse.set_load_factor(factor);
    }

    /// Sets the friction state the next solve starts from: per frictional point j in `state`,
    /// (j, σ_t, g, λ) at the end of the last step ([`crate::solution::Solution::friction_state`]):
    /// the traction and displacement the tangential law starts from, and the normal multiplier
    /// the augmented Lagrangian starts from (the exact law's tractions need the exact
    /// pressures). An empty `state` is the unloaded state (λ_t = 0, g₀ = 0, λ = 0).
    pub fn set_friction_state(&mut self, state: &[(usize, f64, f64, f64)]) {
        for p in self.interface.points.iter_mut() {
            if let Some(f) = p.friction.as_mut() {
                f.multiplier = 0.0;
                f.reference = 0.0;
                p.multiplier = 0.0;
            }
        }
        for &(j, traction, g, lambda) in state {
            let Some(p) = self.interface.points.get_mut(j) else {
                continue;
            };
            if let Some(f) = p.friction.as_mut() {
                f.multiplier = traction;
                f.reference = g;
                p.multiplier = lambda;
            }
        }
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
    /// For a γ sweep ([`crate::gamma_study`]): the paper's iteration, so the pairs' own θ.
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
    crate::contact::check::refuse(&crate::contact::check::check(model, &interface))?;
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
        load_factor: 1.0,
        group_factors: Vec::new(),
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
