//! Scenes with known answers.

mod common;

use rpbrt::image::Image;

fn render(name: &str, scene: &str, spp: u32, threads: usize) -> Image {
    common::render_text(name, scene, spp, threads, Default::default())
}

fn furnace(integrator: &str) -> String {
    format!(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
         Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32 \"bool savefp16\" false\n\
         Sampler \"zsobol\"\nIntegrator \"{integrator}\" \"integer maxdepth\" 100\nWorldBegin\n\
         LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Material \"diffuse\" \"rgb reflectance\" [1 1 1]\nShape \"sphere\" \"float radius\" 1\n"
    )
}

/// A white diffuse sphere inside a uniform white sky: every pixel is 1.
#[test]
fn white_furnace_renders_one() {
    for integrator in ["path", "volpath"] {
        let image = render(integrator, &furnace(integrator), 64, 2);
        let data = image.rgb_data();
        let mean: f64 = data.iter().map(|&v| v as f64).sum::<f64>() / data.len() as f64;
        let worst = data.iter().map(|&v| (v - 1.0).abs()).fold(0.0f32, f32::max);
        eprintln!("{integrator}: mean {mean:.4}, worst pixel error {worst:.4}");
        assert!((mean - 1.0).abs() < 0.01, "{integrator}: mean {mean}");
        assert!(worst < 0.1, "{integrator}: worst {worst}");
    }
}

/// The image for a given seed and spp is identical at any thread count.
#[test]
fn deterministic_across_thread_counts() {
    let scene = furnace("path").replace("[1 1 1]\nShape", "[0.5 0.3 0.2]\nShape");
    let a = render("det1", &scene, 4, 1);
    let b = render("det2", &scene, 4, 2);
    assert_eq!(a.rgb_data(), b.rgb_data());
}

/// The render counts its rays: with nothing to hit, one closest-hit ray per
/// camera sample and no shadow ray; with a diffuse sphere, more of both,
/// and the same counts at any thread count.
#[test]
fn rays_are_counted() {
    let dir = std::env::temp_dir().join(format!("rpbrt-test-rays-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let count = |name: &str, scene: &str, threads: usize| {
        let path = dir.join(format!("{name}.pbrt"));
        std::fs::write(&path, scene).unwrap();
        let overrides = rpbrt::scene::build::RenderOverrides {
            spp: Some(4),
            outfile: Some(dir.join(format!("{name}.exr"))),
            ..Default::default()
        };
        rpbrt::pipeline::render_file(&path, &overrides, threads, false)
            .unwrap()
            .rays
    };
    // A point light: the uniform sky is reached by BSDF samples only (as
    // in pbrt-v4, its light samples are skipped when the BSDF's cover it).
    let sphere = furnace("path").replace(
        "Material",
        "LightSource \"point\" \"point3 from\" [0 0 5]\nMaterial",
    );
    let (empty_scene, _) = sphere.split_at(sphere.find("LightSource \"point\"").unwrap());
    let empty = count("empty", empty_scene, 2);
    assert_eq!((empty.closest_hit, empty.shadow), (32 * 32 * 4, 0));
    let one = count("sphere1", &sphere, 1);
    let two = count("sphere2", &sphere, 2);
    assert_eq!(one, two);
    assert!(
        one.closest_hit > empty.closest_hit && one.shadow > 0,
        "{one:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
