//! Renderer errors. Every error a scene can cause carries the file location
//! it comes from; line and column are computed only when it is printed.

use pbrt_parser::{Location, ParseError};
use std::fmt;
use std::path::Path;

/// An error caused by a scene (as opposed to a bug): what, and where.
#[derive(Debug, Clone)]
pub struct SceneError {
    pub message: String,
    pub location: Location,
}

impl SceneError {
    pub fn new(message: impl Into<String>, location: &Location) -> Self {
        SceneError {
            message: message.into(),
            location: location.clone(),
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location, self.message)?;
        if let Some(excerpt) = self.location.excerpt() {
            write!(f, "\n{excerpt}")?;
        }
        Ok(())
    }
}

impl std::error::Error for SceneError {}

/// Any error rpbrt reports.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("{0}")]
    Parse(#[from] ParseError),
    #[error("{0}")]
    Scene(#[from] SceneError),
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{0}")]
    Image(#[from] crate::image::ImageError),
    /// A command-line tool was asked for something it cannot do (mismatched
    /// image sizes, a missing reference, a malformed list).
    #[error("{0}")]
    Usage(String),
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Shorthand for a scene error at a location.
pub fn scene_error<T>(message: impl Into<String>, location: &Location) -> Result<T> {
    Err(SceneError::new(message, location).into())
}

/// A file the scene names (a PLY mesh, an image, a spectrum) that could not
/// be opened or read: the error points at where the scene names it
/// (`location`, the parameter when there is one) and gives what the file
/// is for, its path and the operating system's reason.
pub fn unreadable_file(
    what: &str,
    path: &Path,
    reason: &dyn fmt::Display,
    location: &Location,
) -> Error {
    SceneError::new(
        format!("{what}: cannot read \"{}\": {reason}", path.display()),
        location,
    )
    .into()
}

/// An image the scene names that could not be used, at `location`: a file
/// the system would not read is [`unreadable_file`]; other failures
/// (format, contents) keep the image reader's message, which names the
/// file.
pub fn image_file_error(what: &str, error: crate::image::ImageError, location: &Location) -> Error {
    match error {
        crate::image::ImageError::Io { path, source } => {
            unreadable_file(what, &path, &source, location)
        }
        other => SceneError::new(format!("{what}: {other}"), location).into(),
    }
}
