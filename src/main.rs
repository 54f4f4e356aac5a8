//! The `rpbrt` command line. Only argument dispatch lives here: each
//! command's arguments and work are in `rpbrt::tools`; `report` and
//! `convergence` are run by the benchmark harness, the `rpbrt-bench`
//! executable (`tools::bench_handoff`).

use clap::Parser as _;
use rpbrt::tools::{
    bcsdf, bench_handoff, cyhair2pbrt, hairgen, imgtool, mie, render_scene, reproduce,
};
use std::process::ExitCode;

#[global_allocator]
static ALLOCATOR: rpbrt::memory::HugePageAllocator = rpbrt::memory::HugePageAllocator;

/// Renders pbrt-v4 scenes (pbrt-v3 scenes are read too): `rpbrt FILE
/// [flags]`, as pbrt. The subcommands compare images and measure speed
/// against error.
#[derive(clap::Parser, Debug)]
#[command(
    name = "rpbrt",
    version,
    about,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
struct Cli {
    #[command(flatten)]
    render: render_scene::RenderArgs,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(clap::Subcommand, Debug)]
enum Command {
    Imgtool(imgtool::ImgtoolArgs),
    /// Error against time of a scene's renders, log–log (run by rpbrt-bench).
    Convergence(bench_handoff::HandOffArgs),
    /// Measure the shared reference scenes against pbrt-v4 into docs/performance.md (run by rpbrt-bench).
    Report(bench_handoff::HandOffArgs),
    /// Parse and build time and peak memory on a generated curve file against pbrt-v4 (run by rpbrt-bench).
    Curves(bench_handoff::HandOffArgs),
    /// Whole renders of scenes at several thread counts against pbrt-v4 (run by rpbrt-bench).
    Scaling(bench_handoff::HandOffArgs),
    /// The dual hair model's azimuthal scattering maps and diffraction spectra.
    Bcsdf(bcsdf::BcsdfArgs),
    /// Writes a CyHair (.hair) file as pbrt-v4 curves.
    Cyhair2pbrt(cyhair2pbrt::Cyhair2pbrtArgs),
    /// Grows hair or fur from a recipe and writes it as pbrt-v4 curves.
    Hairgen(hairgen::HairgenArgs),
    /// Renders the paper's figures (Benamira & Pattanaik 2021) with a page of results.
    Reproduce(reproduce::ReproduceArgs),
    /// Exact (Lorenz–Mie) scattering by a circular cylinder: the wave-optics reference for fibres.
    Mie(mie::MieArgs),
}

fn main() -> ExitCode {
    rpbrt::memory::return_large_blocks_when_freed();
    // pbrt-v4 writes --pixelbounds and --cropwindow as one list (0,120,0,90).
    let args = match render_scene::expand_comma_lists(std::env::args_os()) {
        Ok(args) => args,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let cli = Cli::parse_from(args);
    let (outcome, error_code) = match &cli.command {
        None => (
            render_scene::run(&cli.render).map(|()| ExitCode::SUCCESS),
            1,
        ),
        Some(Command::Imgtool(args)) => (imgtool::run(args), imgtool::ERROR_EXIT_CODE),
        Some(Command::Convergence(args)) => (bench_handoff::run("convergence", args), 1),
        Some(Command::Report(args)) => (bench_handoff::run("report", args), 1),
        Some(Command::Curves(args)) => (bench_handoff::run("curves", args), 1),
        Some(Command::Scaling(args)) => (bench_handoff::run("scaling", args), 1),
        Some(Command::Bcsdf(args)) => (
            bcsdf::run(args)
                .map(|()| ExitCode::SUCCESS)
                .map_err(rpbrt::error::Error::Usage),
            1,
        ),
        Some(Command::Cyhair2pbrt(args)) => (cyhair2pbrt::run(args).map(|()| ExitCode::SUCCESS), 1),
        Some(Command::Hairgen(args)) => (hairgen::run(args).map(|()| ExitCode::SUCCESS), 1),
        Some(Command::Reproduce(args)) => (reproduce::run(args).map(|()| ExitCode::SUCCESS), 1),
        Some(Command::Mie(args)) => (
            mie::run(args)
                .map(|()| ExitCode::SUCCESS)
                .map_err(rpbrt::error::Error::Usage),
            1,
        ),
    };
    outcome.unwrap_or_else(|e| {
        eprintln!("error: {e}");
        ExitCode::from(error_code)
    })
}
