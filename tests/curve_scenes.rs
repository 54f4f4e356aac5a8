//! The shared curve and hair scenes render (a small crop at low spp)
//! without error and without NaN or infinite samples: the Houdini
//! exporter's curve tests (flat, cylinder, ribbon, per-vertex widths,
//! splitdepth) and pbrt-v4-scenes' hair files. Skipped when `../shared` is
//! absent.

mod common;

use rpbrt::pipeline::render_file;
use rpbrt::scene::build::RenderOverrides;
use std::path::{Path, PathBuf};

fn render_crop(file: &Path, out_dir: &Path) -> Result<(), String> {
    let name = file.file_stem().unwrap_or_default().to_string_lossy();
    let overrides = RenderOverrides {
        spp: Some(2),
        seed: Some(1),
        outfile: Some(out_dir.join(format!("{name}.exr"))),
        crop_window: Some([0.4, 0.6, 0.4, 0.6]),
        ..Default::default()
    };
    let report = render_file(file, &overrides, 2, false).map_err(|e| e.to_string())?;
    if report.bad_samples > 0 {
        return Err(format!("{} NaN/infinite samples", report.bad_samples));
    }
    Ok(())
}

fn check_all(tag: &str, files: Vec<PathBuf>, expected_at_least: usize) {
    let out_dir = std::env::temp_dir().join(format!("rpbrt-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&out_dir).expect("temporary directory");
    let mut failures = Vec::new();
    for file in &files {
        if let Err(e) = render_crop(file, &out_dir) {
            failures.push(format!("{}: {e}", file.display()));
        }
    }
    let _ = std::fs::remove_dir_all(&out_dir);
    assert!(
        files.len() >= expected_at_least,
        "only {} scenes found",
        files.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn houdini_curve_tests_render() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    let files: Vec<PathBuf> = common::scene_files(&shared.join("scenes/houdini-pbrt-v4"))
        .into_iter()
        .filter(|f| {
            f.file_name()
                .is_some_and(|n| n.to_string_lossy().contains("curve"))
        })
        .collect();
    check_all("houdini-curves", files, 10);
}

#[test]
fn pbrt_v4_hair_scenes_render() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    let dir = shared.join("scenes/pbrt-v4-scenes/hair");
    let files: Vec<PathBuf> = common::scene_files(&dir)
        .into_iter()
        .filter(|f| f.parent() == Some(dir.as_path()))
        .collect();
    check_all("pbrt-v4-hair", files, 11);
}
