//! The harness's errors: the renderer's own, and the harness's I/O and
//! usage mistakes, each naming what it is about.

use std::path::Path;

/// Any error the harness reports.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A render, a scene or an image the renderer could not handle.
    #[error("{0}")]
    Rpbrt(#[from] rpbrt::Error),
    #[error("{0}")]
    Image(#[from] rpbrt::image::ImageError),
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    /// Asked for something it cannot do (a missing scene, an unreadable
    /// CSV, a render that failed in a child process).
    #[error("{0}")]
    Usage(String),
    /// A report template and the code filling it disagree (a bug, caught
    /// by the template tests).
    #[error("template {template:?}: {message}")]
    Template { template: String, message: String },
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Maps an I/O error on `path` to the harness's error, naming the path.
pub fn io_error(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.display().to_string(),
        source,
    }
}
