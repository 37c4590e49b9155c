//! The seam between the problem and the iterations that solve it.
//!
//! A prepared model ([`Prepared`]: the contact points and the condensed bodies) is the problem;
//! an [`Iteration`] drives its interface state to the penalty problem's solution and reports an
//! [`Outcome`]. Three iterations implement it:
//! - the interface Newton method ([`crate::newton::InterfaceNewton`], the default);
//! - the Robin sweeps of the paper, relaxed or Anderson-accelerated ([`crate::sweeps::Sweeps`]).
//!
//! The augmented Lagrangian ([`crate::augmented`]) is an outer loop around any of them, and
//! [`crate::solver`] picks the iteration the settings name ([`crate::solver::iteration_for`]).

use crate::contact::Interface;
use crate::outcome::{Hooks, Outcome};
use crate::prepared::Prepared;

/// An interface iteration on a prepared model.
pub trait Iteration: Sync {
    /// Runs on `prepared` with the contact points `interface` (the prepared ones, or a copy with
    /// other multipliers: [`crate::augmented`]), from the interface loads `warm` of an earlier
    /// outcome when given and the iteration can use them.
    fn run(
        &self,
        prepared: &Prepared,
        interface: &Interface,
        warm: Option<&[f64]>,
        hooks: Hooks<'_>,
    ) -> Outcome;
}
