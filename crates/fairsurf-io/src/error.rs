//! The one error type of fairsurf-io.

use std::path::PathBuf;

/// What can go wrong reading, checking, solving or writing.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The scene is not valid: `path` is the JSON path of the offending value
    /// (e.g. `surface.control_points[3][2]`), empty for the whole document.
    #[error("{}: {message}", if path.is_empty() { "scene" } else { path.as_str() })]
    Scene {
        /// JSON path.
        path: String,
        /// What was expected and what was found.
        message: String,
    },
    /// A file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A file could not be written (nothing was left behind).
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A surface or mesh cannot be written in the asked format (nothing was
    /// written): e.g. an empty patch list, a patch of degree 0, or an empty
    /// colour range.
    #[error("cannot export {}: {message}", path.display())]
    Export {
        /// The file that was to be written.
        path: PathBuf,
        /// What is wrong with the input.
        message: String,
    },
    /// The solve refused the problem.
    #[error("{0}")]
    Solve(#[from] fairsurf::Error),
}

impl Error {
    /// A scene error at `path`.
    pub fn scene(path: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Scene {
            path: path.into(),
            message: message.into(),
        }
    }
}

/// `Result` with fairsurf-io's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
