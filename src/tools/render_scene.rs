//! The default command, `rpbrt FILE [flags]`: render a scene with pbrt-v4's
//! flags, or check, format or upgrade it.

mod pixel_window;

pub use pixel_window::expand_comma_lists;

use crate::error::Error;
use crate::scene::build::RenderOverrides;
use pbrt_parser::{Formatter, Parser};
use std::io::Write;
use std::path::{Path, PathBuf};

/// `rpbrt FILE [flags]`: pbrt's own command line.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct RenderArgs {
    /// Scene file (.pbrt or .pbrt.gz).
    #[arg(required = true)]
    pub file: Option<PathBuf>,
    /// Print the scene in canonical pbrt-v4 syntax (Include/Import kept as
    /// they are) and exit.
    #[arg(long, conflicts_with = "upgrade")]
    pub format: bool,
    /// Print a pbrt-v3 scene as pbrt-v4 (listing each rewrite on stderr) and
    /// exit.
    #[arg(long)]
    pub upgrade: bool,
    /// Print no warnings, no progress and no summary.
    #[arg(long)]
    pub quiet: bool,
    /// Only read and check the scene; print a summary of what it contains.
    #[arg(long)]
    pub check: bool,
    /// Samples per pixel (overrides the scene's sampler).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Random seed (overrides `Option "seed"`).
    #[arg(long)]
    pub seed: Option<i32>,
    /// Render threads (default: all cores).
    #[arg(long)]
    pub nthreads: Option<usize>,
    /// Output image (.exr, .png or .pfm; overrides the film's filename).
    #[arg(long)]
    pub outfile: Option<PathBuf>,
    /// Render only this window of the image: x0,x1,y0,y1 in [0, 1] (as
    /// pbrt-v4), or x0 x1 y0 y1.
    #[arg(long, num_args = 4, value_names = ["X0", "X1", "Y0", "Y1"], allow_negative_numbers = true)]
    pub cropwindow: Option<Vec<f64>>,
    /// Render only these pixels: x0,x1,y0,y1 (as pbrt-v4), or x0 x1 y0 y1.
    #[arg(long, num_args = 4, value_names = ["X0", "X1", "Y0", "Y1"], allow_negative_numbers = true)]
    pub pixelbounds: Option<Vec<i32>>,
    /// Quick preview, as pbrt-v4: a quarter of the resolution in each axis
    /// and 1 sample per pixel (over --spp and the scene's sampler).
    #[arg(long)]
    pub quick: bool,
    /// Print timing and sample statistics after rendering.
    #[arg(long)]
    pub stats: bool,
    /// Multiplies the edge length of every displaced `plymesh` (overrides
    /// `Option "displacementedgescale"`; pbrt-v4's flag).
    #[arg(long)]
    pub displacement_edge_scale: Option<f64>,
}

/// Renders (or checks, formats, upgrades) the scene.
pub fn run(cli: &RenderArgs) -> Result<(), Error> {
    let Some(file) = &cli.file else {
        return Err(Error::Usage("no scene file given".into()));
    };
    if cli.format || cli.upgrade {
        return format(file, cli.quiet);
    }
    if cli.check {
        let loaded = crate::scene::load(file)?;
        if !cli.quiet {
            for w in &loaded.warnings {
                eprintln!("{w}");
            }
            println!("{}", loaded.scene.summary());
        }
        return Ok(());
    }
    let overrides = overrides(cli)?;
    let threads = cli
        .nthreads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let report = crate::pipeline::render_file(file, &overrides, threads, !cli.quiet)?;
    if !cli.quiet {
        for w in &report.warnings {
            eprintln!("{w}");
        }
        if report.interrupted {
            // Tiles that had started the interrupted wave finished it.
            let more = if report.spp_mean > report.spp_completed as f64 {
                format!(" ({:.1} on average)", report.spp_mean)
            } else {
                String::new()
            };
            eprintln!(
                "interrupted after {} of {} samples per pixel{more}; wrote the partial image",
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
    if report.half_clamped > 0 {
        eprintln!(
            "warning: {} channel values exceeded the half-float range and were clamped to \
             ±65504, the largest finite half, as pbrt-v4 does (the film's \
             \"bool savefp16\" false writes 32-bit floats)",
            report.half_clamped
        );
    }
    if cli.stats {
        println!(
            "resolution {}x{}, {} spp, {} threads\nparse: {:.3} s\nbuild: {:.3} s\nrender: {:.3} s{}\n\
             rays: {} closest-hit, {} shadow\nbad samples: {}\nclamped to half: {}",
            report.resolution.0,
            report.resolution.1,
            report.spp_completed,
            threads,
            report.parse.as_secs_f64(),
            report.build.as_secs_f64(),
            report.render.as_secs_f64(),
            report
                .render_cpu
                .map_or(String::new(), |c| format!(" ({:.3} s CPU)", c.as_secs_f64())),
            report.rays.closest_hit,
            report.rays.shadow,
            report.bad_samples,
            report.half_clamped
        );
        if let Some(bytes) = crate::memory::peak_memory_bytes() {
            println!("peak memory: {} MB", bytes / 1_000_000);
        }
    }
    Ok(())
}

/// The command line's overrides of the scene, checked.
fn overrides(cli: &RenderArgs) -> Result<RenderOverrides, Error> {
    Ok(RenderOverrides {
        // pbrt-v4's --quick sets every sampler's samples per pixel to 1,
        // over --spp and the scene (the resolution is quartered when the
        // film is made).
        spp: if cli.quick { Some(1) } else { cli.spp },
        seed: cli.seed,
        outfile: cli.outfile.clone(),
        crop_window: cli
            .cropwindow
            .as_deref()
            .map(pixel_window::crop_window)
            .transpose()?,
        pixel_bounds: cli
            .pixelbounds
            .as_deref()
            .map(pixel_window::pixel_bounds)
            .transpose()?,
        quick: cli.quick,
        resolution_divisor: None,
        displacement_edge_scale: cli.displacement_edge_scale,
    })
}

/// `--format` / `--upgrade`: directives back to text, streaming.
fn format(file: &Path, quiet: bool) -> Result<(), Error> {
    let mut parser = Parser::open(file)?.follow_includes(false);
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
    if !quiet {
        for w in parser.take_warnings() {
            eprintln!("{w}");
        }
    }
    Ok(())
}
