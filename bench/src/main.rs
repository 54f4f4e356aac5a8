//! The `rpbrt-bench` command line: `convergence`, `report`, `curves` and `scaling`, also
//! run as `rpbrt convergence`, `rpbrt report`, `rpbrt curves` and `rpbrt scaling`. Argument dispatch only.

use clap::Parser as _;
use rpbrt_bench::{convergence, curves, report, scaling};
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
    /// Whole renders of scenes at several thread counts beside pbrt-v4: time, memory, speed-up.
    Scaling(scaling::ScalingArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match &cli.command {
        Command::Convergence(args) => convergence::run(args),
        Command::Report(args) => report::run(args),
        Command::Curves(args) => curves::run(args),
        Command::Scaling(args) => scaling::run(args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
