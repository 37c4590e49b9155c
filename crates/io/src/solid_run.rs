//! A solve in space and its verdict: the decomposition (or the monolithic reference) on a
//! [`SolidModel`], then the independent check of [`contactdd_ddm::solid_balance`], which alone
//! lets a result count as converged.

use contactdd_core::solid::rigid::free_rigid_modes;
use contactdd_ddm::solid_balance::{solid_balance, SolidBalance};
use contactdd_ddm::solid_contact::SolidProgress;
use contactdd_ddm::solid_dd::solve_solid_dd_reported;
use contactdd_ddm::solid_monolithic::{
    solve_solid_monolithic, SolidContactError, SolidContactSolution,
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
    /// The solution.
    pub solution: SolidContactSolution,
    /// The independent check.
    pub balance: SolidBalance,
    /// Whether the result is a solution: the closed set settled and the check passed.
    pub converged: bool,
    /// Why not, when it is not.
    pub reason: Option<String>,
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
    let bodies = model.body_specs();
    let pairs = model.pair_specs();
    let solution = match solver {
        SolidSolver::Decomposition => solve_solid_dd_reported(&bodies, &pairs, report),
        SolidSolver::Monolithic => solve_solid_monolithic(&bodies, &pairs),
    }
    .map_err(|e| named(model, e))?;
    let balance = solid_balance(&bodies, &pairs, &solution)?;
    // The contact law holds to rounding when the pressures come from the displacements; a
    // looser law means the reported pressures are not those of the field.
    let law_tol = 1e-6;
    let reason = if let Some(b) = balance.unbalanced(model.balance_tol) {
        Some(format!(
            "unbalanced: body '{}' leaves {:.1e} of the largest force total unbalanced (balance-tol {:.0e}, rounding floor {:.1e})",
            model.bodies[b].name, balance.bodies[b].imbalance, model.balance_tol, balance.bodies[b].floor
        ))
    } else if balance.contact_law.is_nan() || balance.contact_law > law_tol {
        Some(format!(
            "the pressures differ from the contact law of the displacements by {:.1e} of the largest",
            balance.contact_law
        ))
    } else {
        None
    };
    Ok(SolidOutcome {
        solver,
        converged: reason.is_none(),
        solution,
        balance,
        reason,
    })
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
        e => SolidRunError::Contact(e),
    }
}
