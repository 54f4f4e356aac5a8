//! The dual hair model in whole images: light diffracted through the ring
//! reaches the ground behind a curtain of fibres with low variance and
//! without bias (docs/dual-model.md, "Light through the ring").
//!
//! The scene: 31 horizontal elliptical fibres (a = 30, b = 20 µm,
//! eumelanin 8, width 0.01) 2 cm apart, half a unit above a grey diffuse
//! ground; the camera sits under the curtain looking straight down, so
//! every pixel is ground in the curtain's shadow. Lit from straight above
//! by a distant light, a point light or a small (5°) disk light.

mod common;

#[derive(Clone, Copy, Debug)]
enum Lighting {
    Distant,
    Point,
    SmallDisk,
}

/// The curtain scene; `connect` is the integrator's
/// `connectdiffraction` (false: the ring's light only by BSDF samples).
fn curtain(lighting: Lighting, d_diff: f32, connect: bool) -> String {
    let light = match lighting {
        Lighting::Distant => {
            "LightSource \"distant\" \"point3 from\" [0 0 1] \"point3 to\" [0 0 0] \"rgb L\" [3 3 3]\n"
                .to_string()
        }
        Lighting::Point => "LightSource \"point\" \"point3 from\" [0 0 2] \"rgb I\" [12 12 12]\n".to_string(),
        // Radius 2 tan 2.5°: 5° across, seen from the ground.
        Lighting::SmallDisk => "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [400 400 400] \"bool twosided\" true\nTranslate 0 0 2\nShape \"disk\" \"float radius\" [0.0873]\nAttributeEnd\n".to_string(),
    };
    let mut s = format!(
        "Film \"rgb\" \"integer xresolution\" [72] \"integer yresolution\" [48] \"string filename\" \"out.exr\"
Sampler \"sobol\"
Integrator \"path\" \"integer maxdepth\" [5] \"bool connectdiffraction\" [{connect}]
LookAt 0 0 0.25  0 0 0  0 1 0
Camera \"perspective\" \"float fov\" [45]
WorldBegin
{light}AttributeBegin
Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]
Shape \"trianglemesh\" \"point3 P\" [-3 -3 0 3 -3 0 3 3 0 -3 3 0] \"integer indices\" [0 1 2 0 2 3]
AttributeEnd
AttributeBegin
Material \"hair\" \"float eumelanin\" [8] \"float ellipse_a\" [30] \"float ellipse_b\" [20] \"float d_diff\" [{d_diff}]
"
    );
    for i in 0..31 {
        let y = -0.3 + 0.02 * i as f32;
        s += &format!(
            "Shape \"curve\" \"string type\" \"cylinder\" \"point3 P\" [-0.8 {y} 0.5 -0.3 {y} 0.5 0.3 {y} 0.5 0.8 {y} 0.5] \"float width\" [0.01]\n"
        );
    }
    s + "AttributeEnd\n"
}

/// The region's mean and its pixels' standard deviation over that mean
/// (the stripes the curtain casts and the noise together).
fn region_stats(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    (mean, var.sqrt() / mean)
}

/// The noise alone: the pixels' standard deviation over two renders at
/// different seeds (their difference over √2), over the mean.
fn noise(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let mean = (a.iter().sum::<f64>() + b.iter().sum::<f64>()) / (2.0 * n);
    let var = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>() / (2.0 * n);
    var.sqrt() / mean
}

fn render(name: &str, scene: &str, spp: u32, seed: i32) -> Vec<f64> {
    let overrides = rpbrt::scene::build::RenderOverrides {
        seed: Some(seed),
        ..Default::default()
    };
    common::channel_averages(&common::render_text(name, scene, spp, 2, overrides))
}

/// At 64 spp, d_diff 1 is at most 1.4× as noisy as d_diff 0, both as the
/// region's std/mean and as the noise alone, and its mean is within 3 % of
/// a converged render made without the connection (the BSDF's own samples
/// of the finite lobe, 16× the samples): the connection removes the
/// fireflies and adds no bias.
fn check(lighting: Lighting) {
    let name = format!("{lighting:?}");
    let [d0, d0_again, d1, d1_again] = [(0.0, 1), (0.0, 2), (1.0, 1), (1.0, 2)]
        .map(|(d_diff, seed)| render(&name, &curtain(lighting, d_diff, true), 64, seed));
    let reference = render(&name, &curtain(lighting, 1.0, false), 1024, 3);
    let ((_, rel_d0), (mean_d1, rel_d1)) = (region_stats(&d0), region_stats(&d1));
    let (noise_d0, noise_d1) = (noise(&d0, &d0_again), noise(&d1, &d1_again));
    let (mean_ref, rel_ref) = region_stats(&reference);
    eprintln!(
        "{name}: std/mean d_diff 0 {rel_d0:.3}, d_diff 1 {rel_d1:.3} (ratio {:.2}); noise d_diff 0 {noise_d0:.3}, d_diff 1 {noise_d1:.3} (ratio {:.2}); mean {mean_d1:.5} against the converged {mean_ref:.5} without connection (std/mean {rel_ref:.3}): {:+.2} %",
        rel_d1 / rel_d0,
        noise_d1 / noise_d0,
        100.0 * (mean_d1 / mean_ref - 1.0)
    );
    assert!(
        rel_d1 <= 1.4 * rel_d0,
        "{name}: std/mean {rel_d1:.3} with d_diff 1 against {rel_d0:.3} with d_diff 0"
    );
    assert!(
        noise_d1 <= 1.4 * noise_d0,
        "{name}: noise {noise_d1:.3} with d_diff 1 against {noise_d0:.3} with d_diff 0"
    );
    assert!(
        (mean_d1 / mean_ref - 1.0).abs() <= 0.03,
        "{name}: mean {mean_d1} against the converged {mean_ref}"
    );
}

#[test]
fn diffracted_light_under_a_distant_light() {
    check(Lighting::Distant);
}

#[test]
fn diffracted_light_under_a_point_light() {
    check(Lighting::Point);
}

#[test]
fn diffracted_light_under_a_small_disk_light() {
    check(Lighting::SmallDisk);
}
