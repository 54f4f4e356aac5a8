//! `rpbrt mie` end to end: the CSV files it writes and the messages it
//! gives for bad values. The physics is tested beside the code
//! (src/tools/mie/).

use std::f64::consts::PI;
use std::path::PathBuf;
use std::process::{Command, Output};

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rpbrt-mie-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    dir
}

fn rpbrt_mie(arguments: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rpbrt"))
        .arg("mie")
        .args(arguments)
        .output()
        .expect("rpbrt runs")
}

fn read_table(path: &PathBuf) -> (String, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).expect("the tool wrote the file");
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default().to_string();
    let rows = lines
        .map(|line| line.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

/// One wavelength, oblique incidence: the density covers the full circle
/// on a uniform grid from −180°, integrates to 1 (per radian), peaks
/// forward, is symmetric (|T(Θ)|² = |T(−Θ)|² for every series), and the
/// efficiencies file conserves energy without absorption.
#[test]
fn writes_density_and_efficiencies() {
    let dir = temp_dir("files");
    let csv = dir.join("density.csv");
    let efficiencies = dir.join("efficiencies.csv");
    let output = rpbrt_mie(&[
        "--diameter",
        "20",
        "--wavelength",
        "550",
        "--theta-i",
        "-30",
        "--angles",
        "4096",
        "--csv",
        csv.to_str().unwrap_or_default(),
        "--efficiencies",
        efficiencies.to_str().unwrap_or_default(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(String::from_utf8_lossy(&output.stderr).contains("Q_ext"));

    let (header, rows) = read_table(&csv);
    assert_eq!(header, "theta_deg,density");
    assert_eq!(rows.len(), 4096);
    let parsed: Vec<(f64, f64)> = rows
        .iter()
        .map(|row| {
            (
                row[0].parse().expect("angle"),
                row[1].parse().expect("density"),
            )
        })
        .collect();
    assert!((parsed[0].0 + 180.0).abs() < 1e-9);
    assert!((parsed[2048].0).abs() < 1e-9);
    let integral: f64 = parsed.iter().map(|(_, d)| d).sum::<f64>() * 2.0 * PI / 4096.0;
    assert!((integral - 1.0).abs() < 1e-6, "integral {integral}");
    let peak = parsed.iter().map(|(_, d)| *d).fold(0.0, f64::max);
    assert_eq!(parsed[2048].1, peak, "the peak is forward");
    for j in 1..2048 {
        let (plus, minus) = (parsed[2048 + j].1, parsed[2048 - j].1);
        assert!(
            (plus - minus).abs() <= 1e-6 * plus.max(1e-12),
            "asymmetric at {j}"
        );
    }

    let (header, rows) = read_table(&efficiencies);
    assert_eq!(header, "polarisation,q_ext,q_sca,q_abs");
    assert_eq!(rows.len(), 3);
    for row in rows {
        let q_ext: f64 = row[1].parse().expect("q_ext");
        let q_sca: f64 = row[2].parse().expect("q_sca");
        assert!(q_ext > 1.0 && (q_ext - q_sca).abs() < 1e-9, "{row:?}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_values_are_clear_errors() {
    for (arguments, expected) in [
        (vec!["--diameter", "-5"], "diameter"),
        (vec!["--eta", "0"], "eta"),
        (vec!["--kappa", "-0.1"], "kappa"),
        (vec!["--theta-i", "90"], "theta_i"),
        (vec!["--wavelength", "-550"], "wavelength"),
        (vec!["--diameter", "50", "--angles", "100"], "angles"),
    ] {
        let output = rpbrt_mie(&arguments);
        assert!(!output.status.success(), "{arguments:?} succeeded");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains(expected), "{arguments:?}: {stderr}");
    }
}
