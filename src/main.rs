//! The `rpbrt` command line. Only argument handling lives here; the work is
//! done by the library.

use clap::Parser as _;
use pbrt_parser::{Formatter, Parser};
use rpbrt::error::Error;
use rpbrt::scene::build::RenderOverrides;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// Renders pbrt-v4 scenes (pbrt-v3 scenes are read too).
#[derive(clap::Parser, Debug)]
#[command(name = "rpbrt", version, about)]
struct Cli {
    /// Scene file (.pbrt or .pbrt.gz).
    file: PathBuf,
    /// Print the scene in canonical pbrt-v4 syntax (Include/Import kept as
    /// they are) and exit.
    #[arg(long, conflicts_with = "upgrade")]
    format: bool,
    /// Print a pbrt-v3 scene as pbrt-v4 (listing each rewrite on stderr) and
    /// exit.
    #[arg(long)]
    upgrade: bool,
    /// Print no warnings, no progress and no summary.
    #[arg(long)]
    quiet: bool,
    /// Only read and check the scene; print a summary of what it contains.
    #[arg(long)]
    check: bool,
    /// Samples per pixel (overrides the scene's sampler).
    #[arg(long)]
    spp: Option<u32>,
    /// Random seed (overrides `Option "seed"`).
    #[arg(long)]
    seed: Option<i32>,
    /// Render threads (default: all cores).
    #[arg(long)]
    nthreads: Option<usize>,
    /// Output image (.exr, .png or .pfm; overrides the film's filename).
    #[arg(long)]
    outfile: Option<PathBuf>,
    /// Render only this window of the image: x0 x1 y0 y1 in [0, 1].
    #[arg(long, num_args = 4, value_names = ["X0", "X1", "Y0", "Y1"], allow_negative_numbers = true)]
    cropwindow: Option<Vec<f64>>,
    /// Render only these pixels: x0 x1 y0 y1.
    #[arg(long, num_args = 4, value_names = ["X0", "X1", "Y0", "Y1"])]
    pixelbounds: Option<Vec<i32>>,
    /// Quick preview: a quarter of the resolution, a sixteenth of the samples.
    #[arg(long)]
    quick: bool,
    /// Print timing and sample statistics after rendering.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: &Cli) -> Result<(), Error> {
    if cli.format || cli.upgrade {
        return format(cli);
    }
    if cli.check {
        let loaded = rpbrt::scene::load(&cli.file)?;
        if !cli.quiet {
            for w in &loaded.warnings {
                eprintln!("{w}");
            }
            println!("{}", loaded.scene.summary());
        }
        return Ok(());
    }
    let overrides = RenderOverrides {
        spp: cli.spp,
        seed: cli.seed,
        outfile: cli.outfile.clone(),
        crop_window: cli.cropwindow.as_ref().map(|v| [v[0], v[1], v[2], v[3]]),
        pixel_bounds: cli.pixelbounds.as_ref().map(|v| [v[0], v[1], v[2], v[3]]),
        quick: cli.quick,
    };
    let threads = cli
        .nthreads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let report = rpbrt::pipeline::render_file(&cli.file, &overrides, threads, !cli.quiet)?;
    if !cli.quiet {
        for w in &report.warnings {
            eprintln!("{w}");
        }
        if report.interrupted {
            eprintln!(
                "interrupted after {} of {} samples per pixel; wrote the partial image",
                report.spp_completed, report.spp_requested
            );
        }
        eprintln!("wrote {}", report.output.display());
    }
    if report.bad_samples > 0 {
        eprintln!(
            "warning: {} samples had NaN or infinite radiance and were set to 0",
            report.bad_samples
        );
    }
    if cli.stats {
        println!(
            "resolution {}x{}, {} spp, {} threads\nparse + build: {:.3} s\nrender: {:.3} s\nbad samples: {}",
            report.resolution.0,
            report.resolution.1,
            report.spp_completed,
            threads,
            report.parse_and_build.as_secs_f64(),
            report.render.as_secs_f64(),
            report.bad_samples
        );
    }
    Ok(())
}

/// `--format` / `--upgrade`: directives back to text, streaming.
fn format(cli: &Cli) -> Result<(), Error> {
    let mut parser = Parser::open(&cli.file)?.follow_includes(false);
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut formatter = Formatter::default();
    let io_error = |source| Error::Io {
        path: "<stdout>".to_string(),
        source,
    };
    let mut text = String::with_capacity(1 << 16);
    for directive in parser.by_ref() {
        formatter.write(&directive?.directive, &mut text);
        if text.len() >= 1 << 16 {
            out.write_all(text.as_bytes()).map_err(io_error)?;
            text.clear();
        }
    }
    out.write_all(text.as_bytes()).map_err(io_error)?;
    out.flush().map_err(io_error)?;
    if !cli.quiet {
        for w in parser.take_warnings() {
            eprintln!("{w}");
        }
    }
    Ok(())
}
