//! Helpers shared by the scene-level tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// Runs the `rpbrt` binary with `args`.
pub fn rpbrt<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_rpbrt"))
        .args(args)
        .output()
        .expect("run rpbrt")
}

/// An empty folder for one test's files: `rpbrt-SUITE-PID-NAME` in the
/// system's temporary folder (emptied if an earlier run left it).
pub fn fresh_dir(suite: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rpbrt-{suite}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `../shared` beside the project, or `None` (with a message) when absent.
pub fn shared_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared");
    if dir.join("scenes").is_dir() {
        Some(dir)
    } else {
        eprintln!("skipping: ../shared/scenes is not present beside the project");
        None
    }
}

/// Every `.pbrt` / `.pbrt.gz` below `dir`, sorted.
pub fn scene_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let name = path.to_string_lossy();
                if name.ends_with(".pbrt") || name.ends_with(".pbrt.gz") {
                    out.push(path);
                }
            }
        }
    }
    out.sort();
    out
}

/// Whether an error is an `Include`/`Import` of a file that does not exist
/// (some shared scenes include geometry too large to be shipped).
pub fn is_absent_include(e: &rpbrt::Error) -> bool {
    match e {
        rpbrt::Error::Parse(p) => matches!(
            &p.kind,
            pbrt_parser::ErrorKind::CannotRead { path, .. } if !Path::new(path).exists()
        ),
        _ => false,
    }
}

/// Renders scene text (written to a temporary file) at `spp` on `threads`
/// threads and reads the image back. `extra` overrides more settings.
pub fn render_text(
    name: &str,
    scene: &str,
    spp: u32,
    threads: usize,
    extra: rpbrt::scene::build::RenderOverrides,
) -> rpbrt::image::Image {
    render_text_with_report(name, scene, spp, threads, extra).0
}

/// [`render_text`], with the render's report (bad samples, rays, times).
pub fn render_text_with_report(
    name: &str,
    scene: &str,
    spp: u32,
    threads: usize,
    extra: rpbrt::scene::build::RenderOverrides,
) -> (rpbrt::image::Image, rpbrt::pipeline::RenderReport) {
    let dir = std::env::temp_dir().join(format!("rpbrt-test-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join("out.exr");
    let overrides = rpbrt::scene::build::RenderOverrides {
        spp: Some(spp),
        outfile: Some(out.clone()),
        ..extra
    };
    let report = rpbrt::pipeline::render_file(&path, &overrides, threads, false).unwrap();
    let image = rpbrt::image::Image::read(&out).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    (image, report)
}

/// An image's pixel values (each the average of its R, G, B), row by row;
/// every value must be finite.
pub fn channel_averages(image: &rpbrt::image::Image) -> Vec<f64> {
    assert!(image.first_non_finite().is_none(), "a non-finite pixel");
    (0..image.height())
        .flat_map(|y| (0..image.width()).map(move |x| (x, y)))
        .map(|(x, y)| {
            image.pixel(x, y)[..3]
                .iter()
                .map(|&v| v as f64)
                .sum::<f64>()
                / 3.0
        })
        .collect()
}
