//! `rpbrt-bench scaling` as a user runs it: a shipped scene rendered in
//! child processes at two thread counts.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scaling(extra: &[&str]) -> Output {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pbrt-scenes/spheres.pbrt");
    Command::new(env!("CARGO_BIN_EXE_rpbrt-bench"))
        .args([
            "scaling",
            "--spp",
            "1",
            "--rounds",
            "1",
            "--threads",
            "1,2",
            "--scenes",
        ])
        .arg(scene)
        .args(extra)
        .output()
        .expect("run rpbrt-bench")
}

/// The `rpbrt` beside the harness, as a baseline build would be given.
fn rpbrt() -> PathBuf {
    Path::new(env!("CARGO_BIN_EXE_rpbrt-bench"))
        .with_file_name(format!("rpbrt{}", std::env::consts::EXE_SUFFIX))
}

/// With a baseline: a row per thread count and program, each with times,
/// a peak memory that is the child's own, a speed-up of 1 at the first
/// thread count, and no ratio to pbrt-v4 (none measured).
#[test]
fn measures_a_scene_at_two_thread_counts() {
    let output = scaling(&["--baseline", rpbrt().to_str().unwrap()]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let table = String::from_utf8_lossy(&output.stdout);
    let rows: Vec<Vec<&str>> = table
        .lines()
        .filter(|l| l.starts_with("| spheres |"))
        .map(|l| l.split('|').map(str::trim).collect())
        .collect();
    assert_eq!(rows.len(), 4, "{table}");
    for row in &rows {
        // | scene | threads | program | wall | CPU | peak | speed-up | ÷ pbrt wall | ÷ pbrt memory |
        let wall: f64 = row[4].parse().unwrap();
        let cpu: f64 = row[5].parse().unwrap();
        assert!(wall > 0.0 && cpu > 0.0, "{row:?}");
        let peak: f64 = row[6].trim_end_matches(" MB").parse().unwrap();
        assert!(peak > 5.0 && peak < 1024.0, "{row:?}");
        if row[2] == "1" {
            assert_eq!(row[7], "1.00×", "{row:?}");
        } else {
            assert!(row[7].ends_with('×'), "{row:?}");
        }
        assert_eq!((row[8], row[9]), ("—", "—"), "{row:?}");
    }
    assert_eq!(rows[0][3], "rpbrt");
    assert!(rows[1][3].starts_with("rpbrt (baseline "), "{:?}", rows[1]);
}

/// A pbrt-v4 that fails (here `false`, as a pbrt-v4 binary that stops on
/// an instruction the processor lacks prints nothing): an error naming
/// the program and its exit status.
#[cfg(unix)]
#[test]
fn a_failing_program_is_named_with_its_status() {
    let output = scaling(&["--pbrt", "false"]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("false failed on") && stderr.contains("exit status: 1"),
        "{stderr}"
    );
}
