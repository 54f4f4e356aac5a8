//! Source files and positions in them.
//!
//! A [`Location`] is a source file and a byte offset. Line and column are
//! computed only when a location is printed: the parser never counts lines on
//! its hot path. Files read from disk are read again for that (errors are
//! rare); text parsed from memory keeps its text here.

use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A scene file (or an in-memory text standing for one).
pub struct SourceFile {
    /// Path as given (or a name such as `<string>` for in-memory text).
    pub path: PathBuf,
    /// The text, when it does not live on disk.
    text: Option<Arc<[u8]>>,
}

impl std::fmt::Debug for SourceFile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "SourceFile({})", self.path.display())
    }
}

impl SourceFile {
    pub fn on_disk(path: impl Into<PathBuf>) -> Arc<Self> {
        Arc::new(SourceFile {
            path: path.into(),
            text: None,
        })
    }

    pub fn in_memory(name: impl Into<PathBuf>, text: Arc<[u8]>) -> Arc<Self> {
        Arc::new(SourceFile {
            path: name.into(),
            text: Some(text),
        })
    }

    /// The directory relative paths in this file are resolved against.
    pub fn directory(&self) -> &Path {
        self.path.parent().unwrap_or(Path::new(""))
    }

    /// The bytes of the file up to `end` (all of it when it is shorter).
    fn prefix(&self, end: usize) -> Option<Vec<u8>> {
        if let Some(text) = &self.text {
            return Some(text.to_vec());
        }
        let file = std::fs::File::open(&self.path).ok()?;
        let mut reader = crate::source::decompressing_reader(&self.path, file).ok()?;
        // Read a little past `end` so that the whole offending line can be shown.
        let mut bytes = Vec::new();
        (&mut reader)
            .take(end as u64 + 4096)
            .read_to_end(&mut bytes)
            .ok()?;
        Some(bytes)
    }
}

/// A position in a source file: the file and a byte offset into its
/// (decompressed) text.
#[derive(Clone, Debug)]
pub struct Location {
    pub file: Arc<SourceFile>,
    pub offset: usize,
}

/// A location resolved to 1-based line and column, with the line's text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LineColumn {
    pub line: usize,
    pub column: usize,
    pub line_text: String,
}

impl Location {
    pub fn new(file: Arc<SourceFile>, offset: usize) -> Self {
        Location { file, offset }
    }

    /// A location for things that come from no file (command-line defaults).
    pub fn nowhere() -> Self {
        Location {
            file: SourceFile::in_memory("<default>", Arc::from(&b""[..])),
            offset: 0,
        }
    }

    /// Line, column (1-based, counted in characters) and the line's text.
    pub fn resolve(&self) -> Option<LineColumn> {
        let bytes = self.file.prefix(self.offset)?;
        Some(line_column(&bytes, self.offset))
    }

    /// The offending line with a caret under the column, for error messages.
    pub fn excerpt(&self) -> Option<String> {
        let lc = self.resolve()?;
        let prefix: String = lc
            .line_text
            .chars()
            .take(lc.column - 1)
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        Some(format!("    {}\n    {}^", lc.line_text, prefix))
    }
}

/// Resolves byte `offset` of `bytes` to a line and column.
pub(crate) fn line_column(bytes: &[u8], offset: usize) -> LineColumn {
    let offset = offset.min(bytes.len());
    let before = &bytes[..offset];
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    let line = 1 + before.iter().filter(|&&b| b == b'\n').count();
    let line_end = bytes[offset..]
        .iter()
        .position(|&b| b == b'\n' || b == b'\r')
        .map_or(bytes.len(), |p| offset + p);
    let column = 1 + String::from_utf8_lossy(&bytes[line_start..offset])
        .chars()
        .count();
    LineColumn {
        line,
        column,
        line_text: String::from_utf8_lossy(&bytes[line_start..line_end]).into_owned(),
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.resolve() {
            Some(lc) => write!(f, "{}:{}:{}", self.file.path.display(), lc.line, lc.column),
            None => write!(f, "{}:byte {}", self.file.path.display(), self.offset),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_are_one_based() {
        let text = b"Film \"rgb\"\n  Shape \"sphere\"\n";
        let lc = line_column(text, 13);
        assert_eq!((lc.line, lc.column), (2, 3));
        assert_eq!(lc.line_text, "  Shape \"sphere\"");
        assert_eq!(line_column(text, 0).column, 1);
    }

    #[test]
    fn in_memory_locations_print_with_caret() {
        let file = SourceFile::in_memory("<test>", Arc::from(&b"a\nbcd e"[..]));
        let loc = Location::new(file, 6);
        assert_eq!(loc.to_string(), "<test>:2:5");
        assert_eq!(loc.excerpt().unwrap(), "    bcd e\n        ^");
    }
}
