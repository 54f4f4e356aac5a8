//! The `infinite` light's `portal` in rendered scenes, read from scene
//! files: a room lit through a window in its ceiling renders without NaN,
//! as bright as with the plain environment light and with less noise;
//! unusable portals are errors that name where and why.

mod common;

use rpbrt::image::Image;
use rpbrt::scene::build::RenderOverrides;
use std::path::{Path, PathBuf};

/// A fresh folder for one test's files.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rpbrt-portal-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn render(dir: &Path, scene: &str, seed: i32) -> Result<Image, String> {
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join(format!("out-{seed}.exr"));
    let overrides = RenderOverrides {
        spp: Some(32),
        seed: Some(seed),
        outfile: Some(out.clone()),
        ..Default::default()
    };
    rpbrt::pipeline::render_file(&path, &overrides, 2, false).map_err(|e| format!("{e:#}"))?;
    Ok(Image::read(&out).unwrap())
}

/// The window in the ceiling (y = 3), corners in order so that the lit
/// side is up.
const PORTAL: &str = "\"point3 portal\" [-0.5 3 -0.5  0.5 3 -0.5  0.5 3 0.5  -0.5 3 0.5]";

/// A closed 4 × 3 × 4 room whose only opening is a 1 × 1 window in the
/// ceiling, with a sphere in it, lit by `light`.
fn room(light: &str) -> String {
    format!(
        "LookAt 1.6 1.2 1.7  -0.3 0.8 -0.5  0 1 0\n\
         Camera \"perspective\" \"float fov\" 70\n\
         Film \"rgb\" \"integer xresolution\" 24 \"integer yresolution\" 24\n\
         Integrator \"path\" \"integer maxdepth\" 4\n\
         WorldBegin\n\
         {light}\n\
         Material \"diffuse\" \"rgb reflectance\" [0.6 0.6 0.6]\n\
         Shape \"trianglemesh\" \"point3 P\" [-2 0 -2  2 0 -2  2 0 2  -2 0 2] \"integer indices\" [0 1 2 0 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [-2 0 -2  2 0 -2  2 3 -2  -2 3 -2] \"integer indices\" [0 1 2 0 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [-2 0 2  2 0 2  2 3 2  -2 3 2] \"integer indices\" [0 1 2 0 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [-2 0 -2  -2 0 2  -2 3 2  -2 3 -2] \"integer indices\" [0 1 2 0 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [2 0 -2  2 0 2  2 3 2  2 3 -2] \"integer indices\" [0 1 2 0 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [-2 3 -2  2 3 -2  2 3 -0.5  -2 3 -0.5] \"integer indices\" [0 1 2 0 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [-2 3 0.5  2 3 0.5  2 3 2  -2 3 2] \"integer indices\" [0 1 2 0 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [-2 3 -0.5  -0.5 3 -0.5  -0.5 3 0.5  -2 3 0.5] \"integer indices\" [0 1 2 0 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [0.5 3 -0.5  2 3 -0.5  2 3 0.5  0.5 3 0.5] \"integer indices\" [0 1 2 0 2 3]\n\
         Material \"diffuse\" \"rgb reflectance\" [0.7 0.3 0.2]\n\
         AttributeBegin\n\
         Translate -0.6 0.5 -0.6\n\
         Shape \"sphere\" \"float radius\" 0.5\n\
         AttributeEnd\n"
    )
}

/// A 16 × 16 equal-area environment: a sky brighter towards +z (rotated
/// up to +y by the scene), and a small bright patch.
fn write_environment(dir: &Path) {
    let n = 16;
    let mut data = Vec::with_capacity(n * n * 3);
    for i in 0..n * n {
        let (x, y) = ((i % n) as f32 / n as f32, (i / n) as f32 / n as f32);
        let centre = 1.0 - ((x - 0.5).abs() + (y - 0.5).abs());
        let patch = if (x - 0.56).abs() < 0.05 && (y - 0.53).abs() < 0.05 {
            40.0
        } else {
            0.0
        };
        data.extend([
            0.3 * centre + patch,
            0.4 * centre + patch,
            0.6 * centre + patch,
        ]);
    }
    Image::from_rgb(n as u32, n as u32, data)
        .unwrap()
        .write_pfm(dir.join("sky.pfm"))
        .unwrap();
}

fn mean(image: &Image) -> f64 {
    image.data().iter().map(|&v| v as f64).sum::<f64>() / image.data().len() as f64
}

/// Root-mean-square difference between two renders, relative to the
/// mean: the noise of one render, up to a factor √2.
fn relative_noise(a: &Image, b: &Image) -> f64 {
    let n = a.data().len() as f64;
    let squares: f64 = a
        .data()
        .iter()
        .zip(b.data())
        .map(|(&x, &y)| ((x - y) as f64).powi(2))
        .sum();
    (squares / n).sqrt() / mean(a)
}

/// Light enters only through the window, so the portal changes how the
/// light is sampled but not the image's level; it removes noise.
#[test]
fn a_portal_renders_the_room_as_bright_with_less_noise() {
    let dir = folder("room");
    write_environment(&dir);
    let light = |portal: &str| {
        format!(
            "AttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string filename\" \"sky.pfm\" {portal}\nAttributeEnd"
        )
    };
    let with_portal: Vec<Image> = (0..2)
        .map(|seed| render(&dir, &room(&light(PORTAL)), seed).unwrap())
        .collect();
    let without: Vec<Image> = (0..2)
        .map(|seed| render(&dir, &room(&light("")), seed).unwrap())
        .collect();
    for image in with_portal.iter().chain(&without) {
        assert!(
            image.data().iter().all(|v| v.is_finite()),
            "NaN or infinity"
        );
    }
    let (portal_mean, plain_mean) = (
        (mean(&with_portal[0]) + mean(&with_portal[1])) / 2.0,
        (mean(&without[0]) + mean(&without[1])) / 2.0,
    );
    assert!(portal_mean > 0.0);
    assert!(
        (portal_mean - plain_mean).abs() < 0.06 * plain_mean,
        "portal {portal_mean} vs plain {plain_mean}"
    );
    let portal_noise = relative_noise(&with_portal[0], &with_portal[1]);
    let plain_noise = relative_noise(&without[0], &without[1]);
    assert!(
        portal_noise < 0.8 * plain_noise,
        "noise with portal {portal_noise}, without {plain_noise}"
    );
}

/// Without an image, pbrt-v4 makes `L` into a 1 × 1 image: the room is
/// lit as by the uniform light of the same `L`.
#[test]
fn a_portal_with_l_is_lit_as_by_the_uniform_light() {
    let dir = folder("constant");
    let portal = render(
        &dir,
        &room(&format!(
            "LightSource \"infinite\" \"rgb L\" [0.8 0.9 1.0] {PORTAL}"
        )),
        0,
    )
    .unwrap();
    let uniform = render(
        &dir,
        &room("LightSource \"infinite\" \"rgb L\" [0.8 0.9 1.0]"),
        0,
    )
    .unwrap();
    assert!(portal.data().iter().all(|v| v.is_finite()));
    let (a, b) = (mean(&portal), mean(&uniform));
    assert!(
        a > 0.0 && (a - b).abs() < 0.06 * b,
        "portal {a} vs uniform {b}"
    );
}

/// Each unusable portal is refused at the parameter, saying why.
#[test]
fn unusable_portals_are_located_errors() {
    let dir = folder("errors");
    write_environment(&dir);
    let cases = [
        (
            "\"string filename\" \"sky.pfm\" \"point3 portal\" [0 3 0  1 3 0  1 3 1]",
            "a portal needs 4 corners, but 3 are given",
        ),
        (
            "\"string filename\" \"sky.pfm\" \"point3 portal\" [0 3 0  1 3 0  1.4 3 1  0 3 1]",
            "not a planar rectangle",
        ),
        (
            "\"string filename\" \"sky.pfm\" \"point3 portal\" [0 3 0  1 3 0  1 3.5 1  0 3 1]",
            "not a planar rectangle",
        ),
        (
            "\"string filename\" \"sky.pfm\" \"point3 portal\" [0 3 0  0 3 0  1 3 1  0 3 1]",
            "corners 0 and 1 of the portal coincide",
        ),
        (
            "\"point3 portal\" [0 3 0  1 3 0  1 3 1  0 3 1]",
            "a \"portal\" needs an environment",
        ),
        (
            "\"string filename\" \"sky.pfm\" \"float illuminance\" 5 \"point3 portal\" [0 3 0  1 3 0  1 3 1  0 3 1]",
            "\"illuminance\" with a portal is not supported yet",
        ),
    ];
    for (parameters, reason) in cases {
        let scene = room(&format!("LightSource \"infinite\" {parameters}"));
        let message = render(&dir, &scene, 0).expect_err(parameters);
        assert!(message.contains(reason), "{message}");
        // The light is on line 6 of the scene.
        assert!(message.contains("scene.pbrt:6:"), "{message}");
    }
}

/// A non-RGB `L` with a portal is reduced to RGB, with pbrt-v4's warning
/// pointing at `L`; an RGB one is not warned about.
#[test]
fn a_spectral_l_with_a_portal_is_warned_about() {
    let dir = common::fresh_dir("portal", "warning");
    let run = |l: &str| {
        let path = dir.join("scene.pbrt");
        std::fs::write(
            &path,
            room(&format!("LightSource \"infinite\" {l} {PORTAL}")),
        )
        .unwrap();
        let out = dir.join("out.exr");
        let output = common::rpbrt(&[
            "--spp".as_ref(),
            "2".as_ref(),
            "--outfile".as_ref(),
            out.as_os_str(),
            path.as_os_str(),
        ]);
        assert!(output.status.success(), "{output:?}");
        String::from_utf8_lossy(&output.stderr).into_owned()
    };
    let warned = run("\"blackbody L\" 5500");
    assert!(
        warned.contains("scene.pbrt:6:") && warned.contains("\"L\" is not RGB"),
        "{warned}"
    );
    assert!(!run("\"rgb L\" [1 1 1]").contains("not RGB"));
}
