//! Estimator-level checks of the media against closed forms.

use super::*;
use crate::scene_description::SceneDescription;

/// The description of a scene holding `media` (`MakeNamedMedium` lines).
fn describe(media: &str) -> SceneDescription {
    let text = format!("WorldBegin\n{media}\n");
    crate::scene::load_text(Path::new("media.pbrt"), &text)
        .unwrap()
        .scene
}

fn medium(directive: &str) -> Medium {
    let scene = describe(directive);
    let m = &scene.media[0];
    Medium::create(&m.entity, &m.world_from_medium, Path::new(".")).unwrap()
}

fn wavelengths() -> SampledWavelengths {
    SampledWavelengths::sample_visible(0.3)
}

/// Ratio tracking along `ray` to `t_max`: the mean of Π σn/σmaj times the
/// remaining majorant transmittance (normalised by the first wavelength's
/// sampling density), per wavelength.
fn ratio_tracking(m: &Medium, ray: &Ray, t_max: f32, n: usize) -> SampledSpectrum {
    let lambda = wavelengths();
    let mut rng = Pcg32::new(7);
    let mut sum = SampledSpectrum::ZERO;
    for _ in 0..n {
        let mut tr = SampledSpectrum::ONE;
        let u = rng.uniform_f32();
        let mut inner = Pcg32::new_with_seed(rng.uniform_u32() as u64, 3);
        let t_maj = sample_t_maj(
            m,
            ray,
            t_max,
            u,
            &mut inner,
            &lambda,
            |_, _, mp, sm, t_maj| {
                let sigma_n = (sm - mp.sigma_a - mp.sigma_s).clamp_zero();
                tr *= t_maj * sigma_n / (t_maj[0] * sm[0]);
                true
            },
        );
        sum += tr * t_maj / t_maj[0];
    }
    sum / n as f32
}

#[test]
fn homogeneous_absorber_transmits_exp_minus_sigma_d() {
    // σt = scale · (σa + σs) = 0.5 · (1.2 + 0.4) = 0.8 per unit; d = 2.5.
    let m = medium(
        "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1.2 1.2 1.2] \"rgb sigma_s\" [0.4 0.4 0.4] \"float scale\" 0.5",
    );
    let lambda = wavelengths();
    // The direction's length does not matter: t is in its units.
    let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 0.0);
    let d = 2.5;
    let sigma_t = m.sample_point(Vec3::ZERO, &lambda);
    let sigma_t = sigma_t.sigma_a + sigma_t.sigma_s;
    // Fraction of runs without a collision: exp(−σt[0] d).
    let mut rng = Pcg32::new(11);
    let n = 200_000;
    let mut escaped = 0;
    for _ in 0..n {
        let u = rng.uniform_f32();
        let mut collided = false;
        let t_maj = sample_t_maj(&m, &ray, d / 2.0, u, &mut rng, &lambda, |_, _, _, _, _| {
            collided = true;
            false
        });
        if !collided {
            escaped += 1;
            // Then the majorant transmittance is the whole stretch's.
            let expected = (sigma_t * -d).exp();
            for i in 0..4 {
                assert!((t_maj[i] - expected[i]).abs() < 1e-5 * expected[i].max(1.0));
            }
        }
    }
    let expected = (-sigma_t[0] * d).exp();
    let measured = escaped as f32 / n as f32;
    // 200,000 Bernoulli trials: σ ≈ 0.0009.
    assert!(
        (measured - expected).abs() < 0.004,
        "escaped {measured}, exp(−σt d) = {expected}"
    );
}

#[test]
fn grid_ratio_tracking_matches_the_optical_depth() {
    // Two cells along z (centres at z = −0.5, 0.5 of the box −1…1); along
    // the z axis the trilinear density integrates to 0.4375 (d0 + d1) per
    // unit of the box's own coordinate, so the optical depth through the
    // box (length 2) is σt · 2 · 0.4375 · (d0 + d1).
    let m = medium(
        "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"integer nz\" 2 \"float density\" [0.5 1.5] \"point3 p0\" [-1 -1 -1] \"point3 p1\" [1 1 1] \"spectrum sigma_a\" [360 0.3 830 0.9] \"rgb sigma_s\" [0.2 0.2 0.2]",
    );
    let lambda = wavelengths();
    let p = m.sample_point(Vec3::new(0.0, 0.0, -0.5), &lambda);
    // At the first cell's centre the density is d0 = 0.5.
    let sigma_t = (p.sigma_a + p.sigma_s) / 0.5;
    let ray = Ray::new(Vec3::new(0.0, 0.0, -3.0), Vec3::Z, 0.0);
    let tr = ratio_tracking(&m, &ray, 10.0, 100_000);
    for i in 0..4 {
        let expected = (-sigma_t[i] * 2.0 * 0.4375 * 2.0).exp();
        assert!(
            (tr[i] - expected).abs() < 0.01,
            "λ {}: ratio tracking {} vs exp(−τ) {expected}",
            lambda.lambda[i],
            tr[i]
        );
    }
    // A ray that misses the box meets nothing.
    let miss = Ray::new(Vec3::new(0.0, 3.0, -3.0), Vec3::Z, 0.0);
    assert!(m.majorant(&miss, 10.0, &lambda).is_none());
}

#[test]
fn rgb_grid_and_cloud_stay_below_their_majorants() {
    let rgb = medium(
        "MakeNamedMedium \"r\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"rgb sigma_a\" [0.1 0.5 0.9 2 1 0.5] \"rgb sigma_s\" [1 1 1 0.5 0.5 0.5] \"float scale\" 2",
    );
    let cloud = medium("MakeNamedMedium \"c\" \"string type\" \"cloud\" \"float density\" 3");
    let lambda = wavelengths();
    let ray = Ray::new(Vec3::new(-1.0, 0.5, 0.5), Vec3::X, 0.0);
    let mut rng = Pcg32::new(5);
    for m in [&rgb, &cloud] {
        let seg = m.majorant(&ray, 10.0, &lambda).unwrap();
        assert!((seg.t_min - 1.0).abs() < 1e-5 && (seg.t_max - 2.0).abs() < 1e-5);
        for _ in 0..2000 {
            let p = Vec3::new(rng.uniform_f32(), rng.uniform_f32(), rng.uniform_f32());
            let mp = m.sample_point(p, &lambda);
            let sigma_t = mp.sigma_a + mp.sigma_s;
            for i in 0..4 {
                assert!(sigma_t[i] >= 0.0 && sigma_t[i] <= seg.sigma_maj[i] * (1.0 + 1e-5));
            }
        }
    }
}

#[test]
fn unknown_preset_and_missing_nanovdb_file_are_located_errors() {
    let scene = describe(
        "MakeNamedMedium \"v\" \"string type\" \"nanovdb\" \"string filename\" \"x.nvdb\"",
    );
    let m = &scene.media[0];
    let e = Medium::create(&m.entity, &m.world_from_medium, Path::new(".")).unwrap_err();
    assert!(e.to_string().contains("cannot read \"./x.nvdb\""), "{e}");
    assert!(e.to_string().contains("media.pbrt:2:"), "{e}");
    let scene =
        describe("MakeNamedMedium \"p\" \"string type\" \"homogeneous\" \"string preset\" \"Mud\"");
    let m = &scene.media[0];
    let e = Medium::create(&m.entity, &m.world_from_medium, Path::new(".")).unwrap_err();
    assert!(e.to_string().contains("Mud"), "{e}");
    let skim = medium(
        "MakeNamedMedium \"s\" \"string type\" \"homogeneous\" \"string preset\" \"Skimmilk\"",
    );
    assert!(
        skim.sample_point(Vec3::ZERO, &wavelengths())
            .sigma_s
            .max_component()
            > 0.5
    );
}
