//! `rpbrt-bench convergence` as a user runs it (the same as `rpbrt
//! convergence`, which hands off to it).

use rpbrt::image::Image;
use std::path::{Path, PathBuf};
use std::process::Command;

/// An empty folder for one test's files in the system's temporary folder.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rpbrt-bench-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write_rgb(path: &Path, width: u32, height: u32, data: Vec<f32>) {
    Image::from_rgb(width, height, data)
        .unwrap()
        .write(path)
        .unwrap();
}

/// Runs the `rpbrt-bench` binary with `args`.
fn rpbrt_bench<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_rpbrt-bench"))
        .args(args)
        .output()
        .expect("run rpbrt-bench")
}

/// Nothing emits, so the radiance is 0 everywhere at any spp: the error
/// must be exactly zero at every spp and seed.
#[test]
fn convergence_on_a_constant_scene_has_zero_error() {
    let dir = temp_dir("convergence");
    let scene = dir.join("black.pbrt");
    std::fs::write(
        &scene,
        "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 12\n\
         Camera \"perspective\"\nWorldBegin\n\
         Material \"diffuse\"\nShape \"sphere\" \"float radius\" 100\n",
    )
    .unwrap();
    let reference = dir.join("black-ref.pfm");
    write_rgb(&reference, 16, 12, vec![0.0; 16 * 12 * 3]);
    let out_dir = dir.join("out");
    let out = rpbrt_bench(&[
        "convergence".as_ref(),
        scene.as_os_str(),
        "--reference".as_ref(),
        reference.as_os_str(),
        "--spp".as_ref(),
        "1,4,16".as_ref(),
        "--repeat".as_ref(),
        "2".as_ref(),
        "--quiet".as_ref(),
        "--out".as_ref(),
        out_dir.as_os_str(),
    ]);
    assert!(out.status.success(), "{out:?}");
    let csv = std::fs::read_to_string(out_dir.join("convergence.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let mrse_column = header
        .iter()
        .position(|h| *h == "mrse")
        .expect("an mrse column");
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 6, "3 spp × 2 seeds:\n{csv}");
    for row in &rows {
        assert_eq!(row[mrse_column].parse::<f64>().unwrap(), 0.0, "{csv}");
    }
    assert!(out_dir.join("convergence.png").exists());
}
