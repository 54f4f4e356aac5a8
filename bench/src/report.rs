//! `rpbrt report`: measures and writes `docs/performance.md`.
//!
//! For every scene of the table in `../shared/refs/README.md` it runs the
//! convergence measurement ([`super::convergence`]) at pbrt-v4's listed
//! sample counts, finds the time rpbrt needs to reach pbrt-v4's error at
//! each (interpolated on rpbrt's log–log error-over-time curve) and divides
//! it by pbrt-v4's time; it adds parse and build times, peak memory (a
//! child `rpbrt --stats` process at 1 spp), the dual-model overhead in the
//! form of the paper's Table 2, and the machine and commit. Every figure is
//! measured by this command; the hand-written notes live in
//! `docs/performance-notes.md`, which the report links to. The report's
//! prose is `bench/templates/report.md`; this file computes the figures
//! and formats the tables' rows.

use crate::child::{measure, Program, RenderSettings};
use crate::convergence::{self, curve, time_at_error, Measurement, Renderer, Run};
use crate::dual_overhead;
use crate::error::{io_error, Error};
use crate::provenance::{build_kind, commit, machine, median, today};
use crate::steal::time_without_steal;
use crate::template::Template;
use rpbrt::image::Image;
use rpbrt::pipeline::render_file;
use rpbrt::scene::build::RenderOverrides;
use rpbrt::tools::imgdiff::{block_bias, mrse};
use rpbrt::tools::plot::{Series, ORANGE};
use std::fmt::Display;
use std::path::{Path, PathBuf};

/// The report's prose.
const TEMPLATE: Template = Template {
    name: "bench/templates/report.md",
    text: include_str!("../templates/report.md"),
};

/// Measure every shared reference scene against pbrt-v4 and write the
/// performance report. Takes tens of minutes at the default settings: run
/// it on an otherwise idle machine.
#[derive(clap::Args, Debug)]
pub struct ReportArgs {
    /// The report to write.
    #[arg(long, default_value = "docs/performance.md")]
    pub out: PathBuf,
    /// The shared data folder (holds refs/ and scenes/derived/).
    #[arg(long, default_value = "../shared")]
    pub shared: PathBuf,
    /// Renders (seeds) per sample count.
    #[arg(long, default_value_t = 3)]
    pub repeat: u32,
    /// Render threads (pbrt-v4's figures were measured with 2).
    #[arg(long, default_value_t = 2)]
    pub nthreads: usize,
    /// Render at most this many samples per pixel (for a quick trial of the
    /// report; the figures are then not comparable).
    #[arg(long)]
    pub max_spp: Option<u32>,
    /// Only these scenes (names from the refs table), comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub scenes: Option<Vec<String>>,
    /// Also run this pbrt-v4 binary in the same run (same spp, seeds,
    /// threads), for same-machine, same-time ratios.
    #[arg(long)]
    pub pbrt: Option<PathBuf>,
    /// Where renders and CSV files go.
    #[arg(long, default_value = "target/performance")]
    pub work: PathBuf,
    /// Take each scene's renders from the CSV an earlier run left in
    /// `--work` instead of rendering again (the dual-model table and peak
    /// memory are measured anew): to rewrite the report after a change to
    /// the dual model or to the report itself.
    #[arg(long)]
    pub reuse: bool,
    /// Samples per pixel of the dual-model (Table 2) renders.
    #[arg(long, default_value_t = 32)]
    pub dual_spp: u32,
    /// Rounds of the dual-model renders (each round renders every pair
    /// once, with its own seed).
    #[arg(long, default_value_t = 10)]
    pub dual_repeat: u32,
    /// Measure only the dual-model table and put it in place of the one in
    /// `--out` (the rest of the report is kept as it is).
    #[arg(long)]
    pub dual_only: bool,
}

/// One row of the refs README's figures table.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceRow {
    pub scene: String,
    pub spp: u32,
    /// pbrt-v4's quiet median of 3 runs, where measured.
    pub quiet_seconds: Option<f64>,
    /// pbrt-v4's time as rendered (other work may have shared the machine).
    pub rendered_seconds: f64,
    pub mrse: f64,
    pub block_bias: Option<f64>,
}

impl ReferenceRow {
    /// pbrt-v4's time to compare with: the quiet median where there is one,
    /// and which it is.
    fn time(&self) -> (f64, &'static str) {
        self.quiet_seconds
            .map_or((self.rendered_seconds, " (as rendered)"), |q| {
                (q, " (quiet)")
            })
    }
}

/// The figures table of `../shared/refs/README.md`: rows of `| scene |
/// ref spp | spp | quiet s | as-rendered s | MRSE | block bias |`.
pub fn parse_reference_table(readme: &str) -> Vec<ReferenceRow> {
    readme
        .lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line
                .trim()
                .trim_matches('|')
                .split('|')
                .map(str::trim)
                .collect();
            if cells.len() != 7 {
                return None;
            }
            Some(ReferenceRow {
                scene: cells[0].to_string(),
                spp: cells[2].parse().ok()?,
                quiet_seconds: cells[3].parse().ok(),
                rendered_seconds: cells[4].parse().ok()?,
                mrse: cells[5].parse().ok()?,
                block_bias: cells[6].parse().ok(),
            })
        })
        .collect()
}

/// Peak memory (MB) of a child `rpbrt` render of `scene` at 1 spp, as the
/// operating system counts it (`child.rs`).
fn peak_memory_mb(scene: &Path, threads: usize, out: &Path) -> Option<u64> {
    let settings = RenderSettings {
        threads,
        spp: Some(1),
        seed: None,
    };
    Program::rpbrt()
        .and_then(|rpbrt| measure(&rpbrt, scene, settings, out))
        .map(|measured| measured.peak_mb.round() as u64)
        .map_err(|e| eprintln!("peak memory not measured: {e}"))
        .ok()
}

/// What the report says about one scene.
struct SceneResult {
    name: String,
    runs: Vec<Run>,
    rows: Vec<ReferenceRow>,
    peak_mb: Option<u64>,
    plot: String,
    /// Per rpbrt run (same order as `runs`): block bias against the
    /// reference, from the run's saved render.
    block_bias: Vec<Option<f64>>,
    /// rpbrt at pbrt-v4's seed, per listed spp.
    same_seed: Vec<SameSeed>,
}

/// The seed of pbrt-v4's N-spp renders in `../shared/refs/`.
const PBRT_SEED: i32 = 2;

/// rpbrt rendered at pbrt-v4's seed and spp: the README's figures, and how
/// far the image is from pbrt-v4's render of the same samples.
struct SameSeed {
    spp: u32,
    mrse: f64,
    block_bias: f64,
    /// MRSE against pbrt-v4's own render at that spp.
    from_pbrt: f64,
    /// pbrt-v4's render's MRSE and block bias against the reference.
    pbrt_mrse: f64,
    pbrt_block_bias: f64,
    /// Whole-render seconds, steal removed (kept beside the image for
    /// `--reuse`).
    seconds: Option<f64>,
}

impl SameSeed {
    /// The README's block-bias bound, from pbrt-v4's image.
    fn bound(&self) -> f64 {
        (2.0 * self.pbrt_block_bias).max(0.01)
    }

    /// The README's rule: MRSE ≤ 1.25 × pbrt-v4's, block bias within bound.
    fn passes(&self) -> bool {
        self.mrse <= 1.25 * self.pbrt_mrse && self.block_bias <= self.bound()
    }
}

/// Renders `scene` at pbrt-v4's seed at each listed spp (or, with
/// `--reuse`, reads the previous run's render) and compares it with the
/// reference and with pbrt-v4's render. Rows whose images are missing are
/// left out.
fn same_seed_rows(
    args: &ReportArgs,
    name: &str,
    scene: &Path,
    spp: &[u32],
    work: &Path,
    threads: usize,
) -> Vec<SameSeed> {
    let refs = args.shared.join("refs");
    let Ok(reference) = Image::read(refs.join(format!("{name}-ref.exr"))) else {
        return Vec::new();
    };
    let (w, h) = (reference.width() as usize, reference.height() as usize);
    let r = reference.rgb_data();
    let mut rows = Vec::new();
    for &n in spp {
        let Ok(pbrt) = Image::read(refs.join(format!("{name}-{n}.exr"))) else {
            continue;
        };
        let out = work.join(format!("rpbrt-{n}spp-pbrt-seed.exr"));
        let timing = out.with_extension("seconds");
        if !(args.reuse && out.exists()) {
            eprintln!("{name}: {n} spp at pbrt-v4's seed");
            let overrides = RenderOverrides {
                spp: Some(n),
                seed: Some(PBRT_SEED),
                outfile: Some(out.clone()),
                ..Default::default()
            };
            let (result, seconds, _) =
                time_without_steal(|| render_file(scene, &overrides, threads, false));
            if let Err(e) = result {
                eprintln!("{name}: {n} spp at pbrt-v4's seed: {e}");
                continue;
            }
            std::fs::write(&timing, format!("{seconds}\n")).ok();
        }
        let seconds = std::fs::read_to_string(&timing)
            .ok()
            .and_then(|t| t.trim().parse::<f64>().ok());
        let Ok(ours) = Image::read(&out) else {
            continue;
        };
        let (x, p) = (ours.rgb_data(), pbrt.rgb_data());
        if x.len() != r.len() || p.len() != r.len() {
            continue;
        }
        rows.push(SameSeed {
            spp: n,
            mrse: mrse(&x, &r),
            block_bias: block_bias(&x, &r, w, h, 3, 16),
            from_pbrt: mrse(&x, &p),
            pbrt_mrse: mrse(&p, &r),
            pbrt_block_bias: block_bias(&p, &r, w, h, 3, 16),
            seconds,
        });
    }
    rows
}

/// Block bias (../shared/refs/README.md) of each run's saved render
/// against the reference; `None` where the render is not there.
fn block_biases(work: &Path, reference: &Path, runs: &[Run]) -> Vec<Option<f64>> {
    let Ok(reference) = Image::read(reference) else {
        return vec![None; runs.len()];
    };
    let (w, h) = (reference.width() as usize, reference.height() as usize);
    let reference = reference.rgb_data();
    runs.iter()
        .map(|run| {
            let path = work.join("renders").join(format!(
                "{}-{}spp-seed{}.exr",
                run.renderer.name(),
                run.spp,
                run.seed
            ));
            let image = Image::read(&path).ok()?.rgb_data();
            (image.len() == reference.len()).then(|| block_bias(&image, &reference, w, h, 3, 16))
        })
        .collect()
}

/// Formats a ratio with the goal it is held to.
fn ratio_text(ratio: f64, extrapolated: bool) -> String {
    format!(
        "{ratio:.2}×{}",
        if extrapolated { " (extrap.)" } else { "" }
    )
}

/// The dual-model table ([`dual_overhead`]).
fn dual_model_section(args: &ReportArgs) -> Result<String, Error> {
    dual_overhead::section(&dual_overhead::Settings {
        spp: args.dual_spp,
        rounds: args.dual_repeat,
        shared: &args.shared,
        work: &args.work,
    })
}

pub fn run(args: &ReportArgs) -> Result<(), Error> {
    if args.dual_only {
        let old = std::fs::read_to_string(&args.out).map_err(io_error(&args.out))?;
        let text = dual_overhead::splice(&old, &dual_model_section(args)?);
        std::fs::write(&args.out, text).map_err(io_error(&args.out))?;
        eprintln!("wrote the dual-model table into {}", args.out.display());
        return Ok(());
    }
    let readme_path = args.shared.join("refs/README.md");
    let readme = std::fs::read_to_string(&readme_path).map_err(io_error(&readme_path))?;
    let table = parse_reference_table(&readme);
    let mut names: Vec<String> = Vec::new();
    for row in &table {
        if !names.contains(&row.scene) {
            names.push(row.scene.clone());
        }
    }
    if let Some(only) = &args.scenes {
        names.retain(|n| only.contains(n));
    }
    let docs = args.out.parent().unwrap_or(Path::new("."));
    let plots = docs.join("performance");
    std::fs::create_dir_all(&plots).map_err(io_error(&plots))?;
    let threads = args.nthreads.max(1);

    let mut results = Vec::new();
    let mut skipped = Vec::new();
    for name in &names {
        let rows: Vec<ReferenceRow> = table.iter().filter(|r| &r.scene == name).cloned().collect();
        let scene = args.shared.join(format!("scenes/derived/{name}.pbrt"));
        let reference = args.shared.join(format!("refs/{name}-ref.exr"));
        let mut spp: Vec<u32> = rows.iter().map(|r| r.spp).collect();
        if let Some(max) = args.max_spp {
            spp.iter_mut().for_each(|s| *s = (*s).min(max));
            spp.dedup();
        }
        let work = args.work.join(name);
        if args.reuse {
            eprintln!("{name}: the renders of the previous run");
        } else {
            eprintln!(
                "{name}: rendering at {spp:?} spp, {} seeds each",
                args.repeat
            );
        }
        let m = Measurement {
            scene: &scene,
            reference: &reference,
            spp: &spp,
            repeat: args.repeat,
            threads,
            pbrt: args.pbrt.as_deref(),
            out: &work,
            progress: true,
        };
        let previous = work.join("convergence.csv");
        let measured = if args.reuse {
            std::fs::read_to_string(&previous)
                .map_err(|e| e.to_string())
                .and_then(|text| convergence::parse_csv(&text))
                .map_err(|e| Error::Usage(format!("--reuse: {}: {e}", previous.display())))
        } else {
            convergence::measure(&m)
        };
        let runs = match measured {
            Ok(runs) => runs,
            Err(e) => {
                eprintln!("{name}: skipped: {e}");
                skipped.push(format!("{name}: {e}"));
                continue;
            }
        };
        // pbrt-v4's listed figures, as a curve beside the measured ones.
        let listed = Series {
            label: "pbrt-v4 (listed)".into(),
            colour: ORANGE.map(|c| 0.5 + 0.5 * c),
            points: rows
                .iter()
                .map(|r| (r.quiet_seconds.unwrap_or(r.rendered_seconds), r.mrse))
                .collect(),
        };
        convergence::write_results(&work, name, &runs, vec![listed])?;
        let plot_name = format!("{name}-convergence.png");
        let plot = plots.join(&plot_name);
        std::fs::copy(work.join("convergence.png"), &plot).map_err(io_error(&plot))?;
        let peak_mb = peak_memory_mb(&scene, threads, &work.join("peak-memory.exr"));
        let block_bias = block_biases(&work, &reference, &runs);
        let same_seed = same_seed_rows(args, name, &scene, &spp, &work, threads);
        results.push(SceneResult {
            name: name.clone(),
            block_bias,
            same_seed,
            runs,
            rows,
            peak_mb,
            plot: plot_name,
        });
    }
    let dual = dual_model_section(args)?;
    let mut text = markdown(args, &results, &skipped, &dual)?;
    // The curve-file table (`rpbrt curves --out`) is measured apart: kept.
    if let Ok(old) = std::fs::read_to_string(&args.out) {
        if let Some(section) = crate::curves::section_of(&old) {
            text = crate::curves::splice_section(
                &text,
                crate::curves::HEADING,
                section,
                dual_overhead::HEADING,
            );
        }
    }
    std::fs::write(&args.out, text).map_err(io_error(&args.out))?;
    eprintln!("wrote {}", args.out.display());
    Ok(())
}

/// An optional block of the template: the blank line before it and the
/// filled part, or nothing.
fn block(part: &str, values: &[(&str, &dyn Display)]) -> Result<String, Error> {
    Ok(format!("\n\n{}", TEMPLATE.fill(part, values)?.trim_end()))
}

/// A phrase of the template set inside a sentence (with its space).
fn phrase(part: &str) -> Result<String, Error> {
    Ok(format!(" {}", TEMPLATE.fill(part, &[])?.trim()))
}

/// The report: the template's prose around the measured figures.
fn markdown(
    args: &ReportArgs,
    results: &[SceneResult],
    skipped: &[String],
    dual: &str,
) -> Result<String, Error> {
    let trial = match args.max_spp {
        Some(m) => format!(" {}", TEMPLATE.fill("trial", &[("max_spp", &m)])?.trim()),
        None => String::new(),
    };
    let reuse = if args.reuse {
        phrase("reuse")?
    } else {
        String::new()
    };
    let same_run = if args.pbrt.is_some() {
        phrase("same_run")?
    } else {
        String::new()
    };
    let summary: Vec<String> = results.iter().map(summary_row).collect();
    let skipped = skipped
        .iter()
        .map(|reason| block("skipped", &[("reason", reason)]))
        .collect::<Result<String, Error>>()?;
    let scenes = results
        .iter()
        .map(scene_section)
        .collect::<Result<Vec<String>, Error>>()?;
    TEMPLATE.fill(
        "report",
        &[
            ("date", &today()),
            ("machine", &machine()),
            ("commit", &commit()),
            ("build", &build_kind()),
            ("threads", &args.nthreads),
            ("seeds", &args.repeat.max(1)),
            ("trial", &trial),
            ("reuse", &reuse),
            ("same_run", &same_run),
            ("summary", &summary.join("\n")),
            ("skipped", &skipped),
            ("scenes", &scenes.join("\n\n")),
            ("dual", &dual.trim_end()),
        ],
    )
}

/// rpbrt's curve as (seconds, MRSE) points.
fn rpbrt_points(runs: &[Run]) -> Vec<(f64, f64)> {
    curve(runs, Renderer::Rpbrt)
        .iter()
        .map(|&(_, s, e)| (s, e))
        .collect()
}

/// A scene's row of the summary table.
fn summary_row(r: &SceneResult) -> String {
    let hair = r.name.starts_with("hair");
    let points = rpbrt_points(&r.runs);
    // At the listed spp that has a quiet median: against pbrt-v4 timed in
    // this run (its time and MRSE averaged over the same seeds as rpbrt's)
    // where it was, else against the README's one draw and quiet median.
    let pbrt_curve = curve(&r.runs, Renderer::Pbrt);
    let headline = r
        .rows
        .iter()
        .find(|row| row.quiet_seconds.is_some())
        .and_then(|row| {
            let (seconds, mrse, against) = match pbrt_curve.iter().find(|p| p.0 == row.spp) {
                Some(&(_, s, e)) => (s, e, "same run"),
                None => (row.quiet_seconds?, row.mrse, "README's quiet median"),
            };
            time_at_error(&points, mrse).map(|(s, x)| (s / seconds, x, row.spp, against))
        });
    // Issue 27's goal for hair (issue 6 asked for 0.5×).
    let goal = if hair { 0.4 } else { 1.0 };
    // Against a same-run pbrt-v4: the spread over all its sample counts.
    let same_run_ratios: Vec<f64> = pbrt_curve
        .iter()
        .filter_map(|&(_, s, e)| time_at_error(&points, e).map(|(o, _)| o / s))
        .collect();
    let spread = match (
        same_run_ratios.iter().copied().reduce(f64::min),
        same_run_ratios.iter().copied().reduce(f64::max),
        pbrt_curve.first(),
        pbrt_curve.last(),
    ) {
        (Some(lo), Some(hi), Some(first), Some(last)) if same_run_ratios.len() > 1 => {
            format!("; {lo:.2}–{hi:.2}× over {}–{} spp", first.0, last.0)
        }
        _ => String::new(),
    };
    let ratio = headline.map_or("—".into(), |(ratio, x, spp, against)| {
        format!(
            "{} at pbrt's {spp} spp ({against}{spread}){}",
            ratio_text(ratio, x),
            if ratio <= goal { " ✓" } else { "" }
        )
    });
    let of = |f: fn(&Run) -> Option<f64>| {
        median(r.runs.iter().filter_map(f).collect()).map_or("—".into(), |v| format!("{v:.3}"))
    };
    let rule = if r.same_seed.is_empty() {
        "—".to_string()
    } else {
        let spp: Vec<String> = r.same_seed.iter().map(|row| row.spp.to_string()).collect();
        let failed: Vec<String> = r
            .same_seed
            .iter()
            .filter(|row| !row.passes())
            .map(|row| row.spp.to_string())
            .collect();
        if failed.is_empty() {
            format!("✓ at {} spp", spp.join(", "))
        } else {
            format!("✗ at {} spp", failed.join(", "))
        }
    };
    format!(
        "| {} | {} | {ratio} | ≤ {goal}× | {rule} | {} | {} | {} |",
        r.name,
        if hair { "hair" } else { "other" },
        of(|r| r.parse_seconds),
        of(|r| r.build_seconds),
        r.peak_mb.map_or("—".into(), |mb| format!("{mb} MB"))
    )
}

/// A scene's section: its plot and tables.
fn scene_section(r: &SceneResult) -> Result<String, Error> {
    let mut runs = Vec::new();
    for renderer in [Renderer::Rpbrt, Renderer::Pbrt] {
        for (spp, s, e) in curve(&r.runs, renderer) {
            let stolen: Vec<f64> = r
                .runs
                .iter()
                .filter(|run| run.renderer == renderer && run.spp == spp)
                .map(|run| run.stolen_seconds)
                .collect();
            let stolen = stolen.iter().sum::<f64>() / stolen.len().max(1) as f64;
            runs.push(format!(
                "| {} (this run) | {spp} | {s:.3} | {stolen:.3} | {e:.6} |",
                renderer.name()
            ));
        }
    }
    for row in &r.rows {
        let (s, which) = row
            .quiet_seconds
            .map_or((row.rendered_seconds, "as rendered"), |q| {
                (q, "quiet median")
            });
        runs.push(format!(
            "| pbrt-v4 (refs README, {which}) | {} | {s:.3} | — | {:.6} |",
            row.spp, row.mrse
        ));
    }
    let points = rpbrt_points(&r.runs);
    let pbrt_curve = curve(&r.runs, Renderer::Pbrt);
    // Ratios against the README's times only where pbrt-v4 was not timed
    // in this run (those times were taken on another day, some under load).
    let readme_ratios = if pbrt_curve.is_empty() {
        let rows: Vec<String> = r
            .rows
            .iter()
            .map(|row| {
                let (s, which) = row.time();
                let ours = time_at_error(&points, row.mrse);
                format!(
                    "| {} | {:.6} | {s:.2}{which} | {} | {} |",
                    row.spp,
                    row.mrse,
                    ours.map_or("—".into(), |(o, _)| format!("{o:.2}")),
                    ours.map_or("—".into(), |(o, x)| ratio_text(o / s, x))
                )
            })
            .collect();
        block("readme_ratios", &[("rows", &rows.join("\n"))])?
    } else {
        String::new()
    };
    let accuracy: Vec<String> = r
        .rows
        .iter()
        .filter_map(|row| accuracy_row(r, row))
        .collect();
    let same_seed = if r.same_seed.is_empty() {
        String::new()
    } else {
        let rows: Vec<String> = r
            .same_seed
            .iter()
            .map(|row| same_seed_row(r, row))
            .collect();
        block(
            "same_seed",
            &[("seed", &PBRT_SEED), ("rows", &rows.join("\n"))],
        )?
    };
    let same_run = if pbrt_curve.is_empty() {
        String::new()
    } else {
        let rows: Vec<String> = pbrt_curve
            .into_iter()
            .map(|(spp, s, e)| {
                let ours = time_at_error(&points, e);
                format!(
                    "| {spp} | {s:.2} | {e:.6} | {} | {} |",
                    ours.map_or("—".into(), |(o, _)| format!("{o:.2}")),
                    ours.map_or("—".into(), |(o, x)| ratio_text(o / s, x))
                )
            })
            .collect();
        block("same_run_table", &[("rows", &rows.join("\n"))])?
    };
    Ok(TEMPLATE
        .fill(
            "scene",
            &[
                ("name", &r.name),
                ("plot", &r.plot),
                ("runs", &runs.join("\n")),
                ("readme_ratios", &readme_ratios),
                ("accuracy", &accuracy.join("\n")),
                ("same_seed", &same_seed),
                ("same_run", &same_run),
            ],
        )?
        .trim_end()
        .to_string())
}

/// A row of a scene's accuracy table: rpbrt's seeds at one of pbrt-v4's
/// sample counts (None where rpbrt has no render there).
fn accuracy_row(r: &SceneResult, row: &ReferenceRow) -> Option<String> {
    let ours: Vec<(f64, Option<f64>)> = r
        .runs
        .iter()
        .zip(&r.block_bias)
        .filter(|(run, _)| run.renderer == Renderer::Rpbrt && run.spp == row.spp)
        .map(|(run, bias)| (run.mrse, *bias))
        .collect();
    if ours.is_empty() {
        return None;
    }
    let mean = ours.iter().map(|o| o.0).sum::<f64>() / ours.len() as f64;
    let worst = ours.iter().map(|o| o.0).fold(0.0, f64::max);
    let worst_bias = ours
        .iter()
        .filter_map(|o| o.1)
        .fold(None, |m: Option<f64>, b| Some(m.map_or(b, |m| m.max(b))));
    Some(format!(
        "| {} | {mean:.6} ({worst:.6}) | {:.6} | {:.2} | {} | {} | {} |",
        row.spp,
        row.mrse,
        mean / row.mrse,
        worst_bias.map_or("—".into(), |b| format!("{b:.5}")),
        row.block_bias.map_or("—".into(), |b| format!("{b:.4}")),
        row.block_bias
            .map_or("—".into(), |b| format!("{:.4}", (2.0 * b).max(0.01)))
    ))
}

/// A row of a scene's table at pbrt-v4's seed.
fn same_seed_row(r: &SceneResult, row: &SameSeed) -> String {
    // pbrt-v4 timed in this run where it was (its mean over the seeds at
    // that spp), else the README's time.
    let same_run = curve(&r.runs, Renderer::Pbrt)
        .into_iter()
        .find(|p| p.0 == row.spp)
        .map(|(_, s, _)| (s, " (this run)"));
    let pbrt_seconds =
        same_run.or_else(|| r.rows.iter().find(|x| x.spp == row.spp).map(|x| x.time()));
    let vs = match (row.seconds, pbrt_seconds) {
        (Some(ours), Some((theirs, which))) => {
            format!("{:.2}× of {theirs:.2}{which}", ours / theirs)
        }
        _ => "—".into(),
    };
    format!(
        "| {} | {:.6} | {:.6} | {:.3}{} | {:.5} | {:.4} | {:.4} | {} | {vs} |",
        row.spp,
        row.mrse,
        row.pbrt_mrse,
        row.mrse / row.pbrt_mrse,
        if row.passes() { " ✓" } else { " ✗" },
        row.block_bias,
        row.bound(),
        row.from_pbrt / row.pbrt_mrse,
        row.seconds.map_or("—".into(), |s| format!("{s:.2}"))
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_refs_table() {
        let readme = "| scene | ref spp | spp | q | r | MRSE | block bias |\n|---|---|---|---|---|---|---|\n\
                      | hair-curl-300 | 1024 | 16 | — | 1.37 | 0.001554 | 0.0032 |\n\
                      | hair-curl-300 | 1024 | 64 | 2.55 | 5.09 | 0.0003927 | 0.0022 |\n";
        let rows = parse_reference_table(readme);
        assert_eq!(rows.len(), 2);
        assert_eq!(
            rows[1],
            ReferenceRow {
                scene: "hair-curl-300".into(),
                spp: 64,
                quiet_seconds: Some(2.55),
                rendered_seconds: 5.09,
                mrse: 0.0003927,
                block_bias: Some(0.0022)
            }
        );
        assert_eq!(rows[0].quiet_seconds, None);
    }

    fn args() -> ReportArgs {
        ReportArgs {
            out: "performance.md".into(),
            shared: "../shared".into(),
            repeat: 2,
            nthreads: 2,
            max_spp: None,
            scenes: None,
            pbrt: None,
            work: "work".into(),
            reuse: false,
            dual_spp: 32,
            dual_repeat: 10,
            dual_only: false,
        }
    }

    /// A hair scene whose rpbrt error falls as 1/time (0.1 at 1 s, 0.025
    /// at 4 s), against a pbrt-v4 row of MRSE 0.05 in 4 s (quiet): rpbrt
    /// reaches 0.05 at 2 s, half pbrt-v4's time.
    fn scene(pbrt_runs: bool) -> SceneResult {
        let run = |renderer, spp, seconds, mrse| Run {
            renderer,
            spp,
            seed: 100,
            seconds,
            stolen_seconds: 0.0,
            parse_seconds: Some(0.01),
            build_seconds: Some(0.02),
            mrse,
        };
        let mut runs = vec![
            run(Renderer::Rpbrt, 16, 1.0, 0.1),
            run(Renderer::Rpbrt, 64, 4.0, 0.025),
        ];
        if pbrt_runs {
            runs.push(run(Renderer::Pbrt, 16, 3.0, 0.05));
        }
        SceneResult {
            name: "hair-test".into(),
            block_bias: vec![Some(0.001); runs.len()],
            runs,
            rows: vec![ReferenceRow {
                scene: "hair-test".into(),
                spp: 16,
                quiet_seconds: Some(4.0),
                rendered_seconds: 5.0,
                mrse: 0.05,
                block_bias: Some(0.002),
            }],
            peak_mb: Some(42),
            plot: "hair-test-convergence.png".into(),
            same_seed: vec![SameSeed {
                spp: 16,
                mrse: 0.05,
                block_bias: 0.003,
                from_pbrt: 0.0,
                pbrt_mrse: 0.05,
                pbrt_block_bias: 0.002,
                seconds: Some(2.0),
            }],
        }
    }

    #[test]
    fn the_report_puts_the_figures_into_the_prose() {
        let text = markdown(
            &args(),
            &[scene(false)],
            &[],
            "## Dual model overhead\n\nT\n",
        )
        .unwrap();
        assert!(!text.contains("{{"), "{text}");
        // The equal-error ratio: 2 s against pbrt-v4's 4 s, within the
        // hair goal.
        assert!(
            text.contains("| hair-test | hair | 0.50× at pbrt's 16 spp (README's quiet median) | ≤ 0.4× | ✓ at 16 spp | 0.010 | 0.020 | 42 MB |"),
            "{text}"
        );
        assert!(
            text.contains("| 16 | 0.050000 | 4.00 (quiet) | 2.00 | 0.50× |"),
            "{text}"
        );
        // Seed 2's block bias 0.003 is within max(2 × 0.002, 0.01).
        assert!(text.contains("| 16 | 0.050000 | 0.050000 | 1.000 ✓ | 0.00300 | 0.0100 | 0.0000 | 2.00 | 0.50× of 4.00 (quiet) |"), "{text}");
        assert!(
            text.contains("2 render threads, 2 seeds per sample count. Hand-written"),
            "{text}"
        );
        assert!(
            !text.contains("Same run, against")
                && !text.contains("Skipped")
                && !text.contains("trial run")
        );
        assert!(text.ends_with("## Dual model overhead\n\nT\n"), "{text}");
        // Sections follow each other after one blank line.
        assert!(!text.contains("\n\n\n"), "{text}");
    }

    #[test]
    fn every_optional_part_fills() {
        let args = ReportArgs {
            max_spp: Some(8),
            reuse: true,
            pbrt: Some("pbrt".into()),
            ..args()
        };
        let text = markdown(&args, &[scene(true), scene(true)], &["x: why".into()], "D").unwrap();
        assert!(!text.contains("{{"), "{text}");
        assert!(
            text.contains("sample count — **trial run capped at 8 spp"),
            "{text}"
        );
        assert!(
            text.contains("pbrt-v4's** (the scenes' renders taken"),
            "{text}"
        );
        assert!(
            text.contains("there instead. With `--pbrt`, pbrt-v4"),
            "{text}"
        );
        assert!(
            text.contains("\n\nSkipped: x: why\n\n## hair-test\n"),
            "{text}"
        );
        assert_eq!(
            text.matches("Same run, against the pbrt-v4 binary").count(),
            2
        );
        // pbrt-v4's same-run 0.05 in 3 s: rpbrt's 2 s is 0.67× of it,
        // in the scene's table and in the summary (not the README's 4 s).
        assert!(
            text.contains("| 16 | 3.00 | 0.050000 | 2.00 | 0.67× |"),
            "{text}"
        );
        assert!(
            text.contains("| hair-test | hair | 0.67× at pbrt's 16 spp (same run) | ≤ 0.4× |"),
            "{text}"
        );
        // With pbrt-v4 in the run, no ratio is taken against the README's
        // times: the scene has no README ratio table, and rpbrt at
        // pbrt-v4's seed (2 s) is set against the same-run 3 s.
        assert!(!text.contains("4.00 (quiet)"), "{text}");
        assert!(
            text.contains("| 2.00 | 0.67× of 3.00 (this run) |"),
            "{text}"
        );
        assert!(!text.contains("\n\n\n"), "{text}");
    }
}
