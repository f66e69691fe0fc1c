//! Errors of the renderer.

/// What can go wrong when rendering.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An option is out of range; `name` is the option's name.
    #[error("{name}: {message}")]
    Option {
        /// The option (width, height, range, view, zebra, resolution, …).
        name: &'static str,
        /// What is wrong with it.
        message: String,
    },
    /// Nothing to draw.
    #[error("nothing to render: give at least one surface")]
    NoPanels,
    /// A panel without patches.
    #[error("panel {panel} has no patches")]
    EmptyPanel {
        /// Index of the panel.
        panel: usize,
    },
    /// The PNG encoder failed (usually the writer underneath).
    #[error("cannot encode PNG: {0}")]
    Png(String),
}

/// Results of the renderer.
pub type Result<T, E = Error> = std::result::Result<T, E>;
