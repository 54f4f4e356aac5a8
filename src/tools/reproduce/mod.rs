//! `rpbrt reproduce`: the paper's figures. (Being written.)

use crate::error::{Error, Result};

/// Renders the figures of Benamira & Pattanaik 2021 from `pbrt-scenes/paper/`.
#[derive(clap::Args, Debug)]
pub struct ReproduceArgs {}

pub fn run(_args: &ReproduceArgs) -> Result<()> {
    Err(Error::Usage("reproduce: not written yet".into()))
}
