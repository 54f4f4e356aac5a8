//! The BVH light sampler on a scene with many small lights: the same mean
//! as the power sampler (both are unbiased), with less error at equal spp.

mod common;

use rpbrt::tools::imgdiff::mrse;

/// 64 small emitting quads of varied colour and orientation in an 8 × 8
/// grid above a diffuse floor and a few boxes.
fn scene(light_sampler: &str) -> String {
    let mut lights = String::new();
    for i in 0..64 {
        let (x, z) = ((i % 8) as f32 - 3.5, (i / 8) as f32 - 3.5);
        let tilt = (i * 37 % 60) as f32 - 30.0;
        let rgb = [
            1.0 + (i % 3) as f32,
            1.0 + (i / 3 % 3) as f32,
            1.0 + (i / 9 % 3) as f32,
        ];
        let twosided = if i % 5 == 0 { "true" } else { "false" };
        lights.push_str(&format!(
            "AttributeBegin\n  Translate {} 2.5 {}\n  Rotate {tilt} 1 0 0\n  \
             AreaLightSource \"diffuse\" \"rgb L\" [{} {} {}] \"float scale\" 4 \"bool twosided\" {twosided}\n  \
             Shape \"bilinearmesh\" \"point3 P\" [-0.08 0 -0.08  0.08 0 -0.08  -0.08 0 0.08  0.08 0 0.08]\n\
             AttributeEnd\n",
            x * 1.2,
            z * 1.2,
            rgb[0],
            rgb[1],
            rgb[2]
        ));
    }
    format!(
        r#"LookAt 0 6 9  0 0 0  0 1 0
Camera "perspective" "float fov" 45
Film "rgb" "integer xresolution" 64 "integer yresolution" 48 "bool savefp16" false
Sampler "zsobol"
Integrator "path" "integer maxdepth" 3 "string lightsampler" "{light_sampler}"
WorldBegin
Material "diffuse" "rgb reflectance" [0.6 0.6 0.6]
Shape "trianglemesh" "point3 P" [-8 0 -8  8 0 -8  8 0 8  -8 0 8] "integer indices" [0 1 2 0 2 3]
AttributeBegin
  Translate -1.5 0.5 0.5
  Shape "sphere" "float radius" 0.5
AttributeEnd
AttributeBegin
  Translate 1.5 0.7 -0.5
  Shape "sphere" "float radius" 0.7
AttributeEnd
{lights}"#
    )
}

#[test]
fn bvh_sampler_converges_to_the_power_sampler_with_less_error() {
    let render = |sampler: &str, spp: u32, seed: i32| {
        let overrides = rpbrt::scene::build::RenderOverrides {
            seed: Some(seed),
            ..Default::default()
        };
        common::render_text(
            &format!("lbvh-{sampler}-{spp}"),
            &scene(sampler),
            spp,
            2,
            overrides,
        )
        .rgb_data()
    };
    let mean = |v: &[f32]| v.iter().map(|&x| x as f64).sum::<f64>() / v.len() as f64;
    // The reference: both samplers at high spp, averaged.
    let reference_bvh = render("bvh", 256, 1);
    let reference_power = render("power", 256, 2);
    let reference: Vec<f32> = reference_bvh
        .iter()
        .zip(&reference_power)
        .map(|(a, b)| 0.5 * (a + b))
        .collect();
    let (m_bvh, m_power) = (mean(&reference_bvh), mean(&reference_power));
    // Equal spp, another seed.
    let bvh = render("bvh", 16, 3);
    let power = render("power", 16, 3);
    let (e_bvh, e_power) = (mrse(&bvh, &reference), mrse(&power, &reference));
    eprintln!(
        "image mean at 256 spp: bvh {m_bvh:.5}, power {m_power:.5}; MRSE at 16 spp: bvh {e_bvh:.5}, power {e_power:.5} (ratio {:.2})",
        e_power / e_bvh
    );
    // Means agree within the noise of a 256-spp image mean (< 1 %).
    assert!(
        ((m_bvh - m_power) / m_power).abs() < 0.01,
        "means {m_bvh} vs {m_power}"
    );
    assert!(
        e_bvh < e_power,
        "bvh MRSE {e_bvh} not below power's {e_power}"
    );
}
