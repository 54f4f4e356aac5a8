//! Image textures and alpha cutouts in rendered scenes.

use rpbrt::image::Image;
use rpbrt::scene::build::RenderOverrides;
use std::path::{Path, PathBuf};

/// A scratch directory holding a 2×1 RGB image, left texel `left`, right
/// texel `right` (linear PFM).
fn scratch(name: &str, left: f32, right: f32) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rpbrt-texalpha-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let data = vec![left, left, left, right, right, right];
    Image::new(2, 1, &["R", "G", "B"], data)
        .unwrap()
        .write(dir.join("halves.pfm"))
        .unwrap();
    dir
}

fn render(dir: &Path, scene: &str, spp: u32) -> Image {
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join("out.exr");
    let overrides = RenderOverrides {
        spp: Some(spp),
        outfile: Some(out.clone()),
        ..Default::default()
    };
    rpbrt::pipeline::render_file(&path, &overrides, 2, false).unwrap();
    let image = Image::read(&out).unwrap();
    std::fs::remove_dir_all(dir).ok();
    image
}

/// Camera straight down −z at a 16×16 image that a 2×2 quad at the origin
/// fills; box pixel filter, so a pixel sees only its own column of the quad.
const VIEW: &str = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 20\n\
     Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 \"bool savefp16\" false\n\
     PixelFilter \"box\"\n";

/// The quad z = `z`, uv (0,0) at (−s,−s) to (1,1) at (s,s).
fn quad(z: f32, s: f32, extra: &str) -> String {
    format!(
        "Shape \"trianglemesh\" \"point3 P\" [ -{s} -{s} {z}  {s} -{s} {z}  {s} {s} {z}  -{s} {s} {z} ]\n\
         \"point2 uv\" [ 0 0 1 0 1 1 0 1 ] \"integer indices\" [ 0 1 2 0 2 3 ] {extra}\n"
    )
}

/// Mean of each image half (pixel columns 0–7, 8–15) over RGB.
fn half_means(image: &Image) -> (f32, f32) {
    let (mut left, mut right) = (0.0, 0.0);
    for y in 0..16 {
        for x in 0..16 {
            let p = image.pixel(x, y);
            let v = (p[0] + p[1] + p[2]) / 3.0;
            if x < 8 {
                left += v / 128.0;
            } else {
                right += v / 128.0;
            }
        }
    }
    (left, right)
}

/// A black quad cut out by an image alpha (1 on its u < ½ half, 0 on the
/// other) in front of a white sky: half the pixels see the sky. Camera
/// space is left-handed: world x < 0 (u < ½) is the image's right half.
#[test]
fn alpha_cut_quad_lets_half_the_pixels_see_the_sky() {
    let dir = scratch("sky", 1.0, 0.0);
    let scene = format!(
        "{VIEW}WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Texture \"cut\" \"float\" \"imagemap\" \"string filename\" \"halves.pfm\" \"string filter\" \"point\"\n\
         Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{}",
        quad(0.0, 1.0, "\"texture alpha\" \"cut\"")
    );
    let image = render(&dir, &scene, 4);
    let (left, right) = half_means(&image);
    eprintln!("alpha-cut quad: left half {left:.4}, right half {right:.4}");
    assert!((left - 1.0).abs() < 0.01, "left half should be sky: {left}");
    assert!(
        right.abs() < 1e-6,
        "right half should be the black quad: {right}"
    );
}

/// A constant alpha of ½ lets about half of the rays through, chosen by a
/// hash of each ray; alpha 0 removes the shape.
#[test]
fn fractional_alpha_passes_that_fraction_of_rays() {
    for (alpha, expected, tolerance) in [(0.5, 0.5, 0.05), (0.0, 1.0, 1e-3)] {
        let dir = scratch(&format!("frac{alpha}"), 1.0, 1.0);
        let scene = format!(
            "{VIEW}WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
             Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{}",
            quad(0.0, 1.0, &format!("\"float alpha\" {alpha}"))
        );
        let image = render(&dir, &scene, 16);
        let (left, right) = half_means(&image);
        let mean = (left + right) / 2.0;
        eprintln!("alpha {alpha}: mean {mean:.4}");
        assert!(
            (mean - expected).abs() < tolerance,
            "alpha {alpha}: mean {mean}"
        );
    }
}

/// A white floor under an occluder cut out on one half, lit straight from
/// above: light reaches the floor through the cut-out half only, so shadow
/// rays test alpha too.
#[test]
fn shadow_rays_pass_through_cut_out_parts() {
    let dir = scratch("shadow", 1.0, 0.0);
    let scene = format!(
        "{VIEW}WorldBegin\nLightSource \"distant\" \"point3 from\" [0 0 10] \"point3 to\" [0 0 0] \"rgb L\" [3 3 3]\n\
         Texture \"cut\" \"float\" \"imagemap\" \"string filename\" \"halves.pfm\" \"string filter\" \"point\"\n\
         Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n{}\
         Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{}",
        quad(-1.0, 10.0, ""),
        quad(1.0, 10.0, "\"texture alpha\" \"cut\"")
    );
    let image = render(&dir, &scene, 4);
    let (left, right) = half_means(&image);
    eprintln!("shadow: lit half {left:.4}, occluded half {right:.4}");
    // Lambertian 0.5 under irradiance 3: 0.5 · 3 / π.
    let lit = 1.5 / std::f32::consts::PI;
    assert!(
        (left - lit).abs() < 0.02 * lit,
        "lit half {left}, expected {lit}"
    );
    assert!(right.abs() < 1e-6, "occluded half {right}");
}

/// A spectrum image texture as a diffuse reflectance under a white sky:
/// each half of the quad renders its texel's albedo.
#[test]
fn image_texture_reflectance_renders_its_texels() {
    let dir = scratch("albedo", 0.25, 0.75);
    let scene = format!(
        "{VIEW}Integrator \"path\" \"integer maxdepth\" 1\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Texture \"halves\" \"spectrum\" \"imagemap\" \"string filename\" \"halves.pfm\" \"string filter\" \"point\"\n\
         Material \"diffuse\" \"texture reflectance\" \"halves\"\n{}",
        quad(0.0, 1.0, "")
    );
    let image = render(&dir, &scene, 16);
    let (left, right) = half_means(&image);
    eprintln!("image reflectance: {left:.4} (texel 0.75), {right:.4} (texel 0.25)");
    assert!((left - 0.75).abs() < 0.02, "{left}");
    assert!((right - 0.25).abs() < 0.01, "{right}");
}

/// Build errors name the directive at fault and what is wrong.
#[test]
fn imagemap_and_alpha_errors_name_their_directive() {
    let dir = scratch("errors", 1.0, 0.0);
    let build_error = |world: &str| -> String {
        let path = dir.join("scene.pbrt");
        let text = format!("{VIEW}WorldBegin\n{world}");
        std::fs::write(&path, &text).unwrap();
        let loaded = rpbrt::scene::load(&path).unwrap();
        match rpbrt::scene::build::build(loaded.scene, &RenderOverrides::default()) {
            Ok(_) => panic!("no error for {world:?}"),
            Err(e) => e.to_string(),
        }
    };
    let cases = [
        (
            "Texture \"t\" \"float\" \"imagemap\" \"string filename\" \"halves.pfm\" \"string wrap\" \"mirror\"\n",
            "scene.pbrt:6:1: \"mirror\": wrap mode unknown",
        ),
        (
            "Texture \"t\" \"float\" \"imagemap\" \"string filename\" \"absent.png\"\n",
            "scene.pbrt:6:32: imagemap texture: cannot read \"",
        ),
        (
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"halves.pfm\" \"string encoding\" \"gamma\"\n",
            "scene.pbrt:6:1: \"gamma\": unknown color encoding",
        ),
        (
            "Texture \"t\" \"float\" \"checkerboard\" \"string mapping\" \"cubic\"\n",
            "scene.pbrt:6:1: 2D texture mapping \"cubic\" unknown",
        ),
        (
            "AttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" \"halves.pfm\" \"rgb L\" [1 1 1]\n  Shape \"sphere\"\nAttributeEnd\n",
            "scene.pbrt:7:58: area light: both \"L\" and \"filename\" are given",
        ),
        (
            "AttributeBegin\nAreaLightSource \"diffuse\" \"string filename\" \"absent.pfm\"\n  Shape \"sphere\"\nAttributeEnd\n",
            "scene.pbrt:7:27: area light: cannot read \"",
        ),
    ];
    for (world, expected) in cases {
        let e = build_error(world);
        assert!(e.contains(expected), "expected {expected:?} in:\n{e}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Form factor from a point to a parallel rectangle a × b at height h
/// with one corner straight above the point.
fn corner_form_factor(a: f64, b: f64, h: f64) -> f64 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * std::f64::consts::PI)
}

/// An emitter of constant alpha 0 is never hit but still lights the scene
/// (pbrt-v4's invisible area light, reached by light sampling alone): a
/// Lambertian floor under a two-sided emitting square (half-side 4,
/// height 6, L = 1) above the camera reflects ρ · L · F, F the form
/// factor, whether the emitter is visible or not.
#[test]
fn invisible_emitter_lights_the_floor_as_a_visible_one() {
    let view = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 4\n\
         Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 \"bool savefp16\" false\n\
         Integrator \"path\" \"integer maxdepth\" 1\n";
    let (s, h) = (4.0, 6.0);
    let expected = 0.5 * 4.0 * corner_form_factor(s, s, h);
    for alpha in ["", "\"float alpha\" 0"] {
        let dir = scratch(&format!("invisible{}", alpha.len()), 1.0, 1.0);
        let scene = format!(
            "{view}WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n{}\
             AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool twosided\" true\n\
             Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{}AttributeEnd\n",
            quad(0.0, 10.0, ""),
            quad(h as f32, s as f32, alpha)
        );
        let image = render(&dir, &scene, 16);
        let (left, right) = half_means(&image);
        let mean = f64::from(left + right) / 2.0;
        eprintln!("emitter {alpha:?}: floor {mean:.4}, expected {expected:.4}");
        assert!(
            (mean - expected).abs() < 0.02 * expected,
            "{alpha:?}: {mean} vs {expected}"
        );
    }
}

/// Alpha ½ on an emitter seen straight on: half of the camera rays hit it
/// (a hash of the ray) and half of the points hit emit (a hash of the
/// point), as pbrt-v4 tests both: a quarter of L on average.
#[test]
fn alpha_masks_an_emitters_radiance() {
    let dir = scratch("masked", 1.0, 1.0);
    let scene = format!(
        "{VIEW}WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n\
         Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{}",
        quad(0.0, 1.0, "\"float alpha\" 0.5")
    );
    let image = render(&dir, &scene, 16);
    let (left, right) = half_means(&image);
    let mean = (left + right) / 2.0;
    eprintln!("emitter of alpha 0.5: mean {mean:.4}");
    assert!((mean - 0.25).abs() < 0.03, "{mean}");
}

/// An emitter with an image: the radiance at (u, v) is the image's
/// bilinear RGB at (u, 1 − v), times `scale`. Texels 1 (u < ½) and 0
/// (u > ½), centres at u = ¼ and ¾, so the radiance is 1 up to u = ¼,
/// falls linearly to 0 at u = ¾ and stays 0; the view (half-width
/// 5 tan 10°) sees u from c = ½ − 5 tan 10° / 2 to 1 − c.
#[test]
fn image_emitter_renders_its_texels() {
    let dir = scratch("emitimage", 1.0, 0.0);
    let scene = format!(
        "{VIEW}WorldBegin\nAreaLightSource \"diffuse\" \"string filename\" \"halves.pfm\" \"float scale\" 2\n\
         Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{}",
        quad(0.0, 1.0, "")
    );
    let image = render(&dir, &scene, 16);
    let (left, right) = half_means(&image);
    let c = 0.5 - 5.0 * 10f32.to_radians().tan() / 2.0;
    let width = 0.5 - c;
    // ∫ over [c, ½]: (¼ − c) · 1 + ¼ · ¾; over [½, 1 − c]: ¼ · ¼.
    let bright = 2.0 * ((0.25 - c) + 0.25 * 0.75) / width;
    let dim = 2.0 * (0.25 * 0.25) / width;
    eprintln!("image emitter: u > ½ {left:.4} ({dim:.4}), u < ½ {right:.4} ({bright:.4})");
    assert!((right - bright).abs() < 0.01, "{right} vs {bright}");
    assert!((left - dim).abs() < 0.01, "{left} vs {dim}");
}
