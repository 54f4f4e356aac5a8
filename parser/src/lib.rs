//! A streaming parser for pbrt-v4 scene files (pbrt-v3 files are read too,
//! their names mapped to pbrt-v4 meaning).
//!
//! [`Parser`] is a pull iterator of [`Located`] directives. It follows
//! `Include` and `Import` (paths relative to the including file, `.gz` read
//! transparently) unless told not to, and reads each file through a window so
//! that a file of any size streams; with two threads or more (rayon's pool)
//! a window's text is parsed in segments at once, with the directives,
//! locations and errors of the reading in order. It knows the file format
//! only, nothing of rendering.
//!
//! ```
//! let mut parser = pbrt_parser::Parser::from_text("<doc>", "Shape \"sphere\" \"float radius\" 2");
//! let shape = parser.next().unwrap().unwrap();
//! assert_eq!(shape.directive.keyword(), "Shape");
//! ```

mod directive;
mod error;
mod format;
mod grammar;
pub mod lexer;
mod list;
mod location;
mod name;
pub mod param;
mod source;
pub mod upgrade;

pub use directive::{ActiveTransform, Directive, Entity, Located};
pub use error::{ErrorKind, ParseError};
pub use format::Formatter;
pub use list::List;
pub use location::{LineColumn, Location, SourceFile};
pub use name::Name;
pub use param::{Param, ParamType, Values};
pub use source::decompressing_reader;

use source::Source;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A note for the user that is not an error (a pbrt-v3 name upgraded, a
/// deprecated directive).
#[derive(Clone, Debug)]
pub struct Warning {
    pub message: String,
    pub location: Location,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: warning: {}", self.location, self.message)
    }
}

/// Reads directives from a scene file and the files it includes.
pub struct Parser {
    stack: Vec<Source>,
    follow_includes: bool,
    in_world: bool,
    failed: bool,
    warnings: Vec<Warning>,
    warned: HashSet<String>,
    /// The largest read window any file has needed, in bytes.
    peak_window: usize,
}

impl Parser {
    /// Opens a scene file (`.gz` is decompressed).
    pub fn open(path: impl AsRef<Path>) -> Result<Self, ParseError> {
        let file = SourceFile::on_disk(path.as_ref());
        let source = Source::open(file, None)?;
        Ok(Self::with_source(source))
    }

    /// Parses text held in memory; `name` stands for its file name, and
    /// includes are resolved against its directory.
    pub fn from_text(name: impl Into<PathBuf>, text: impl Into<Vec<u8>>) -> Self {
        let text: Vec<u8> = text.into();
        let file = SourceFile::in_memory(name, Arc::from(text.as_slice()));
        Self::with_source(Source::from_text(file, text))
    }

    fn with_source(source: Source) -> Self {
        Parser {
            stack: vec![source],
            follow_includes: true,
            in_world: false,
            failed: false,
            warnings: Vec::new(),
            warned: HashSet::new(),
            peak_window: 0,
        }
    }

    /// Whether `Include`/`Import` are followed (the default) or returned as
    /// directives (for `--format`, which prints them as they are).
    pub fn follow_includes(mut self, follow: bool) -> Self {
        self.follow_includes = follow;
        self
    }

    /// The most text held in memory for one file at once (bytes): the
    /// parser streams, so this stays near the window size however large the
    /// file, unless a single directive is larger.
    pub fn peak_window_bytes(&self) -> usize {
        self.peak_window
    }

    /// Warnings so far (each distinct message once).
    pub fn take_warnings(&mut self) -> Vec<Warning> {
        std::mem::take(&mut self.warnings)
    }

    fn warn(&mut self, message: String, location: &Location) {
        if self.warned.insert(message.clone()) {
            self.warnings.push(Warning {
                message,
                location: location.clone(),
            });
        }
    }

    fn include(&mut self, path: &str, location: &Location) -> Result<(), ParseError> {
        let including = &self.stack.last().expect("include from an open file").file;
        let mut resolved = resolve_path(including.directory(), path);
        // pbrt-v4 resolves against the main file's directory; try that too.
        if !resolved.exists() {
            let main = resolve_path(self.stack[0].file.directory(), path);
            if main.exists() {
                resolved = main;
            }
        }
        let canonical = std::fs::canonicalize(&resolved).ok();
        let cyclic = canonical.is_some()
            && self
                .stack
                .iter()
                .any(|s| std::fs::canonicalize(&s.file.path).ok() == canonical);
        if cyclic {
            return Err(ParseError::new(
                ErrorKind::CyclicInclude(path.to_string()),
                location.clone(),
            ));
        }
        let source = Source::open(SourceFile::on_disk(resolved), Some(location))?;
        self.stack.push(source);
        Ok(())
    }

    fn next_directive(&mut self) -> Result<Option<Located>, ParseError> {
        loop {
            let Some(top) = self.stack.last_mut() else {
                return Ok(None);
            };
            let next = top.next_directive();
            self.peak_window = self.peak_window.max(top.peak_window);
            let Some((mut located, deprecated)) = next? else {
                self.stack.pop();
                continue;
            };
            if deprecated {
                self.warn(
                    "TransformBegin/TransformEnd are deprecated in pbrt-v4 and read as AttributeBegin/AttributeEnd".into(),
                    &located.location,
                );
            }
            match &located.directive {
                Directive::Import(_) if !self.in_world => {
                    return Err(ParseError::new(
                        ErrorKind::ImportOutsideWorld,
                        located.location,
                    ));
                }
                Directive::Include(path) | Directive::Import(path) if self.follow_includes => {
                    let path = path.clone();
                    self.include(&path, &located.location)?;
                    continue;
                }
                Directive::WorldBegin => self.in_world = true,
                _ => {}
            }
            let mut notes = Vec::new();
            upgrade::upgrade(&mut located.directive, &mut notes);
            for note in notes {
                self.warn(note, &located.location);
            }
            return Ok(Some(located));
        }
    }
}

/// Resolves a path written in a scene file against the file's directory.
pub fn resolve_path(directory: &Path, path: &str) -> PathBuf {
    let p = Path::new(path);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        directory.join(p)
    }
}

impl Iterator for Parser {
    type Item = Result<Located, ParseError>;

    /// The next directive; after an error, nothing more.
    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        match self.next_directive() {
            Ok(Some(d)) => Some(Ok(d)),
            Ok(None) => None,
            Err(e) => {
                self.failed = true;
                Some(Err(e))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_all(text: &str) -> Result<Vec<Directive>, ParseError> {
        Parser::from_text("<test>", text)
            .map(|r| r.map(|l| l.directive))
            .collect()
    }

    #[test]
    fn directives_and_params() {
        let ds = parse_all(
            "# a scene\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n\
             WorldBegin\nAttributeBegin\n Translate 1 -.5 +2\n Shape \"sphere\" \"float radius\" [ 2 ]\nAttributeEnd\n",
        )
        .unwrap();
        assert_eq!(ds.len(), 7);
        assert_eq!(
            ds[0],
            Directive::LookAt([0., 0., 5., 0., 0., 0., 0., 1., 0.])
        );
        assert_eq!(ds[4], Directive::Translate([1.0, -0.5, 2.0]));
        let Directive::Shape(shape) = &ds[5] else {
            panic!()
        };
        assert_eq!(shape.kind, "sphere");
        assert_eq!(shape.params[0].numbers(), &[2.0]);
    }

    #[test]
    fn errors_point_at_the_bad_token() {
        let e = parse_all("Shape \"sphere\"\n  \"float radius\" [ 1 2x ]").unwrap_err();
        assert!(
            matches!(e.kind, ErrorKind::BadNumber(ref t) if t == "2x"),
            "{e}"
        );
        assert_eq!(e.location.to_string(), "<test>:2:22");
    }

    #[test]
    fn an_unclosed_bracket_is_reported_where_it_opens() {
        let text = "WorldBegin\nShape \"sphere\" \"float radius\" [ 1\n# no bracket\n";
        let e = parse_all(text).unwrap_err();
        assert_eq!(e.location.to_string(), "<test>:2:31");
        assert_eq!(
            e.kind,
            ErrorKind::UnclosedBracket {
                to_end: text.len() - text.find('[').unwrap()
            }
        );
        let printed = e.to_string();
        assert!(
            printed.starts_with(
                "<test>:2:31: '[' is never closed: the file ends at line 4, column 1 with no ']'"
            ),
            "{printed}"
        );
        // The excerpt shows the bracket's line with a caret under it.
        assert!(
            printed.ends_with(&format!("\n    {}^", " ".repeat(30))),
            "{printed}"
        );
        // Directives with a fixed count of numbers too.
        let e = parse_all("Translate [ 1 2 3").unwrap_err();
        assert_eq!(e.location.to_string(), "<test>:1:11");
        assert!(e.to_string().contains("line 1, column 18"), "{e}");
        // Strings and bools.
        for text in ["Shape \"x\" \"string a\" [ \"b\"", "Option \"b\" [ true"] {
            let e = parse_all(text).unwrap_err();
            assert!(
                matches!(e.kind, ErrorKind::UnclosedBracket { .. }),
                "{text}: {e}"
            );
        }
    }

    #[test]
    fn an_unclosed_bracket_is_found_across_window_refills() {
        // The '[' lies in the first window, the end of the file two
        // windows later: both positions are still right.
        let dir = std::env::temp_dir().join(format!("pbrt-parser-bracket-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("unclosed.pbrt");
        let mut text = String::from("WorldBegin\nShape \"trianglemesh\"\n  \"point3 P\" [\n");
        let mut lines = 3;
        while text.len() < 2 * (1 << 20) + 777 {
            text.push_str("0.25 1 -3e-2 4 5 6 7 8 9\n");
            lines += 1;
        }
        std::fs::write(&path, &text).unwrap();
        let e = Parser::open(&path)
            .unwrap()
            .find_map(|d| d.err())
            .expect("an error");
        assert_eq!(e.location.to_string(), format!("{}:3:14", path.display()));
        let printed = e.to_string();
        assert!(
            printed.contains(&format!("the file ends at line {}, column 1", lines + 1)),
            "{printed}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn import_outside_world_is_an_error() {
        let e = parse_all("Import \"x.pbrt\"").unwrap_err();
        assert_eq!(e.kind, ErrorKind::ImportOutsideWorld);
    }

    #[test]
    fn format_round_trips() {
        let text = "Texture \"t\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 1 0.5 0.25 ] \"string s\" \"a\\\"b\"\n\
                    Option \"bool disablepixeljitter\" true\nMediumInterface \"a\" \"\"\n";
        let first = parse_all(text).unwrap();
        let formatted: String = first.iter().map(|d| format!("{d}\n")).collect();
        assert_eq!(parse_all(&formatted).unwrap(), first);
    }

    #[test]
    fn streams_across_window_edges() {
        // Many directives so that the file crosses several windows; numbers
        // and strings land on the window edges.
        let dir = std::env::temp_dir().join(format!("pbrt-parser-stream-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("big.pbrt");
        let mut text = String::new();
        let mut i = 0u64;
        while text.len() < 3 * (1 << 20) + 12345 {
            text.push_str(&format!(
                "Shape \"curve\" \"point3 P\" [ {} 1.25 -3e-2 4 5 6 7 8 9 10 11 {} ] # c{i}\n",
                i as f64 * 0.001,
                i
            ));
            i += 1;
        }
        std::fs::write(&path, &text).unwrap();
        // Two threads: the window holds two segments per thread.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        pool.install(|| {
            let mut parser = Parser::open(&path).unwrap();
            let count = parser
                .by_ref()
                .map(|d| {
                    let d = d.unwrap();
                    let Directive::Shape(e) = d.directive else {
                        panic!()
                    };
                    e.params[0].numbers()[11]
                })
                .enumerate()
                .inspect(|(k, last)| assert_eq!(*k as f64, *last))
                .count();
            assert_eq!(count as u64, i);
            // The file is 3 MiB; the window never held more than two chunks.
            assert!(
                parser.peak_window_bytes() <= 2 << 20,
                "{}",
                parser.peak_window_bytes()
            );
        });
        std::fs::remove_dir_all(&dir).ok();
    }
}
