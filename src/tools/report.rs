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
//! `docs/performance-notes.md`, which the report links to.

use super::convergence::{self, curve, time_at_error, Measurement, Renderer, Run};
use super::dual_overhead;
use super::io_error;
use super::plot::{Series, ORANGE};
use super::provenance::{commit, machine, median, today};
use super::steal::time_without_steal;
use crate::error::Error;
use crate::pipeline::render_file;
use crate::scene::build::RenderOverrides;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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

/// Peak memory (MB) of a child `rpbrt --stats` render of `scene` at 1 spp.
fn peak_memory_mb(scene: &Path, threads: usize, out: &Path) -> Option<u64> {
    let exe = std::env::current_exe().ok()?;
    let output = std::process::Command::new(exe)
        .arg(scene)
        .args([
            "--spp",
            "1",
            "--quiet",
            "--stats",
            "--nthreads",
            &threads.to_string(),
            "--outfile",
        ])
        .arg(out)
        .output()
        .ok()?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    stdout.lines().find_map(|l| {
        l.strip_prefix("peak memory: ")?
            .strip_suffix(" MB")?
            .parse()
            .ok()
    })
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
    use crate::image::Image;
    use crate::tools::imgdiff::{block_bias, mrse};
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
    let Ok(reference) = crate::image::Image::read(reference) else {
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
            let image = crate::image::Image::read(&path).ok()?.rgb_data();
            (image.len() == reference.len())
                .then(|| crate::tools::imgdiff::block_bias(&image, &reference, w, h, 3, 16))
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
    let text = markdown(args, &results, &skipped, &dual);
    std::fs::write(&args.out, text).map_err(io_error(&args.out))?;
    eprintln!("wrote {}", args.out.display());
    Ok(())
}

fn markdown(args: &ReportArgs, results: &[SceneResult], skipped: &[String], dual: &str) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "# Performance\n");
    let _ = writeln!(
        t,
        "<!-- Generated by `cargo run --release -- report --out docs/performance.md` (src/tools/report.rs); \
         do not edit by hand: hand-written notes go in performance-notes.md. -->\n"
    );
    let _ = writeln!(
        t,
        "Goal (issue 6): at equal error, **≤ 0.5× pbrt-v4's time on hair scenes, ≤ 1× elsewhere**.\n\n\
         Measured {} on {} at commit {}, {} render threads, {} seeds per sample count{}. \
         Hand-written notes (profiles, benchmarks, parser figures): [performance-notes.md](performance-notes.md).\n",
        today(),
        machine(),
        commit(),
        args.nthreads,
        args.repeat.max(1),
        args.max_spp.map_or(String::new(), |m| format!(
            " — **trial run capped at {m} spp: these figures are not comparable with pbrt-v4's**"
        )) + if args.reuse {
            " (the scenes' renders taken from the previous run's CSV files with `--reuse`; the \
             dual-model table and peak memory measured at this commit)"
        } else {
            ""
        }
    );
    let _ = writeln!(
        t,
        "## How it is measured\n\n\
         - Scenes, references and pbrt-v4's figures: the table of `../shared/refs/README.md` (scenes from \
         `../shared/scenes/derived/`). rpbrt renders each at pbrt-v4's listed sample counts with seeds 100, 101, …; \
         error is MRSE against `NAME-ref.exr` as that README defines it, time the whole render (parse, build, render, \
         write; in-process, so without process start-up), both averaged over the seeds.\n\
         - **Steal**: the machine is a 2-core virtual machine whose hypervisor takes CPU time from it (\"steal\", \
         `vmstat`'s `st`: 20–45 % at busy hours). Every time here is wall clock *less the time stolen during it* \
         (from `/proc/stat`, averaged over the CPUs; src/tools/steal.rs), the time the render would take on a quiet \
         machine such as the one pbrt-v4's figures come from; the tables give the stolen seconds beside it.\n\
         - **Equal-error time ratio**: rpbrt's time to reach pbrt-v4's MRSE at a listed spp, interpolated linearly on \
         rpbrt's log–log error-over-time curve (the end segment extended when pbrt-v4's error lies outside rpbrt's \
         measured range, marked \"extrap.\"), divided by pbrt-v4's time at that spp. The pbrt-v4 time is the README's \
         **quiet median of 3** where it has one: its \"as rendered\" times were taken while other work shared the \
         machine (up to 2.5× slower), so ratios against them, shown for the other sample counts, flatter rpbrt. \
         pbrt-v4's renders at a scene's listed sample counts share one seed, and its `sobol` sampler gives a pixel's \
         i-th sample the same point at any spp, so each is the first samples of the next: one draw, not three. Where \
         a few fireflies set the MRSE (hair-curl-300) that draw's luck sets the ratio; performance-notes.md compares \
         the two renderers' tails of bright samples there instead.{}\n\
         - **At pbrt-v4's seed**: rpbrt also renders each scene once at pbrt-v4's seed and spp. It draws pbrt-v4's \
         samples (same sampler, randomisation and order of dimensions), so this compares the two renderers on the \
         same draw: with the `sobol` sampler the two images are the same but for float rounding.\n\
         - Parse: scene file → scene description; build: shapes, lights, materials and BVH (medians over the renders). \
         Peak memory: `VmHWM` of a separate `rpbrt --stats` process rendering the scene at 1 spp (the film and scene \
         dominate; it does not grow with spp).\n",
        if args.pbrt.is_some() {
            " With `--pbrt`, pbrt-v4 was also run in this same run (same spp, seeds, threads); those \
             same-run ratios are the fairest comparison."
        } else {
            ""
        }
    );
    let _ = writeln!(t, "## Summary\n");
    let _ = writeln!(
        t,
        "| scene | kind | equal-error time ratio vs pbrt-v4 (quiet median) | goal | README's rule at pbrt-v4's seed | parse s | build s | peak memory |\n|---|---|---|---|---|---|---|---|"
    );
    for r in results {
        let hair = r.name.starts_with("hair");
        let points: Vec<(f64, f64)> = curve(&r.runs, Renderer::Rpbrt)
            .iter()
            .map(|&(_, s, e)| (s, e))
            .collect();
        let headline = r
            .rows
            .iter()
            .find_map(|row| Some((row, row.quiet_seconds?)))
            .and_then(|(row, quiet)| {
                time_at_error(&points, row.mrse).map(|(s, x)| (s / quiet, x, row.spp))
            });
        let goal = if hair { 0.5 } else { 1.0 };
        let ratio = headline.map_or("—".into(), |(ratio, x, spp)| {
            format!(
                "{} at pbrt's {spp} spp{}",
                ratio_text(ratio, x),
                if ratio <= goal { " ✓" } else { "" }
            )
        });
        let of = |f: fn(&Run) -> Option<f64>| {
            median(r.runs.iter().filter_map(f).collect())
                .map_or("—".into(), |v| format!("{v:.3}"))
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
        let _ = writeln!(
            t,
            "| {} | {} | {ratio} | ≤ {goal}× | {rule} | {} | {} | {} |",
            r.name,
            if hair { "hair" } else { "other" },
            of(|r| r.parse_seconds),
            of(|r| r.build_seconds),
            r.peak_mb.map_or("—".into(), |mb| format!("{mb} MB"))
        );
    }
    for s in skipped {
        let _ = writeln!(t, "\nSkipped: {s}");
    }
    for r in results {
        let _ = writeln!(
            t,
            "\n## {}\n\n![{} convergence](performance/{})\n",
            r.name, r.name, r.plot
        );
        let _ = writeln!(
            t,
            "| renderer | spp | seconds (mean, steal removed) | of the wall clock, stolen | MRSE (mean) |\n|---|---|---|---|---|"
        );
        for renderer in [Renderer::Rpbrt, Renderer::Pbrt] {
            for (spp, s, e) in curve(&r.runs, renderer) {
                let stolen: Vec<f64> = r
                    .runs
                    .iter()
                    .filter(|run| run.renderer == renderer && run.spp == spp)
                    .map(|run| run.stolen_seconds)
                    .collect();
                let stolen = stolen.iter().sum::<f64>() / stolen.len().max(1) as f64;
                let _ = writeln!(
                    t,
                    "| {} (this run) | {spp} | {s:.3} | {stolen:.3} | {e:.6} |",
                    renderer.name()
                );
            }
        }
        for row in &r.rows {
            let (s, which) = row
                .quiet_seconds
                .map_or((row.rendered_seconds, "as rendered"), |q| {
                    (q, "quiet median")
                });
            let _ = writeln!(
                t,
                "| pbrt-v4 (refs README, {which}) | {} | {s:.3} | — | {:.6} |",
                row.spp, row.mrse
            );
        }
        let points: Vec<(f64, f64)> = curve(&r.runs, Renderer::Rpbrt)
            .iter()
            .map(|&(_, s, e)| (s, e))
            .collect();
        let _ = writeln!(t, "\n| pbrt-v4 spp | pbrt-v4 MRSE | pbrt-v4 s | rpbrt s at that MRSE | ratio |\n|---|---|---|---|---|");
        for row in &r.rows {
            let (s, which) = row.time();
            let ours = time_at_error(&points, row.mrse);
            let _ = writeln!(
                t,
                "| {} | {:.6} | {s:.2}{which} | {} | {} |",
                row.spp,
                row.mrse,
                ours.map_or("—".into(), |(o, _)| format!("{o:.2}")),
                ours.map_or("—".into(), |(o, x)| ratio_text(o / s, x))
            );
        }
        let _ = writeln!(
            t,
            "\nAccuracy at pbrt-v4's sample counts (pass: MRSE ≤ 1.25 × pbrt-v4's, block bias ≤ max(2 × pbrt-v4's, 0.01)):\n\n\
             | spp | rpbrt MRSE: mean (worst seed) | pbrt-v4 MRSE | ratio of means | rpbrt block bias: worst seed | pbrt-v4 block bias | bound |\n\
             |---|---|---|---|---|---|---|"
        );
        for row in &r.rows {
            let ours: Vec<(f64, Option<f64>)> = r
                .runs
                .iter()
                .zip(&r.block_bias)
                .filter(|(run, _)| run.renderer == Renderer::Rpbrt && run.spp == row.spp)
                .map(|(run, bias)| (run.mrse, *bias))
                .collect();
            if ours.is_empty() {
                continue;
            }
            let mean = ours.iter().map(|o| o.0).sum::<f64>() / ours.len() as f64;
            let worst = ours.iter().map(|o| o.0).fold(0.0, f64::max);
            let worst_bias = ours
                .iter()
                .filter_map(|o| o.1)
                .fold(None, |m: Option<f64>, b| Some(m.map_or(b, |m| m.max(b))));
            let _ = writeln!(
                t,
                "| {} | {mean:.6} ({worst:.6}) | {:.6} | {:.2} | {} | {} | {} |",
                row.spp,
                row.mrse,
                mean / row.mrse,
                worst_bias.map_or("—".into(), |b| format!("{b:.5}")),
                row.block_bias.map_or("—".into(), |b| format!("{b:.4}")),
                row.block_bias
                    .map_or("—".into(), |b| format!("{:.4}", (2.0 * b).max(0.01)))
            );
        }
        if !r.same_seed.is_empty() {
            let _ = writeln!(
                t,
                "\nAt pbrt-v4's seed ({PBRT_SEED}, that of its renders at these spp): the same rule, with the luck of \
                 pbrt-v4's draw on both sides, and the MRSE between the two renders as a fraction of pbrt-v4's against \
                 the reference (near 0: the same samples give the same image; about 2: independent renders; block bias \
                 here computed from pbrt-v4's image, so the bound may differ from the README's by rounding):\n\n\
                 | spp | rpbrt MRSE | pbrt-v4 MRSE | ratio | rpbrt block bias | bound | MRSE between the two / pbrt-v4's | rpbrt s (steal removed) | vs pbrt-v4's s (README) |\n\
                 |---|---|---|---|---|---|---|---|---|"
            );
            for row in &r.same_seed {
                let pbrt_seconds = r.rows.iter().find(|x| x.spp == row.spp).map(|x| x.time());
                let vs = match (row.seconds, pbrt_seconds) {
                    (Some(ours), Some((theirs, which))) => {
                        format!("{:.2}× of {theirs:.2}{which}", ours / theirs)
                    }
                    _ => "—".into(),
                };
                let _ = writeln!(
                    t,
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
                );
            }
        }
        let pbrt_curve = curve(&r.runs, Renderer::Pbrt);
        if !pbrt_curve.is_empty() {
            let _ = writeln!(t, "\nSame run, against the pbrt-v4 binary:\n\n| spp | pbrt-v4 s | pbrt-v4 MRSE | rpbrt s at that MRSE | ratio |\n|---|---|---|---|---|");
            for (spp, s, e) in pbrt_curve {
                let ours = time_at_error(&points, e);
                let _ = writeln!(
                    t,
                    "| {spp} | {s:.2} | {e:.6} | {} | {} |",
                    ours.map_or("—".into(), |(o, _)| format!("{o:.2}")),
                    ours.map_or("—".into(), |(o, x)| ratio_text(o / s, x))
                );
            }
        }
    }
    let _ = writeln!(t, "\n{dual}");
    t
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
}
