//! rpbrt's `cyhair` shape: the strands of a file in Cem Yuksel's binary
//! HAIR format (the format of the public hair models pbrt-v4's hair scenes
//! are made from; pbrt-v4 issue #237), read when the scene is built and
//! drawn as curves (see `curve`). Not a pbrt-v4 shape.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `filename` | string | — (required) | the `.hair` file, relative to the scene file |
//! | `scale` | float | 1 | multiplies the file's points (and its thicknesses) |
//! | `width` | float | the file's | the strands' width in scene units, overriding the file's thickness (else thickness × `scale`) |
//! | `type` | string | "flat" | `flat` or `cylinder`, as for `curve` (`ribbon` needs normals a HAIR file has not: an error) |
//! | `basis` | string | "catmullrom" | `catmullrom`: a Catmull-Rom spline through each strand's points (end tangents from mirrored end points), converted to cubic Béziers, one per file segment; `polyline`: each file segment as a straight cubic Bézier between its two points |
//! | `splitdepth` | integer | 3 | each segment is split into 2^splitdepth pieces for the BVH, as for `curve` |
//!
//! Widths are object-space lengths, scaled by the transform as `curve`'s;
//! each Bézier segment takes the widths of its two file points. The file's
//! transparency and colour arrays are read and checked but not used: the
//! material decides the strands' colour (rpbrt's hair material takes one
//! colour per shape; to colour strands from the file, convert it with
//! `cyhair2pbrt` and give each strand's `Shape` its own material).
//!
//! **Strands.** The geometry is [`for_each_strand`]'s, which
//! `rpbrt cyhair2pbrt` writes as pbrt-v4 curves too: each strand's Bézier
//! control points in object space, rounded to f32 once, and its widths,
//! taken as the `curve` shape takes a curve's (one curve per strand when
//! linear along it, else one per segment), so the converted file builds
//! the same segments bit for bit. Each strand starts a strand of its own
//! (`CurveSegment::strand_start`): a material that orients an elliptical
//! fibre (`ShapeStorage::set_fibre_frames`) gives it its own transported
//! frame, and with `ellipse_random` its own angle (`strand_angle` of the
//! directive's offset and the strand's index in the file).
//!
//! **The format** (little-endian): a 128-byte header: `"HAIR"`, u32 hair
//! (strand) count, u32 point count, u32 flags (bit 0: segments array, 1:
//! points, 2: thickness, 3: transparency, 4: colour), u32 default segments
//! (per strand when there is no segments array), f32 default thickness,
//! f32 default transparency, 3 × f32 default colour, 88 bytes of text.
//! Then, each only when its flag is set: u16 segments[hair count], f32
//! points[3 × point count], f32 thickness[point count], f32
//! transparency[point count], f32 colour[3 × point count]. A strand of s
//! segments has s + 1 points; they must add up to the point count. The
//! file's length is checked against the header's sizes before any array is
//! read (a corrupt header allocates nothing), the arrays are read in
//! chunks, and every error (a missing file, a bad magic, a short header, a
//! truncated array, counts that disagree, a non-finite value) names the
//! file, the byte offset and what was expected, at the `filename`
//! parameter's `file:line:col`.

use super::curve::splines::{catmull_rom_to_bezier, line_to_cubic_bezier};
use super::curve::{self, CurvePiece, CurveSegment, CurveType};
use crate::error::{scene_error, unreadable_file, Error, Result, SceneError};
use crate::math::Transform;
use crate::scene_description;
use glam::DVec3;
use pbrt_parser::{Location, ParamType};
use std::io::{BufReader, Read};
use std::path::Path;

/// Size of the HAIR header.
const HEADER_BYTES: u64 = 128;

const HAS_SEGMENTS: u32 = 1;
const HAS_POINTS: u32 = 2;
const HAS_THICKNESS: u32 = 4;
const HAS_TRANSPARENCY: u32 = 8;
const HAS_COLOUR: u32 = 16;

/// The contents of a HAIR file.
#[derive(Clone, Debug, PartialEq)]
pub struct HairFile {
    /// Segments of each strand (a strand of s segments has s + 1 points).
    pub segments: Vec<u32>,
    /// All strands' points, strand after strand.
    pub points: Vec<[f32; 3]>,
    /// Thickness per point; `None`: `default_thickness` for all.
    pub thickness: Option<Vec<f32>>,
    pub default_thickness: f32,
    pub transparency: Option<Vec<f32>>,
    pub default_transparency: f32,
    pub colour: Option<Vec<[f32; 3]>>,
    pub default_colour: [f32; 3],
}

impl HairFile {
    pub fn thickness_at(&self, point: usize) -> f32 {
        self.thickness
            .as_ref()
            .map_or(self.default_thickness, |t| t[point])
    }
}

/// An error about the file at `path`, at byte `offset`.
fn file_error(path: &Path, offset: u64, message: impl std::fmt::Display, loc: &Location) -> Error {
    SceneError::new(
        format!("cyhair: \"{}\": byte {offset}: {message}", path.display()),
        loc,
    )
    .into()
}

/// The arrays the header announces, in file order: (name, bytes).
fn arrays(hair_count: u32, point_count: u32, flags: u32) -> Vec<(&'static str, u64)> {
    let (h, p) = (hair_count as u64, point_count as u64);
    [
        ("segments", HAS_SEGMENTS, 2 * h),
        ("points", HAS_POINTS, 12 * p),
        ("thickness", HAS_THICKNESS, 4 * p),
        ("transparency", HAS_TRANSPARENCY, 4 * p),
        ("colour", HAS_COLOUR, 12 * p),
    ]
    .into_iter()
    .filter(|(_, flag, _)| flags & flag != 0)
    .map(|(name, _, bytes)| (name, bytes))
    .collect()
}

/// Reads a HAIR file. Errors name the file and the byte offset and point
/// at `loc` (the parameter that names the file).
pub fn read_hair(path: &Path, loc: &Location) -> Result<HairFile> {
    let unreadable = |source: &dyn std::fmt::Display| unreadable_file("cyhair", path, source, loc);
    let file = std::fs::File::open(path).map_err(|e| unreadable(&e))?;
    let length = file.metadata().map_err(|e| unreadable(&e))?.len();
    read_hair_from(BufReader::with_capacity(1 << 16, file), length, path, loc)
}

/// Reads the bytes of a HAIR file held in memory, exactly as [`read_hair`]
/// reads a file (`path` only names it in errors). For fuzzing and tests.
pub fn read_hair_bytes(bytes: &[u8], path: &Path, loc: &Location) -> Result<HairFile> {
    read_hair_from(bytes, bytes.len() as u64, path, loc)
}

/// Reads a HAIR file of `length` bytes from `source`.
fn read_hair_from(source: impl Read, length: u64, path: &Path, loc: &Location) -> Result<HairFile> {
    let mut reader = Reader {
        inner: source,
        offset: 0,
        path,
        loc,
    };
    if length < HEADER_BYTES {
        return Err(file_error(
            path,
            length,
            format!("the file ends inside the header (expected a {HEADER_BYTES}-byte header, the file has {length} bytes)"),
            loc,
        ));
    }
    let mut header = [0u8; HEADER_BYTES as usize];
    reader.read(&mut header, "the header")?;
    if &header[0..4] != b"HAIR" {
        return Err(file_error(
            path,
            0,
            format!(
                "expected the magic \"HAIR\", found {:?} (not a HAIR file)",
                String::from_utf8_lossy(&header[0..4])
            ),
            loc,
        ));
    }
    let u32_at = |i: usize| u32::from_le_bytes(header[i..i + 4].try_into().unwrap());
    let f32_at = |i: usize| f32::from_le_bytes(header[i..i + 4].try_into().unwrap());
    let (hair_count, point_count, flags) = (u32_at(4), u32_at(8), u32_at(12));
    let default_segments = u32_at(16);
    let default_thickness = f32_at(20);
    let default_transparency = f32_at(24);
    let default_colour = [f32_at(28), f32_at(32), f32_at(36)];
    for (i, (what, value)) in [
        ("default thickness", default_thickness),
        ("default transparency", default_transparency),
        ("default colour (red)", default_colour[0]),
        ("default colour (green)", default_colour[1]),
        ("default colour (blue)", default_colour[2]),
    ]
    .into_iter()
    .enumerate()
    {
        if !value.is_finite() {
            return Err(file_error(
                path,
                20 + 4 * i as u64,
                format!("expected a finite {what}, found {value}"),
                loc,
            ));
        }
    }
    if flags & HAS_POINTS == 0 {
        return Err(file_error(
            path,
            12,
            format!("expected a points array (flags bit 1), found flags {flags:#x}"),
            loc,
        ));
    }
    // The file's length against the header's sizes, before any array is
    // allocated.
    let mut end = HEADER_BYTES;
    for (name, bytes) in arrays(hair_count, point_count, flags) {
        let start = end;
        end += bytes;
        if length < end {
            return Err(file_error(
                path,
                length,
                format!(
                    "the file ends inside the {name} array (bytes {start}–{end}; the header's {hair_count} strands and {point_count} points need {} bytes, the file has {length})",
                    total_length(hair_count, point_count, flags)
                ),
                loc,
            ));
        }
    }
    if length > end {
        return Err(file_error(
            path,
            end,
            format!(
                "expected the end of the file after the header's {hair_count} strands and {point_count} points, found {} more bytes",
                length - end
            ),
            loc,
        ));
    }

    let segments: Vec<u32> = if flags & HAS_SEGMENTS != 0 {
        let start = reader.offset;
        let segments = reader.values::<2, u32>(hair_count as usize, "segments", |b| {
            u16::from_le_bytes(b) as u32
        })?;
        let total: u64 = segments.iter().map(|&s| s as u64 + 1).sum();
        if total != point_count as u64 {
            return Err(file_error(
                path,
                start,
                format!("the strands' segments need {total} points (each strand of s segments has s + 1), the header says {point_count}"),
                loc,
            ));
        }
        segments
    } else {
        let total = hair_count as u64 * (default_segments as u64 + 1);
        if total != point_count as u64 {
            return Err(file_error(
                path,
                16,
                format!("{hair_count} strands of {default_segments} segments (the default; no segments array) need {total} points, the header says {point_count}"),
                loc,
            ));
        }
        vec![default_segments; hair_count as usize]
    };
    let n = point_count as usize;
    let points = reader.finite_triples(n, "points")?;
    let thickness = if flags & HAS_THICKNESS != 0 {
        let start = reader.offset;
        let thickness = reader.finite_floats(n, "thickness")?;
        if let Some(i) = thickness.iter().position(|&t| t < 0.0) {
            return Err(file_error(
                path,
                start + 4 * i as u64,
                format!("expected a thickness ≥ 0, found {}", thickness[i]),
                loc,
            ));
        }
        Some(thickness)
    } else {
        None
    };
    let transparency = if flags & HAS_TRANSPARENCY != 0 {
        Some(reader.finite_floats(n, "transparency")?)
    } else {
        None
    };
    let colour = if flags & HAS_COLOUR != 0 {
        Some(reader.finite_triples(n, "colour")?)
    } else {
        None
    };
    Ok(HairFile {
        segments,
        points,
        thickness,
        default_thickness,
        transparency,
        default_transparency,
        colour,
        default_colour,
    })
}

/// The bytes of a HAIR file holding `hair` (what [`read_hair`] reads back
/// as `hair`): its optional arrays where present, and a segments array
/// unless `segments_array` is false, when every strand must have the same
/// number of segments (the header's default). For tests and tools that
/// make hair; `Err` says why `hair` cannot be written (a strand of more
/// than 65,535 segments, counts that disagree).
pub fn hair_bytes(hair: &HairFile, segments_array: bool) -> std::result::Result<Vec<u8>, String> {
    let too_many = || "a HAIR file holds at most 2³² − 1 strands and points".to_string();
    let hair_count = u32::try_from(hair.segments.len()).map_err(|_| too_many())?;
    let point_count = u32::try_from(hair.points.len()).map_err(|_| too_many())?;
    let needed: u64 = hair.segments.iter().map(|&s| s as u64 + 1).sum();
    if needed != point_count as u64 {
        return Err(format!(
            "the strands' segments need {needed} points, there are {point_count}"
        ));
    }
    let per_point = |name: &str, len: Option<usize>| match len {
        Some(len) if len != hair.points.len() => Err(format!(
            "the {name} array has {len} values for {point_count} points"
        )),
        _ => Ok(()),
    };
    per_point("thickness", hair.thickness.as_ref().map(Vec::len))?;
    per_point("transparency", hair.transparency.as_ref().map(Vec::len))?;
    per_point("colour", hair.colour.as_ref().map(Vec::len))?;
    let default_segments = if segments_array {
        0
    } else {
        let first = hair.segments.first().copied().unwrap_or(0);
        if hair.segments.iter().any(|&s| s != first) {
            return Err("strands of different segment counts need a segments array".into());
        }
        first
    };
    if segments_array && hair.segments.iter().any(|&s| s > u16::MAX as u32) {
        return Err("a strand of the segments array has at most 65,535 segments".into());
    }
    let flags = [
        (segments_array, HAS_SEGMENTS),
        (true, HAS_POINTS),
        (hair.thickness.is_some(), HAS_THICKNESS),
        (hair.transparency.is_some(), HAS_TRANSPARENCY),
        (hair.colour.is_some(), HAS_COLOUR),
    ]
    .iter()
    .filter(|(on, _)| *on)
    .fold(0, |flags, (_, flag)| flags | flag);
    let mut b = Vec::with_capacity(total_length(hair_count, point_count, flags) as usize);
    b.extend_from_slice(b"HAIR");
    for v in [hair_count, point_count, flags, default_segments] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    let floats =
        |b: &mut Vec<u8>, v: &[f32]| v.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    floats(&mut b, &[hair.default_thickness, hair.default_transparency]);
    floats(&mut b, &hair.default_colour);
    // The 88 bytes of file information: text, zero-padded.
    b.extend_from_slice(b"written by rpbrt");
    b.resize(HEADER_BYTES as usize, 0);
    if segments_array {
        for &s in &hair.segments {
            b.extend_from_slice(&(s as u16).to_le_bytes());
        }
    }
    floats(&mut b, hair.points.as_flattened());
    if let Some(t) = &hair.thickness {
        floats(&mut b, t);
    }
    if let Some(t) = &hair.transparency {
        floats(&mut b, t);
    }
    if let Some(c) = &hair.colour {
        floats(&mut b, c.as_flattened());
    }
    Ok(b)
}

/// The file length a header announces.
fn total_length(hair_count: u32, point_count: u32, flags: u32) -> u64 {
    HEADER_BYTES
        + arrays(hair_count, point_count, flags)
            .iter()
            .map(|(_, bytes)| bytes)
            .sum::<u64>()
}

/// A file read in order, knowing its offset for errors.
struct Reader<'a, R: Read> {
    inner: R,
    offset: u64,
    path: &'a Path,
    loc: &'a Location,
}

impl<R: Read> Reader<'_, R> {
    fn read(&mut self, buffer: &mut [u8], what: &str) -> Result<()> {
        self.inner.read_exact(buffer).map_err(|e| {
            file_error(
                self.path,
                self.offset,
                format!("cannot read {what}: {e}"),
                self.loc,
            )
        })?;
        self.offset += buffer.len() as u64;
        Ok(())
    }

    /// `count` values of `N` bytes each, read in chunks.
    fn values<const N: usize, T>(
        &mut self,
        count: usize,
        what: &str,
        convert: impl Fn([u8; N]) -> T,
    ) -> Result<Vec<T>> {
        // The file's length was checked against `count`.
        let mut values = Vec::with_capacity(count);
        let mut buffer = vec![0u8; N * 8192];
        let mut left = count;
        while left > 0 {
            let chunk = left.min(8192);
            let bytes = &mut buffer[..N * chunk];
            self.read(bytes, &format!("the {what} array"))?;
            values.extend(
                bytes
                    .chunks_exact(N)
                    .map(|b| convert(b.try_into().unwrap())),
            );
            left -= chunk;
        }
        Ok(values)
    }

    /// `count` finite f32s.
    fn finite_floats(&mut self, count: usize, what: &str) -> Result<Vec<f32>> {
        let start = self.offset;
        let values = self.values::<4, f32>(count, what, f32::from_le_bytes)?;
        self.check_finite(start, &values, what, 1)?;
        Ok(values)
    }

    /// `count` triples of finite f32s.
    fn finite_triples(&mut self, count: usize, what: &str) -> Result<Vec<[f32; 3]>> {
        let start = self.offset;
        let values = self.values::<12, [f32; 3]>(count, what, |b| {
            let f = |i: usize| f32::from_le_bytes(b[i..i + 4].try_into().unwrap());
            [f(0), f(4), f(8)]
        })?;
        self.check_finite(start, values.as_flattened(), what, 3)?;
        Ok(values)
    }

    fn check_finite(&self, start: u64, values: &[f32], what: &str, per_point: usize) -> Result<()> {
        match values.iter().position(|v| !v.is_finite()) {
            Some(i) => Err(file_error(
                self.path,
                start + 4 * i as u64,
                format!(
                    "expected a finite number in the {what} array (point {}), found {}",
                    i / per_point,
                    values[i]
                ),
                self.loc,
            )),
            None => Ok(()),
        }
    }
}

/// How a strand's points become Bézier segments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// Each file segment as a straight cubic Bézier between its points.
    Polyline,
    /// A Catmull-Rom spline through the points (end tangents from mirrored
    /// end points), as one cubic Bézier per file segment.
    CatmullRom,
}

impl Basis {
    /// The basis by its parameter name (`polyline`, `catmullrom`).
    pub fn from_name(name: &str) -> Option<Basis> {
        match name {
            "polyline" => Some(Basis::Polyline),
            "catmullrom" => Some(Basis::CatmullRom),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Basis::Polyline => "polyline",
            Basis::CatmullRom => "catmullrom",
        }
    }
}

/// How a HAIR file's points and thicknesses become curves: the `cyhair`
/// shape's `basis`, `scale` and `width`, and `cyhair2pbrt`'s options of
/// the same names (both convert through [`for_each_strand`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conversion {
    pub basis: Basis,
    /// Multiplies the points (and the thicknesses, unless `width`).
    pub scale: f64,
    /// Every strand's width (object space), instead of thickness × scale.
    pub width: Option<f64>,
}

impl Conversion {
    /// Why the scale or the width cannot be used, if so (the caller says
    /// where).
    pub fn check(&self) -> std::result::Result<(), String> {
        if !self.scale.is_finite() || self.scale <= 0.0 {
            return Err(format!("cyhair \"scale\" must be > 0, not {}", self.scale));
        }
        if let Some(w) = self.width {
            if !w.is_finite() || w < 0.0 {
                return Err(format!("cyhair \"width\" must be ≥ 0, not {w}"));
            }
        }
        Ok(())
    }
}

/// One strand as cubic Bézier segments in object space, what both the
/// `cyhair` shape and `cyhair2pbrt` draw. Single precision, as a pbrt file
/// stores it: the shape transforms exactly these values, so a converted
/// file that carries them exactly renders the same geometry bit for bit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StrandCurves {
    /// The 3n + 1 control points of the strand's n segments (consecutive
    /// segments share an end point, as in a pbrt-v4 Bézier curve).
    pub cp: Vec<[f32; 3]>,
    /// The width at each of the strand's n + 1 file points.
    pub widths: Vec<f32>,
}

impl StrandCurves {
    pub fn segment_count(&self) -> usize {
        self.widths.len().saturating_sub(1)
    }

    /// Segment `s`'s four control points.
    pub fn segment(&self, s: usize) -> [[f32; 3]; 4] {
        [
            self.cp[3 * s],
            self.cp[3 * s + 1],
            self.cp[3 * s + 2],
            self.cp[3 * s + 3],
        ]
    }

    /// `Some((width0, width1))` when one pbrt-v4 curve over all the
    /// strand's segments gives every file point its width (a curve's
    /// widths are linear in the segment index: always so for a constant
    /// thickness); `None`: the strand needs a curve per segment, each with
    /// the widths of its two points.
    pub fn whole_curve_widths(&self) -> Option<(f32, f32)> {
        let n = self.segment_count();
        let (w0, w1) = (*self.widths.first()?, *self.widths.last()?);
        (0..n)
            .all(|s| curve::segment_widths(w0, w1, s, n) == [self.widths[s], self.widths[s + 1]])
            .then_some((w0, w1))
    }

    /// Segment `s`'s widths as the strand's curve, or its own curve, gives
    /// them (`whole`: [`Self::whole_curve_widths`]), computed as the
    /// `curve` shape computes them.
    pub fn segment_widths(&self, s: usize, whole: Option<(f32, f32)>) -> [f32; 2] {
        match whole {
            Some((w0, w1)) => curve::segment_widths(w0, w1, s, self.segment_count()),
            None => curve::segment_widths(self.widths[s], self.widths[s + 1], 0, 1),
        }
    }
}

/// Calls `each(k, curves)` for each strand k of `hair` (numbered in file
/// order) that has a segment; a strand of one point draws nothing. An
/// error at `loc` if the scale takes a point or a width past single
/// precision.
pub fn for_each_strand(
    hair: &HairFile,
    conversion: &Conversion,
    loc: &Location,
    mut each: impl FnMut(usize, &StrandCurves) -> Result<()>,
) -> Result<()> {
    let scale = conversion.scale;
    let point = |i: usize| DVec3::from(hair.points[i].map(|x| x as f64)) * scale;
    let width_at = |i: usize| {
        (conversion
            .width
            .unwrap_or_else(|| hair.thickness_at(i) as f64 * scale)) as f32
    };
    let mut strand = StrandCurves::default();
    let mut first = 0usize;
    for (k, &strand_segments) in hair.segments.iter().enumerate() {
        let n = strand_segments as usize;
        let last = first + n;
        strand.cp.clear();
        strand.widths.clear();
        // Catmull-Rom tangents (the points' central differences, halved),
        // with mirrored points beyond the ends.
        let at = |j: isize| -> DVec3 {
            if j < 0 {
                2.0 * point(first) - point(first + 1)
            } else if j as usize > n {
                2.0 * point(last) - point(last - 1)
            } else {
                point(first + j as usize)
            }
        };
        for s in 0..n {
            let (p0, p1) = (point(first + s), point(first + s + 1));
            let bez = match conversion.basis {
                Basis::Polyline => line_to_cubic_bezier(p0, p1),
                Basis::CatmullRom => {
                    let j = s as isize;
                    catmull_rom_to_bezier(at(j - 1), p0, p1, at(j + 2))
                }
            };
            // Consecutive segments share the end point.
            let from = if s == 0 { 0 } else { 1 };
            strand
                .cp
                .extend(bez[from..].iter().map(|q| q.as_vec3().to_array()));
        }
        if n > 0 {
            strand.widths.extend((first..=last).map(width_at));
            if !strand.cp.as_flattened().iter().all(|x| x.is_finite())
                || !strand.widths.iter().all(|w| w.is_finite())
            {
                return scene_error(
                    format!("cyhair: strand {k}: its points or widths × scale {scale} pass the largest single-precision number"),
                    loc,
                );
            }
            each(k, &strand)?;
        }
        first = last + 1;
    }
    Ok(())
}

/// The curve segments (in render space) and their BVH pieces of a
/// `cyhair` shape.
pub fn create_cyhair(
    shape: &scene_description::Shape,
    render_from_object: &Transform,
    reverse_orientation: bool,
    base_directory: &Path,
    segments: &mut Vec<CurveSegment>,
    pieces: &mut Vec<CurvePiece>,
) -> Result<()> {
    let p = &shape.entity.params;
    let loc = &shape.entity.location.0;
    let (filename, filename_at) = p
        .string_at("filename")?
        .unwrap_or_else(|| (String::new(), loc.clone()));
    let scale = p.float("scale", 1.0)?;
    let width = if p.find("width", &[ParamType::Float])?.is_some() {
        Some(p.float("width", 1.0)?)
    } else {
        None
    };
    let kind_name = p.string("type", "flat")?;
    let basis = p.string("basis", "catmullrom")?;
    let split_depth = p.int("splitdepth", 3)?.clamp(0, 10) as u32;
    if filename.is_empty() {
        return scene_error("cyhair: \"filename\" must be given", loc);
    }
    if shape.area_light.is_some() {
        return scene_error(
            "curves cannot be area lights: emission from curves is not supported (as in pbrt-v4)",
            loc,
        );
    }
    let kind = curve::curve_type(&kind_name, loc)?;
    if kind == CurveType::Ribbon {
        return scene_error(
            "cyhair: curve type \"ribbon\" needs normals, which a HAIR file does not have (use flat or cylinder)",
            loc,
        );
    }
    let Some(basis) = Basis::from_name(&basis) else {
        return scene_error(
            format!("cyhair basis \"{basis}\" unknown (expected catmullrom or polyline)"),
            loc,
        );
    };
    let conversion = Conversion {
        basis,
        scale,
        width,
    };
    conversion.check().or_else(|e| scene_error(e, loc))?;
    let path = pbrt_parser::resolve_path(base_directory, &filename);
    let hair = read_hair(&path, &filename_at)?;
    append_segments(
        &hair,
        &conversion,
        kind,
        split_depth,
        render_from_object,
        reverse_orientation,
        segments,
        pieces,
        loc,
    )
}

/// The strands of `hair` as curve segments in render space: each
/// [`StrandCurves`] segment transformed and its widths scaled exactly as
/// the `curve` shape does it for the curves `cyhair2pbrt` writes.
#[allow(clippy::too_many_arguments)]
fn append_segments(
    hair: &HairFile,
    conversion: &Conversion,
    kind: CurveType,
    split_depth: u32,
    m: &Transform,
    reverse_orientation: bool,
    segments: &mut Vec<CurveSegment>,
    pieces: &mut Vec<CurvePiece>,
    loc: &Location,
) -> Result<()> {
    let width_scale = curve::width_scale(m);
    let flip_normal = reverse_orientation ^ m.swaps_handedness();
    for_each_strand(hair, conversion, loc, |_, strand| {
        let whole = strand.whole_curve_widths();
        for s in 0..strand.segment_count() {
            let cp = strand
                .segment(s)
                .map(|q| m.point(DVec3::from(q.map(|x| x as f64))).as_vec3());
            let w = strand.segment_widths(s, whole).map(|w| w * width_scale);
            // Each strand is its own fibre frame's strand.
            let segment = CurveSegment::unoriented(cp, w, kind, flip_normal, s == 0);
            curve::push_segment(segment, split_depth, segments, pieces, loc)?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::build::{build, RenderOverrides};
    use crate::scene::load_text;
    use glam::Vec3;
    use std::path::PathBuf;

    fn temporary_directory(test: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("rpbrt-cyhair-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// What a test HAIR file holds; `None` arrays are left out (their flag
    /// clear).
    struct Hair {
        hair_count: u32,
        point_count: u32,
        default_segments: u32,
        default_thickness: f32,
        segments: Option<Vec<u16>>,
        points: Option<Vec<[f32; 3]>>,
        thickness: Option<Vec<f32>>,
        transparency: Option<Vec<f32>>,
        colour: Option<Vec<[f32; 3]>>,
    }

    impl Hair {
        /// Strands of the given points, with a segments array.
        fn strands(strands: &[Vec<[f32; 3]>]) -> Hair {
            let points: Vec<[f32; 3]> = strands.iter().flatten().copied().collect();
            Hair {
                hair_count: strands.len() as u32,
                point_count: points.len() as u32,
                default_segments: 0,
                default_thickness: 0.5,
                segments: Some(strands.iter().map(|s| (s.len() - 1) as u16).collect()),
                points: Some(points),
                thickness: None,
                transparency: None,
                colour: None,
            }
        }

        fn bytes(&self) -> Vec<u8> {
            let mut b = Vec::new();
            b.extend_from_slice(b"HAIR");
            let flags = [
                self.segments.is_some(),
                self.points.is_some(),
                self.thickness.is_some(),
                self.transparency.is_some(),
                self.colour.is_some(),
            ]
            .iter()
            .enumerate()
            .map(|(i, &on)| (on as u32) << i)
            .sum::<u32>();
            for v in [
                self.hair_count,
                self.point_count,
                flags,
                self.default_segments,
            ] {
                b.extend_from_slice(&v.to_le_bytes());
            }
            for v in [self.default_thickness, 1.0, 0.1, 0.2, 0.3] {
                b.extend_from_slice(&v.to_le_bytes());
            }
            b.resize(128, b'.');
            if let Some(s) = &self.segments {
                s.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
            }
            let floats = |b: &mut Vec<u8>, v: &[f32]| {
                v.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()))
            };
            if let Some(p) = &self.points {
                floats(&mut b, p.as_flattened());
            }
            if let Some(t) = &self.thickness {
                floats(&mut b, t);
            }
            if let Some(t) = &self.transparency {
                floats(&mut b, t);
            }
            if let Some(c) = &self.colour {
                floats(&mut b, c.as_flattened());
            }
            b
        }
    }

    fn here() -> Location {
        Location::nowhere()
    }

    fn read_bytes(dir: &Path, name: &str, bytes: &[u8]) -> Result<HairFile> {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        read_hair(&path, &here())
    }

    fn three_strands() -> Vec<Vec<[f32; 3]>> {
        vec![
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
            vec![
                [0.0, 1.0, 0.0],
                [0.5, 1.5, 0.0],
                [1.0, 1.0, 0.5],
                [2.0, 1.0, 1.0],
            ],
            vec![[0.0, 2.0, 0.0], [0.0, 2.0, 1.0], [0.0, 3.0, 2.0]],
        ]
    }

    #[test]
    fn every_optional_array_present_is_read() {
        let dir = temporary_directory("all");
        let mut hair = Hair::strands(&three_strands());
        let n = hair.point_count as usize;
        hair.thickness = Some((0..n).map(|i| 0.1 * i as f32).collect());
        hair.transparency = Some((0..n).map(|i| 0.01 * i as f32).collect());
        hair.colour = Some((0..n).map(|i| [i as f32, 0.5, 0.25]).collect());
        let read = read_bytes(&dir, "all.hair", &hair.bytes()).unwrap();
        assert_eq!(read.segments, vec![1, 3, 2]);
        assert_eq!(read.points, three_strands().concat());
        assert_eq!(read.thickness, hair.thickness);
        assert_eq!(read.transparency, hair.transparency);
        assert_eq!(read.colour, hair.colour);
        assert_eq!(read.thickness_at(3), 0.3);
        assert_eq!(read.default_colour, [0.1, 0.2, 0.3]);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn absent_arrays_take_the_header_defaults() {
        let dir = temporary_directory("defaults");
        // Two strands of the default 2 segments, no segments or thickness
        // array.
        let points: Vec<[f32; 3]> = (0..6).map(|i| [i as f32, 0.0, 0.0]).collect();
        let hair = Hair {
            hair_count: 2,
            point_count: 6,
            default_segments: 2,
            default_thickness: 0.25,
            segments: None,
            points: Some(points.clone()),
            thickness: None,
            transparency: None,
            colour: None,
        };
        let read = read_bytes(&dir, "defaults.hair", &hair.bytes()).unwrap();
        assert_eq!(read.segments, vec![2, 2]);
        assert_eq!(read.points, points);
        assert_eq!(read.thickness, None);
        assert_eq!(read.thickness_at(5), 0.25);
        assert_eq!(read.transparency, None);
        assert_eq!(read.colour, None);
        // Curves from it: 4 segments, the default thickness × scale wide.
        let (mut segments, mut pieces) = (Vec::new(), Vec::new());
        let conversion = Conversion {
            basis: Basis::CatmullRom,
            scale: 2.0,
            width: None,
        };
        append_segments(
            &read,
            &conversion,
            CurveType::Cylinder,
            1,
            &Transform::IDENTITY,
            false,
            &mut segments,
            &mut pieces,
            &here(),
        )
        .unwrap();
        assert_eq!(segments.len(), 4);
        assert_eq!(pieces.len(), 8);
        assert!(segments.iter().all(|s| s.width == [0.5, 0.5]));
        // Collinear points: the Catmull-Rom segments are straight, through
        // the points.
        assert_eq!(segments[3].cp[3], Vec3::new(10.0, 0.0, 0.0));
        assert!(segments[1].cp.iter().all(|p| p.y == 0.0 && p.z == 0.0));
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A scene of one cyhair shape of 3 strands of 1, 3 and 2 segments,
    /// built: its curve segments join the file's points times the scale,
    /// under the shape's transform.
    #[test]
    fn a_built_scene_has_the_files_strands() {
        let dir = temporary_directory("scene");
        let mut hair = Hair::strands(&three_strands());
        hair.thickness = Some((0..9).map(|i| 0.01 * (i + 1) as f32).collect());
        std::fs::write(dir.join("three.hair"), hair.bytes()).unwrap();
        let scene = |basis: &str, extra: &str| {
            let text = format!(
                "WorldBegin\nTranslate 0 0 5\nShape \"cyhair\" \"string filename\" \"three.hair\" \"float scale\" 2 \"string basis\" \"{basis}\" {extra}\n"
            );
            let loaded = load_text(&dir.join("scene.pbrt"), &text).unwrap();
            build(loaded.scene, &RenderOverrides::default()).map(|b| b.shapes)
        };
        let storage = scene("polyline", "").unwrap();
        let segments = &storage.curve_segments;
        assert_eq!(segments.len(), 1 + 3 + 2);
        assert_eq!(storage.curve_pieces.len(), 6 * 8);
        // The render space of a default scene is the camera's: compare
        // through the segments' ends relative to the first point.
        let origin = segments[0].cp[0];
        let strands = three_strands();
        let mut k = 0;
        for strand in &strands {
            for pair in strand.windows(2) {
                let expect = |p: [f32; 3]| Vec3::from(p) * 2.0;
                let s = &segments[k];
                let (a, b) = (s.cp[0] - origin, s.cp[3] - origin);
                assert!((a - expect(pair[0])).length() < 1e-5, "{k}: {a} {pair:?}");
                assert!((b - expect(pair[1])).length() < 1e-5, "{k}: {b} {pair:?}");
                // Straight: the inner control points on the chord.
                let third = s.cp[0] + (s.cp[3] - s.cp[0]) / 3.0;
                assert!((s.cp[1] - third).length() < 1e-5);
                k += 1;
            }
        }
        // Widths: the file's thickness × scale (at points 1 and 2 for the
        // second strand's first segment), or the override.
        assert!(
            (segments[1].width[0] - 0.06).abs() < 1e-6,
            "{:?}",
            segments[1].width
        );
        assert!((segments[1].width[1] - 0.08).abs() < 1e-6);
        let wide = scene("polyline", "\"float width\" 0.3").unwrap();
        assert!(wide
            .curve_segments
            .iter()
            .all(|s| (s.width[0] - 0.3).abs() < 1e-6));
        // Catmull-Rom: the same ends, smooth joins (the tangents of
        // consecutive segments agree).
        let smooth = scene("catmullrom", "\"string type\" \"cylinder\"").unwrap();
        let s = &smooth.curve_segments;
        assert_eq!(s.len(), 6);
        for (a, b) in s.iter().zip(segments) {
            assert!((a.cp[0] - b.cp[0]).length() < 1e-5 && (a.cp[3] - b.cp[3]).length() < 1e-5);
            assert_eq!(a.kind, CurveType::Cylinder);
        }
        for k in [1, 2, 4] {
            let out = s[k].cp[3] - s[k].cp[2];
            let into = s[k + 1].cp[1] - s[k + 1].cp[0];
            assert!((out - into).length() < 1e-5, "{k}: {out} {into}");
        }
        // Parameter errors.
        let error = |basis: &str, extra: &str| scene(basis, extra).unwrap_err().to_string();
        let e = error("bspline", "");
        assert!(
            e.contains("basis \"bspline\" unknown") && e.contains("scene.pbrt:3:"),
            "{e}"
        );
        let e = error("polyline", "\"string type\" \"ribbon\"");
        assert!(e.contains("needs normals"), "{e}");
        let e = error("polyline", "\"float width\" -1");
        assert!(e.contains("\"width\" must be ≥ 0"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Every broken file gives an error naming the file, the byte offset
    /// and what was expected, at the scene's location; none panics.
    #[test]
    fn broken_files_give_located_errors() {
        let dir = temporary_directory("broken");
        let good = {
            let mut hair = Hair::strands(&three_strands());
            hair.thickness = Some(vec![0.1; 9]);
            hair
        };
        let error_of = |name: &str, bytes: &[u8]| {
            std::fs::write(dir.join(name), bytes).unwrap();
            let text = format!("WorldBegin\nShape \"cyhair\" \"string filename\" \"{name}\"\n");
            let loaded = load_text(&dir.join("scene.pbrt"), &text).unwrap();
            let e = build(loaded.scene, &RenderOverrides::default())
                .err()
                .unwrap_or_else(|| panic!("{name} was accepted"))
                .to_string();
            assert!(e.contains("scene.pbrt:2:") && e.contains(name), "{e}");
            e
        };
        let bytes = good.bytes();
        assert_eq!(bytes.len(), 128 + 6 + 9 * 12 + 9 * 4);

        // Truncated: inside the thickness array.
        let e = error_of("truncated.hair", &bytes[..bytes.len() - 3]);
        assert!(
            e.contains("byte 275:")
                && e.contains("inside the thickness array")
                && e.contains("need 278 bytes"),
            "{e}"
        );
        let e = error_of("points.hair", &bytes[..200]);
        assert!(
            e.contains("byte 200:") && e.contains("inside the points array"),
            "{e}"
        );
        let e = error_of("short.hair", &bytes[..100]);
        assert!(
            e.contains("byte 100:") && e.contains("128-byte header"),
            "{e}"
        );
        let e = error_of("empty.hair", &[]);
        assert!(e.contains("byte 0:") && e.contains("header"), "{e}");
        let mut long = bytes.clone();
        long.extend_from_slice(&[0; 5]);
        let e = error_of("long.hair", &long);
        assert!(e.contains("byte 278:") && e.contains("5 more bytes"), "{e}");
        let mut magic = bytes.clone();
        magic[..4].copy_from_slice(b"HAIX");
        let e = error_of("magic.hair", &magic);
        assert!(
            e.contains("byte 0:") && e.contains("expected the magic \"HAIR\""),
            "{e}"
        );

        // Inconsistent header: segments that do not add up.
        let mut inconsistent = Hair::strands(&three_strands());
        inconsistent.segments = Some(vec![1, 3, 3]);
        let e = error_of("sum.hair", &inconsistent.bytes());
        assert!(
            e.contains("byte 128:") && e.contains("need 10 points") && e.contains("says 9"),
            "{e}"
        );
        let mut defaults = Hair::strands(&three_strands());
        defaults.segments = None;
        defaults.default_segments = 3;
        let e = error_of("defaults.hair", &defaults.bytes());
        assert!(
            e.contains("byte 16:") && e.contains("need 12 points") && e.contains("says 9"),
            "{e}"
        );
        // A huge point count in a small file allocates nothing.
        let mut huge = bytes.clone();
        huge[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
        let e = error_of("huge.hair", &huge);
        assert!(e.contains("inside the points array"), "{e}");
        // No points array.
        let mut no_points = Hair::strands(&three_strands());
        no_points.points = None;
        let e = error_of("nopoints.hair", &no_points.bytes());
        assert!(
            e.contains("byte 12:") && e.contains("expected a points array"),
            "{e}"
        );

        // Non-finite values: a point, a thickness, a default.
        let mut nan = bytes.clone();
        nan[134 + 12 * 4 + 4..134 + 12 * 4 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = error_of("nan.hair", &nan);
        assert!(
            e.contains("byte 186:") && e.contains("finite number in the points array (point 4)"),
            "{e}"
        );
        let mut inf = bytes.clone();
        inf[242 + 8..242 + 12].copy_from_slice(&f32::INFINITY.to_le_bytes());
        let e = error_of("inf.hair", &inf);
        assert!(
            e.contains("byte 250:") && e.contains("thickness array (point 2), found inf"),
            "{e}"
        );
        let mut negative = bytes.clone();
        negative[242..246].copy_from_slice(&(-1.0f32).to_le_bytes());
        let e = error_of("negative.hair", &negative);
        assert!(
            e.contains("byte 242:") && e.contains("thickness ≥ 0"),
            "{e}"
        );
        let mut default = bytes.clone();
        default[20..24].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = error_of("default.hair", &default);
        assert!(
            e.contains("byte 20:") && e.contains("finite default thickness"),
            "{e}"
        );

        // A missing file.
        let text = "WorldBegin\nShape \"cyhair\" \"string filename\" \"missing.hair\"\n";
        let loaded = load_text(&dir.join("scene.pbrt"), text).unwrap();
        let e = build(loaded.scene, &RenderOverrides::default())
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("scene.pbrt:2:") && e.contains("missing.hair") && e.contains("cannot read"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Random bytes after a valid header start, and random headers, give
    /// errors or hair, never a panic.
    #[test]
    fn random_files_never_panic() {
        let dir = temporary_directory("random");
        let mut rng = crate::shapes::test_support::TestRng::new(7);
        let good = Hair::strands(&three_strands()).bytes();
        for i in 0..200 {
            let mut bytes = good.clone();
            let flips = 1 + (rng.uniform() * 4.0) as usize;
            for _ in 0..flips {
                let k = ((rng.uniform() * 40.0) as usize).min(bytes.len() - 1);
                let k = if i % 2 == 0 {
                    k
                } else {
                    ((rng.uniform() * bytes.len() as f32) as usize).min(bytes.len() - 1)
                };
                bytes[k] = (rng.uniform() * 256.0) as u8;
            }
            let cut = if i % 3 == 0 {
                (rng.uniform() * bytes.len() as f32) as usize
            } else {
                bytes.len()
            };
            if let Ok(hair) = read_bytes(&dir, "random.hair", &bytes[..cut]) {
                let (mut segments, mut pieces) = (Vec::new(), Vec::new());
                let conversion = Conversion {
                    basis: Basis::CatmullRom,
                    scale: 1.0,
                    width: None,
                };
                let _ = append_segments(
                    &hair,
                    &conversion,
                    CurveType::Flat,
                    0,
                    &Transform::IDENTITY,
                    false,
                    &mut segments,
                    &mut pieces,
                    &here(),
                );
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// `hair_bytes` writes what `read_hair` reads back, with and without
    /// the segments array and every optional array; it refuses what a
    /// HAIR file cannot hold.
    #[test]
    fn written_hair_reads_back() {
        let dir = temporary_directory("write");
        let strands = three_strands();
        let n = 9;
        let mut hair = HairFile {
            segments: vec![1, 3, 2],
            points: strands.concat(),
            thickness: Some((0..n).map(|i| 0.1 * i as f32).collect()),
            default_thickness: 0.5,
            transparency: Some(vec![0.25; n]),
            default_transparency: 0.75,
            colour: Some((0..n).map(|i| [i as f32, 0.5, 0.25]).collect()),
            default_colour: [0.1, 0.2, 0.3],
        };
        let bytes = hair_bytes(&hair, true).unwrap();
        assert_eq!(read_bytes(&dir, "w.hair", &bytes).unwrap(), hair);
        assert!(hair_bytes(&hair, false).unwrap_err().contains("different"));
        hair.thickness = None;
        hair.transparency = None;
        hair.colour = None;
        hair.segments = vec![2, 2, 2];
        let bytes = hair_bytes(&hair, false).unwrap();
        assert_eq!(bytes.len(), 128 + 9 * 12);
        assert_eq!(read_bytes(&dir, "w2.hair", &bytes).unwrap(), hair);
        hair.segments = vec![2, 2];
        assert!(hair_bytes(&hair, true)
            .unwrap_err()
            .contains("need 6 points"));
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A strand's widths go in one curve when pbrt-v4's lerp over its
    /// segments gives every point's width, else a curve per segment; a
    /// scale past f32 is an error, not an infinite point.
    #[test]
    fn strand_widths_choose_the_curves() {
        let strand = |widths: Vec<f32>| StrandCurves {
            cp: vec![[0.0; 3]; 3 * (widths.len() - 1) + 1],
            widths,
        };
        assert_eq!(strand(vec![0.5; 4]).whole_curve_widths(), Some((0.5, 0.5)));
        assert_eq!(
            strand(vec![0.0, 1.0, 2.0, 3.0]).whole_curve_widths(),
            Some((0.0, 3.0))
        );
        let bumpy = strand(vec![0.1, 0.3, 0.2]);
        assert_eq!(bumpy.whole_curve_widths(), None);
        assert_eq!(bumpy.segment_widths(1, None), [0.3, 0.2]);
        let hair = HairFile {
            segments: vec![1],
            points: vec![[0.0; 3], [1e30, 0.0, 0.0]],
            thickness: None,
            default_thickness: 1.0,
            transparency: None,
            default_transparency: 1.0,
            colour: None,
            default_colour: [1.0; 3],
        };
        let conversion = Conversion {
            basis: Basis::Polyline,
            scale: 1e10,
            width: None,
        };
        let e = for_each_strand(&hair, &conversion, &here(), |_, _| Ok(()))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("strand 0") && e.contains("single-precision"),
            "{e}"
        );
    }
}
