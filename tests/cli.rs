//! The `rpbrt` command line: summary, `--format`, `--upgrade`, errors.

use std::path::PathBuf;
use std::process::Command;

fn rpbrt(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_rpbrt"))
        .args(args)
        .output()
        .expect("run rpbrt");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn write_temp(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rpbrt-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn summary_of_the_shipped_scene() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/pbrt-scenes/hair-strands.pbrt");
    let (ok, stdout, _) = rpbrt(&["--check", scene]);
    assert!(ok);
    assert!(
        stdout.contains("curve: 4") && stdout.contains("sphere: 2"),
        "{stdout}"
    );
}

#[test]
fn upgrade_prints_pbrt_v4_and_lists_rewrites() {
    let v3 = write_temp(
        "v3.pbrt",
        "Film \"image\" \"integer xresolution\" 10\nWorldBegin\nMaterial \"matte\" \"color Kd\" [.5 .5 .5]\n\
         Shape \"sphere\"\nWorldEnd\n",
    );
    let (ok, stdout, stderr) = rpbrt(&["--upgrade", v3.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("Film \"rgb\""), "{stdout}");
    assert!(
        stdout.contains("Material \"diffuse\"\n    \"rgb reflectance\" [ 0.5 0.5 0.5 ]"),
        "{stdout}"
    );
    assert!(!stdout.contains("WorldEnd"), "{stdout}");
    assert!(
        stderr.contains("pbrt-v3 Material \"matte\" read as \"diffuse\""),
        "{stderr}"
    );
    // The upgraded text is a valid pbrt-v4 scene with no further rewrites.
    let v4 = write_temp("v4.pbrt", &stdout);
    let (ok, _, stderr) = rpbrt(&["--upgrade", v4.to_str().unwrap()]);
    assert!(ok && stderr.is_empty(), "{stderr}");
}

#[test]
fn errors_exit_non_zero_with_location() {
    let bad = write_temp(
        "bad.pbrt",
        "WorldBegin\nShape \"sphere\" \"float radius\" [ 1 2x ]\n",
    );
    let (ok, _, stderr) = rpbrt(&[bad.to_str().unwrap()]);
    assert!(!ok);
    assert!(
        stderr.contains("bad.pbrt:2:35: bad number \"2x\""),
        "{stderr}"
    );
    let (ok, _, stderr) = rpbrt(&["/nonexistent/scene.pbrt"]);
    assert!(!ok && stderr.contains("cannot read"), "{stderr}");
}

#[test]
fn curves_as_area_lights_are_refused_with_a_message() {
    let scene = write_temp(
        "curve-light.pbrt",
        "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\nAttributeBegin\n\
         AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n\
         Shape \"curve\" \"point3 P\" [0 0 0 1 0 0 2 0 0 3 0 0] \"float width\" 0.1\nAttributeEnd\n",
    );
    let out = scene.with_extension("exr");
    let (ok, _, stderr) = rpbrt(&[
        scene.to_str().unwrap(),
        "--outfile",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("curve-light.pbrt:5:1") && stderr.contains("curves cannot be area lights"),
        "{stderr}"
    );
    assert!(!out.exists(), "no image is written on error");
}

/// A small lit scene (40 × 30, 16 spp), rendered to `name`.exr beside it.
fn small_scene(name: &str, light_scale: &str, film_extra: &str) -> (PathBuf, PathBuf) {
    let scene = write_temp(
        &format!("{name}.pbrt"),
        &format!(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
             Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 30 {film_extra}\n\
             Sampler \"zsobol\" \"integer pixelsamples\" 16\nWorldBegin\n\
             LightSource \"point\" \"point3 from\" [ 0 0 2 ] \"float scale\" {light_scale}\n\
             Material \"diffuse\"\nShape \"sphere\" \"float radius\" 1\n"
        ),
    );
    let out = scene.with_extension("exr");
    (scene, out)
}

/// `--stats`' first line: "resolution WxH, N spp, ...".
fn stats_line(stdout: &str) -> &str {
    stdout.lines().next().unwrap_or("")
}

#[test]
fn window_flags_take_pbrt_v4s_comma_lists_and_four_numbers() {
    let (scene, out) = small_scene("window", "1", "");
    let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let forms: [&[&str]; 5] = [
        &["--pixelbounds", "10,30,5,20"],
        &["--pixelbounds=10,30,5,20"],
        &["--pixelbounds", "10", "30", "5", "20"],
        &["--cropwindow", "0.25,0.75,0.1666,0.6666"],
        &["--cropwindow", "0.25", "0.75", "0.1666", "0.6666"],
    ];
    for flags in forms {
        let mut args = flags.to_vec();
        args.extend([scene, "--outfile", out, "--spp", "1", "--stats", "--quiet"]);
        let (ok, stdout, stderr) = rpbrt(&args);
        assert!(ok, "{flags:?}: {stderr}");
        assert!(
            stats_line(&stdout).starts_with("resolution 20x15,"),
            "{flags:?}: {stdout}"
        );
        let (_, window) = rpbrt::image::Image::read_exr_with_window(out).unwrap();
        assert_eq!(
            (window.origin, window.full_resolution),
            ((10, 5), (40, 30)),
            "{flags:?}"
        );
    }
}

#[test]
fn bad_window_values_are_clear_errors() {
    let (scene, out) = small_scene("bad-window", "1", "");
    let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let cases: [(&[&str], &str); 8] = [
        (
            &["--pixelbounds", "0,20,0"],
            "--pixelbounds takes four values",
        ),
        (
            &["--cropwindow=0,1,0,1,1"],
            "--cropwindow takes four values",
        ),
        (&["--pixelbounds", "0,x,0,10"], "invalid value 'x'"),
        (&["--pixelbounds", "5,5,0,10"], "holds no pixels"),
        (
            &["--pixelbounds", "50,60,0,10"],
            "leaves no pixel of the 40x30 image",
        ),
        (
            &["--cropwindow", "0,1.5,0,1"],
            "1.5 is not a fraction of the image",
        ),
        (
            &["--cropwindow", "0,nan,0,1"],
            "NaN is not a fraction of the image",
        ),
        (&["--cropwindow", "0.5,0.5,0,1"], "is empty"),
    ];
    for (flags, message) in cases {
        let mut args = flags.to_vec();
        args.extend([scene, "--outfile", out, "--spp", "1"]);
        let (ok, _, stderr) = rpbrt(&args);
        assert!(!ok, "{flags:?} succeeded");
        assert!(
            stderr.contains(message) && !stderr.contains("panicked"),
            "{flags:?}: {stderr}"
        );
    }
    // Bounds reaching past the image are clipped to it, with a warning.
    let (ok, stdout, stderr) = rpbrt(&[
        "--pixelbounds",
        "-5,20,0,50",
        scene,
        "--outfile",
        out,
        "--spp",
        "1",
        "--stats",
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stats_line(&stdout).starts_with("resolution 20x30,"),
        "{stdout}"
    );
    assert!(
        stderr.contains("reaches outside the 40x30 image; rendering 0,20,0,30"),
        "{stderr}"
    );
}

#[test]
fn quick_renders_a_quarter_resolution_at_one_sample_per_pixel() {
    let (scene, out) = small_scene("quick", "1", "");
    let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
    for spp in [None, Some("64")] {
        let mut args = vec![scene, "--quick", "--outfile", out, "--stats", "--quiet"];
        if let Some(spp) = spp {
            args.extend(["--spp", spp]);
        }
        let (ok, stdout, stderr) = rpbrt(&args);
        assert!(ok, "{stderr}");
        assert!(
            stats_line(&stdout).starts_with("resolution 10x7, 1 spp,"),
            "--spp {spp:?}: {stdout}"
        );
    }
}

/// Under `--quick` a Film's own bounds are those of the reduced image, as
/// pbrt-v4 reads them after dividing the resolution: `pixelbounds` clipped
/// to it, `cropwindow` taken of it.
#[test]
fn quick_keeps_the_films_own_bounds_on_the_reduced_image() {
    for (name, film, expected) in [
        ("quick-pb", "\"integer pixelbounds\" [ 2 8 0 30 ]", (6, 7)),
        ("quick-crop", "\"float cropwindow\" [ 0 0.5 0 1 ]", (5, 7)),
    ] {
        let (scene, out) = small_scene(name, "1", film);
        let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
        let (ok, _, stderr) = rpbrt(&[scene, "--quick", "--outfile", out, "--quiet"]);
        assert!(ok, "{stderr}");
        let image = rpbrt::image::Image::read(out).unwrap();
        assert_eq!((image.width(), image.height()), expected, "{film}");
    }
}

#[test]
fn radiance_beyond_the_half_range_is_clamped_and_counted() {
    let (scene, out) = small_scene("huge-light", "1e9", "");
    let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let (ok, stdout, stderr) = rpbrt(&[scene, "--outfile", out, "--spp", "1", "--stats"]);
    assert!(ok, "{stderr}");
    let image = rpbrt::image::Image::read(out).unwrap();
    assert_eq!(image.format(), rpbrt::image::PixelFormat::Half);
    assert!(image.data().iter().all(|v| v.is_finite()));
    let clamped = image.data().iter().filter(|v| v.abs() == 65504.0).count();
    assert!(clamped > 0, "the light is bright enough to clamp");
    assert!(
        stderr.contains(&format!(
            "warning: {clamped} channel values exceeded the half-float range and were clamped"
        )),
        "{stderr}"
    );
    assert!(
        stdout.contains(&format!("clamped to half: {clamped}")),
        "{stdout}"
    );
    // 32-bit float EXRs keep the values, and nothing is clamped.
    let (scene, out) = small_scene("huge-light-f32", "1e9", "\"bool savefp16\" false");
    let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let (ok, _, stderr) = rpbrt(&[scene, "--outfile", out, "--spp", "1"]);
    assert!(ok && !stderr.contains("half-float range"), "{stderr}");
    let image = rpbrt::image::Image::read(out).unwrap();
    assert!(image.data().iter().any(|&v| v > 65504.0 && v.is_finite()));
}

/// The README's first command (render a shipped hair scene) works as
/// written, from the repository's root, with the output put elsewhere.
#[test]
fn the_readmes_first_command_renders() {
    let root = env!("CARGO_MANIFEST_DIR");
    let readme = std::fs::read_to_string(format!("{root}/README.md")).unwrap();
    let command = readme
        .lines()
        .find_map(|l| l.trim().strip_prefix("cargo run --release -- "))
        .expect("a `cargo run --release -- ...` line in the README");
    let mut args: Vec<String> = command.split_whitespace().map(String::from).collect();
    let out = std::env::temp_dir().join(format!("rpbrt-readme-{}.png", std::process::id()));
    // The README writes next to the user; the test writes to a temporary file.
    if let Some(i) = args.iter().position(|a| a == "--outfile") {
        args[i + 1] = out.display().to_string();
    }
    let status = Command::new(env!("CARGO_BIN_EXE_rpbrt"))
        .args(&args)
        .arg("--quiet")
        .current_dir(root)
        .status()
        .unwrap();
    assert!(status.success(), "{command}");
    let image = rpbrt::image::Image::read(&out).unwrap();
    assert!(image.width() > 0);
    let _ = std::fs::remove_file(&out);
}
