//! Errors of setting up and solving a contact problem.

use thiserror::Error;

use contactdd_core::{BodyError, GmshError};

/// A problem description that cannot be turned into a model, or a body that cannot be factorised.
#[derive(Debug, Error)]
pub enum SetupError {
    /// The problem file could not be read.
    #[error("cannot read '{path}': {source}")]
    Io {
        /// Path.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// TOML syntax or schema error (the message names the key and line).
    #[error("{0}")]
    Toml(String),
    /// A problem with one body's description.
    #[error("body '{body}': {message}")]
    Body {
        /// Body name.
        body: String,
        /// What is wrong.
        message: String,
    },
    /// A problem with one contact pair.
    #[error("contact pair '{pair}': {message}")]
    Pair {
        /// Pair name.
        pair: String,
        /// What is wrong.
        message: String,
    },
    /// A problem with the solver settings.
    #[error("solver: {0}")]
    Solver(String),
    /// Gmsh file problem.
    #[error("body '{body}': mesh file '{path}': {source}")]
    Gmsh {
        /// Body name.
        body: String,
        /// File.
        path: String,
        /// Cause.
        source: GmshError,
    },
    /// A body cannot be assembled or factorised.
    #[error(transparent)]
    Factor(#[from] BodyError),
    /// A problem with one material of the problem file.
    #[error("material '{material}': {message}")]
    Material {
        /// Material name (key of `[materials]`).
        material: String,
        /// What is wrong.
        message: String,
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
    /// An error found in a problem file: the file name, then the error. (The inner error is part
    /// of the message, not a `source`, so that `{:#}` chains do not print it twice.)
    #[error("{file}: {error}")]
    InFile {
        /// The file (or source name) the problem was read from.
        file: String,
        /// The error.
        error: Box<SetupError>,
    },
}

impl SetupError {
    /// Wraps a core error as an error of body `body`.
    pub fn body(body: &str, e: impl std::fmt::Display) -> SetupError {
        SetupError::Body {
            body: body.to_string(),
            message: e.to_string(),
        }
    }
}
