//! The `rpbrt-bench` command line: `convergence`, `report` and `curves`, also run as
//! `rpbrt convergence`, `rpbrt report` and `rpbrt curves`. Argument dispatch only.

use clap::Parser as _;
use rpbrt_bench::{convergence, curves, report};
use std::process::ExitCode;

/// rpbrt's benchmark harness: error against time, and the performance
/// report against pbrt-v4.
#[derive(clap::Parser, Debug)]
#[command(name = "rpbrt-bench", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Subcommand, Debug)]
enum Command {
    Convergence(convergence::ConvergenceArgs),
    Report(report::ReportArgs),
    /// Parse and build time and peak memory on a generated curve file (the refs README's 120 MB form).
    Curves(curves::CurvesArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match &cli.command {
        Command::Convergence(args) => convergence::run(args),
        Command::Report(args) => report::run(args),
        Command::Curves(args) => curves::run(args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
