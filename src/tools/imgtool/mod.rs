//! `rpbrt imgtool`: image comparison and conversion, as pbrt-v4's `imgtool`.

mod assemble;
mod convert;
mod diff;

pub use assemble::{assemble, AssembleArgs};
pub use convert::ConvertArgs;
pub use diff::DiffArgs;

use crate::error::Error;
use crate::image::Image;
use std::path::Path;
use std::process::ExitCode;

/// Exit code of `rpbrt imgtool` when it cannot do its work (unreadable
/// files, mismatched sizes); 1 is kept for "images differ by more than
/// `--tolerance`", as diff(1) does.
pub const ERROR_EXIT_CODE: u8 = 2;

/// Image tools.
#[derive(clap::Args, Debug)]
pub struct ImgtoolArgs {
    #[command(subcommand)]
    command: ImgtoolCommand,
}

#[derive(clap::Subcommand, Debug)]
enum ImgtoolCommand {
    Diff(DiffArgs),
    Convert(ConvertArgs),
    Assemble(AssembleArgs),
}

pub fn run(args: &ImgtoolArgs) -> Result<ExitCode, Error> {
    match &args.command {
        ImgtoolCommand::Diff(args) => diff::run(args),
        ImgtoolCommand::Convert(args) => convert::run(args).map(|()| ExitCode::SUCCESS),
        ImgtoolCommand::Assemble(args) => assemble::run(args).map(|()| ExitCode::SUCCESS),
    }
}

/// Reads an image as linear RGB: (width, height, interleaved R, G, B).
pub fn read_rgb(path: &Path) -> Result<(usize, usize, Vec<f32>), Error> {
    let image = Image::read(path)?;
    let rgb = image.rgb_data();
    if rgb.is_empty() {
        return Err(Error::Usage(format!(
            "{}: no R, G, B or single channel to compare (channels {:?})",
            path.display(),
            image.channels()
        )));
    }
    Ok((image.width() as usize, image.height() as usize, rgb))
}
