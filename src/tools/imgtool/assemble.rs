//! `rpbrt imgtool assemble`: joins the pieces of an image rendered with
//! `--pixelbounds` or `--cropwindow` (as pbrt-v4's `imgtool assemble`).
//!
//! Each piece must be an OpenEXR file: rpbrt writes a partial render as
//! just the rendered pixels, placed by the EXR data window inside a
//! display window of the film's full resolution (as pbrt-v4 does). PNG and
//! PFM cannot say where they belong, so they are refused.

use crate::error::Error;
use crate::image::{DataWindow, Image, PixelFormat};
use std::path::{Path, PathBuf};

/// Join partial renders (EXR) into the full image. Every pixel must be
/// covered; pieces may overlap only where they agree.
#[derive(clap::Args, Debug)]
pub struct AssembleArgs {
    /// The pieces (.exr written by `rpbrt --pixelbounds`/`--cropwindow`).
    #[arg(required = true)]
    pub pieces: Vec<PathBuf>,
    /// The whole image (.exr keeps the pieces' precision exactly; .pfm,
    /// .png also work).
    #[arg(long)]
    pub outfile: PathBuf,
}

pub fn run(args: &AssembleArgs) -> Result<(), Error> {
    let image = assemble(&args.pieces)?;
    let is_exr = args
        .outfile
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if is_exr {
        image.write_exr(&args.outfile, image.format() == PixelFormat::Half)?;
    } else {
        image.write(&args.outfile)?;
    }
    Ok(())
}

/// The full image the pieces make up. Its format is half if every piece
/// is (so writing it as half loses nothing), else float.
pub fn assemble(pieces: &[PathBuf]) -> Result<Image, Error> {
    let usage =
        |path: &Path, message: String| Error::Usage(format!("{}: {message}", path.display()));
    let mut canvas: Option<(Vec<f32>, Vec<bool>, DataWindow, Vec<String>)> = None;
    let mut all_half = true;
    for path in pieces {
        let is_exr = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
        if !is_exr {
            return Err(usage(
                path,
                "pieces must be OpenEXR files (only they record where they lie in the image)"
                    .into(),
            ));
        }
        let (piece, window) = Image::read_exr_with_window(path)?;
        all_half &= piece.format() == PixelFormat::Half;
        let (full_w, full_h) = window.full_resolution;
        let (data, covered, first, channels) = canvas.get_or_insert_with(|| {
            let pixels = full_w as usize * full_h as usize;
            (
                vec![0.0; pixels * piece.channel_count()],
                vec![false; pixels],
                window,
                piece.channels().to_vec(),
            )
        });
        if window.full_resolution != first.full_resolution {
            return Err(usage(
                path,
                format!(
                    "belongs to a {full_w}×{full_h} image, the first piece to a {}×{} one",
                    first.full_resolution.0, first.full_resolution.1
                ),
            ));
        }
        if piece.channels() != channels.as_slice() {
            return Err(usage(
                path,
                format!(
                    "has channels {:?}, the first piece {channels:?}",
                    piece.channels()
                ),
            ));
        }
        let n = channels.len();
        let (ox, oy) = window.origin;
        for y in 0..piece.height() {
            for x in 0..piece.width() {
                let (fx, fy) = (ox + x as i32, oy + y as i32);
                if fx < 0 || fy < 0 || fx >= full_w as i32 || fy >= full_h as i32 {
                    return Err(usage(
                        path,
                        format!("pixel ({fx}, {fy}) lies outside the {full_w}×{full_h} image"),
                    ));
                }
                let index = fy as usize * full_w as usize + fx as usize;
                let value = piece.pixel(x, y);
                let target = &mut data[index * n..(index + 1) * n];
                if covered[index] && target != value {
                    return Err(usage(
                        path,
                        format!("pixel ({fx}, {fy}) differs from an earlier piece's"),
                    ));
                }
                target.copy_from_slice(value);
                covered[index] = true;
            }
        }
    }
    let Some((data, covered, window, channels)) = canvas else {
        return Err(Error::Usage("no pieces to assemble".into()));
    };
    let (w, h) = window.full_resolution;
    if let Some(missing) = covered.iter().position(|c| !c) {
        return Err(Error::Usage(format!(
            "the pieces leave pixel ({}, {}) of the {w}×{h} image uncovered",
            missing % w as usize,
            missing / w as usize
        )));
    }
    let format = if all_half {
        PixelFormat::Half
    } else {
        PixelFormat::Float
    };
    Ok(Image::from_parts(
        w,
        h,
        channels,
        data,
        crate::image::ColorEncoding::Linear,
        format,
    )?)
}
