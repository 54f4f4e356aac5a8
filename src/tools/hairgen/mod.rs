//! `rpbrt hairgen`: pbrt-v4 curves grown from a recipe. (Being written.)

use crate::error::{Error, Result};

/// Grows hair or fur and writes it as pbrt-v4 curves.
#[derive(clap::Args, Debug)]
pub struct HairgenArgs {}

pub fn run(_args: &HairgenArgs) -> Result<()> {
    Err(Error::Usage("hairgen: not written yet".into()))
}
