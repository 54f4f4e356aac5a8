//! `rpbrt convergence`: error against time. Renders a scene at several
//! sample counts (several seeds each), measures each render's whole time
//! and its MRSE against a reference, and writes `convergence.csv` and a
//! log–log plot `convergence.png` — with a pbrt-v4 binary's curve beside
//! rpbrt's when one is given.
//!
//! Timing: rpbrt renders run in this process and are timed around the
//! whole of [`render_file`] (parse, build, render, write the EXR, drop the
//! scene), so process start-up (a few ms) is not counted. pbrt-v4 runs as a
//! child process timed from spawn to exit (its whole process).

use crate::error::{io_error, Error};
use crate::steal::time_without_steal;
use rpbrt::image::Image;
use rpbrt::pipeline::render_file;
use rpbrt::scene::build::RenderOverrides;
use rpbrt::tools::imgdiff::mrse;
use rpbrt::tools::plot::{log_log_plot, Series, BLUE, ORANGE};
use rpbrt::tools::progress_bar;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Render a scene at several sample counts and plot its error (MRSE
/// against the reference) over its time, log–log.
#[derive(clap::Args, Debug)]
pub struct ConvergenceArgs {
    /// Scene file.
    pub scene: PathBuf,
    /// Reference image the renders are compared with.
    #[arg(long)]
    pub reference: PathBuf,
    /// Samples per pixel to render at, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [1u32, 4, 16, 64, 256])]
    pub spp: Vec<u32>,
    /// Renders (seeds) per sample count; time and MRSE are averaged.
    #[arg(long, default_value_t = 1)]
    pub repeat: u32,
    /// Also run this pbrt-v4 binary, same spp, seeds and threads.
    #[arg(long)]
    pub pbrt: Option<PathBuf>,
    /// Render threads (default: all cores).
    #[arg(long)]
    pub nthreads: Option<usize>,
    /// Output directory (created): convergence.csv, convergence.png, renders/.
    #[arg(long)]
    pub out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// Which renderer made a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Renderer {
    Rpbrt,
    Pbrt,
}

impl Renderer {
    pub fn name(self) -> &'static str {
        match self {
            Renderer::Rpbrt => "rpbrt",
            Renderer::Pbrt => "pbrt-v4",
        }
    }
}

/// One render.
#[derive(Clone, Debug)]
pub struct Run {
    pub renderer: Renderer,
    pub spp: u32,
    pub seed: i32,
    /// Whole render, wall clock less the time the virtual machine's CPUs
    /// were stolen meanwhile (see [`crate::steal`]); curves and ratios use
    /// this.
    pub seconds: f64,
    /// Of the wall clock, the time lost to steal.
    pub stolen_seconds: f64,
    /// rpbrt only: reading the scene, and building it (shapes, BVH).
    pub parse_seconds: Option<f64>,
    pub build_seconds: Option<f64>,
    pub mrse: f64,
}

/// What to measure.
pub struct Measurement<'a> {
    pub scene: &'a Path,
    pub reference: &'a Path,
    pub spp: &'a [u32],
    pub repeat: u32,
    pub threads: usize,
    pub pbrt: Option<&'a Path>,
    /// Renders go to `out/renders/`.
    pub out: &'a Path,
    pub progress: bool,
}

/// The seed of the `k`-th repeat; away from the seeds the shared
/// references were rendered with (1 and 2).
pub(crate) fn seed(k: u32) -> i32 {
    100 + k as i32
}

/// Renders every (renderer, spp, seed) and measures time and MRSE.
pub fn measure(m: &Measurement) -> Result<Vec<Run>, Error> {
    let reference = Image::read(m.reference)?;
    let reference_rgb = reference.rgb_data();
    let renders = m.out.join("renders");
    std::fs::create_dir_all(&renders).map_err(io_error(&renders))?;
    let renderers: Vec<Renderer> = std::iter::once(Renderer::Rpbrt)
        .chain(m.pbrt.map(|_| Renderer::Pbrt))
        .collect();
    let total = (renderers.len() * m.spp.len() * m.repeat as usize) as u64;
    let bar = progress_bar(
        total,
        "{bar:30} {pos}/{len} renders, {elapsed} {msg}",
        m.progress,
    );
    let mut runs = Vec::new();
    for &spp in m.spp {
        for k in 0..m.repeat.max(1) {
            for &renderer in &renderers {
                let seed = seed(k);
                bar.set_message(format!("{} {spp} spp seed {seed}", renderer.name()));
                let out = renders.join(format!("{}-{spp}spp-seed{seed}.exr", renderer.name()));
                let (timings, seconds, stolen_seconds) =
                    time_without_steal(|| match (renderer, m.pbrt) {
                        (Renderer::Pbrt, Some(pbrt)) => {
                            run_pbrt(pbrt, m, spp, seed, &out).map(|()| (None, None))
                        }
                        _ => {
                            let overrides = RenderOverrides {
                                spp: Some(spp),
                                seed: Some(seed),
                                outfile: Some(out.clone()),
                                ..Default::default()
                            };
                            render_file(m.scene, &overrides, m.threads, false)
                                .map(|r| (Some(r.parse.as_secs_f64()), Some(r.build.as_secs_f64())))
                                .map_err(Error::from)
                        }
                    });
                let (parse_seconds, build_seconds) = timings?;
                let image = Image::read(&out)?;
                if (image.width(), image.height()) != (reference.width(), reference.height()) {
                    return Err(Error::Usage(format!(
                        "{} is {}×{} but the reference {} is {}×{}",
                        out.display(),
                        image.width(),
                        image.height(),
                        m.reference.display(),
                        reference.width(),
                        reference.height()
                    )));
                }
                runs.push(Run {
                    renderer,
                    spp,
                    seed,
                    seconds,
                    stolen_seconds,
                    parse_seconds,
                    build_seconds,
                    mrse: mrse(&image.rgb_data(), &reference_rgb),
                });
                bar.inc(1);
            }
        }
    }
    bar.finish_and_clear();
    Ok(runs)
}

/// Runs pbrt-v4 from the scene's folder (as the shared references were
/// made).
fn run_pbrt(pbrt: &Path, m: &Measurement, spp: u32, seed: i32, out: &Path) -> Result<(), Error> {
    let absolute = |p: &Path| std::path::absolute(p).map_err(io_error(p));
    let scene = absolute(m.scene)?;
    let out = absolute(out)?;
    let folder = scene.parent().unwrap_or(Path::new("."));
    let output = std::process::Command::new(pbrt)
        .current_dir(folder)
        .args([
            "--quiet",
            "--nthreads",
            &m.threads.to_string(),
            "--spp",
            &spp.to_string(),
        ])
        .args(["--seed", &seed.to_string(), "--outfile"])
        .arg(&out)
        .arg(&scene)
        .output()
        .map_err(io_error(pbrt))?;
    if !output.status.success() {
        return Err(Error::Usage(format!(
            "{} failed ({}): {}",
            pbrt.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        )));
    }
    Ok(())
}

/// A renderer's curve: per sample count, the mean seconds and mean MRSE
/// over its seeds, in increasing sample count.
pub fn curve(runs: &[Run], renderer: Renderer) -> Vec<(u32, f64, f64)> {
    let mut spps: Vec<u32> = runs
        .iter()
        .filter(|r| r.renderer == renderer)
        .map(|r| r.spp)
        .collect();
    spps.sort_unstable();
    spps.dedup();
    spps.into_iter()
        .map(|spp| {
            let of: Vec<&Run> = runs
                .iter()
                .filter(|r| r.renderer == renderer && r.spp == spp)
                .collect();
            let n = of.len() as f64;
            (
                spp,
                of.iter().map(|r| r.seconds).sum::<f64>() / n,
                of.iter().map(|r| r.mrse).sum::<f64>() / n,
            )
        })
        .collect()
}

/// The time at which a curve of (seconds, error) points reaches `error`,
/// interpolated linearly in log time and log error between the two points
/// that bracket it; beyond the curve's ends, the end segment is extended
/// (then `extrapolated` is true). `None` if the curve cannot say (fewer
/// than two points with error > 0, or a flat segment).
pub fn time_at_error(points: &[(f64, f64)], error: f64) -> Option<(f64, bool)> {
    let mut logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(t, e)| *t > 0.0 && *e > 0.0)
        .map(|(t, e)| (t.ln(), e.ln()))
        .collect();
    logs.sort_by(|a, b| a.0.total_cmp(&b.0));
    if logs.len() < 2 || error <= 0.0 {
        return None;
    }
    let target = error.ln();
    let at = |(t0, e0): (f64, f64), (t1, e1): (f64, f64)| {
        (e1 != e0).then(|| (t0 + (target - e0) * (t1 - t0) / (e1 - e0)).exp())
    };
    for pair in logs.windows(2) {
        let (lo, hi) = (pair[0].1.min(pair[1].1), pair[0].1.max(pair[1].1));
        if (lo..=hi).contains(&target) {
            return at(pair[0], pair[1]).map(|t| (t, false));
        }
    }
    // Past the ends: the error falls with time, so a larger error than the
    // first point's lies before it, a smaller one after the last.
    let (first, last) = (logs[0], logs[logs.len() - 1]);
    let segment = if target > first.1.max(last.1) || (target > last.1 && first.1 > last.1) {
        (logs[0], logs[1])
    } else {
        (logs[logs.len() - 2], last)
    };
    at(segment.0, segment.1).map(|t| (t, true))
}

/// `convergence.csv`: one line per render.
pub fn csv(runs: &[Run]) -> String {
    let mut text =
        String::from("renderer,spp,seed,seconds,stolen_seconds,parse_seconds,build_seconds,mrse\n");
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.4}"));
    for r in runs {
        let _ = writeln!(
            text,
            "{},{},{},{:.4},{:.4},{},{},{:.6e}",
            r.renderer.name(),
            r.spp,
            r.seed,
            r.seconds,
            r.stolen_seconds,
            opt(r.parse_seconds),
            opt(r.build_seconds),
            r.mrse
        );
    }
    text
}

/// The log–log plot of MRSE over seconds for the runs' renderers, plus
/// `extra` curves (e.g. pbrt-v4's published figures).
pub fn plot(title: &str, runs: &[Run], extra: Vec<Series>) -> Result<Image, Error> {
    let mut series = Vec::new();
    for (renderer, colour) in [(Renderer::Rpbrt, BLUE), (Renderer::Pbrt, ORANGE)] {
        let points: Vec<(f64, f64)> = curve(runs, renderer)
            .iter()
            .map(|&(_, t, e)| (t, e))
            .collect();
        if !points.is_empty() {
            series.push(Series {
                label: renderer.name().into(),
                colour,
                points,
            });
        }
    }
    series.extend(extra);
    Ok(log_log_plot(title, "seconds", "MRSE", &series)?)
}

/// Reads back what [`csv`] wrote (the report's `--reuse`).
pub fn parse_csv(text: &str) -> Result<Vec<Run>, String> {
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    if header != "renderer,spp,seed,seconds,stolen_seconds,parse_seconds,build_seconds,mrse" {
        return Err(format!(
            "not a convergence.csv of this version (header {header:?})"
        ));
    }
    lines
        .enumerate()
        .map(|(i, line)| {
            let bad = || format!("line {}: cannot read {line:?}", i + 2);
            let f: Vec<&str> = line.split(',').collect();
            if f.len() != 8 {
                return Err(bad());
            }
            let number = |s: &str| s.parse::<f64>().map_err(|_| bad());
            let optional = |s: &str| {
                if s.is_empty() {
                    Ok(None)
                } else {
                    number(s).map(Some)
                }
            };
            Ok(Run {
                renderer: match f[0] {
                    "rpbrt" => Renderer::Rpbrt,
                    "pbrt-v4" => Renderer::Pbrt,
                    _ => return Err(bad()),
                },
                spp: f[1].parse().map_err(|_| bad())?,
                seed: f[2].parse().map_err(|_| bad())?,
                seconds: number(f[3])?,
                stolen_seconds: number(f[4])?,
                parse_seconds: optional(f[5])?,
                build_seconds: optional(f[6])?,
                mrse: number(f[7])?,
            })
        })
        .collect()
}

/// Writes `convergence.csv` and `convergence.png` into `out`.
pub fn write_results(
    out: &Path,
    title: &str,
    runs: &[Run],
    extra: Vec<Series>,
) -> Result<(), Error> {
    let csv_path = out.join("convergence.csv");
    std::fs::write(&csv_path, csv(runs)).map_err(io_error(&csv_path))?;
    plot(title, runs, extra)?.write(out.join("convergence.png"))?;
    Ok(())
}

/// The number of threads to use: `requested`, or all cores.
pub fn threads(requested: Option<usize>) -> usize {
    requested
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1)
}

pub fn run(args: &ConvergenceArgs) -> Result<(), Error> {
    if args.spp.is_empty() || args.spp.contains(&0) {
        return Err(Error::Usage(
            "--spp needs sample counts of at least 1".into(),
        ));
    }
    let m = Measurement {
        scene: &args.scene,
        reference: &args.reference,
        spp: &args.spp,
        repeat: args.repeat,
        threads: threads(args.nthreads),
        pbrt: args.pbrt.as_deref(),
        out: &args.out,
        progress: !args.quiet,
    };
    let runs = measure(&m)?;
    let title = args
        .scene
        .file_stem()
        .map_or(String::new(), |s| s.to_string_lossy().into_owned());
    write_results(&args.out, &title, &runs, Vec::new())?;
    println!("renderer  spp  seconds  MRSE");
    for renderer in [Renderer::Rpbrt, Renderer::Pbrt] {
        for (spp, seconds, error) in curve(&runs, renderer) {
            println!("{:8} {spp:4} {seconds:8.3}  {error:.6}", renderer.name());
        }
    }
    eprintln!("wrote {}", args.out.join("convergence.csv").display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_at_error_interpolates_log_log() {
        // Error ∝ 1/time: exact on the log–log line.
        let points = [(1.0, 0.1), (4.0, 0.025), (16.0, 0.00625)];
        let (t, extrapolated) = time_at_error(&points, 0.05).unwrap();
        assert!((t - 2.0).abs() < 1e-9 && !extrapolated, "{t}");
        let (t, extrapolated) = time_at_error(&points, 0.001).unwrap();
        assert!((t - 100.0).abs() < 1e-6 && extrapolated, "{t}");
        let (t, extrapolated) = time_at_error(&points, 1.0).unwrap();
        assert!((t - 0.1).abs() < 1e-9 && extrapolated, "{t}");
        assert_eq!(time_at_error(&points[..1], 0.05), None);
        assert_eq!(time_at_error(&[(1.0, 0.0), (2.0, 0.0)], 0.05), None);
    }

    #[test]
    fn curves_average_over_seeds() {
        let run = |spp, seconds, mrse| Run {
            renderer: Renderer::Rpbrt,
            spp,
            seed: 1,
            seconds,
            stolen_seconds: 0.5,
            parse_seconds: None,
            build_seconds: None,
            mrse,
        };
        let runs = [run(4, 2.0, 0.2), run(1, 1.0, 0.5), run(4, 4.0, 0.4)];
        assert_eq!(
            curve(&runs, Renderer::Rpbrt),
            [(1, 1.0, 0.5), (4, 3.0, 0.30000000000000004)]
        );
        assert!(curve(&runs, Renderer::Pbrt).is_empty());
        assert!(csv(&runs).starts_with("renderer,spp,seed,seconds,stolen_seconds,parse_seconds,build_seconds,mrse\nrpbrt,4,1,2.0000,0.5000,,,2.000000e-1\n"));
        let back = parse_csv(&csv(&runs)).unwrap();
        assert_eq!(back.len(), 3);
        assert_eq!((back[1].spp, back[1].seconds, back[1].mrse), (1, 1.0, 0.5));
        assert!(parse_csv("renderer,spp\n").is_err());
    }
}
