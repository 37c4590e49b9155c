//! Errors of reading a problem: the file itself, its TOML, its Gmsh meshes, or the problem it
//! describes ([`SetupError`], shared with the numerical crates).

use thiserror::Error;

use contactdd_core::GmshError;
use contactdd_ddm::SetupError;

/// A problem file or description that cannot be turned into a model.
#[derive(Debug, Error)]
pub enum LoadError {
    /// The problem file could not be read.
    #[error("cannot read '{path}': {source}")]
    Io {
        /// Path.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// TOML syntax or schema error (the message names the key and line).
    #[error("{file}: {}", source.to_string().trim_end())]
    Toml {
        /// The file (or source name) being parsed.
        file: String,
        /// The parser's error.
        source: toml::de::Error,
    },
    /// A Gmsh mesh file of a body that cannot be read.
    #[error("body '{body}': mesh file '{path}': {source}")]
    Gmsh {
        /// Body name.
        body: String,
        /// File.
        path: String,
        /// Cause.
        source: GmshError,
    },
    /// The problem is invalid (names the body, pair, material or key).
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// An error found in a problem file: the file name, then the error. (The inner error is part
    /// of the message, not a `source`, so that `{:#}` chains do not print it twice.)
    #[error("{file}: {error}")]
    InFile {
        /// The file (or source name) the problem was read from.
        file: String,
        /// The error.
        error: Box<LoadError>,
    },
}
