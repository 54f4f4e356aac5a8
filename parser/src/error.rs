//! Parse errors: what was wrong, and where.

use crate::location::Location;
use std::fmt;

/// What went wrong. Each message says what was expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ErrorKind {
    #[error("unknown directive \"{0}\"")]
    UnknownDirective(String),
    #[error("unterminated string: expected a closing '\"' before the end of the line")]
    UnterminatedString,
    #[error("bad number \"{0}\"")]
    BadNumber(String),
    #[error("expected {expected}, found {found}")]
    Expected {
        expected: &'static str,
        found: String,
    },
    #[error("malformed parameter declaration \"{0}\": expected \"type name\"")]
    MalformedDeclaration(String),
    #[error("unknown parameter type \"{ty}\" in \"{ty} {name}\"")]
    UnknownParameterType { ty: String, name: String },
    #[error("\"{ty} {name}\": {count} values given, expected a multiple of {multiple}")]
    WrongValueCount {
        ty: &'static str,
        name: String,
        count: usize,
        multiple: usize,
    },
    #[error("\"{ty} {name}\": expected {expected} values")]
    WrongValueKind {
        ty: &'static str,
        name: String,
        expected: &'static str,
    },
    #[error("\"integer {name}\": {value} is not an integer")]
    NonIntegerValue { name: String, value: f64 },
    #[error("\"{ty} {name}\": expected one value, found none")]
    NoValues { ty: &'static str, name: String },
    #[error("mixed values in one list: expected all {expected}")]
    MixedValues { expected: &'static str },
    #[error("{directive}: expected {expected} numbers, found {found}")]
    WrongArgumentCount {
        directive: &'static str,
        expected: usize,
        found: usize,
    },
    #[error("cannot read \"{path}\": {message}")]
    CannotRead { path: String, message: String },
    #[error("\"{0}\" includes itself (cyclic Include/Import)")]
    CyclicInclude(String),
    #[error("Import is only allowed inside the world block (after WorldBegin)")]
    ImportOutsideWorld,
    #[error("text is not valid UTF-8")]
    InvalidUtf8,
    #[error("unexpected end of file: expected {0}")]
    UnexpectedEof(&'static str),
}

/// A parse error at a location.
#[derive(Debug, Clone)]
pub struct ParseError {
    pub kind: ErrorKind,
    pub location: Location,
}

impl ParseError {
    pub fn new(kind: ErrorKind, location: Location) -> Self {
        ParseError { kind, location }
    }
}

impl fmt::Display for ParseError {
    /// `file:line:col: message`, then the offending line with a caret.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location, self.kind)?;
        if let Some(excerpt) = self.location.excerpt() {
            write!(f, "\n{excerpt}")?;
        }
        Ok(())
    }
}

impl std::error::Error for ParseError {}
