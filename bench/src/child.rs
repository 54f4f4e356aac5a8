//! Programs run as child processes and measured (`curves`, `scaling`):
//! each measurement is a process of its own, so that its peak resident
//! memory is its own: the operating system's figure for the child
//! (`wait4`'s `ru_maxrss`), with its user and system CPU time; rpbrt's
//! parse and build times come from its `--stats`.

use crate::error::{io_error, Error, Result};
use crate::executable::rpbrt_executable;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What one child process took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    pub wall_s: f64,
    /// User + system CPU time.
    pub cpu_s: f64,
    pub peak_mb: f64,
    /// From `rpbrt --stats` (None for pbrt-v4).
    pub parse_s: Option<f64>,
    pub build_s: Option<f64>,
}

/// The options `curves` and `scaling` share: the thread counts, the
/// rounds, and the programs measured beside rpbrt.
#[derive(clap::Args, Debug)]
pub struct MeasureArgs {
    /// Thread counts to measure, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    pub threads: Vec<usize>,
    /// Interleaved rounds (each program once per round); medians are given.
    #[arg(long, default_value_t = 3)]
    pub rounds: usize,
    /// Another rpbrt executable to measure beside this one (e.g. an older
    /// build, for a before/after table).
    #[arg(long)]
    pub baseline: Option<PathBuf>,
    /// A pbrt-v4 executable to measure beside rpbrt.
    #[arg(long)]
    pub pbrt: Option<PathBuf>,
}

impl MeasureArgs {
    /// At least one round and one thread count, none of them 0
    /// (`command` names the subcommand in the error).
    pub fn check(&self, command: &str) -> Result<()> {
        if self.rounds == 0 || self.threads.is_empty() || self.threads.contains(&0) {
            return Err(Error::Usage(format!(
                "{command}: --rounds and every --threads count must be at least 1"
            )));
        }
        Ok(())
    }

    /// The programs to measure: the `rpbrt` beside this harness, then the
    /// baseline (another rpbrt build) and pbrt-v4 where given.
    pub fn programs(&self) -> Result<Vec<Program>> {
        let mut programs = vec![Program::rpbrt()?];
        if let Some(baseline) = &self.baseline {
            programs.push(Program {
                label: format!("rpbrt (baseline {})", baseline.display()),
                executable: baseline.clone(),
                is_pbrt: false,
            });
        }
        if let Some(pbrt) = &self.pbrt {
            programs.push(Program {
                label: "pbrt-v4".into(),
                executable: pbrt.clone(),
                is_pbrt: true,
            });
        }
        Ok(programs)
    }
}

/// A program a table has rows for.
pub struct Program {
    pub label: String,
    pub executable: PathBuf,
    /// pbrt-v4 (its command line has no `--stats`).
    pub is_pbrt: bool,
}

impl Program {
    /// The `rpbrt` beside this harness.
    pub fn rpbrt() -> Result<Program> {
        Ok(Program {
            label: "rpbrt".into(),
            executable: rpbrt_executable()?,
            is_pbrt: false,
        })
    }
}

/// How a render is run: `--nthreads`, and `--spp` and `--seed` where
/// given (else the scene's own).
#[derive(Clone, Copy, Debug)]
pub struct RenderSettings {
    pub threads: usize,
    pub spp: Option<u32>,
    pub seed: Option<u64>,
}

/// Runs `program` on `scene` as `settings` say, writing `image`, and
/// measures it.
pub fn measure(
    program: &Program,
    scene: &Path,
    settings: RenderSettings,
    image: &Path,
) -> Result<Measured> {
    let mut command = std::process::Command::new(&program.executable);
    command.arg("--nthreads").arg(settings.threads.to_string());
    if let Some(spp) = settings.spp {
        command.arg("--spp").arg(spp.to_string());
    }
    if let Some(seed) = settings.seed {
        command.arg("--seed").arg(seed.to_string());
    }
    if program.is_pbrt {
        command
            .arg("--quiet")
            .arg("--outfile")
            .arg(image)
            .arg(scene);
    } else {
        command
            .arg(scene)
            .args(["--quiet", "--stats", "--outfile"])
            .arg(image);
    }
    let (output, usage) = run_child(command, &program.executable)?;
    if !output.status.success() {
        // The status too: a program killed by a signal (pbrt-v4 built for
        // instructions this processor lacks: SIGILL) prints nothing.
        return Err(Error::Usage(format!(
            "{} failed on {} ({}): {}",
            program.executable.display(),
            scene.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        )));
    }
    let stdout = String::from_utf8_lossy(&output.stdout);
    Ok(Measured {
        wall_s: usage.wall_s,
        cpu_s: usage.cpu_s,
        peak_mb: usage.peak_mb,
        parse_s: stats_seconds(&stdout, "parse: "),
        build_s: stats_seconds(&stdout, "build: "),
    })
}

/// Seconds on the `--stats` line starting with `prefix` (`parse: 1.23 s`).
fn stats_seconds(stats: &str, prefix: &str) -> Option<f64> {
    stats.lines().find_map(|l| {
        l.strip_prefix(prefix)?
            .strip_suffix(" s")?
            .trim()
            .parse()
            .ok()
    })
}

/// A finished child's resource use.
struct Usage {
    wall_s: f64,
    cpu_s: f64,
    peak_mb: f64,
}

/// Runs `command` to the end (its output captured) and returns what the
/// operating system counted for it: `wait4` gives the child's own peak
/// resident memory and CPU time.
#[cfg(unix)]
fn run_child(
    mut command: std::process::Command,
    executable: &Path,
) -> Result<(std::process::Output, Usage)> {
    use std::io::Read;
    use std::os::unix::process::ExitStatusExt;
    let start = Instant::now();
    let mut child = command
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .map_err(io_error(executable))?;
    let (mut stdout, mut stderr) = (Vec::new(), Vec::new());
    // Read both pipes to their end before waiting (a full pipe would block
    // the child); stderr on its own thread.
    let mut err_pipe = child.stderr.take();
    let err_reader = std::thread::spawn(move || {
        let mut buffer = Vec::new();
        if let Some(pipe) = err_pipe.as_mut() {
            let _ = pipe.read_to_end(&mut buffer);
        }
        buffer
    });
    if let Some(pipe) = child.stdout.as_mut() {
        let _ = pipe.read_to_end(&mut stdout);
    }
    stderr.extend(err_reader.join().unwrap_or_default());
    let mut status: libc::c_int = 0;
    // SAFETY: an all-zero rusage is a valid value for wait4 to fill.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waits for our own child, which `child` never waits for.
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    if pid < 0 {
        return Err(io_error(executable)(std::io::Error::last_os_error()));
    }
    let wall_s = start.elapsed().as_secs_f64();
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    Ok((
        std::process::Output {
            status: std::process::ExitStatus::from_raw(status),
            stdout,
            stderr,
        },
        Usage {
            wall_s,
            cpu_s: seconds(usage.ru_utime) + seconds(usage.ru_stime),
            // ru_maxrss is in kilobytes on Linux.
            peak_mb: usage.ru_maxrss as f64 / 1024.0,
        },
    ))
}

#[cfg(not(unix))]
fn run_child(
    _command: std::process::Command,
    _executable: &Path,
) -> Result<(std::process::Output, Usage)> {
    Err(Error::Usage(
        "a child's peak memory is read with wait4, on unix only".into(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_stats_lines() {
        let stats = "wrote x.exr\nparse: 1.479 s\nbuild: 6.956 s\nrender: 0.168 s (0.073 s CPU)\n";
        assert_eq!(stats_seconds(stats, "parse: "), Some(1.479));
        assert_eq!(stats_seconds(stats, "build: "), Some(6.956));
        assert_eq!(stats_seconds(stats, "bake: "), None);
    }

    /// The operating system's count is the child's own: a child that
    /// touches 64 MB peaks above that, and one that does nothing far below.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_child_s_peak_memory_is_its_own() {
        let run = |script: &str| {
            let mut command = std::process::Command::new("sh");
            command.arg("-c").arg(script);
            run_child(command, Path::new("sh")).unwrap().1
        };
        // `head -c` of /dev/zero into a shell variable would need bash;
        // dd with a 64 MB block holds the whole block in memory.
        let big = run("dd if=/dev/zero of=/dev/null bs=64M count=1 2>/dev/null");
        let small = run("true");
        assert!(big.peak_mb > 64.0, "{}", big.peak_mb);
        assert!(small.peak_mb < 32.0, "{}", small.peak_mb);
        assert!(big.wall_s >= 0.0 && big.cpu_s >= 0.0);
    }
}
