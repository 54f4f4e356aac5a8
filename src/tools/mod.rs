//! Tools around rendering: the command-line commands (each with its clap
//! arguments and its `run`), image comparison, convergence runs and the
//! performance report, and generated test scenes.

pub mod bcsdf;
pub mod convergence;
pub mod curvegen;
pub mod cyhair2pbrt;
pub mod dual_overhead;
pub mod flip;
pub mod hairgen;
pub mod heat_map;
pub mod imgdiff;
pub mod imgtool;
pub mod mie;
pub mod mie_compare;
pub mod peak_memory;
pub mod plot;
pub mod provenance;
pub mod render_scene;
pub mod report;
pub mod reproduce;
pub mod steal;

/// A progress bar of `total` steps in indicatif's `template`, or a hidden
/// one where it would not help (`visible` false: stderr is not a terminal,
/// or the work is too small to watch).
pub(crate) fn progress_bar(total: u64, template: &str, visible: bool) -> indicatif::ProgressBar {
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
