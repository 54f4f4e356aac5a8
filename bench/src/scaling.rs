//! `rpbrt-bench scaling` (also `rpbrt scaling`): whole renders of scenes
//! at several thread counts, rpbrt beside pbrt-v4: wall and CPU time, peak
//! memory, each program's speed-up over its own time at the first thread
//! count, and rpbrt's ratios to pbrt-v4 (issue 27's 2–16 thread table).
//!
//! Every render is a child process of its own (`child.rs`); programs,
//! scenes and thread counts are run in interleaved rounds (each render
//! once per round), so that a machine's slow minute falls on all of them,
//! and the table gives medians over the rounds. Both renderers render at
//! the same `--spp` and `--seed`: with the shared scenes' `halton` and
//! `sobol` samplers rpbrt draws pbrt-v4's samples (performance.md, "at
//! pbrt-v4's seed"), so equal samples are equal error and the time ratio
//! is the equal-error ratio.
//!
//! | option | default | meaning |
//! |---|---|---|
//! | `--scenes` | — | scene files, comma separated |
//! | `--threads` | 1,2 | thread counts (`--nthreads`) |
//! | `--spp` | 16 | samples per pixel of every render |
//! | `--seed` | 100 | `--seed` of every render |
//! | `--rounds` | 3 | interleaved rounds |
//! | `--baseline` | — | another `rpbrt` executable to measure beside this one (before/after) |
//! | `--pbrt` | — | a pbrt-v4 executable to measure beside rpbrt |

use crate::child::{measure, MeasureArgs, Measured, Program, RenderSettings};
use crate::error::{Error, Result};
use crate::provenance::{commit, machine, median, today};
use std::fmt::Write;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct ScalingArgs {
    /// Scene files to render, comma separated.
    #[arg(long, value_delimiter = ',', required = true)]
    pub scenes: Vec<PathBuf>,
    /// Samples per pixel of every render.
    #[arg(long, default_value_t = 16)]
    pub spp: u32,
    /// The seed of every render.
    #[arg(long, default_value_t = 100)]
    pub seed: u64,
    /// The thread counts (speed-ups are over the first), rounds and
    /// programs.
    #[command(flatten)]
    pub measuring: MeasureArgs,
}

pub fn run(args: &ScalingArgs) -> Result<()> {
    args.measuring.check("scaling")?;
    if args.spp == 0 {
        return Err(Error::Usage("scaling: --spp must be at least 1".into()));
    }
    if let Some(missing) = args.scenes.iter().find(|s| !s.is_file()) {
        return Err(Error::Usage(format!(
            "scaling: {} is not a file",
            missing.display()
        )));
    }
    let programs = args.measuring.programs()?;
    let image = std::env::temp_dir().join(format!("rpbrt-scaling-{}.exr", std::process::id()));
    // results[scene][threads][program]: one Measured per round.
    let mut results = vec![
        vec![vec![Vec::new(); programs.len()]; args.measuring.threads.len()];
        args.scenes.len()
    ];
    for round in 0..args.measuring.rounds {
        for (s, scene) in args.scenes.iter().enumerate() {
            for (t, &threads) in args.measuring.threads.iter().enumerate() {
                for (p, program) in programs.iter().enumerate() {
                    eprintln!(
                        "round {}/{}: {} on {} with {threads} thread(s)",
                        round + 1,
                        args.measuring.rounds,
                        program.label,
                        scene.display()
                    );
                    let settings = RenderSettings {
                        threads,
                        spp: Some(args.spp),
                        seed: Some(args.seed),
                    };
                    results[s][t][p].push(measure(program, scene, settings, &image)?);
                }
            }
        }
    }
    let _ = std::fs::remove_file(&image);
    print!("{}", table(args, &programs, &results));
    Ok(())
}

/// The Markdown table: a row per scene, thread count and program, medians
/// over the rounds.
fn table(args: &ScalingArgs, programs: &[Program], results: &[Vec<Vec<Vec<Measured>>>]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Measured {} on {} at commit {} (`rpbrt-bench scaling`): {} spp, seed {}, whole \
         processes (parse, build, render, write), medians of {} interleaved rounds. Speed-up: \
         the program's wall time at {} thread(s) over its wall time here.\n",
        today(),
        machine(),
        commit(),
        args.spp,
        args.seed,
        args.measuring.rounds,
        args.measuring.threads[0],
    );
    out.push_str(
        "| scene | threads | program | wall s | CPU s (user + sys) | peak memory | speed-up | \
         wall ÷ pbrt-v4's | memory ÷ pbrt-v4's |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let pbrt = programs.iter().position(|p| p.is_pbrt);
    for (s, scene) in args.scenes.iter().enumerate() {
        let name = scene.file_stem().map_or_else(
            || scene.display().to_string(),
            |n| n.to_string_lossy().into(),
        );
        let med = |t: usize, p: usize, f: fn(&Measured) -> f64| {
            median(results[s][t][p].iter().map(f).collect())
        };
        for t in 0..args.measuring.threads.len() {
            for (p, program) in programs.iter().enumerate() {
                let wall = med(t, p, |m| m.wall_s);
                let peak = med(t, p, |m| m.peak_mb);
                let speed_up = ratio(med(0, p, |m| m.wall_s), wall);
                let (to_pbrt_wall, to_pbrt_peak) = match pbrt {
                    Some(q) if q != p => (
                        ratio(wall, med(t, q, |m| m.wall_s)),
                        ratio(peak, med(t, q, |m| m.peak_mb)),
                    ),
                    _ => ("—".into(), "—".into()),
                };
                let _ = writeln!(
                    out,
                    "| {name} | {} | {} | {} | {} | {} | {speed_up} | {to_pbrt_wall} | {to_pbrt_peak} |",
                    args.measuring.threads[t],
                    program.label,
                    seconds(wall),
                    seconds(med(t, p, |m| m.cpu_s)),
                    peak.map_or("—".into(), |mb| format!("{mb:.0} MB")),
                );
            }
        }
    }
    out
}

/// `a ÷ b` as `0.42×`, or a dash.
fn ratio(a: Option<f64>, b: Option<f64>) -> String {
    match (a, b) {
        (Some(a), Some(b)) if b > 0.0 => format!("{:.2}×", a / b),
        _ => "—".into(),
    }
}

fn seconds(s: Option<f64>) -> String {
    s.map_or("—".into(), |s| format!("{s:.2}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One scene at 1 and 4 threads, rpbrt and pbrt-v4, two rounds of
    /// made-up figures: medians, speed-ups over 1 thread and the ratios
    /// to pbrt-v4 at the same thread count.
    #[test]
    fn the_table_gives_speed_ups_and_ratios_to_pbrt() {
        let args = ScalingArgs {
            scenes: vec![PathBuf::from("scenes/hair.pbrt")],
            spp: 8,
            seed: 1,
            measuring: MeasureArgs {
                threads: vec![1, 4],
                rounds: 2,
                baseline: None,
                pbrt: None,
            },
        };
        let program = |label: &str, is_pbrt| Program {
            label: label.into(),
            executable: PathBuf::from(label),
            is_pbrt,
        };
        let programs = [program("rpbrt", false), program("pbrt-v4", true)];
        let m = |wall_s, peak_mb| Measured {
            wall_s,
            cpu_s: 2.0 * wall_s,
            peak_mb,
            parse_s: None,
            build_s: None,
        };
        let results = vec![vec![
            // 1 thread: rpbrt 4 s (median of 3 and 5), pbrt-v4 10 s.
            vec![
                vec![m(3.0, 100.0), m(5.0, 100.0)],
                vec![m(10.0, 200.0), m(10.0, 200.0)],
            ],
            // 4 threads: rpbrt 1 s, pbrt-v4 2 s.
            vec![
                vec![m(1.0, 110.0), m(1.0, 110.0)],
                vec![m(2.0, 200.0), m(2.0, 200.0)],
            ],
        ]];
        let text = table(&args, &programs, &results);
        let rows: Vec<&str> = text.lines().filter(|l| l.starts_with("| hair")).collect();
        assert_eq!(
            rows,
            [
                "| hair | 1 | rpbrt | 4.00 | 8.00 | 100 MB | 1.00× | 0.40× | 0.50× |",
                "| hair | 1 | pbrt-v4 | 10.00 | 20.00 | 200 MB | 1.00× | — | — |",
                "| hair | 4 | rpbrt | 1.00 | 2.00 | 110 MB | 4.00× | 0.50× | 0.55× |",
                "| hair | 4 | pbrt-v4 | 2.00 | 4.00 | 200 MB | 5.00× | — | — |",
            ]
        );
    }
}
