//! The `rpbrt` command line. Only argument handling lives here; the work is
//! done by the library.

use clap::Parser as _;
use pbrt_parser::{Formatter, Parser};
use rpbrt::error::Error;
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
    /// Print no warnings and no summary.
    #[arg(long)]
    quiet: bool,
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
    let loaded = rpbrt::scene::load(&cli.file)?;
    if !cli.quiet {
        for w in &loaded.warnings {
            eprintln!("{w}");
        }
        println!("{}", loaded.scene.summary());
        eprintln!("rpbrt: rendering is not implemented yet; the scene was read and checked.");
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
