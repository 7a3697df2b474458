//! Why a figure could not be drawn or written.

use std::path::PathBuf;

/// Why a figure could not be made; every message names the file concerned.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// The data cannot be plotted as given (e.g. times and angles of different lengths).
    #[error("{}: invalid plot data: {reason}", .path.display())]
    InvalidInput {
        /// File that was to be written.
        path: PathBuf,
        /// What is wrong with the data.
        reason: String,
    },
    /// The embedded font could not be registered with plotters.
    #[error("{}: the embedded font could not be loaded", .path.display())]
    Font {
        /// File that was to be written.
        path: PathBuf,
    },
    /// Plotters failed while drawing.
    #[error("{}: drawing failed: {reason}", .path.display())]
    Draw {
        /// File that was being drawn.
        path: PathBuf,
        /// Plotters' message.
        reason: String,
    },
    /// The PNG encoder failed.
    #[error("{}: PNG encoding failed: {reason}", .path.display())]
    Encode {
        /// File that was being encoded.
        path: PathBuf,
        /// The encoder's message.
        reason: String,
    },
    /// Creating the folder, writing the temporary file or renaming it failed.
    #[error("{}: {source}", .path.display())]
    Io {
        /// File (or folder) concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}
