//! # contactdd-io
//!
//! The file front end of contactdd, shared by the command line and the Python module: the numerical
//! crates (`contactdd-core`, `contactdd-ddm`) read and write no file format, this crate does.
//!
//! Data flow: a TOML problem file → [`problem`] (plain serde types, the file's schema) →
//! [`setup`] (one resolve step: every name checked first by [`names`], then validated `Model` and
//! `Settings`, built by a
//! [`model_builder::ModelBuilder`] from [`meshes`], [`bodies`] and [`pairs`], with
//! [`solver_settings`] and [`load_steps`] for the `[solver]` table, [`history`] for `[[steps]]`) → the solver of
//! `contactdd-ddm` → [`output`] (`summary.json` from [`summary`], `contact.csv`, `history.csv`
//! and the sweep CSV from [`csv_tables`], the load-step tables of [`steps`]) and [`vtu`] (one
//! `.vtu` per body, ASCII or binary, written by [`body_vtus`] and read back by [`vtu_read`],
//! with the derived [`fields`] and the support [`reactions`]). [`atomic`] writes every file
//! without ever leaving a half-written one, [`result_set`] a result folder so that `summary.json` exists only for a complete one;
//! [`number`] is the one float format of the text files. The processes of a distributed solve
//! share the resolve step through [`distributed_setup`] and the result folder through
//! [`distributed_results`] ([`packed`] carries their data). docs/outputs.md describes the results.
//!
//! Gmsh meshes are read by `contactdd_core::gmsh`, not here: that reader only builds a mesh and
//! needs no dependency, so pure-numerics users can read meshes without this crate (see that
//! module's docs).

pub mod atomic;
pub mod bodies;
pub mod body_vtus;
pub mod csv_tables;
pub mod distributed_results;
pub mod distributed_setup;
pub mod error;
pub mod fields;
pub mod history;
pub mod load_steps;
pub mod meshes;
pub mod model_builder;
pub mod names;
pub mod nearest_segment;
pub mod number;
pub mod output;
pub mod packed;
pub mod pairs;
pub mod problem;
pub mod reactions;
pub mod result_set;
pub mod setup;
pub mod solid_problem;
pub mod solid_results;
pub mod solid_run;
pub mod solid_setup;
pub mod solid_vtu;
pub mod solver_settings;
pub mod steps;
pub mod summary;
pub mod vtu;
pub mod vtu_options;
pub mod vtu_read;
pub mod write_problem;

pub use error::LoadError;
pub use setup::{load_file, load_str, read_problem, resolve, Loaded, ProblemFile};
