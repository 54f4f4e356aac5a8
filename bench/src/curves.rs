//! `rpbrt-bench curves` (also `rpbrt curves`): parse and build time and
//! peak memory on a generated curve file of the form
//! `../shared/refs/README.md` measured pbrt-v4 on (606,208 random cylinder
//! curves, 120 MB, one hair material, 16 × 16 pixels, 1 spp).
//!
//! Each measurement is a separate child process (`rpbrt FILE --stats`, and
//! pbrt-v4 with `--pbrt`; `child.rs`). Programs are run in interleaved
//! rounds (every program once per round), so that a machine's slow minute
//! falls on all of them, and the table gives medians over the rounds.
//!
//! | option | default | meaning |
//! |---|---|---|
//! | `--lines` | 606208 | curves in the generated file |
//! | `--threads` | 1,2 | thread counts to measure (`--nthreads`) |
//! | `--rounds` | 3 | interleaved rounds |
//! | `--file` | a temporary file | where the scene is written (kept if given) |
//! | `--baseline` | — | another `rpbrt` executable to measure beside this one (before/after) |
//! | `--pbrt` | — | a pbrt-v4 executable to measure beside rpbrt |
//! | `--out` | — | a report (`docs/performance.md`) to write the table into, as its section [`HEADING`] (else printed) |
//!
//! `rpbrt report` keeps that section when it rewrites the report.

use crate::child::{measure, MeasureArgs, Measured, Program, RenderSettings};
use crate::error::{io_error, Result};
use crate::provenance::{commit, machine, median, today};
use std::fmt::Write;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct CurvesArgs {
    /// Curves in the generated file (606208: the refs README's 120 MB).
    #[arg(long, default_value_t = 606_208)]
    pub lines: usize,
    #[command(flatten)]
    pub measuring: MeasureArgs,
    /// Where to write the generated scene (kept); else a temporary file,
    /// removed afterwards.
    #[arg(long)]
    pub file: Option<PathBuf>,
    /// A report (e.g. docs/performance.md) to write the table into, as its
    /// section "## Memory and build at scale"; else printed.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The heading of the report's section this command writes.
pub const HEADING: &str = "## Memory and build at scale";

/// Where the section headed `heading` of `report` begins and ends (at the
/// next `## ` heading or the end), if it has one.
fn section_range(report: &str, heading: &str) -> Option<std::ops::Range<usize>> {
    let start = report.find(heading)?;
    let body = start + heading.len();
    let end = report[body..]
        .find("\n## ")
        .map_or(report.len(), |i| body + i + 1);
    Some(start..end)
}

/// `report` with its section headed `heading` replaced by `section`;
/// without one, `section` goes before the heading `before` (or at the end).
pub fn splice_section(report: &str, heading: &str, section: &str, before: &str) -> String {
    let range = section_range(report, heading).unwrap_or_else(|| {
        let at = report.find(before).unwrap_or(report.len());
        at..at
    });
    format!(
        "{}{section}{}",
        &report[..range.start],
        &report[range.end..]
    )
}

/// The section headed [`HEADING`] of `report`, if it has one.
pub fn section_of(report: &str) -> Option<&str> {
    section_range(report, HEADING).map(|range| &report[range])
}

pub fn run(args: &CurvesArgs) -> Result<()> {
    args.measuring.check("curves")?;
    let temporary = args.file.is_none();
    let file = args.file.clone().unwrap_or_else(|| {
        std::env::temp_dir().join(format!("rpbrt-curves-{}.pbrt", std::process::id()))
    });
    let text = rpbrt::tools::curvegen::curve_scene(args.lines, 1);
    std::fs::write(&file, &text).map_err(io_error(&file))?;
    let megabytes = text.len() as f64 / 1e6;
    drop(text);

    let programs = args.measuring.programs()?;
    let out_dir = std::env::temp_dir();
    // results[threads][program] = one Measured per round.
    let mut results = vec![vec![Vec::new(); programs.len()]; args.measuring.threads.len()];
    for round in 0..args.measuring.rounds {
        for (t, &threads) in args.measuring.threads.iter().enumerate() {
            for (p, program) in programs.iter().enumerate() {
                eprintln!(
                    "round {}/{}: {} with {threads} thread(s)",
                    round + 1,
                    args.measuring.rounds,
                    program.label
                );
                let image = out_dir.join(format!("rpbrt-curves-{}-{p}.exr", std::process::id()));
                let settings = RenderSettings {
                    threads,
                    spp: None,
                    seed: None,
                };
                let measured = measure(program, &file, settings, &image)?;
                let _ = std::fs::remove_file(&image);
                results[t][p].push(measured);
            }
        }
    }
    if temporary {
        let _ = std::fs::remove_file(&file);
    }
    let table = table(args, megabytes, &programs, &results);
    match &args.out {
        Some(out) => {
            let old = std::fs::read_to_string(out).map_err(io_error(out))?;
            let section = format!("{HEADING}\n\n{table}\n");
            let text = splice_section(&old, HEADING, &section, crate::dual_overhead::HEADING);
            std::fs::write(out, text).map_err(io_error(out))?;
            eprintln!("wrote the curve-file table into {}", out.display());
        }
        None => print!("{table}"),
    }
    Ok(())
}

/// The Markdown table: one row per thread count and program, medians over
/// the rounds, and each program's ratio to the first (rpbrt).
fn table(
    args: &CurvesArgs,
    megabytes: f64,
    programs: &[Program],
    results: &[Vec<Vec<Measured>>],
) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Measured {} on {} at commit {} (`rpbrt-bench curves`): {} curves, {megabytes:.1} MB, \
         parse + build + 1 spp at 16 × 16, child processes, medians of {} interleaved rounds.\n",
        today(),
        machine(),
        commit(),
        args.lines,
        args.measuring.rounds
    );
    out.push_str(
        "| threads | program | wall s | CPU s (user + sys) | parse s | build s | peak memory | memory ÷ rpbrt's | wall ÷ rpbrt's |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    let optional = |v: Option<f64>| v.map_or("—".to_string(), |s| format!("{s:.2}"));
    for (t, &threads) in args.measuring.threads.iter().enumerate() {
        let med = |p: usize, f: &dyn Fn(&Measured) -> Option<f64>| {
            median(results[t][p].iter().filter_map(f).collect())
        };
        let base_wall = med(0, &|m| Some(m.wall_s));
        let base_peak = med(0, &|m| Some(m.peak_mb));
        for (p, program) in programs.iter().enumerate() {
            let wall = med(p, &|m| Some(m.wall_s));
            let peak = med(p, &|m| Some(m.peak_mb));
            let ratio = |a: Option<f64>, b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) if b > 0.0 => format!("{:.2}×", a / b),
                _ => "—".into(),
            };
            let _ = writeln!(
                out,
                "| {threads} | {} | {} | {} | {} | {} | {} | {} | {} |",
                program.label,
                optional(wall),
                optional(med(p, &|m| Some(m.cpu_s))),
                optional(med(p, &|m| m.parse_s)),
                optional(med(p, &|m| m.build_s)),
                peak.map_or("—".into(), |mb| format!("{mb:.0} MB")),
                ratio(peak, base_peak),
                ratio(wall, base_wall),
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_section_is_replaced_or_put_before_the_dual_table() {
        let dual = crate::dual_overhead::HEADING;
        let new = format!("{HEADING}\n\nnew\n");
        let without = format!("# P\n\n## a\n\nx\n{dual}\n\nd\n");
        let with = splice_section(&without, HEADING, &new, dual);
        assert_eq!(
            with,
            format!("# P\n\n## a\n\nx\n{HEADING}\n\nnew\n{dual}\n\nd\n")
        );
        assert_eq!(section_of(&with), Some(new.as_str()));
        let newer = format!("{HEADING}\n\nnewer\n");
        let again = splice_section(&with, HEADING, &newer, dual);
        assert_eq!(again, with.replace("new\n", "newer\n"));
        // At the end of a report, to its end.
        let last = format!("# P\n{HEADING}\n\nold\n");
        assert_eq!(
            splice_section(&last, HEADING, &new, dual),
            format!("# P\n{new}")
        );
    }
}
