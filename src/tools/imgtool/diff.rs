//! `rpbrt imgtool diff`: how far an image is from a reference.

use super::read_rgb;
use crate::error::Error;
use crate::tools::heat_map::heat_map;
use crate::tools::imgdiff::{block_bias, Metric};
use std::path::PathBuf;
use std::process::ExitCode;

/// Compare an image with a reference: prints the error and the 16 × 16 block
/// bias of ../shared/refs/README.md. Exit code 0 if the error is within
/// `--tolerance` (or none is given), 1 if not, 2 on failure.
#[derive(clap::Args, Debug)]
pub struct DiffArgs {
    /// The reference image (.exr, .pfm, .png).
    #[arg(long)]
    pub reference: PathBuf,
    /// The image to compare.
    pub image: PathBuf,
    /// Error metric: mean of per-pixel errors.
    #[arg(long, value_enum, default_value_t = Metric::Mrse)]
    pub metric: Metric,
    /// Largest acceptable error; above it the exit code is 1.
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// Write a false-colour heat map of the per-pixel error (.png): black is
    /// no error, light yellow the largest (1 for FLIP).
    #[arg(long)]
    pub outfile: Option<PathBuf>,
}

pub fn run(args: &DiffArgs) -> Result<ExitCode, Error> {
    let (w, h, image) = read_rgb(&args.image)?;
    let (rw, rh, reference) = read_rgb(&args.reference)?;
    if (w, h) != (rw, rh) {
        return Err(Error::Usage(format!(
            "{} is {w}×{h} but the reference {} is {rw}×{rh}",
            args.image.display(),
            args.reference.display()
        )));
    }
    let errors = args.metric.pixel_errors(&image, &reference, w, h);
    let error = errors.iter().sum::<f64>() / errors.len() as f64;
    println!(
        "{} {error:.6}  block bias {:.5}",
        args.metric.name(),
        block_bias(&image, &reference, w, h, 3, 16)
    );
    if let Some(out) = &args.outfile {
        let scale = match args.metric {
            Metric::Flip => 1.0,
            _ => errors.iter().copied().fold(0.0, f64::max),
        };
        heat_map(&errors, w as u32, h as u32, scale)?.write(out)?;
        eprintln!("wrote {} (light yellow = {scale:.4})", out.display());
    }
    Ok(match args.tolerance {
        Some(tolerance) if !(error <= tolerance) => {
            eprintln!(
                "{} {error:.6} exceeds the tolerance {tolerance}",
                args.metric.name()
            );
            ExitCode::FAILURE
        }
        _ => ExitCode::SUCCESS,
    })
}
