//! The `[solver]` table → iteration [`Settings`]: every key checked, then applied over a base.
//! Starting values the table leaves out follow the model's size (`starting_values`).

use contactdd_core::DIM;
use contactdd_ddm::settings::ANDERSON_DEPTH;
use contactdd_ddm::{Accelerator, CoarseMode, Gamma, Model, Settings, SetupError};

use crate::error::solver_error;
use crate::number::format_f64 as num;
use crate::problem::{AcceleratorSpec, CoarseSpec, GammaSpec, SolverSpec};

/// Most worker threads a problem file (`solver.threads`) or the command line (`--threads`) may ask
/// for: more than any machine this runs on, low enough that a typo cannot make the thread pool
/// exhaust the system.
pub const MAX_THREADS: usize = 1024;

/// A `[solver]` table applied to `base`: every key given is checked and replaces the value of
/// `base`, absent keys keep it. `threads` is checked (1 to [`MAX_THREADS`]) but is not
/// part of [`Settings`]; read it from `spec`.
pub fn settings(spec: &SolverSpec, base: &Settings) -> Result<Settings, SetupError> {
    let mut s = base.clone();
    if let Some(method) = spec.method {
        s.method = method;
    }
    if let Some(g) = spec.gamma {
        s.gamma = gamma(g)?;
    }
    iteration_kind(spec, &mut s);
    if let Some(tol) = spec.tol {
        s.tol = tol;
    }
    if let Some(b) = spec.balance_tol {
        s.balance_tol = Some(b);
    }
    if let Some(e) = spec.equilibrium_tol {
        s.equilibrium_tol = e;
    }
    if let Some(max_iter) = spec.max_iter {
        s.max_iter = max_iter;
    }
    if let Some(g) = spec.gap_tol {
        s.gap_tol = Some(g);
    }
    if let Some(n) = spec.max_updates {
        s.max_updates = n;
    }
    if let Some(c) = spec.condensation {
        s.condensation = c;
    }
    if let Some(u0) = spec.u0 {
        s.u0 = u0;
    }
    if let Some(u_prev) = spec.u_prev {
        s.u_prev = u_prev;
    }
    s.validate()
        .map_err(|e| solver_error(e.key, e.reason(num)))?;
    check_threads(spec)?;
    Ok(s)
}

/// `threads`, the one key of the `[solver]` table that is not part of [`Settings`] (whose values
/// [`Settings::validate`] checks).
fn check_threads(spec: &SolverSpec) -> Result<(), SetupError> {
    match spec.threads {
        Some(0) => Err(solver_error("threads", "must be at least 1, got 0")),
        Some(n) if n > MAX_THREADS => Err(solver_error(
            "threads",
            format!("must be at most {MAX_THREADS}, got {n}"),
        )),
        _ => Ok(()),
    }
}

/// The accelerator and the coarse correction. A constant γ without an `accelerator` or `coarse`
/// key asks for the paper's one-level iteration, so those keys then default to `none` and `off`;
/// a `method` or `gamma = "auto"` alone asks for the two-level sweeps (the default interface
/// Newton method uses neither); with `accelerator = "anderson"`, `coarse` defaults to `off`.
fn iteration_kind(spec: &SolverSpec, s: &mut Settings) {
    let paper = matches!(spec.gamma, Some(GammaSpec::Value(_)));
    if spec.accelerator.is_none() && (spec.method.is_some() || spec.gamma.is_some()) {
        s.use_sweeps();
    }
    s.accelerator = match spec.accelerator {
        Some(AcceleratorSpec::Anderson) => Accelerator::Anderson {
            depth: ANDERSON_DEPTH,
        },
        Some(AcceleratorSpec::None) => Accelerator::None,
        Some(AcceleratorSpec::Newton) => Accelerator::Newton,
        None if paper => Accelerator::None,
        None => s.accelerator,
    };
    s.coarse = match spec.coarse {
        Some(CoarseSpec::Off) => CoarseMode::Off,
        Some(CoarseSpec::Chains) => CoarseMode::Chains,
        Some(CoarseSpec::All) => CoarseMode::All,
        // Anderson's secant columns and the coarse step's rigid jumps do not mix well (measured:
        // docs/two-level.md), so an accelerated solve runs without coarse correction unless asked;
        // the interface Newton method handles rigid motions itself.
        None if paper || s.accelerator != Accelerator::None => CoarseMode::Off,
        None if spec.accelerator == Some(AcceleratorSpec::None) => CoarseMode::Chains,
        None => s.coarse,
    };
}

/// A `gamma` value → a γ rule: `"auto"`, or a constant γ > 0.
pub fn gamma(spec: GammaSpec) -> Result<Gamma, SetupError> {
    match spec {
        GammaSpec::Auto => Ok(Gamma::Auto),
        GammaSpec::Value(g) if g.is_finite() && g > 0.0 => Ok(Gamma::Constant(g)),
        GammaSpec::Value(g) => Err(solver_error(
            "gamma",
            format!("must be a positive number or \"auto\", got {}", num(g)),
        )),
    }
}

/// The model's size: the longest side of the bounding box of every body's nodes.
pub fn model_size(model: &Model) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; DIM], [f64::NEG_INFINITY; DIM]);
    for (l, h) in (0..model.bodies.len()).map(|b| model.bounds(b)) {
        for d in 0..DIM {
            lo[d] = lo[d].min(l[d]);
            hi[d] = hi[d].max(h[d]);
        }
    }
    (hi[0] - lo[0]).max(hi[1] - lo[1])
}

/// `settings` with the starting values the `[solver]` table leaves out set relative to the
/// model's size L: u0 = L/20 000 and u-prev = L/10 000. An absolute default would make the
/// iteration depend on the length unit. The fractions give a model 2 units long the former
/// absolute defaults 1e-4 and 2e-4 (bit for bit), so the measured iteration counts of
/// `examples/hertz.toml` and `examples/stack.toml` stand; the notch benchmarks set the paper's
/// values explicitly.
pub(crate) fn starting_values(
    mut settings: Settings,
    spec: &SolverSpec,
    model: &Model,
) -> Settings {
    let size = model_size(model);
    if spec.u0.is_none() {
        settings.u0 = size / U0_FRACTION;
    }
    if spec.u_prev.is_none() {
        settings.u_prev = size / U_PREV_FRACTION;
    }
    settings
}

/// The model's size over the default u0.
const U0_FRACTION: f64 = 20_000.0;

/// The model's size over the default u-prev.
const U_PREV_FRACTION: f64 = 10_000.0;
