//! One scene file being read: a window of its text, refilled as the parser
//! moves on, so that a huge file is never held whole in memory.
//!
//! The grammar runs on complete input. A directive is accepted only when the
//! text after it (past space and comments) is not the end of the window, so a
//! number or string cut by the window's edge is never taken for a whole one;
//! otherwise the window grows (doubling, so re-parsing stays linear) and the
//! directive is parsed again.

use crate::directive::Located;
use crate::error::{ErrorKind, ParseError};
use crate::grammar;
use crate::lexer;
use crate::location::{Location, SourceFile};
use std::io::{BufReader, Read};
use std::path::Path;
use std::sync::Arc;

/// Bytes read at a time.
const CHUNK: usize = 1 << 20;

/// A reader of the file's text, decompressing `.gz` files.
pub fn decompressing_reader(
    path: &Path,
    file: std::fs::File,
) -> std::io::Result<Box<dyn Read + Send>> {
    let gz = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    if gz {
        Ok(Box::new(flate2::read::MultiGzDecoder::new(
            BufReader::with_capacity(CHUNK, file),
        )))
    } else {
        Ok(Box::new(file))
    }
}

pub(crate) struct Source {
    pub file: Arc<SourceFile>,
    reader: Option<Box<dyn Read + Send>>,
    buf: Vec<u8>,
    /// Parse position in `buf`.
    pos: usize,
    /// Offset in the file of `buf[0]`.
    base: usize,
    /// The largest the window has been, in bytes.
    pub peak_window: usize,
}

impl Source {
    pub fn open(file: Arc<SourceFile>, location: Option<&Location>) -> Result<Self, ParseError> {
        let cannot_read = |e: std::io::Error| {
            ParseError::new(
                ErrorKind::CannotRead {
                    path: file.path.display().to_string(),
                    message: e.to_string(),
                },
                location
                    .cloned()
                    .unwrap_or_else(|| Location::new(file.clone(), 0)),
            )
        };
        let handle = std::fs::File::open(&file.path).map_err(cannot_read)?;
        let reader = decompressing_reader(&file.path, handle).map_err(cannot_read)?;
        Ok(Source {
            file: file.clone(),
            reader: Some(reader),
            buf: Vec::new(),
            pos: 0,
            base: 0,
            peak_window: 0,
        })
    }

    pub fn from_text(file: Arc<SourceFile>, text: Vec<u8>) -> Self {
        Source {
            file,
            reader: None,
            peak_window: text.len(),
            buf: text,
            pos: 0,
            base: 0,
        }
    }

    fn at_eof(&self) -> bool {
        self.reader.is_none()
    }

    /// Drops what has been parsed and reads at least as much again as is
    /// buffered (at least a chunk).
    fn read_more(&mut self) -> Result<(), ParseError> {
        if self.pos > 0 {
            self.buf.drain(..self.pos);
            self.base += self.pos;
            self.pos = 0;
        }
        let want = self.buf.len().max(CHUNK);
        let Some(reader) = self.reader.as_mut() else {
            return Ok(());
        };
        self.buf.reserve(want);
        // `read_to_end` fills the spare capacity without zeroing it first
        // (a loop of `resize` and `read` zeroed the rest of the chunk after
        // every short read: 1 % of a hair scene's parse and build), and
        // retries interrupted reads.
        match reader.by_ref().take(want as u64).read_to_end(&mut self.buf) {
            // Short of `want` only at the end of the file.
            Ok(n) if n < want => self.reader = None,
            Ok(_) => {}
            Err(e) => {
                self.peak_window = self.peak_window.max(self.buf.capacity());
                return Err(ParseError::new(
                    ErrorKind::CannotRead {
                        path: self.file.path.display().to_string(),
                        message: e.to_string(),
                    },
                    Location::new(self.file.clone(), self.base + self.buf.len()),
                ));
            }
        }
        self.peak_window = self.peak_window.max(self.buf.capacity());
        Ok(())
    }

    /// The next directive, or `None` at the end of the file; `true` with
    /// it when it was written as the deprecated TransformBegin/End.
    pub fn next_directive(&mut self) -> Result<Option<(Located, bool)>, ParseError> {
        loop {
            let outcome = {
                let window = &self.buf[self.pos..];
                let start = lexer::skip_space(window);
                let start_offset = window.len() - start.len();
                let at = |rest: &[u8]| self.base + self.pos + (window.len() - rest.len());
                if start.is_empty() {
                    Outcome::End(start_offset)
                } else {
                    let locate = |rest: &[u8]| Location::new(self.file.clone(), at(rest));
                    match grammar::directive(start, &locate) {
                        Ok((rest, directive)) => {
                            if lexer::skip_space(rest).is_empty() && !self.at_eof() {
                                Outcome::NeedMore
                            } else {
                                Outcome::Directive(
                                    directive,
                                    at(start),
                                    window.len() - rest.len(),
                                    start.starts_with(b"TransformBegin")
                                        || start.starts_with(b"TransformEnd"),
                                )
                            }
                        }
                        Err(_) if !self.at_eof() => Outcome::NeedMore,
                        Err(nom::Err::Error(e) | nom::Err::Failure(e)) => {
                            Outcome::Error(e.kind, at(e.input))
                        }
                        Err(nom::Err::Incomplete(_)) => {
                            Outcome::Error(ErrorKind::UnexpectedEof("more input"), at(&[]))
                        }
                    }
                }
            };
            match outcome {
                Outcome::End(skipped) => {
                    if self.at_eof() {
                        return Ok(None);
                    }
                    self.pos += skipped;
                    self.read_more()?;
                }
                Outcome::NeedMore => self.read_more()?,
                Outcome::Directive(directive, offset, consumed, deprecated) => {
                    self.pos += consumed;
                    let located = Located {
                        directive,
                        location: Location::new(self.file.clone(), offset),
                    };
                    return Ok(Some((located, deprecated)));
                }
                Outcome::Error(kind, offset) => {
                    return Err(ParseError::new(
                        kind,
                        Location::new(self.file.clone(), offset),
                    ))
                }
            }
        }
    }
}

enum Outcome {
    End(usize),
    NeedMore,
    Directive(crate::directive::Directive, usize, usize, bool),
    Error(ErrorKind, usize),
}
