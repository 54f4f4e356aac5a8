//! `rpbrt report` and `rpbrt convergence`: run by the benchmark harness,
//! the `rpbrt-bench` executable (crate `bench/`), found beside this one.
//!
//! The harness renders through this library, so this library cannot
//! depend on it (Cargo refuses a cycle between packages); the two
//! subcommands pass their arguments through to it unread, with its exit
//! status, and say how to build it when it is not there.

use crate::error::Error;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The harness's executable name (without the platform's suffix).
pub const HARNESS: &str = "rpbrt-bench";

/// The arguments of a handed-off subcommand, all passed through (`--help`
/// too, so that the harness prints its own).
#[derive(clap::Args, Debug)]
#[command(disable_help_flag = true)]
pub struct HandOffArgs {
    #[arg(
        trailing_var_arg = true,
        allow_hyphen_values = true,
        num_args = 0..,
        value_name = "ARGS"
    )]
    pub args: Vec<OsString>,
}

/// Where the harness is expected: beside `executable` (this program), as
/// Cargo builds a workspace's binaries into one folder.
pub fn harness_path(executable: &Path) -> PathBuf {
    executable.with_file_name(format!("{HARNESS}{}", std::env::consts::EXE_SUFFIX))
}

/// Runs `rpbrt-bench SUBCOMMAND ARGS…` and returns its exit status.
pub fn run(subcommand: &str, args: &HandOffArgs) -> Result<ExitCode, Error> {
    let me = std::env::current_exe().map_err(|source| Error::Io {
        path: "<the rpbrt executable>".into(),
        source,
    })?;
    let harness = harness_path(&me);
    if !harness.is_file() {
        return Err(Error::Usage(format!(
            "`rpbrt {subcommand}` is run by the benchmark harness, {}, which is not built: \
             build it with `cargo build --release -p {HARNESS}` (or `cargo build --release \
             --workspace`), then run this again",
            harness.display()
        )));
    }
    let mut command = std::process::Command::new(&harness);
    command.arg(subcommand).args(&args.args);
    // Its usage lines then read `rpbrt SUBCOMMAND`, as the user typed.
    #[cfg(unix)]
    std::os::unix::process::CommandExt::arg0(&mut command, "rpbrt");
    let status = command.status().map_err(|source| Error::Io {
        path: harness.display().to_string(),
        source,
    })?;
    // A status without a code (killed by a signal) is a failure.
    Ok(match status.code() {
        Some(0) => ExitCode::SUCCESS,
        Some(code) => ExitCode::from(u8::try_from(code).unwrap_or(1)),
        None => ExitCode::FAILURE,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_harness_is_looked_for_beside_the_executable() {
        let path = harness_path(Path::new("/a/b/rpbrt"));
        assert_eq!(path.parent(), Some(Path::new("/a/b")));
        assert!(path
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with(HARNESS)));
    }
}
