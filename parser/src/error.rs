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
    /// A `[` with no `]` before the end of the file, reported at the `[`.
    /// `to_end` is the number of bytes from the `[` to the end of the file:
    /// where the file ends is resolved to line:col only when printed.
    #[error("'[' is never closed")]
    UnclosedBracket { to_end: usize },
    /// Something other than a value or `]` inside a `[` list (often a
    /// missing `]`). `back` is the number of bytes back to the `[`, whose
    /// line:col is printed with the error.
    #[error("expected {expected}, found {found}")]
    NotInList {
        expected: &'static str,
        found: String,
        back: usize,
    },
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

impl ParseError {
    /// `line L, column C` of the byte at `offset` in the error's file.
    fn line_column(&self, offset: usize) -> String {
        let at = Location::new(self.location.file.clone(), offset);
        match at.resolve() {
            Some(lc) => format!("line {}, column {}", lc.line, lc.column),
            None => format!("byte {offset}"),
        }
    }

    /// What the message adds about another position: where the file ends
    /// for an unclosed `[`, where the list began for a bad list element.
    fn note(&self) -> Option<String> {
        let offset = self.location.offset;
        match self.kind {
            ErrorKind::UnclosedBracket { to_end } => Some(format!(
                ": the file ends at {} with no ']'",
                self.line_column(offset + to_end)
            )),
            ErrorKind::NotInList { back, .. } => Some(format!(
                " (in the list that '[' opens at {})",
                self.line_column(offset.saturating_sub(back))
            )),
            _ => None,
        }
    }
}

impl fmt::Display for ParseError {
    /// `file:line:col: message`, then the offending line with a caret.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location, self.kind)?;
        if let Some(note) = self.note() {
            f.write_str(&note)?;
        }
        if let Some(excerpt) = self.location.excerpt() {
            write!(f, "\n{excerpt}")?;
        }
        Ok(())
    }
}

impl std::error::Error for ParseError {}
