//! Errors for people: every error names the file, the line and the problem.

use std::path::PathBuf;

/// What went wrong while reading or learning.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A problem with one line of an input file.
    #[error("{file}:{line}: {msg}")]
    Parse {
        /// The file.
        file: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        msg: String,
    },
    /// A problem with a whole file (empty, unreadable, unknown format).
    #[error("{file}: {msg}")]
    File {
        /// The file.
        file: PathBuf,
        /// What is wrong with it.
        msg: String,
    },
    /// An I/O error, with the file it happened on (the OS error is its `source()`, which
    /// `{:#}` of an `anyhow::Error` prints after the file).
    #[error("{file}")]
    Io {
        /// The file.
        file: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The data do not support the requested computation.
    #[error("{0}")]
    Data(String),
}

impl Error {
    /// The file the error is about, if it names one.
    pub fn file(&self) -> Option<&std::path::Path> {
        match self {
            Error::Parse { file, .. } | Error::File { file, .. } | Error::Io { file, .. } => {
                Some(file)
            }
            Error::Data(_) => None,
        }
    }
}

/// `Result` with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
