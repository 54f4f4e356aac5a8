//! `rpbrt-bench curves` as a user runs it: a small generated curve file,
//! measured in child processes.

use std::process::Command;

/// A generated file of 3,000 curves, kept where asked: the table has one
/// row per thread count, each with times and a peak memory that is the
/// child's own (more than the scene's curves need, less than a gigabyte),
/// and the file is the generator's.
#[test]
fn measures_a_generated_curve_file() {
    let file = std::env::temp_dir().join(format!("rpbrt-bench-curves-{}.pbrt", std::process::id()));
    let output = Command::new(env!("CARGO_BIN_EXE_rpbrt-bench"))
        .args([
            "curves",
            "--lines",
            "3000",
            "--rounds",
            "1",
            "--threads",
            "1,2",
            "--file",
        ])
        .arg(&file)
        .output()
        .expect("run rpbrt-bench");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = std::fs::read_to_string(&file).unwrap();
    let _ = std::fs::remove_file(&file);
    assert_eq!(text.matches("Shape \"curve\"").count(), 3000);
    let table = String::from_utf8_lossy(&output.stdout);
    let rows: Vec<Vec<&str>> = table
        .lines()
        .filter(|l| l.starts_with("| 1 |") || l.starts_with("| 2 |"))
        .map(|l| l.split('|').map(str::trim).collect())
        .collect();
    assert_eq!(rows.len(), 2, "{table}");
    for row in rows {
        // | threads | program | wall | CPU | parse | build | peak | ratios |
        let seconds: Vec<f64> = row[3..7].iter().map(|c| c.parse().unwrap()).collect();
        assert!(seconds.iter().all(|&s| s >= 0.0), "{row:?}");
        assert!(seconds[0] >= seconds[3], "wall at least the build: {row:?}");
        let peak: f64 = row[7].trim_end_matches(" MB").parse().unwrap();
        assert!(peak > 5.0 && peak < 1024.0, "{row:?}");
        assert_eq!(row[8], "1.00×");
    }
}
