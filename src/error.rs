//! Renderer errors. Every error a scene can cause carries the file location
//! it comes from; line and column are computed only when it is printed.

use pbrt_parser::{Location, ParseError};
use std::fmt;

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
