//! `rpbrt imgtool convert`: between EXR, PFM and PNG, with exposure and
//! clamping.

use crate::error::Error;
use crate::image::{DataWindow, Image};
use std::path::PathBuf;

/// Convert an image to another format (chosen by the output's extension:
/// .exr as 32-bit floats, .pfm, .png as 8-bit sRGB).
#[derive(clap::Args, Debug)]
pub struct ConvertArgs {
    /// The image to read (.exr, .pfm, .png, .tga, .jpg).
    pub input: PathBuf,
    /// The image to write.
    #[arg(long)]
    pub outfile: PathBuf,
    /// Scale linear values by 2^EXPOSURE first.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Clamp linear values to at most this (after the exposure).
    #[arg(long)]
    pub clamp: Option<f32>,
}

pub fn run(args: &ConvertArgs) -> Result<(), Error> {
    let is_exr = |p: &std::path::Path| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    // An EXR's place in a larger image survives EXR → EXR.
    let (image, window) = if is_exr(&args.input) {
        let (image, window) = Image::read_exr_with_window(&args.input)?;
        (image, Some(window))
    } else {
        (Image::read(&args.input)?, None)
    };
    let scale = args.exposure.exp2();
    let limit = args.clamp.unwrap_or(f32::INFINITY);
    let mut linear = image.to_linear();
    for v in linear.data_mut() {
        // f32::min would turn a NaN into the limit; keep it so the write
        // refuses it.
        if !v.is_nan() {
            *v = (*v * scale).min(limit);
        }
    }
    if is_exr(&args.outfile) {
        let window = window.filter(|w| *w != DataWindow::whole(image.width(), image.height()));
        linear.write_exr_in_window(&args.outfile, false, window.as_ref())?;
    } else {
        linear.write(&args.outfile)?;
    }
    Ok(())
}
