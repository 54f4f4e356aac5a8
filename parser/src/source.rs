//! One scene file being read: a window of its text, refilled as the parser
//! moves on, so that a huge file is never held whole in memory.
//!
//! The grammar runs on complete input. A directive is accepted only when the
//! text after it (past space and comments) is not the end of the window, so a
//! number or string cut by the window's edge is never taken for a whole one;
//! otherwise the window grows (doubling, so re-parsing stays linear) and the
//! directive is parsed again.
//!
//! With two threads or more (rayon's pool), the window's text is cut into
//! segments at lines that begin with a directive's keyword and the
//! segments are parsed at once, two per thread ([`Source::parse_ahead`]).
//! A line's start is never inside a comment, and inside a string only after
//! a backslash-newline; a capitalised bare word there can only be a
//! directive. Each segment is parsed as a whole text. Its directives are
//! kept only if it parses without error and every segment before it did:
//! then its start was a directive's start in the file read in order, and
//! its directives are the ones that reading gives (a directive ends where
//! the next keyword or the segment's end begins, alike). From the first
//! segment that fails, the file is read in order as before, so that a bad
//! file reports the same first error at the same place.

use crate::directive::Located;
use crate::error::{ErrorKind, ParseError};
use crate::grammar;
use crate::lexer;
use crate::location::{Location, SourceFile};
use rayon::prelude::*;
use std::collections::VecDeque;
use std::io::{BufReader, Read};
use std::path::Path;
use std::sync::Arc;

/// Bytes read at a time.
const CHUNK: usize = 1 << 20;

/// The text a segment of a parallel parse holds, at least (it ends at the
/// next directive's line): a few milliseconds of work, so that rayon's
/// hand-off costs nothing beside it.
const SEGMENT: usize = 1 << 18;

/// Segments parsed at once per thread: two, so that a thread with a slow
/// segment holds the others up less.
const SEGMENTS_PER_THREAD: usize = 2;

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
    /// Directives parsed ahead from whole segments, the file's next ones.
    ahead: VecDeque<(Located, bool)>,
    /// The file offset up to which directives are read in order: the end
    /// of a window that held too little for segments (so that it is not
    /// searched for them again before every directive), or the end of
    /// everything once a segment failed.
    in_order_until: usize,
    /// The vectors segments are parsed into, kept from one group to the
    /// next: made afresh, each was mapped and unmapped per group, and that
    /// held the process's memory-map lock while the other threads faulted.
    segment_directives: Vec<Vec<(Located, bool)>>,
    /// Directives read from segments parsed in parallel (for tests).
    #[cfg(test)]
    from_segments: usize,
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
        Ok(Self::new(file.clone(), Some(reader), Vec::new()))
    }

    pub fn from_text(file: Arc<SourceFile>, text: Vec<u8>) -> Self {
        Self::new(file, None, text)
    }

    /// A source whose window holds `text`, then what `reader` gives.
    fn new(file: Arc<SourceFile>, reader: Option<Box<dyn Read + Send>>, text: Vec<u8>) -> Self {
        Source {
            file,
            reader,
            peak_window: text.len(),
            buf: text,
            pos: 0,
            base: 0,
            ahead: VecDeque::new(),
            in_order_until: 0,
            segment_directives: Vec::new(),
            #[cfg(test)]
            from_segments: 0,
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
        if self.ahead.is_empty() {
            self.parse_ahead()?;
        }
        if let Some(next) = self.ahead.pop_front() {
            return Ok(Some(next));
        }
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
                                    deprecated(start),
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

impl Source {
    /// Parses the window's next segments at once (see the module's doc)
    /// into `ahead`. Leaves `ahead` empty where the next directive is to
    /// be read in order: one thread, a failed segment, less than two
    /// segments' text left at the end of the file, or a directive longer
    /// than the window.
    fn parse_ahead(&mut self) -> Result<(), ParseError> {
        if self.base + self.pos < self.in_order_until || rayon::current_num_threads() < 2 {
            return Ok(());
        }
        let Some(cuts) = self.cut_segments()? else {
            return Ok(());
        };
        let segments = cuts.len() - 1;
        if self.segment_directives.len() < segments {
            self.segment_directives.resize_with(segments, Vec::new);
        }
        let (text, start, file) = (&self.buf[self.pos..], self.base + self.pos, &self.file);
        let parsed: Vec<bool> = self.segment_directives[..segments]
            .par_iter_mut()
            .zip(cuts.par_windows(2))
            .map(|(directives, w)| parse_segment(&text[w[0]..w[1]], start + w[0], file, directives))
            .collect();
        for (k, parsed) in parsed.into_iter().enumerate() {
            if !parsed {
                // Read on in order from this segment's start.
                self.pos += cuts[k];
                self.in_order_until = usize::MAX;
                self.segment_directives = Vec::new();
                return Ok(());
            }
            #[cfg(test)]
            {
                self.from_segments += self.segment_directives[k].len();
            }
            self.ahead.extend(self.segment_directives[k].drain(..));
        }
        self.pos += cuts[cuts.len() - 1];
        Ok(())
    }

    /// Where the window's next text is cut into segments (offsets from
    /// `pos`, the first 0): about two segments per thread, read first
    /// when the window holds less; `None` where there are not two.
    fn cut_segments(&mut self) -> Result<Option<Vec<usize>>, ParseError> {
        let group = rayon::current_num_threads() * SEGMENTS_PER_THREAD * SEGMENT;
        while self.buf.len() - self.pos < group && !self.at_eof() {
            self.read_more()?;
        }
        let text = &self.buf[self.pos..];
        let mut cuts = vec![0];
        let mut from = SEGMENT;
        while from < text.len() {
            let Some(cut) = directive_line_at_or_after(text, from) else {
                break;
            };
            cuts.push(cut);
            from = cut + SEGMENT;
        }
        // The last segment runs to the end of the file, or, before it, to
        // the last cut (the rest is read with the next window).
        if self.at_eof() {
            cuts.push(text.len());
        }
        if cuts.len() < 3 {
            self.in_order_until = self.base + self.buf.len();
            return Ok(None);
        }
        Ok(Some(cuts))
    }
}

/// The first position at or after `from` that begins a line's first word
/// when that word is capitalised (a directive's keyword), past the line's
/// indentation. `ActiveTransform`'s arguments are skipped: they are the
/// capitalised words that are not directives.
fn directive_line_at_or_after(text: &[u8], from: usize) -> Option<usize> {
    let mut at = from;
    loop {
        let newline = at + text.get(at..)?.iter().position(|&b| b == b'\n')?;
        let indented = &text[newline + 1..];
        let word_start = newline
            + 1
            + indented
                .iter()
                .take_while(|&&b| b == b' ' || b == b'\t')
                .count();
        let line = &text[word_start..];
        let argument = [&b"StartTime"[..], b"EndTime", b"All"].iter().any(|w| {
            line.starts_with(w) && line.get(w.len()).is_none_or(|&b| lexer::is_delimiter(b))
        });
        if line.first().is_some_and(u8::is_ascii_uppercase) && !argument {
            return Some(word_start);
        }
        at = newline + 1;
    }
}

/// Whether the directive at the start of `text` is written with a
/// deprecated name (TransformBegin/End).
fn deprecated(text: &[u8]) -> bool {
    text.starts_with(b"TransformBegin") || text.starts_with(b"TransformEnd")
}

/// Reads the directives of a segment that starts with one, as a whole
/// text (`offset`: its place in the file), into `directives` (emptied
/// first); `false` at any error.
fn parse_segment(
    text: &[u8],
    offset: usize,
    file: &Arc<SourceFile>,
    directives: &mut Vec<(Located, bool)>,
) -> bool {
    directives.clear();
    let mut rest = lexer::skip_space(text);
    while !rest.is_empty() {
        let at = |r: &[u8]| offset + (text.len() - r.len());
        let locate = |r: &[u8]| Location::new(file.clone(), at(r));
        let Ok((after, directive)) = grammar::directive(rest, &locate) else {
            return false;
        };
        directives.push((
            Located {
                directive,
                location: Location::new(file.clone(), at(rest)),
            },
            deprecated(rest),
        ));
        rest = lexer::skip_space(after);
    }
    true
}

enum Outcome {
    End(usize),
    NeedMore,
    Directive(crate::directive::Directive, usize, usize, bool),
    Error(ErrorKind, usize),
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every directive of `text` as `Debug` prints it (its parameters'
    /// locations too) with its offset, then the error and its offset if
    /// there is one, read with `threads` threads; and how many directives
    /// came from segments parsed in parallel.
    fn read(text: &[u8], threads: usize) -> (Vec<String>, usize) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let file = SourceFile::in_memory("<test>", Arc::from(text));
            let mut source = Source::from_text(file, text.to_vec());
            let mut out = Vec::new();
            loop {
                match source.next_directive() {
                    Ok(Some((d, deprecated))) => out.push(format!(
                        "{:?} at {} {deprecated}",
                        d.directive, d.location.offset
                    )),
                    Ok(None) => break,
                    Err(e) => {
                        out.push(format!("error {:?} at {}", e.kind, e.location.offset));
                        break;
                    }
                }
            }
            (out, source.from_segments)
        })
    }

    /// A scene text of about `size` bytes that uses what could mislead a
    /// cut: directives over several lines, indentation, comments naming
    /// directives, `ActiveTransform`'s capitalised arguments on their own
    /// line, a string continued by a backslash-newline onto a line that
    /// starts with a keyword, bare bools, deprecated names.
    fn scene(size: usize) -> String {
        let mut text = String::from("WorldBegin\n");
        let mut i = 0u32;
        while text.len() < size {
            let x = f64::from(i) * 0.001;
            text.push_str(&match i % 9 {
                0 => format!("AttributeBegin\n  Translate {x} 2 3\n"),
                1 => format!(
                    "Shape \"curve\" \"point3 P\" [ {x} 1 2 3 4 5 6 7 8 9 10 11 ] \"float width\" [ 0.01 ]\n"
                ),
                2 => format!(
                    "Shape \"trianglemesh\"\n    \"point3 P\" [ 0 0 {x}\n 1 0 0\n 0 1 0 ]\n    \"integer indices\" [ 0 1 2 ]\n"
                ),
                3 => "# Shape \"sphere\" in a comment\nAttributeEnd\n".to_string(),
                4 => "ActiveTransform\nStartTime\nActiveTransform\n  All\n".to_string(),
                5 => format!("Texture \"t{i}\" \"spectrum\" \"imagemap\" \"string filename\" \"a\\\nShape b.png\"\n"),
                6 => "TransformBegin\nTransformEnd\n".to_string(),
                7 => "MakeNamedMaterial \"m\"\n  \"bool remaproughness\"\n  true \"string type\" \"coateddiffuse\"\n".to_string(),
                _ => format!("\tShape \"sphere\" \"float radius\" {x}\n"),
            });
            i += 1;
        }
        text
    }

    #[test]
    fn segments_read_as_the_file_read_in_order() {
        let text = scene(3 * (1 << 20));
        let (in_order, none) = read(text.as_bytes(), 1);
        assert_eq!(none, 0);
        assert!(
            !in_order.last().unwrap().starts_with("error"),
            "{:?}",
            in_order.last()
        );
        for threads in [2, 4, 7] {
            let (parallel, from_segments) = read(text.as_bytes(), threads);
            assert!(
                from_segments > in_order.len() / 2,
                "{threads} threads: {from_segments} of {} from segments",
                in_order.len()
            );
            assert!(parallel == in_order, "{threads} threads");
        }
    }

    #[test]
    fn errors_are_those_of_the_file_read_in_order() {
        let text = scene(3 * (1 << 20) / 2);
        let bad = [
            "Shape \"sphere\" \"float radius\" [ 1 2x ]\n",
            "Foo 1 2\n",
            "Shape \"sphere\" \"float radius\"\n",
            "\"float orphan\" 1\n",
            "Translate 1 2\n",
            "Shape \"x\" \"float a\" [ 1 2\n",
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"unterminated\n",
            "ActiveTransform\nShape \"sphere\"\n",
        ];
        // At line starts spread over the text, several near where
        // segments are cut.
        let lines: Vec<usize> = text.match_indices('\n').map(|(at, _)| at + 1).collect();
        let mut positions: Vec<usize> = (1..12).map(|k| lines[k * lines.len() / 12]).collect();
        for cut in [SEGMENT, 2 * SEGMENT, 4 * SEGMENT] {
            let after = lines.partition_point(|&l| l < cut);
            positions.extend(&lines[after.saturating_sub(2)..(after + 2).min(lines.len())]);
        }
        let mut errors = 0;
        for (k, &at) in positions.iter().enumerate() {
            let error = bad[k % bad.len()];
            let mut broken = text.clone();
            broken.insert_str(at, error);
            let (in_order, _) = read(broken.as_bytes(), 1);
            // (A parameter after a directive's is one of its own.)
            errors += usize::from(in_order.last().unwrap().starts_with("error"));
            let (parallel, _) = read(broken.as_bytes(), 4);
            assert!(parallel == in_order, "{error:?} at {at}");
        }
        assert!(errors + 4 > positions.len(), "{errors} errors");
    }
}
