//! Errors of setting up and solving a contact problem.
//!
//! Variants that wrap an error of the core keep it as their typed `source`; the others carry a
//! message for a value that is wrong in itself. Reading files has its own errors in
//! `contactdd-io`.

use thiserror::Error;

use contactdd_core::memory::OutOfMemory;
use contactdd_core::{BodyError, MaterialError, MeshError, SupportError};

/// A problem description that cannot be turned into a model, or a body that cannot be factorised.
#[derive(Debug, Error)]
pub enum SetupError {
    /// A problem with one body's description.
    #[error("body '{body}': {message}")]
    Body {
        /// Body name.
        body: String,
        /// What is wrong.
        message: String,
    },
    /// A body's mesh, boundary or load that the core rejects.
    #[error("body '{body}': {}{source}", key_prefix(key))]
    Mesh {
        /// Body name.
        body: String,
        /// The key of the body's description at fault (may be empty).
        key: String,
        /// Cause.
        source: MeshError,
    },
    /// A support of a body that cannot be applied.
    #[error("body '{body}': {}{source}", key_prefix(key))]
    Support {
        /// Body name.
        body: String,
        /// The key of the body's description at fault (may be empty).
        key: String,
        /// Cause.
        source: SupportError,
    },
    /// A problem with one contact pair.
    #[error("contact pair '{pair}': {message}")]
    Pair {
        /// Pair name.
        pair: String,
        /// What is wrong.
        message: String,
    },
    /// A boundary of a contact pair that its body's mesh rejects.
    #[error("contact pair '{pair}': {key}: body '{body}': {source}")]
    PairBoundary {
        /// Pair name.
        pair: String,
        /// The key of the pair's description at fault.
        key: String,
        /// Body name.
        body: String,
        /// Cause.
        source: MeshError,
    },
    /// A problem with the solver settings.
    #[error("solver: {0}")]
    Solver(String),
    /// An error that one process of a distributed solve met, in its words: every process
    /// reports the same one (`crate::exchange`).
    #[error("{0}")]
    Distributed(String),
    /// A body cannot be assembled or factorised.
    #[error(transparent)]
    Factor(#[from] BodyError),
    /// The factorisations would need more memory than the system has available.
    #[error(transparent)]
    Memory(#[from] OutOfMemory),
    /// A problem with one material of the problem file.
    #[error("material '{material}': {message}")]
    Material {
        /// Material name (key of `[materials]`).
        material: String,
        /// What is wrong.
        message: String,
    },
    /// Material constants that the core rejects (the message names the key).
    #[error("material '{material}': {}: {source}", material_key(source))]
    MaterialValue {
        /// Material name (key of `[materials]`).
        material: String,
        /// Cause.
        source: MaterialError,
    },
    /// A body with neither supports nor a contact pair.
    #[error("body '{body}' has no supports and no contact pair: it would float")]
    Floating {
        /// Body name.
        body: String,
    },
    /// A problem with a top-level key of the problem file.
    #[error("{key}: {message}")]
    Invalid {
        /// The key.
        key: String,
        /// What is wrong.
        message: String,
    },
}

/// `"key: "`, or nothing for an empty key.
fn key_prefix(key: &str) -> String {
    if key.is_empty() {
        String::new()
    } else {
        format!("{key}: ")
    }
}

/// The key of a material table that `e` is about.
fn material_key(e: &MaterialError) -> &'static str {
    match e {
        MaterialError::YoungModulus(_) => "young",
        MaterialError::PoissonRatio(_) => "poisson",
    }
}

/// A singular Robin problem: the body has lost its hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Singular;
