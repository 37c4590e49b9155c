//! Errors of reading a problem: the file itself, its TOML, its Gmsh meshes, or the problem it
//! describes ([`SetupError`], shared with the numerical crates), and the constructors that name
//! the body, pair or `[solver]` key of a [`SetupError`].

use thiserror::Error;

use contactdd_core::names::{is_hidden, shown};
use contactdd_core::{GmshError, MeshError};
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
    #[error("{file}: {}", excerpt(&source.to_string()))]
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

/// Longest line of a parser message that is echoed whole; longer lines end in `…`.
pub const MAX_ECHOED_LINE: usize = 200;

/// A parser message with every line cut to [`MAX_ECHOED_LINE`] characters and its control and
/// invisible formatting characters escaped ([`contactdd_core::names::is_hidden`]): the parser
/// echoes the offending source line, which can be megabytes long (a huge string, deeply nested
/// brackets) or hold a raw terminal escape (a tab is kept). Line and column numbers are in the first line, so
/// nothing needed is lost.
pub fn excerpt(message: &str) -> String {
    let lines: Vec<String> = message
        .trim_end()
        .lines()
        .map(|line| {
            let (line, cut) = match line.char_indices().nth(MAX_ECHOED_LINE) {
                Some((cut, _)) => (&line[..cut], "…"),
                None => (line, ""),
            };
            let mut out = String::with_capacity(line.len());
            for c in line.chars() {
                // A tab is harmless, and common in indented source lines.
                match is_hidden(c) && c != '\t' {
                    true => out.extend(c.escape_unicode()),
                    false => out.push(c),
                }
            }
            out + cut
        })
        .collect();
    lines.join("\n")
}

/// The error of a problem without bodies.
pub(crate) fn no_bodies() -> SetupError {
    SetupError::Invalid {
        key: "bodies".into(),
        message: "the problem has no bodies; it needs at least one".into(),
    }
}

/// An invalid value of body `body` at `key`.
pub(crate) fn body_error(body: &str, key: &str, message: impl std::fmt::Display) -> SetupError {
    SetupError::Body {
        body: shown(body),
        message: format!("{key}: {message}"),
    }
}

/// A mesh error of body `body` at `key`.
pub(crate) fn mesh_error(body: &str, key: &str, source: MeshError) -> SetupError {
    SetupError::Mesh {
        body: shown(body),
        key: key.to_string(),
        source,
    }
}

/// An invalid value of contact pair `pair` at `key`.
pub(crate) fn pair_error(pair: &str, key: &str, message: impl std::fmt::Display) -> SetupError {
    SetupError::Pair {
        pair: shown(pair),
        message: format!("{key}: {message}"),
    }
}

/// An invalid value of the `[solver]` table at `key`.
pub(crate) fn solver_error(key: &str, message: impl std::fmt::Display) -> SetupError {
    SetupError::Solver(format!("{key}: {message}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_lines_are_cut() {
        assert_eq!(excerpt("a\nb\n"), "a\nb");
        let long = "é".repeat(MAX_ECHOED_LINE + 1);
        let cut = excerpt(&format!("head\n{long}"));
        assert_eq!(cut, format!("head\n{}…", "é".repeat(MAX_ECHOED_LINE)));
        assert_eq!(excerpt("a\u{1b}[2Jb\u{7}"), "a\\u{1b}[2Jb\\u{7}");
    }
}
