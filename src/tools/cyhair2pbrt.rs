//! `rpbrt cyhair2pbrt IN.hair OUT.pbrt[.gz]`: a file in Cem Yuksel's HAIR
//! format as pbrt-v4 `Shape "curve"`s, to `Include` inside a world block
//! (so pbrt-v4 itself can render the hair the `cyhair` shape draws).
//!
//! The strands go through the `cyhair` shape's own conversion
//! (`shapes::cyhair::for_each_strand`: the same basis, scale and width
//! options), and each becomes `"string basis" "bezier"` curves: one
//! `Shape` of 3n + 1 points per strand when the `curve` shape's linear
//! width0 → width1 gives each of its points its width (always so for a
//! constant thickness, the common file), else one `Shape` per segment
//! with the widths of its two points. Read by rpbrt, the file gives the
//! same curve segments as the `cyhair` shape, bit for bit: every number is
//! written as the shortest decimal that reads back as the same f64 as the
//! f32 the shape uses (rpbrt's parser reads f64; pbrt-v4's reads the same
//! f32). pbrt-v4 computes a curve's inner widths as (1 − t)·w0 + t·w1
//! where rpbrt computes w0 + (w1 − w0)·t: they can differ in the last bit.
//!
//! The output is written to a temporary file beside it and renamed when
//! complete, so a failure never leaves a half-written file; `.gz` is
//! gzip-compressed. A progress bar shows on a terminal for big files.

use crate::error::{Error, Result};
use crate::shapes::cyhair::{self, Basis, Conversion, HairFile, StrandCurves};
use crate::tools::io_error;
use flate2::write::GzEncoder;
use indicatif::ProgressBar;
use pbrt_parser::Location;
use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Writes a CyHair (`.hair`) file's strands as pbrt-v4 `Shape "curve"`s.
#[derive(clap::Args, Debug)]
pub struct Cyhair2pbrtArgs {
    /// The CyHair file to read.
    pub input: PathBuf,
    /// The pbrt file to write (`.gz`: gzip-compressed).
    pub output: PathBuf,
    /// How the points become Bézier segments (the `cyhair` shape's
    /// `basis`).
    #[arg(long, value_enum, default_value_t = BasisArg::Catmullrom)]
    pub basis: BasisArg,
    /// Multiplies the points and the thicknesses.
    #[arg(long, default_value_t = 1.0)]
    pub scale: f64,
    /// Every strand's width, instead of the file's thickness × scale.
    #[arg(long)]
    pub width: Option<f64>,
    /// The curves' `type`.
    #[arg(long = "type", value_enum, default_value_t = TypeArg::Flat)]
    pub kind: TypeArg,
}

/// `--basis`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum BasisArg {
    Catmullrom,
    Polyline,
}

/// `--type` (`ribbon` needs normals a HAIR file has not).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum TypeArg {
    Flat,
    Cylinder,
}

impl TypeArg {
    fn name(self) -> &'static str {
        match self {
            TypeArg::Flat => "flat",
            TypeArg::Cylinder => "cylinder",
        }
    }
}

/// Strands at which a progress bar is worth showing.
const PROGRESS_FROM: usize = 20_000;

/// What was written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Written {
    pub strands: usize,
    /// `Shape` directives (a strand's one, or one per segment).
    pub shapes: usize,
    /// Strands written as one curve each.
    pub whole_strands: usize,
}

pub fn run(args: &Cyhair2pbrtArgs) -> Result<()> {
    let start = Instant::now();
    let conversion = Conversion {
        basis: match args.basis {
            BasisArg::Catmullrom => Basis::CatmullRom,
            BasisArg::Polyline => Basis::Polyline,
        },
        scale: args.scale,
        width: args.width,
    };
    conversion.check().map_err(|e| usage(&e))?;
    let hair = cyhair::read_hair(&args.input, &Location::nowhere()).map_err(plain)?;
    let written = convert(&hair, &conversion, args)?;
    println!(
        "{}: {} strands as {} curves ({} whole, {} a curve per segment) in {:.2} s",
        args.output.display(),
        written.strands,
        written.shapes,
        written.whole_strands,
        written.strands - written.whole_strands,
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn usage(message: &str) -> Error {
    Error::Usage(format!("cyhair2pbrt: {message}"))
}

/// The reader's and the conversion's errors name the file and the byte
/// (or the strand) already; they come from no scene location.
fn plain(e: Error) -> Error {
    match e {
        Error::Scene(e) => usage(&e.message),
        other => other,
    }
}

/// Writes the file: to a temporary beside the output, renamed at the end.
fn convert(hair: &HairFile, conversion: &Conversion, args: &Cyhair2pbrtArgs) -> Result<Written> {
    let output = &args.output;
    let temporary = Temporary::beside(output)?;
    let file = File::create(&temporary.path).map_err(io_error(output))?;
    let gzip = output.extension().is_some_and(|e| e == "gz");
    let bar = super::progress_bar(
        hair.segments.len() as u64,
        "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} strands",
        hair.segments.len() >= PROGRESS_FROM && std::io::stderr().is_terminal(),
    );
    let write_error = |e: std::io::Error| Error::Io {
        path: output.display().to_string(),
        source: e,
    };
    let written = if gzip {
        // Level 1: for 20,000 strands of 64 segments, 2.5 s and 99 MB
        // against 15 s and 82 MB at the default level 6.
        let gz = GzEncoder::new(file, flate2::Compression::fast());
        let mut out = BufWriter::with_capacity(1 << 20, gz);
        let written = write_curves(&mut out, hair, conversion, args, &bar)?;
        out.into_inner()
            .map_err(|e| write_error(e.into_error()))?
            .finish()
            .map_err(write_error)?;
        written
    } else {
        let mut out = BufWriter::with_capacity(1 << 20, file);
        let written = write_curves(&mut out, hair, conversion, args, &bar)?;
        out.flush().map_err(write_error)?;
        written
    };
    bar.finish_and_clear();
    temporary.rename_to(output)?;
    Ok(written)
}

/// The header comment and the curves; a write error names the output.
fn write_curves(
    out: &mut impl Write,
    hair: &HairFile,
    conversion: &Conversion,
    args: &Cyhair2pbrtArgs,
    bar: &ProgressBar,
) -> Result<Written> {
    let output = &args.output;
    let io = |e: std::io::Error| Error::Io {
        path: output.display().to_string(),
        source: e,
    };
    let width = match conversion.width {
        Some(w) => format!("{w} (--width)"),
        None => format!("the file's thickness × {}", conversion.scale),
    };
    write!(
        out,
        "# {} strands ({} points) of the HAIR file \"{}\", written by `rpbrt cyhair2pbrt`:\n\
         # basis {} (as cubic Béziers), scale {}, width {}, type {}.\n\
         # One Shape per strand, or per segment where a strand's widths are not linear along it.\n",
        hair.segments.len(),
        hair.points.len(),
        args.input.display(),
        conversion.basis.name(),
        conversion.scale,
        width,
        args.kind.name(),
    )
    .map_err(io)?;
    let head = format!(
        "Shape \"curve\" \"string type\" [ \"{}\" ] \"string basis\" [ \"bezier\" ]",
        args.kind.name()
    );
    let mut written = Written::default();
    let mut line = String::with_capacity(1 << 12);
    cyhair::for_each_strand(hair, conversion, &Location::nowhere(), |k, strand| {
        line.clear();
        let (count, whole) = shape_lines(&mut line, &head, strand);
        written.strands += 1;
        written.shapes += count;
        written.whole_strands += whole as usize;
        out.write_all(line.as_bytes()).map_err(io)?;
        if k % 1024 == 0 {
            bar.set_position(k as u64);
        }
        Ok(())
    })
    .map_err(plain)?;
    Ok(written)
}

/// A strand's `Shape` lines into `line`: how many, and whether the
/// strand is one curve.
fn shape_lines(line: &mut String, head: &str, strand: &StrandCurves) -> (usize, bool) {
    use std::fmt::Write as _;
    let curve = |line: &mut String, cp: &[[f32; 3]], w0: f32, w1: f32| {
        line.push_str(head);
        line.push_str(" \"point3 P\" [");
        for x in cp.as_flattened() {
            let _ = write!(line, " {}", number(*x));
        }
        if w0.to_bits() == w1.to_bits() {
            let _ = writeln!(line, " ] \"float width\" [ {} ]", number(w0));
        } else {
            let _ = writeln!(
                line,
                " ] \"float width0\" [ {} ] \"float width1\" [ {} ]",
                number(w0),
                number(w1)
            );
        }
    };
    match strand.whole_curve_widths() {
        Some((w0, w1)) => {
            curve(line, &strand.cp, w0, w1);
            (1, true)
        }
        None => {
            let n = strand.segment_count();
            for s in 0..n {
                curve(
                    line,
                    &strand.cp[3 * s..3 * s + 4],
                    strand.widths[s],
                    strand.widths[s + 1],
                );
            }
            (n, false)
        }
    }
}

/// The shortest decimal that reads back as `x` both as an f32 (pbrt-v4)
/// and as an f64 (rpbrt's parser, which then transforms it in f64): the
/// f32's shortest form would read back as a different f64.
fn number(x: f32) -> f64 {
    x as f64
}

/// A temporary file beside the output, removed unless renamed to it.
struct Temporary {
    path: PathBuf,
    renamed: bool,
}

impl Temporary {
    fn beside(output: &Path) -> Result<Temporary> {
        let name = output
            .file_name()
            .ok_or_else(|| usage(&format!("\"{}\" is not a file name", output.display())))?;
        let mut temporary = std::ffi::OsString::from(".");
        temporary.push(name);
        temporary.push(format!(".{}.tmp", std::process::id()));
        Ok(Temporary {
            path: output.with_file_name(temporary),
            renamed: false,
        })
    }

    fn rename_to(mut self, output: &Path) -> Result<()> {
        std::fs::rename(&self.path, output).map_err(io_error(output))?;
        self.renamed = true;
        Ok(())
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if !self.renamed {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every number reads back as the f32 written, as f32 and as f64.
    #[test]
    fn numbers_round_trip() {
        for x in [
            0.1f32,
            1.0 / 3.0,
            -2.5e-8,
            12345.678,
            f32::MAX,
            f32::MIN_POSITIVE,
            0.0,
            -0.0,
        ] {
            let text = number(x).to_string();
            assert_eq!(
                text.parse::<f32>().unwrap().to_bits(),
                x.to_bits(),
                "{text}"
            );
            assert_eq!(text.parse::<f64>().unwrap(), x as f64, "{text}");
        }
    }
}
