//! `rpbrt bcsdf` until the CLI's subcommands land: the dual hair model's
//! azimuthal maps and diffraction spectra (see `rpbrt::tools::bcsdf`).
//! `cargo run --release --example bcsdf -- --logistic-scale 0.01 --csv m.csv --png m.png`

use clap::Parser;
use rpbrt::tools::bcsdf::{run, BcsdfArgs};

#[derive(Parser)]
#[command(name = "bcsdf")]
struct Cli {
    #[command(flatten)]
    args: BcsdfArgs,
}

fn main() -> std::process::ExitCode {
    match run(&Cli::parse().args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("bcsdf: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
