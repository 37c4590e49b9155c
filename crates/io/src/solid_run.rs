//! A solve in space and its verdict: the decomposition (or the monolithic reference) on a
//! [`SolidModel`], then the independent check of [`contactdd_ddm::solid_balance`], which alone
//! lets a result count as converged.

use contactdd_core::solid::rigid::free_rigid_modes;
use contactdd_ddm::solid_balance::{solid_balance, SolidBalance};
use contactdd_ddm::solid_contact::SolidProgress;
use contactdd_ddm::solid_dd::solve_solid_dd_steps;
use contactdd_ddm::solid_monolithic::{
    solve_solid_monolithic_from, SolidBodySpec, SolidContactError, SolidContactSolution,
    SolidPairSpec,
};

use crate::solid_setup::SolidModel;

/// Which solver runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolidSolver {
    /// The decomposition: every body factorised once, Newton on the contact points.
    Decomposition,
    /// The monolithic reference: Newton on the coupled system.
    Monolithic,
}

impl SolidSolver {
    /// The name the console, the summary and Python print.
    pub fn label(self) -> &'static str {
        match self {
            SolidSolver::Decomposition => "interface newton (decomposition in space)",
            SolidSolver::Monolithic => "monolithic reference (semismooth newton)",
        }
    }
}

/// A solve's result and verdict.
#[derive(Clone, Debug)]
pub struct SolidOutcome {
    /// The solver that ran.
    pub solver: SolidSolver,
    /// The solution (of the last load step).
    pub solution: SolidContactSolution,
    /// The independent check (of the last load step, or of the first that fails it).
    pub balance: SolidBalance,
    /// Whether the result is a solution: the closed set settled and the check passed, at every
    /// load step.
    pub converged: bool,
    /// Why not, when it is not.
    pub reason: Option<String>,
    /// Every load step, in order (one without `load-steps`).
    pub steps: Vec<SolidStep>,
}

/// One load step of a solve.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidStep {
    /// The load factor.
    pub factor: f64,
    /// The Newton steps it took.
    pub newton_steps: usize,
    /// Its worst body imbalance.
    pub imbalance: f64,
    /// Whether it passed the independent check.
    pub converged: bool,
    /// Every pair's normal force Σ w p.
    pub pair_forces: Vec<f64>,
    /// Every pair's tangential force Σ w τ on its reference side (zero without friction).
    pub tangential_forces: Vec<[f64; 3]>,
    /// The mean displacement of the monitored face, if any.
    pub monitor: Option<[f64; 3]>,
}

/// Why a solve in space has no result.
#[derive(Debug, thiserror::Error)]
pub enum SolidRunError {
    /// A body its supports leave free that the closed contact points do not hold.
    #[error(
        "body '{body}' is not held: its supports leave {free} of its 6 rigid motions free, and at \
         Newton step {step} no closed contact point resists one of them; check that its loads and \
         supports press it against its partners"
    )]
    NotHeld {
        /// The body.
        body: String,
        /// The rigid motions its supports leave free.
        free: usize,
        /// The Newton step.
        step: usize,
    },
    /// A floating body that friction cannot hold.
    #[error(
        "body '{body}' slides: its loads do {work:.3e} of work along a free rigid motion that \
         friction opposes by at most {resistance:.3e}, so no equilibrium exists; support it, \
         raise the friction or lower its tangential loads"
    )]
    Slides {
        /// The body.
        body: String,
        /// The loads' work along the motion.
        work: f64,
        /// The most friction opposes.
        resistance: f64,
    },
    /// The solver's error.
    #[error(transparent)]
    Contact(#[from] SolidContactError),
}

/// Solves `model` with `solver` and checks the result. Errors where no result exists (a body
/// neither its supports nor closed points hold, a closed set that does not settle, a pair that
/// cannot be built).
pub fn run_solid(model: &SolidModel, solver: SolidSolver) -> Result<SolidOutcome, SolidRunError> {
    run_solid_reported(model, solver, &|_| {})
}

/// [`run_solid`], the decomposition telling `report` of each phase as it ends.
pub fn run_solid_reported(
    model: &SolidModel,
    solver: SolidSolver,
    report: &(dyn Fn(SolidProgress) + Sync),
) -> Result<SolidOutcome, SolidRunError> {
    let pairs = model.pair_specs();
    let factors = &model.load_factors;
    let solutions = match solver {
        SolidSolver::Decomposition => {
            solve_solid_dd_steps(&model.body_specs(), &pairs, factors, report)
        }
        SolidSolver::Monolithic => monolithic_steps(model, &pairs),
    }
    .map_err(|e| named(model, e))?;
    let mut steps = Vec::with_capacity(solutions.len());
    let mut verdict: Option<(SolidBalance, Option<String>)> = None;
    for (k, (solution, &factor)) in solutions.iter().zip(factors).enumerate() {
        let balance = solid_balance(&scaled(model, factor), &pairs, solution)?;
        let reason = reason(model, &balance).map(|r| match factors.len() {
            1 => r,
            _ => format!("load step {} (factor {factor}): {r}", k + 1),
        });
        steps.push(step_of(
            model,
            solution,
            (factor, &balance, reason.is_none()),
        ));
        if !verdict.as_ref().is_some_and(|v| v.1.is_some()) {
            verdict = Some((balance, reason));
        }
    }
    let (Some(solution), Some((balance, reason))) = (solutions.into_iter().last(), verdict) else {
        return Err(SolidContactError::NotSettled { steps: 0 }.into());
    };
    Ok(SolidOutcome {
        solver,
        converged: reason.is_none(),
        solution,
        balance,
        reason,
        steps,
    })
}

/// The monolithic reference at every load factor, each increment starting where the last ended
/// (which matters only to friction).
fn monolithic_steps(
    model: &SolidModel,
    pairs: &[SolidPairSpec],
) -> Result<Vec<SolidContactSolution>, SolidContactError> {
    let mut solutions: Vec<SolidContactSolution> = Vec::new();
    for &f in &model.load_factors {
        let next = solve_solid_monolithic_from(&scaled(model, f), pairs, solutions.last())?;
        solutions.push(next);
    }
    Ok(solutions)
}

/// The bodies as the solvers take them, every load and prescribed value times `factor`.
fn scaled(model: &SolidModel, factor: f64) -> Vec<SolidBodySpec<'_>> {
    let mut bodies = model.body_specs();
    for b in &mut bodies {
        b.load.iter_mut().for_each(|v| *v *= factor);
        b.prescribed.iter_mut().for_each(|(_, v)| *v *= factor);
    }
    bodies
}

/// Why `balance` does not pass, if it does not.
fn reason(model: &SolidModel, balance: &SolidBalance) -> Option<String> {
    // The contact law holds to rounding when the pressures come from the displacements; a
    // looser law means the reported pressures are not those of the field.
    let law_tol = 1e-6;
    if let Some(b) = balance.unbalanced(model.balance_tol) {
        Some(format!(
            "unbalanced: body '{}' leaves {:.1e} of the largest force total unbalanced (balance-tol {:.0e}, rounding floor {:.1e})",
            model.bodies[b].name, balance.bodies[b].imbalance, model.balance_tol, balance.bodies[b].floor
        ))
    } else if balance.contact_law.is_nan() || balance.contact_law > law_tol {
        Some(format!(
            "the pressures differ from the contact law of the displacements by {:.1e} of the largest",
            balance.contact_law
        ))
    } else if balance.friction_law.is_nan() || balance.friction_law > law_tol {
        Some(format!(
            "the tractions differ from the friction law of the displacements by {:.1e} of the largest pressure",
            balance.friction_law
        ))
    } else {
        None
    }
}

/// The record of one load step.
fn step_of(
    model: &SolidModel,
    sol: &SolidContactSolution,
    (factor, balance, converged): (f64, &SolidBalance, bool),
) -> SolidStep {
    let pair_forces = (0..model.pairs.len())
        .map(|k| {
            let points = sol.points.iter().filter(|q| q.pair == k);
            points.map(|q| q.weight * q.pressure).sum()
        })
        .collect();
    let tangential_forces = (0..model.pairs.len())
        .map(|k| tangential_force(sol, k))
        .collect();
    let monitor = model.monitor.as_ref().and_then(|(b, face)| {
        let mut nodes = model.bodies[*b].mesh.face(face).ok()?.to_vec();
        nodes.sort_unstable();
        nodes.dedup();
        let u = &sol.displacements[*b];
        let mean = |c: usize| nodes.iter().map(|&v| u[3 * v + c]).sum::<f64>() / nodes.len() as f64;
        Some([mean(0), mean(1), mean(2)])
    });
    SolidStep {
        factor,
        newton_steps: sol.newton_steps,
        imbalance: balance.worst(),
        converged,
        pair_forces,
        tangential_forces,
        monitor,
    }
}

/// The resultant Σ w τ of pair `pair`'s tangential tractions on its reference side.
pub fn tangential_force(sol: &SolidContactSolution, pair: usize) -> [f64; 3] {
    let mut r = [0.0; 3];
    for q in sol.points.iter().filter(|q| q.pair == pair) {
        if let Some(f) = &q.friction {
            let t = f.traction_vector();
            (0..3).for_each(|c| r[c] += q.weight * t[c]);
        }
    }
    r
}

/// The solver's error with the body's name where it names one.
fn named(model: &SolidModel, e: SolidContactError) -> SolidRunError {
    match e {
        SolidContactError::NotHeld { body, step } => {
            let b = &model.bodies[body];
            let dofs: Vec<usize> = b.prescribed.iter().map(|&(d, _)| d).collect();
            SolidRunError::NotHeld {
                body: b.name.clone(),
                free: free_rigid_modes(&b.mesh, &dofs),
                step,
            }
        }
        SolidContactError::Slides {
            body,
            work,
            resistance,
        } => SolidRunError::Slides {
            body: model.bodies[body].name.clone(),
            work,
            resistance,
        },
        e => SolidRunError::Contact(e),
    }
}
