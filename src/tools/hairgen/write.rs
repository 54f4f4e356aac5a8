//! The output: pbrt-v4 text, gzip-compressed when the name ends in `.gz`.
//!
//! A header of `#` comments (the recipe as a command line, the seed, the
//! strand and segment counts), then one line per strand:
//!
//! ```text
//! Shape "curve" "string type" "cylinder" "string basis" "bezier" "float width0" [ 0.0005 ] "float width1" [ 0.0002 ] "point3 P" [ x y z ... ]
//! ```
//!
//! with 3n + 1 control points for n cubic Bézier segments (pbrt-v4 makes
//! one curve per segment and interpolates the widths linearly across them:
//! a root-to-tip taper). Positions are written with a fixed number of
//! decimals, a millionth of the hair's extent; widths with four
//! significant digits. The file holds only shapes: `Include` it inside the
//! world block under the material (and transform) the hair should have.

use crate::error::Result;
use crate::tools::io_error;
use flate2::write::GzEncoder;
use glam::DVec3;
use std::fmt::Write as _;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A plain or gzip-compressed output file, written beside its final name
/// (`NAME.partial`) and renamed when complete, so a failed or interrupted
/// run leaves no truncated file under the name asked for.
pub struct Sink {
    stream: Stream,
    partial: PathBuf,
    path: PathBuf,
}

enum Stream {
    Plain(BufWriter<File>),
    Gzip(GzEncoder<BufWriter<File>>),
}

impl Sink {
    pub fn create(path: &Path) -> Result<Self> {
        let mut partial = path.as_os_str().to_owned();
        partial.push(".partial");
        let partial = PathBuf::from(partial);
        let file =
            BufWriter::with_capacity(1 << 20, File::create(&partial).map_err(io_error(path))?);
        let gzip = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
        let stream = if gzip {
            Stream::Gzip(GzEncoder::new(file, flate2::Compression::new(6)))
        } else {
            Stream::Plain(file)
        };
        Ok(Sink {
            stream,
            partial,
            path: path.to_path_buf(),
        })
    }

    pub fn write(&mut self, text: &str) -> Result<()> {
        let result = match &mut self.stream {
            Stream::Plain(w) => w.write_all(text.as_bytes()),
            Stream::Gzip(w) => w.write_all(text.as_bytes()),
        };
        result.map_err(io_error(&self.partial))
    }

    /// Flushes everything (and the gzip trailer) and gives the file its name.
    pub fn finish(self) -> Result<()> {
        let Sink {
            stream,
            partial,
            path,
        } = self;
        let file = match stream {
            Stream::Plain(w) => w,
            Stream::Gzip(w) => w.finish().map_err(io_error(&partial))?,
        };
        file.into_inner()
            .map_err(|e| io_error(&partial)(e.into_error()))?;
        std::fs::rename(&partial, &path).map_err(io_error(&path))
    }

    /// Removes the unfinished file (after an error).
    pub fn abandon(self) {
        drop(self.stream);
        let _ = std::fs::remove_file(&self.partial);
    }
}

/// Decimals that resolve a millionth of `extent`.
pub fn decimals_for(extent: f64) -> usize {
    if !(extent > 0.0 && extent.is_finite()) {
        return 6;
    }
    (5.0 - extent.log10().floor()).clamp(0.0, 15.0) as usize
}

/// Appends `value` with `decimals` decimals, trailing zeros dropped.
pub fn push_number(out: &mut String, value: f64, decimals: usize) {
    let start = out.len();
    let _ = write!(out, "{value:.decimals$}");
    if out[start..].contains('.') {
        let trimmed = out[start..]
            .trim_end_matches('0')
            .trim_end_matches('.')
            .len();
        out.truncate(start + trimmed);
    }
    if &out[start..] == "-0" {
        out.truncate(start);
        out.push('0');
    }
}

/// Appends `value` with `digits` significant digits.
pub fn push_significant(out: &mut String, value: f64, digits: usize) {
    let decimals = if value == 0.0 || !value.is_finite() {
        0
    } else {
        (digits as f64 - 1.0 - value.abs().log10().floor()).clamp(0.0, 20.0) as usize
    };
    push_number(out, value, decimals);
}

/// `value` with six significant digits (the header's recipe).
pub fn short(value: f64) -> String {
    let mut s = String::new();
    push_significant(&mut s, value, 6);
    s
}

/// Appends one strand's `Shape "curve"` line.
pub fn push_curve(out: &mut String, points: &[DVec3], widths: (f64, f64), decimals: usize) {
    out.push_str(
        "Shape \"curve\" \"string type\" \"cylinder\" \"string basis\" \"bezier\" \"float width0\" [ ",
    );
    push_significant(out, widths.0, 4);
    out.push_str(" ] \"float width1\" [ ");
    push_significant(out, widths.1, 4);
    out.push_str(" ] \"point3 P\" [");
    for p in points {
        for c in [p.x, p.y, p.z] {
            out.push(' ');
            push_number(out, c, decimals);
        }
    }
    out.push_str(" ]\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    fn number(v: f64, d: usize) -> String {
        let mut s = String::new();
        push_number(&mut s, v, d);
        s
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(number(1.5, 5), "1.5");
        assert_eq!(number(2.0, 5), "2");
        assert_eq!(number(-0.000001, 5), "0");
        assert_eq!(number(-1.234567, 3), "-1.235");
        assert_eq!(number(1234.0, 0), "1234");
        let mut s = String::new();
        push_significant(&mut s, 0.000123456, 4);
        assert_eq!(s, "0.0001235");
        assert_eq!(short(0.0123967998), "0.0123968");
        assert_eq!(short(-2.5), "-2.5");
        assert_eq!(decimals_for(1.0), 5);
        assert_eq!(decimals_for(0.2), 6);
        assert_eq!(decimals_for(30.0), 4);
    }

    #[test]
    fn a_curve_line_has_its_points_and_widths() {
        let mut s = String::new();
        push_curve(
            &mut s,
            &[DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            (0.01, 0.002),
            4,
        );
        assert_eq!(
            s,
            "Shape \"curve\" \"string type\" \"cylinder\" \"string basis\" \"bezier\" \"float width0\" [ 0.01 ] \"float width1\" [ 0.002 ] \"point3 P\" [ 0 0 0 1 0 0 0 1 0 0 0 1 ]\n"
        );
    }
}
