//! # contactdd-ddm
//!
//! Unilateral contact of several linear elastic bodies by domain decomposition: every body is
//! factorised once and condensed onto its contact points, and an interface iteration couples
//! them. By default that is the interface Newton method ([`newton`]); the penalty Robin domain
//! decomposition of Prokopyshyn & Shakhno (see `docs/method.md`), with its five Robin
//! coefficient rules ([`Method`]) and relaxation γ, runs as the Robin sweeps ([`sweeps`]).
//!
//! Data flow: a problem description (the `contactdd-io` crate reads files) → [`Model`] →
//! [`prepared`] (the contact geometry of [`contact`], per-body factorisation and condensation of
//! [`condensed`], the [`coarse`] space) → an [`iteration::Iteration`] (inside the [`augmented`]
//! Lagrangian loop where pairs ask for it) → [`Solution`], checked by [`equilibrium`]. [`solver`]
//! runs that flow. This crate reads and writes no file format.

pub mod anderson;
pub mod augmented;
pub mod benchmark;
pub mod coarse;
pub mod condensed;
pub mod contact;
pub mod contact3d;
pub mod equilibrium;
pub mod error;
pub mod exchange;
pub mod facts;
pub mod force_balance;
pub mod gamma_study;
pub mod history;
pub mod iteration;
mod measures;
pub mod method;
pub mod model;
pub mod monolithic;
pub mod newton;
pub mod outcome;
pub mod prepared;
pub mod relaxation;
pub mod settings;
pub mod shared_rows;
pub mod solid_balance;
pub mod solid_contact;
pub mod solid_dd;
mod solid_friction;
pub mod solid_monolithic;
mod solid_monolithic_friction;
mod solid_newton;
pub mod solution;
pub mod solver;
pub mod sparse_body;
pub mod steps;
pub mod sweeps;

pub use coarse::CoarseMode;
pub use condensed::Condensation;
pub use contact::formulation::{Enforcement, Forces, InnerPenalty, Penalty};
pub use contact::friction::{Friction, Status as FrictionStatus};
pub use contact::gap_profile::GapProfile;
pub use contact::Formulation;
pub use error::SetupError;
pub use facts::BodyFacts;
pub use gamma_study::{sweep, sweep_with, SweepHooks, SweepRun};
pub use method::Method;
pub use model::{ContactPair, Model, Remote};
pub use monolithic::{solve_monolithic, MonolithicSolution};
pub use outcome::{Hooks, Record, Stop};
pub use relaxation::Gamma;
pub use settings::{Accelerator, InvalidSetting, Settings};
pub use solution::Solution;
pub use solver::{prepare, prepare_on, prepare_with, solve, solve_from, Preparation, Prepared};
