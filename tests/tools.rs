//! The measuring tools as a user runs them: `rpbrt imgtool diff|assemble`,
//! a frame split into `--pixelbounds` tiles rendered by separate processes
//! (docs/scaling.md), and `rpbrt report|convergence` handing off to the
//! benchmark harness (whose own tests are in `bench/tests/`).
mod common;
use common::rpbrt;

use rpbrt::image::Image;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn temp_dir(name: &str) -> PathBuf {
    common::fresh_dir("tools", name)
}

fn write_rgb(path: &Path, width: u32, height: u32, data: Vec<f32>) {
    Image::from_rgb(width, height, data)
        .unwrap()
        .write(path)
        .unwrap();
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The number after `label` in the tool's output.
fn figure_after(text: &str, label: &str) -> f64 {
    let rest = &text[text
        .find(label)
        .unwrap_or_else(|| panic!("no {label} in {text}"))
        + label.len()..];
    rest.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn diff_of_an_image_with_itself_is_zero() {
    let dir = temp_dir("self");
    let image = dir.join("a.pfm");
    let data: Vec<f32> = (0..8 * 4 * 3)
        .map(|i| (i as f32 * 0.37).sin().abs() * 3.0)
        .collect();
    write_rgb(&image, 8, 4, data);
    for metric in ["mse", "mrse", "mae", "flip"] {
        let out = rpbrt(&[
            "imgtool".as_ref(),
            "diff".as_ref(),
            "--metric".as_ref(),
            metric.as_ref(),
            "--tolerance".as_ref(),
            "0".as_ref(),
            "--reference".as_ref(),
            image.as_os_str(),
            image.as_os_str(),
        ]);
        assert_eq!(out.status.code(), Some(0), "{metric}: {out:?}");
        assert_eq!(
            figure_after(&stdout(&out), metric.to_uppercase().as_str()),
            0.0,
            "{metric}"
        );
        assert_eq!(figure_after(&stdout(&out), "block bias"), 0.0);
    }
}

#[test]
fn diff_gives_known_errors_and_exit_codes() {
    let dir = temp_dir("known");
    let (reference, image) = (dir.join("ref.pfm"), dir.join("img.pfm"));
    // Reference 1 everywhere; the image is 1.1 on the left half, 1 on the right.
    write_rgb(&reference, 4, 2, vec![1.0; 4 * 2 * 3]);
    let data = (0..4 * 2)
        .flat_map(|p| [if p % 4 < 2 { 1.1 } else { 1.0 }; 3])
        .collect();
    write_rgb(&image, 4, 2, data);
    let diff = |metric: &str, tolerance: &str| {
        rpbrt(&[
            "imgtool".as_ref(),
            "diff".as_ref(),
            "--metric".as_ref(),
            metric.as_ref(),
            "--tolerance".as_ref(),
            tolerance.as_ref(),
            "--reference".as_ref(),
            reference.as_os_str(),
            image.as_os_str(),
        ])
    };
    // Half the pixels have (x − r)² / (r² + 0.01) = 0.01 / 1.01.
    let expected_mrse = 0.5 * 0.01 / 1.01;
    let out = diff("mrse", "1");
    assert_eq!(out.status.code(), Some(0));
    assert!(
        (figure_after(&stdout(&out), "MRSE") - expected_mrse).abs() < 1e-6,
        "{out:?}"
    );
    let out = diff("mse", "1");
    assert!(
        (figure_after(&stdout(&out), "MSE") - 0.005).abs() < 1e-6,
        "{out:?}"
    );
    let out = diff("mae", "1");
    assert!(
        (figure_after(&stdout(&out), "MAE") - 0.05).abs() < 1e-6,
        "{out:?}"
    );
    // Above the tolerance: 1; unreadable input: 2.
    assert_eq!(diff("mrse", "0.004").status.code(), Some(1));
    let missing = dir.join("missing.pfm");
    let out = rpbrt(&[
        "imgtool".as_ref(),
        "diff".as_ref(),
        "--reference".as_ref(),
        missing.as_os_str(),
        image.as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
}

#[test]
fn four_tiles_in_four_processes_assemble_to_the_single_render() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/pbrt-scenes/spheres.pbrt");
    let dir = temp_dir("tiles");
    let render = |out: &Path, bounds: Option<[&str; 4]>| {
        let mut args: Vec<&std::ffi::OsStr> = vec![
            scene.as_ref(),
            "--spp".as_ref(),
            "2".as_ref(),
            "--quiet".as_ref(),
        ];
        args.extend(["--outfile".as_ref(), out.as_os_str()]);
        if let Some(bounds) = bounds {
            args.push("--pixelbounds".as_ref());
            args.extend(bounds.into_iter().map(std::ffi::OsStr::new));
        }
        Command::new(env!("CARGO_BIN_EXE_rpbrt"))
            .args(args)
            .spawn()
            .expect("run rpbrt")
    };
    // spheres.pbrt is 400 × 300; tiles of unequal sizes.
    let tiles = [
        ["0", "150", "0", "110"],
        ["150", "400", "0", "110"],
        ["0", "150", "110", "300"],
        ["150", "400", "110", "300"],
    ];
    let pieces: Vec<PathBuf> = (0..4).map(|i| dir.join(format!("tile{i}.exr"))).collect();
    let children: Vec<_> = tiles
        .iter()
        .zip(&pieces)
        .map(|(bounds, piece)| render(piece, Some(*bounds)))
        .collect();
    for mut child in children {
        assert!(child.wait().unwrap().success());
    }
    let whole = dir.join("whole.exr");
    assert!(render(&whole, None).wait().unwrap().success());

    let assembled = dir.join("assembled.exr");
    let mut args = vec![
        "imgtool".as_ref(),
        "assemble".as_ref(),
        "--outfile".as_ref(),
        assembled.as_os_str(),
    ];
    args.extend(pieces.iter().map(|p| p.as_os_str()));
    let out = rpbrt(&args);
    assert!(out.status.success(), "{out:?}");

    let (a, b) = (
        Image::read(&assembled).unwrap(),
        Image::read(&whole).unwrap(),
    );
    assert_eq!((a.width(), a.height()), (400, 300));
    assert_eq!((b.width(), b.height()), (400, 300));
    let (a, b) = (a.rgb_data(), b.rgb_data());
    let differing = a
        .iter()
        .zip(&b)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count();
    assert_eq!(differing, 0, "{differing} of {} values differ", a.len());
    assert!(b.iter().any(|&v| v > 0.0));
}

/// `rpbrt report` and `rpbrt convergence` run the `rpbrt-bench` beside
/// the `rpbrt` executable: with a stand-in harness (a script printing its
/// arguments and exiting 7) the arguments arrive unread, `--help` among
/// them, and its exit status comes back; without one, the error says how
/// to build it.
#[cfg(unix)]
#[test]
fn report_and_convergence_hand_off_to_the_harness() {
    use std::os::unix::fs::PermissionsExt;
    let dir = temp_dir("handoff");
    let exe = dir.join("rpbrt");
    std::fs::copy(env!("CARGO_BIN_EXE_rpbrt"), &exe).unwrap();
    let run = |args: &[&str]| Command::new(&exe).args(args).output().unwrap();

    let out = run(&["report", "--pbrt", "/x/pbrt"]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let error = String::from_utf8_lossy(&out.stderr);
    assert!(
        error.contains("rpbrt-bench") && error.contains("cargo build --release -p rpbrt-bench"),
        "{error}"
    );

    let harness = dir.join("rpbrt-bench");
    std::fs::write(&harness, "#!/bin/sh\necho \"$@\"\nexit 7\n").unwrap();
    std::fs::set_permissions(&harness, std::fs::Permissions::from_mode(0o755)).unwrap();
    for (args, passed) in [
        (
            &["report", "--pbrt", "/x/pbrt"][..],
            "report --pbrt /x/pbrt",
        ),
        (&["report", "--help"][..], "report --help"),
        (
            &["convergence", "s.pbrt", "--spp", "1,4", "-q"][..],
            "convergence s.pbrt --spp 1,4 -q",
        ),
    ] {
        let out = run(args);
        assert_eq!(out.status.code(), Some(7), "{args:?}: {out:?}");
        assert_eq!(stdout(&out).trim(), passed);
    }
}
