//! pbrt-v4's rendering options (`Option "disablepixeljitter"`,
//! `Option "forcediffuse"`): each changes the image as pbrt-v4's does, and
//! each test fails if the option is ignored.

mod common;

use rpbrt::scene::build::RenderOverrides;

/// A diffuse (or `material`) plane under a point light near it, seen from
/// above at 1 spp with the independent sampler, direct light only: the
/// radiance changes fast across each pixel.
fn lit_plane(options: &str, material: &str) -> String {
    format!(
        "{options}\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
         Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8 \"bool savefp16\" false\n\
         Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" 1\nWorldBegin\n\
         LightSource \"point\" \"point3 from\" [0.3 0.2 0.4] \"rgb I\" [1 1 1]\n\
         {material}\n\
         Shape \"trianglemesh\" \"point3 P\" [-5 -5 0  5 -5 0  5 5 0  -5 5 0]\n\
         \"integer indices\" [0 1 2  0 2 3]\n"
    )
}

fn render(name: &str, scene: &str, spp: u32, seed: i32) -> Vec<f32> {
    let overrides = RenderOverrides {
        seed: Some(seed),
        ..Default::default()
    };
    common::render_text(name, scene, spp, 1, overrides)
        .rgb_data()
        .to_vec()
}

/// Without pixel jitter every camera sample is at its pixel's centre with
/// filter weight 1: with fixed wavelengths and only direct light from a
/// point light, the image no longer depends on the seed (nor on the sample
/// count). With jitter it does, which shows the scene can tell.
#[test]
fn disablepixeljitter_samples_pixel_centres() {
    let fixed = "Option \"disablewavelengthjitter\" true\nOption \"disablepixeljitter\" true";
    let diffuse = "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]";
    let scene = lit_plane(fixed, diffuse);
    let a = render("nojitter-a", &scene, 1, 1);
    let b = render("nojitter-b", &scene, 1, 2);
    assert!(a.iter().all(|v| *v > 0.0), "{a:?}");
    assert_eq!(a, b, "different seeds give different pixels");
    let many = render("nojitter-4", &scene, 4, 3);
    for (x, y) in a.iter().zip(&many) {
        assert!((x - y).abs() <= 1e-5 * x.abs(), "1 spp {x}, 4 spp {y}");
    }

    let jittered = lit_plane("Option \"disablewavelengthjitter\" true", diffuse);
    let c = render("jitter-a", &jittered, 1, 1);
    let d = render("jitter-b", &jittered, 1, 2);
    let changed = c
        .iter()
        .zip(&d)
        .filter(|(x, y)| (*x - *y).abs() > 1e-3 * x.abs())
        .count();
    assert!(
        changed > c.len() / 2,
        "only {changed} of {} values differ",
        c.len()
    );
}

/// Under `forcediffuse` a mirror (a smooth conductor of reflectance 0.7)
/// becomes a diffuse surface of its albedo: at near-normal incidence, 0.7.
/// It then renders as a diffuse plane of reflectance 0.7 does (within the
/// Fresnel curve's rise over the 20° half-field, < 0.5 %); without the
/// option the mirror shows nothing of the point light.
#[test]
fn forcediffuse_renders_a_mirror_as_its_albedo() {
    let mirror = "Material \"conductor\" \"rgb reflectance\" [0.7 0.7 0.7]";
    let diffuse = "Material \"diffuse\" \"rgb reflectance\" [0.7 0.7 0.7]";
    let fixed = "Option \"disablewavelengthjitter\" true\nOption \"disablepixeljitter\" true";
    let forced = render(
        "forced-mirror",
        &lit_plane(&format!("{fixed}\nOption \"forcediffuse\" true"), mirror),
        1,
        1,
    );
    let matte = render("matte", &lit_plane(fixed, diffuse), 1, 1);
    for (f, m) in forced.iter().zip(&matte) {
        assert!(
            *m > 0.0 && (f / m - 1.0).abs() < 0.005,
            "forced {f} vs diffuse {m}"
        );
    }
    let plain = render("plain-mirror", &lit_plane(fixed, mirror), 1, 1);
    assert!(plain.iter().all(|v| *v == 0.0), "{plain:?}");
    // A diffuse material is its own diffuse equivalent.
    let forced_matte = render(
        "forced-matte",
        &lit_plane(&format!("{fixed}\nOption \"forcediffuse\" true"), diffuse),
        1,
        1,
    );
    for (f, m) in forced_matte.iter().zip(&matte) {
        assert!((f - m).abs() <= 1e-5 * m, "forced {f} vs diffuse {m}");
    }
}

/// Glass becomes a diffuse reflector of its albedo R + T/η² (radiance
/// mode; 0.04 + 0.96/2.25 at normal incidence for η = 1.5, within 0.1 %
/// over a 10° half-field). Smooth glass shows nothing of a point light;
/// forced diffuse, it renders as a diffuse plane of that reflectance with
/// the same samples, up to the noise of the albedo's estimate.
#[test]
fn forcediffuse_renders_glass_as_its_albedo() {
    let glass = "Material \"dielectric\" \"float eta\" 1.5";
    let albedo = 0.04 + 0.96 / 2.25;
    let diffuse =
        format!("Material \"diffuse\" \"spectrum reflectance\" [300 {albedo} 800 {albedo}]");
    let forced_option = "Option \"forcediffuse\" true";
    let narrow = |scene: String| scene.replace("\"float fov\" 40", "\"float fov\" 20");
    let forced = render(
        "forced-glass",
        &narrow(lit_plane(forced_option, glass)),
        64,
        1,
    );
    let matte = render("matte-glass", &narrow(lit_plane("", &diffuse)), 64, 1);
    for (f, m) in forced.iter().zip(&matte) {
        assert!(
            *m > 0.0 && (f / m - 1.0).abs() < 0.02,
            "forced {f} vs diffuse {m}"
        );
    }
    let plain = render("plain-glass", &narrow(lit_plane("", glass)), 4, 1);
    assert!(plain.iter().all(|v| *v == 0.0), "{plain:?}");
}
