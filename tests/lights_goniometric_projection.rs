//! Goniometric and projection lights in rendered scenes, read from scene
//! files: a goniometric light with a constant image is a point light, and
//! the two normalise `power` alike; scene errors name where they are.

use rpbrt::image::Image;
use rpbrt::scene::build::RenderOverrides;
use std::path::{Path, PathBuf};

/// A fresh folder for one test's files.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rpbrt-lights-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn render(dir: &Path, scene: &str) -> Result<Image, String> {
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join("out.exr");
    let overrides = RenderOverrides {
        spp: Some(4),
        outfile: Some(out.clone()),
        ..Default::default()
    };
    rpbrt::pipeline::render_file(&path, &overrides, 2, false).map_err(|e| format!("{e:#}"))?;
    Ok(Image::read(&out).unwrap())
}

/// A plane under a light 2 units above it, seen from above.
fn scene(light: &str) -> String {
    format!(
        "LookAt 0 6 6  0 0 0  0 1 0\n\
         Camera \"perspective\" \"float fov\" 50\n\
         Film \"rgb\" \"integer xresolution\" 24 \"integer yresolution\" 24\n\
         Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 2\n\
         WorldBegin\n\
         AttributeBegin\n\
         Translate 0.3 2 -0.4\n\
         Rotate 35 1 0.5 0\n\
         {light}\n\
         AttributeEnd\n\
         Material \"diffuse\"\n\
         Shape \"trianglemesh\" \"point3 P\" [-5 0 -5  5 0 -5  5 0 5  -5 0 5] \"integer indices\" [0 1 2 0 2 3]\n"
    )
}

fn assert_same(a: &Image, b: &Image) {
    let mut lit = 0;
    for (x, y) in a.data().iter().zip(b.data()) {
        // The film is written as half floats: one half-float step apart.
        assert!((x - y).abs() <= 1e-3 * y.abs() + 1e-6, "{x} vs {y}");
        lit += (*y > 0.0) as usize;
    }
    assert!(lit > a.data().len() / 2, "the plane should be lit");
}

#[test]
fn goniometric_with_a_constant_image_renders_as_a_point_light() {
    let dir = folder("gonio-point");
    Image::new(8, 8, &["R", "G", "B"], vec![0.5; 8 * 8 * 3])
        .unwrap()
        .write_pfm(dir.join("half.pfm"))
        .unwrap();
    let gonio = render(
        &dir,
        &scene("LightSource \"goniometric\" \"string filename\" \"half.pfm\" \"rgb I\" [0.2 0.5 0.9] \"float scale\" 6"),
    )
    .unwrap();
    let point = render(
        &dir,
        &scene("LightSource \"point\" \"rgb I\" [0.2 0.5 0.9] \"float scale\" 3"),
    )
    .unwrap();
    assert_same(&gonio, &point);
    // `power` divides by the image's mean, so the image's level drops out.
    let gonio = render(
        &dir,
        &scene("LightSource \"goniometric\" \"string filename\" \"half.pfm\" \"float power\" 20"),
    )
    .unwrap();
    let point = render(&dir, &scene("LightSource \"point\" \"float power\" 20")).unwrap();
    assert_same(&gonio, &point);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn light_image_errors_are_located_and_name_the_file() {
    let dir = folder("errors");
    for kind in ["goniometric", "projection"] {
        let error = render(
            &dir,
            &scene(&format!(
                "LightSource \"{kind}\" \"string filename\" \"nothere.exr\""
            )),
        )
        .unwrap_err();
        assert!(error.contains("scene.pbrt:9:"), "{error}");
        assert!(error.contains("nothere.exr"), "{error}");
    }
    // pbrt-v4's projection light reads no "I".
    Image::new(4, 2, &["R", "G", "B"], vec![1.0; 4 * 2 * 3])
        .unwrap()
        .write_pfm(dir.join("slide.pfm"))
        .unwrap();
    let error = render(
        &dir,
        &scene("LightSource \"projection\" \"string filename\" \"slide.pfm\" \"rgb I\" [1 1 1]"),
    )
    .unwrap_err();
    assert!(
        error.contains("scene.pbrt:9:") && error.contains("rgb I"),
        "{error}"
    );
    // A non-square goniometric map is refused.
    let error = render(
        &dir,
        &scene("LightSource \"goniometric\" \"string filename\" \"slide.pfm\""),
    )
    .unwrap_err();
    assert!(error.contains("not square"), "{error}");
    std::fs::remove_dir_all(&dir).ok();
}
