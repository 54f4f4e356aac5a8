//! `rpbrt cyhair2pbrt IN.hair OUT.pbrt[.gz]`: a CyHair file as pbrt-v4
//! curves. (Being written.)

use crate::error::{Error, Result};
use std::path::PathBuf;

/// Writes a CyHair (`.hair`) file's strands as pbrt-v4 `Shape "curve"`s.
#[derive(clap::Args, Debug)]
pub struct Cyhair2pbrtArgs {
    /// The CyHair file to read.
    pub input: PathBuf,
    /// The pbrt file to write (`.gz`: gzip-compressed).
    pub output: PathBuf,
}

pub fn run(_args: &Cyhair2pbrtArgs) -> Result<()> {
    Err(Error::Usage("cyhair2pbrt: not written yet".into()))
}
