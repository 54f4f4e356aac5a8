//! The integrators other than `path`: analytic answers (ambient occlusion,
//! white furnaces), agreement with `path` within noise, and the same image
//! at any thread count.

mod common;

use rpbrt::image::Image;

fn render(name: &str, scene: &str, spp: u32, threads: usize) -> Image {
    common::render_text(name, scene, spp, threads, Default::default())
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

/// A white diffuse sphere in a uniform white sky, seen by `integrator`.
fn furnace(integrator: &str) -> String {
    format!(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
         Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 \"bool savefp16\" false\n\
         Sampler \"zsobol\"\nIntegrator {integrator}\nWorldBegin\n\
         LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Material \"diffuse\" \"rgb reflectance\" [1 1 1]\nShape \"sphere\" \"float radius\" 1\n"
    )
}

/// Every integrator that follows light sees 1 everywhere in a white
/// furnace (a convex sphere: light reflects once, then escapes).
#[test]
fn white_furnace_is_one() {
    for integrator in [
        "\"randomwalk\"",
        "\"simplepath\"",
        "\"simplepath\" \"bool samplelights\" false",
        "\"simplepath\" \"bool samplebsdf\" false",
        "\"simplepath\" \"bool samplelights\" false \"bool samplebsdf\" false",
    ] {
        let image = render("furnace", &furnace(integrator), 256, 2);
        let values = common::channel_averages(&image);
        let m = mean(&values);
        let worst = values.iter().map(|v| (v - 1.0).abs()).fold(0.0, f64::max);
        eprintln!("{integrator}: mean {m:.4}, worst pixel {worst:.4}");
        assert!((m - 1.0).abs() < 0.01, "{integrator}: mean {m}");
        assert!(worst < 0.15, "{integrator}: worst pixel {worst}");
    }
}

/// Ambient occlusion: a camera below a disk of radius `r` at height `h`
/// (0.9 < h), looking at the point of a large floor under the disk's
/// centre through a narrow view.
fn occlusion_scene(params: &str, r: f32, h: f32) -> String {
    format!(
        "LookAt 1 0 0.9  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" 0.5\n\
         Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8 \"bool savefp16\" false\n\
         Sampler \"zsobol\"\nIntegrator \"ambientocclusion\" {params}\nWorldBegin\n\
         Material \"diffuse\"\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n\
         \"point3 P\" [-100 -100 0  100 -100 0  100 100 0  -100 100 0]\n\
         AttributeBegin\nTranslate 0 0 {h}\nShape \"disk\" \"float radius\" {r}\nAttributeEnd\n"
    )
}

/// Under a disk of radius r at height h, the cosine-weighted fraction of
/// the sky that is open is 1 − sin²θ with tan θ = r/h, i.e. h²/(r² + h²),
/// by either way of sampling; with `maxdistance` below h nothing occludes.
#[test]
fn ambient_occlusion_under_a_disk() {
    let (r, h) = (1.0f32, 1.0f32);
    let expected = (h * h / (r * r + h * h)) as f64;
    for (params, want) in [
        ("", expected),
        ("\"bool cossample\" false", expected),
        ("\"float maxdistance\" 0.5", 1.0),
    ] {
        let image = render("ao-disk", &occlusion_scene(params, r, h), 1024, 2);
        let m = mean(&common::channel_averages(&image));
        eprintln!("ambient occlusion {params:?}: {m:.4} (expected {want:.4})");
        assert!((m - want).abs() < 0.01, "{params}: {m} against {want}");
    }
}

/// An open floor is fully unoccluded: 1 (white) at every pixel.
#[test]
fn ambient_occlusion_of_an_open_plane_is_one() {
    let scene = occlusion_scene("", 1.0, 1.0).replace("Shape \"disk\"", "#");
    let image = render("ao-open", &scene, 64, 2);
    for (i, rgb) in image.rgb_data().chunks(3).enumerate() {
        // The illuminant sampled at 4 wavelengths per sample: noise in the
        // colour, none in whether the point is lit.
        let v = (rgb[0] + rgb[1] + rgb[2]) as f64 / 3.0;
        assert!((v - 1.0).abs() < 0.05, "pixel {i}: {rgb:?}");
    }
    let m = mean(&common::channel_averages(&image));
    eprintln!("open plane: mean {m:.4}");
    assert!((m - 1.0).abs() < 0.01, "{m}");
}

/// A small diffuse box lit by an area light, by `integrator`.
fn small_box(integrator: &str) -> String {
    format!(
        "LookAt 0 -3.5 1  0 0 1  0 0 1\nCamera \"perspective\" \"float fov\" 45\n\
         Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32 \"bool savefp16\" false\n\
         Sampler \"zsobol\"\nIntegrator {integrator} \"integer maxdepth\" 5\nWorldBegin\n\
         AttributeBegin\nTranslate 0 0 1.99\nReverseOrientation\n\
         AreaLightSource \"diffuse\" \"rgb L\" [8 8 8]\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n\
         \"point3 P\" [-0.3 -0.3 0  0.3 -0.3 0  0.3 0.3 0  -0.3 0.3 0]\nAttributeEnd\n\
         Material \"diffuse\" \"rgb reflectance\" [0.7 0.6 0.5]\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3  4 5 6 4 6 7  8 9 10 8 10 11  12 13 14 12 14 15]\n\
         \"point3 P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0   -1 -1 2  -1 1 2  1 1 2  1 -1 2\n\
         -1 1 0  1 1 0  1 1 2  -1 1 2   -1 -1 0  -1 1 0  -1 1 2  -1 -1 2]\n\
         Material \"diffuse\" \"rgb reflectance\" [0.2 0.6 0.3]\n\
         Shape \"sphere\" \"float radius\" 0.4\n"
    )
}

/// Per 8×8 block and over the whole image, two renders' means agree within
/// `block_tol` and `mean_tol` (relative).
fn assert_agree(name: &str, a: &Image, b: &Image, mean_tol: f64, block_tol: f64) {
    let (va, vb) = (common::channel_averages(a), common::channel_averages(b));
    let (ma, mb) = (mean(&va), mean(&vb));
    eprintln!("{name}: means {ma:.6} and {mb:.6}");
    assert!((ma / mb - 1.0).abs() < mean_tol, "{name}: means {ma} {mb}");
    let w = a.width() as usize;
    let mut worst = 0.0f64;
    for by in (0..a.height() as usize).step_by(8) {
        for bx in (0..w).step_by(8) {
            let block = |v: &[f64]| {
                let mut s = 0.0;
                for y in by..by + 8 {
                    for x in bx..bx + 8 {
                        s += v[y * w + x];
                    }
                }
                s / 64.0
            };
            let (sa, sb) = (block(&va), block(&vb));
            let rel = (sa - sb).abs() / sa.max(sb).max(0.05);
            worst = worst.max(rel);
        }
    }
    eprintln!("{name}: worst block difference {worst:.4}");
    assert!(worst < block_tol, "{name}: block difference {worst}");
}

/// `simplepath` and `randomwalk` converge to what `path` does.
#[test]
fn simple_integrators_agree_with_path() {
    let reference = render("box-path", &small_box("\"path\""), 1024, 2);
    let simple = render("box-simple", &small_box("\"simplepath\""), 1024, 2);
    assert_agree("simplepath", &reference, &simple, 0.02, 0.06);
    let uniform = render(
        "box-simple-uniform",
        &small_box("\"simplepath\" \"bool samplebsdf\" false"),
        1024,
        2,
    );
    assert_agree(
        "simplepath, uniform directions",
        &reference,
        &uniform,
        0.02,
        0.08,
    );
}

/// Light traced from the lights and splatted onto the film converges to
/// what `path` finds along camera rays.
#[test]
fn light_path_agrees_with_path() {
    let reference = render("lp-path", &small_box("\"path\""), 1024, 2);
    let light = render("lp-light", &small_box("\"lightpath\""), 1024, 2);
    assert_agree("lightpath", &reference, &light, 0.02, 0.08);
}

/// Bidirectional path tracing converges to what `path` finds.
#[test]
fn bdpt_agrees_with_path() {
    let reference = render("bd-path", &small_box("\"path\""), 1024, 2);
    let bdpt = render("bd-bdpt", &small_box("\"bdpt\""), 1024, 2);
    assert_agree("bdpt", &reference, &bdpt, 0.02, 0.06);
}

/// `bdpt` and `path` agree on the shared Cornell box (a quarter of its
/// resolution, 64 spp).
#[test]
fn bdpt_agrees_with_path_on_the_cornell_box() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    let Ok(text) = std::fs::read_to_string(shared.join("scenes/derived/cornell-box-256.pbrt"))
    else {
        eprintln!("skipping: the Cornell box is not in ../shared");
        return;
    };
    let quarter = rpbrt::scene::build::RenderOverrides {
        resolution_divisor: Some(4),
        ..Default::default()
    };
    let path = common::render_text("cb-path", &text, 64, 2, quarter.clone());
    let bdpt = text.replace("Integrator \"path\"", "Integrator \"bdpt\"");
    assert_ne!(bdpt, text);
    let bdpt = common::render_text("cb-bdpt", &bdpt, 64, 2, quarter);
    assert_agree("Cornell box", &path, &bdpt, 0.02, 0.06);
}

/// `bdpt` and `path` agree on the shared Veach scenes (a quarter of their
/// resolution, 64 spp; their models found where the scenes are): over the
/// image (path's caustics through the lamps' glass are fireflies at this
/// count, so blocks are not compared). About three minutes: run with
/// `--ignored`.
#[test]
#[ignore = "slow (minutes): run with --ignored"]
fn bdpt_agrees_with_path_on_the_veach_scenes() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    for name in ["veach-bidir", "veach-mis"] {
        let dir = shared.join(format!("scenes/gonsolo-bitterli/{name}/pbrt"));
        let Ok(text) = std::fs::read_to_string(dir.join("scene-v4.pbrt")) else {
            eprintln!("skipping: {name} is not in ../shared");
            continue;
        };
        let text = text.replace("\"models/", &format!("\"{}/models/", dir.display()));
        let with = |integrator: &str| {
            let start = text.find("Integrator \"").unwrap();
            let end = start + text[start + 12..].find('"').unwrap() + 13;
            format!(
                "{}Integrator \"{integrator}\"{}",
                &text[..start],
                &text[end..]
            )
        };
        let quarter = rpbrt::scene::build::RenderOverrides {
            resolution_divisor: Some(4),
            ..Default::default()
        };
        let path = common::render_text("veach-path", &with("path"), 64, 2, quarter.clone());
        let bdpt = common::render_text("veach-bdpt", &with("bdpt"), 64, 2, quarter);
        let (mp, mb) = (
            mean(&common::channel_averages(&path)),
            mean(&common::channel_averages(&bdpt)),
        );
        eprintln!("{name}: means {mp:.6} (path) and {mb:.6} (bdpt)");
        assert!((mb / mp - 1.0).abs() < 0.03, "{name}: {mp} {mb}");
    }
}

/// Inside a sphere that emits 1/2 and reflects half of what reaches it
/// (diffusely), radiance is 1/2 · Σ (1/2)^k = 1 everywhere (less
/// (1/2)^(maxdepth+1) for the paths cut off).
fn enclosure(integrator: &str) -> String {
    format!(
        "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 60\n\
         Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 \"bool savefp16\" false\n\
         Sampler \"zsobol\"\nIntegrator {integrator} \"integer maxdepth\" 20\nWorldBegin\n\
         ReverseOrientation\nAreaLightSource \"diffuse\" \"rgb L\" [0.5 0.5 0.5]\n\
         Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\nShape \"sphere\" \"float radius\" 1\n"
    )
}

/// The emitting furnace is 1 for every integrator that traces light.
#[test]
fn emitting_furnace_is_one() {
    for integrator in ["\"path\"", "\"bdpt\"", "\"lightpath\""] {
        let image = render("enclosure", &enclosure(integrator), 32, 2);
        let m = mean(&common::channel_averages(&image));
        eprintln!("{integrator}: enclosure mean {m:.4}");
        assert!((m - 1.0).abs() < 0.02, "{integrator}: {m}");
    }
}

/// The same image at one thread and at two, for each integrator.
#[test]
fn deterministic_across_thread_counts() {
    for integrator in ["\"randomwalk\"", "\"simplepath\"", "\"ambientocclusion\""] {
        let scene = small_box(integrator).replace(
            "\"integer maxdepth\" 5",
            if integrator.contains("ambient") {
                ""
            } else {
                "\"integer maxdepth\" 5"
            },
        );
        let a = render("det1", &scene, 4, 1);
        let b = render("det2", &scene, 4, 2);
        assert_eq!(a.rgb_data(), b.rgb_data(), "{integrator}");
    }
}

/// Integrators pbrt-v4 has that rpbrt does not: a located error.
#[test]
fn unsupported_integrators_are_located_errors() {
    for name in ["sppm", "mlt"] {
        let dir = common::fresh_dir("integrators", name);
        let path = dir.join("scene.pbrt");
        std::fs::write(&path, furnace(&format!("\"{name}\""))).unwrap();
        let overrides = rpbrt::scene::build::RenderOverrides {
            outfile: Some(dir.join("out.exr")),
            ..Default::default()
        };
        let Err(e) = rpbrt::pipeline::render_file(&path, &overrides, 1, false) else {
            panic!("{name} rendered");
        };
        let message = e.to_string();
        assert!(
            message.contains("not supported yet") && message.contains("scene.pbrt:5:1"),
            "{message}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// bdpt in a scene with media: pbrt-v4's bdpt scatters in them and rpbrt's
/// does not yet, so a located error rather than a different image.
#[test]
fn bdpt_with_media_is_a_located_error() {
    let dir = common::fresh_dir("integrators", "bdpt-media");
    let path = dir.join("scene.pbrt");
    let text = format!(
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nMediumInterface \"\" \"fog\"\n{}",
        furnace("\"bdpt\"")
    );
    std::fs::write(&path, text).unwrap();
    let overrides = rpbrt::scene::build::RenderOverrides {
        outfile: Some(dir.join("out.exr")),
        ..Default::default()
    };
    let Err(e) = rpbrt::pipeline::render_file(&path, &overrides, 1, false) else {
        panic!("bdpt rendered a scene with media");
    };
    let message = e.to_string();
    assert!(
        message.contains("\"bdpt\" with participating media is not supported yet")
            && message.contains("scene.pbrt:7:1"),
        "{message}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
