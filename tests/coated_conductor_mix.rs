//! The `coatedconductor` and `mix` materials in rendered scenes: a white
//! furnace for the coated conductor, and a mix that is each of its
//! materials at amount 0 and 1 and their average at ½.

mod common;

use common::{channel_averages, render_text};
use rpbrt::scene::build::RenderOverrides;

/// A unit sphere seen whole (its silhouette inside the image) under a
/// white sky of radiance 1; enough bounces that nothing is cut short.
fn furnace(materials: &str, material: &str, spp: u32, name: &str) -> Vec<f64> {
    let scene = format!(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
         Film \"rgb\" \"integer xresolution\" 24 \"integer yresolution\" 24 \"bool savefp16\" false\n\
         Integrator \"path\" \"integer maxdepth\" 50\n\
         WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n{materials}\n{material}\n\
         Shape \"sphere\" \"float radius\" 1\n"
    );
    channel_averages(&render_text(
        name,
        &scene,
        spp,
        2,
        RenderOverrides::default(),
    ))
}

/// The pixels that see the sphere (well inside its silhouette) and the sky
/// pixels' mean (the sky's radiance as the film records it).
fn sphere_and_sky(pixels: &[f64]) -> (Vec<f64>, f64) {
    let (mut sphere, mut sky) = (Vec::new(), Vec::new());
    for (i, &v) in pixels.iter().enumerate() {
        let (x, y) = ((i % 24) as f64 + 0.5 - 12.0, (i / 24) as f64 + 0.5 - 12.0);
        // The sphere's silhouette has a radius of about 8.6 pixels.
        let r = (x * x + y * y).sqrt();
        if r < 7.0 {
            sphere.push(v);
        } else if r > 10.5 {
            sky.push(v);
        }
    }
    let sky = sky.iter().sum::<f64>() / sky.len() as f64;
    (sphere, sky)
}

/// A lossless conductor (reflectance 1, clamped to 0.9999 as pbrt-v4 does)
/// under a clear coating of negligible thickness keeps all the light: each
/// pixel of the sphere is the sky's radiance. Smooth, the sphere's mean is
/// within 1 % of it and every pixel within 2 % (the walk is stochastic and
/// ends after `maxdepth` bounces, losing a little); rough
/// coat and base, and a scattering layer without absorption (albedo 1),
/// the mean does not exceed the sky (energy ≤ 1) by more than the noise.
/// (Rough, much is lost: the microfacet models scatter once, and light
/// bounces often between the layers; pbrt-v4 loses as much.)
#[test]
fn coated_conductor_white_furnace() {
    let cases = [
        ("smooth", "", 0.99, 1.003),
        ("rough", "\"float interface.roughness\" 0.3 \"float conductor.roughness\" 0.5", 0.0, 1.02),
        ("medium", "\"float interface.roughness\" 0.2 \"rgb albedo\" [1 1 1] \"float g\" 0.5 \"float thickness\" 0.1", 0.0, 1.02),
    ];
    for (name, extra, lowest, highest) in cases {
        let thickness = if name == "medium" {
            ""
        } else {
            "\"float thickness\" 0.00001"
        };
        let material = format!(
            "Material \"coatedconductor\" \"rgb reflectance\" [1 1 1] {thickness} \"integer maxdepth\" 100 {extra}"
        );
        let pixels = furnace("", &material, 64, &format!("furnace-{name}"));
        let (sphere, sky) = sphere_and_sky(&pixels);
        let mean = sphere.iter().sum::<f64>() / sphere.len() as f64 / sky;
        let (lo, hi) = sphere.iter().fold((f64::MAX, 0.0f64), |(lo, hi), &v| {
            (lo.min(v / sky), hi.max(v / sky))
        });
        eprintln!("coatedconductor furnace {name}: sky {sky:.4}, sphere/sky mean {mean:.4}, range {lo:.4}..{hi:.4}");
        assert!((sky - 1.0).abs() < 0.02, "sky {sky}");
        assert!(mean <= highest && mean >= lowest, "{name}: mean {mean}");
        if name == "smooth" {
            assert!(lo >= 0.98 && hi <= 1.02, "{name}: {lo}..{hi}");
        }
    }
}

/// pbrt-v4's parameters are checked: `reflectance` with `conductor.eta` is
/// an error, and so is a mix naming an undefined material or not two.
#[test]
fn coated_conductor_and_mix_errors() {
    let dir = std::env::temp_dir().join(format!("rpbrt-ccmix-errors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let build_error = |world: &str| -> String {
        let path = dir.join("scene.pbrt");
        std::fs::write(
            &path,
            format!("Camera \"perspective\"\nWorldBegin\n{world}"),
        )
        .unwrap();
        let loaded = match rpbrt::scene::load(&path) {
            Ok(loaded) => loaded,
            Err(e) => return e.to_string(),
        };
        match rpbrt::scene::build::build(loaded.scene, &RenderOverrides::default()) {
            Ok(_) => panic!("no error for {world:?}"),
            Err(e) => e.to_string(),
        }
    };
    let cases = [
        (
            "Material \"coatedconductor\" \"rgb reflectance\" [0.5 0.5 0.5] \"rgb conductor.eta\" [1 1 1]\nShape \"sphere\"\n",
            "scene.pbrt:3:1: coatedconductor: \"reflectance\" cannot be given with",
        ),
        (
            "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"a\" \"b\"]\nNamedMaterial \"m\"\nShape \"sphere\"\n",
            "scene.pbrt:3:1: mix material: material \"a\" is not defined",
        ),
        (
            "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\nMakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" \"a\"\nNamedMaterial \"m\"\nShape \"sphere\"\n",
            "mix: \"materials\" must name two materials, not 1",
        ),
    ];
    for (world, expected) in cases {
        let e = build_error(world);
        assert!(e.contains(expected), "expected {expected:?} in:\n{e}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

const TWO: &str = "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.8 0.1 0.1]\n\
    MakeNamedMaterial \"gold\" \"string type\" \"coatedconductor\" \"float interface.roughness\" 0.1 \
    \"spectrum conductor.eta\" \"metal-Au-eta\" \"spectrum conductor.k\" \"metal-Au-k\" \"float conductor.roughness\" 0.3\n";

/// A mix of amount 0 renders exactly as its first material, of amount 1
/// exactly as its second (the choice draws no sample, so the rest of each
/// path is the same), and of amount ½ as their average, to within noise.
#[test]
fn mix_is_each_material_at_the_ends_and_their_average_between() {
    let spp = 64;
    let red = furnace(TWO, "NamedMaterial \"red\"", spp, "mix-red");
    let gold = furnace(TWO, "NamedMaterial \"gold\"", spp, "mix-gold");
    let mixed = |amount: f32, name: &str| {
        let materials = format!(
            "{TWO}MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"red\" \"gold\"] \"float amount\" {amount}"
        );
        furnace(&materials, "NamedMaterial \"m\"", spp, name)
    };
    assert_eq!(
        mixed(0.0, "mix-0"),
        red,
        "amount 0 is not the first material"
    );
    assert_eq!(
        mixed(1.0, "mix-1"),
        gold,
        "amount 1 is not the second material"
    );
    let half = mixed(0.5, "mix-half");
    let (half, _) = sphere_and_sky(&half);
    let (red, _) = sphere_and_sky(&red);
    let (gold, _) = sphere_and_sky(&gold);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let expected = (mean(&red) + mean(&gold)) / 2.0;
    eprintln!(
        "mix ½: {:.4}, average of the two {expected:.4} (red {:.4}, gold {:.4})",
        mean(&half),
        mean(&red),
        mean(&gold)
    );
    assert!(
        (mean(&half) - expected).abs() < 0.02 * expected,
        "{} vs {expected}",
        mean(&half)
    );
}
