//! Tools around rendering: the command-line commands (each with its clap
//! arguments and its `run`), image comparison, plots, and generated test
//! scenes. The benchmark harness (convergence runs, the performance
//! report) is the `rpbrt-bench` crate in `bench/`, which uses these;
//! `bench_handoff` runs it for `rpbrt report` and `rpbrt convergence`.

pub mod bcsdf;
pub mod bench_handoff;
pub mod curvegen;
pub mod cyhair2pbrt;
pub mod flip;
pub mod hairgen;
pub mod heat_map;
pub mod imgdiff;
pub mod imgtool;
pub mod mie;
pub mod mie_compare;
pub mod plot;
pub mod render_scene;
pub mod reproduce;

/// A progress bar of `total` steps in indicatif's `template`, or a hidden
/// one where it would not help (`visible` false: stderr is not a terminal,
/// or the work is too small to watch). Public for the benchmark harness.
pub fn progress_bar(total: u64, template: &str, visible: bool) -> indicatif::ProgressBar {
    if !visible {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template(template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// Maps an I/O error on `path` to the crate's error, naming the path.
pub(crate) fn io_error(
    path: &std::path::Path,
) -> impl Fn(std::io::Error) -> crate::error::Error + '_ {
    move |source| crate::error::Error::Io {
        path: path.display().to_string(),
        source,
    }
}
