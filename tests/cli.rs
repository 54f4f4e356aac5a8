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
