//! The measured BxDF on synthetic files ([`super::synthetic`]): densities
//! that integrate to what sampling keeps, samples that follow them, values
//! that agree between `f` and `sample_f`, and the albedo a file of known
//! meaning must have.

use super::synthetic::Synthetic;
use super::*;
use crate::bxdfs::test_support::{
    assert_chi2_passes, integrate_sphere, sampling_consistency, spherical_direction,
    test_directions, tilted_bsdf, Accumulator, Pcg32Source,
};
use crate::bxdfs::BxDF;

fn lambda(values: [f32; 4]) -> SampledWavelengths {
    SampledWavelengths {
        lambda: values,
        pdf: [1.0; 4],
    }
}

const VISIBLE: [f32; 4] = [430.0, 520.0, 610.0, 690.0];

fn bxdf(file: &Synthetic) -> MeasuredBxDF {
    MeasuredBxDF::new(file.data(), &lambda(VISIBLE))
}

/// A rough isotropic file with varying spectra, and an anisotropic one.
fn files() -> Vec<(&'static str, Synthetic)> {
    let mut varying = Synthetic::ggx(0.35);
    varying.varying = true;
    let mut anisotropic = Synthetic::ggx(0.3);
    anisotropic.alpha_y = 0.55;
    anisotropic.anisotropic = true;
    anisotropic.varying = true;
    vec![("isotropic", varying), ("anisotropic", anisotropic)]
}

fn sample(b: &MeasuredBxDF, wo: Vec3, u: Vec2) -> Option<BSDFSample> {
    b.sample_f(wo, 0.5, u, TransportMode::Radiance, BxDFReflTransFlags::All)
}

#[test]
fn pdf_integrates_to_the_fraction_of_samples_kept() {
    // Sampling drops the normals that reflect ωo below the surface, so ∫ pdf
    // over the sphere is the fraction of samples returned, not 1.
    let mut rng = Pcg32Source::new(41);
    for (name, file) in files() {
        let b = bxdf(&file);
        for wo in [
            Vec3::new(0.1, 0.05, 0.99).normalize(),
            spherical_direction(0.9, 2.0),
            -spherical_direction(0.5, -1.0),
        ] {
            let integral = integrate_sphere(
                |wi| b.pdf(wo, wi, TransportMode::Radiance, BxDFReflTransFlags::All),
                400,
                800,
            ) as f64;
            let n = 40_000;
            let kept = (0..n)
                .filter(|_| sample(&b, wo, rng.next_vec2()).is_some())
                .count() as f64
                / n as f64;
            eprintln!("{name}, wo = {wo}: ∫ pdf = {integral:.4}, kept {kept:.4}");
            assert!(
                (integral - kept).abs() < 0.01,
                "{name}, {wo}: {integral} vs {kept}"
            );
            // Rough (α ≈ 0.3) lobes lose some tenth of their normals.
            assert!(integral > 0.75, "{name}, {wo}: {integral}");
        }
    }
}

#[test]
fn samples_follow_the_pdf() {
    for (seed, (name, file)) in files().into_iter().enumerate() {
        let bsdf = tilted_bsdf(BxDF::Measured(bxdf(&file)));
        let mut rng = Pcg32Source::new(50 + seed as u64);
        let wos = test_directions(&mut rng, 2, true);
        assert_chi2_passes(&format!("measured {name}"), &bsdf, &wos, &mut rng);
    }
}

#[test]
fn sampling_is_consistent_with_f_and_pdf() {
    let mut rng = Pcg32Source::new(43);
    for (name, file) in files() {
        let b = bxdf(&file);
        for wo in test_directions(&mut rng, 3, true) {
            let report =
                sampling_consistency(&b, wo, TransportMode::Radiance, 40_000, 300_000, &mut rng);
            eprintln!(
                "measured {name}, wo = {wo}: sampled {:.4} ± {:.4}, uniform {:.4} ± {:.4}, z = {:.2}, max pdf rel. err {:.1e}, max f rel. err {:.1e}",
                report.importance.mean, report.importance.std_error, report.uniform.mean,
                report.uniform.std_error, report.z_score(), report.max_pdf_relative_error,
                report.max_f_relative_error
            );
            assert!(report.z_score() < 4.5, "{name}, {wo}: {report:?}");
            assert!(
                report.pdf_mismatches * 1000 <= report.samples,
                "{name}, {wo}: {report:?}"
            );
            assert!(
                report.max_f_relative_error < 1e-2,
                "{name}, {wo}: {report:?}"
            );
        }
    }
}

#[test]
fn f_is_finite_non_negative_and_reflection_only() {
    let mut rng = Pcg32Source::new(44);
    for (name, file) in files() {
        let b = bxdf(&file);
        assert_eq!(b.flags(), BxDFFlags::GLOSSY_REFLECTION);
        for _ in 0..20_000 {
            let theta = |u: f32| (u * std::f32::consts::PI) as f64;
            let wo = spherical_direction(theta(rng.next_f32()), 6.3 * rng.next_f32() as f64);
            let wi = spherical_direction(theta(rng.next_f32()), 6.3 * rng.next_f32() as f64);
            let f = b.f(wo, wi, TransportMode::Radiance);
            assert!(
                f.0.iter().all(|v| v.is_finite() && *v >= 0.0),
                "{name}: {wo} {wi}: {f:?}"
            );
            let pdf = b.pdf(wo, wi, TransportMode::Radiance, BxDFReflTransFlags::All);
            assert!(pdf.is_finite() && pdf >= 0.0, "{name}: {wo} {wi}: {pdf}");
            if wo.z * wi.z <= 0.0 {
                assert!(f.is_zero() && pdf == 0.0, "{name}: {wo} {wi}");
            }
            let only_t = b.pdf(
                wo,
                wi,
                TransportMode::Radiance,
                BxDFReflTransFlags::Transmission,
            );
            assert_eq!(only_t, 0.0);
        }
        let wo = spherical_direction(0.4, 0.3);
        let none = b.sample_f(
            wo,
            0.5,
            Vec2::splat(0.3),
            TransportMode::Radiance,
            BxDFReflTransFlags::Transmission,
        );
        assert!(none.is_none());
    }
}

#[test]
fn an_isotropic_file_turns_with_the_pair() {
    let b = bxdf(&files()[0].1);
    for (t_o, t_i, dphi) in [(0.3, 0.8, 2.0), (1.1, 0.2, -0.7), (0.6, 0.6, 3.0)] {
        let reference = b.f(
            spherical_direction(t_o, 0.0),
            spherical_direction(t_i, dphi),
            TransportMode::Radiance,
        );
        for turn in [0.9, -2.5, 3.1] {
            let f = b.f(
                spherical_direction(t_o, turn),
                spherical_direction(t_i, dphi + turn),
                TransportMode::Radiance,
            );
            for (a, r) in f.0.iter().zip(reference.0) {
                assert!(
                    (a - r).abs() <= 2e-3 * r.max(1e-3),
                    "{f:?} vs {reference:?}"
                );
            }
        }
    }
}

#[test]
fn constant_spectra_reflect_their_value_times_the_visible_fraction() {
    // f = R D / (4 σ(ωo) cos θi): the albedo is R times the fraction of
    // ωo's visible normals that reflect it upwards, at every wavelength
    // (between the table's wavelengths it interpolates, outside it clamps).
    let mut file = Synthetic::ggx(0.25);
    file.values = vec![0.2, 0.5, 0.9, 0.4];
    let data = file.data();
    let wavelengths = [380.0, 450.0, 650.0, 760.0];
    let expected_r = [0.2, 0.35, 0.65, 0.4];
    let b = MeasuredBxDF::new(data, &lambda(wavelengths));
    let mut rng = Pcg32Source::new(45);
    for wo in [
        spherical_direction(0.2, 0.5),
        spherical_direction(0.8, -2.0),
        spherical_direction(1.2, 1.0),
    ] {
        let fraction = file.visible_reflecting_fraction(wo);
        let mut albedo = [
            Accumulator::default(),
            Accumulator::default(),
            Accumulator::default(),
            Accumulator::default(),
        ];
        for _ in 0..100_000 {
            let weight = sample(&b, wo, rng.next_vec2())
                .map_or(SampledSpectrum::ZERO, |bs| bs.f * (bs.wi.z.abs() / bs.pdf));
            for (a, w) in albedo.iter_mut().zip(weight.0) {
                a.add(w as f64);
            }
        }
        // The same by quadrature of f.
        let quadrature = integrate_sphere(
            |wi| b.f(wo, wi, TransportMode::Radiance).0[1] * wi.z.max(0.0),
            400,
            800,
        ) as f64;
        for (k, a) in albedo.iter().enumerate() {
            let estimate = a.estimate();
            let expected = expected_r[k] * fraction;
            eprintln!(
                "wo = {wo}, λ = {}: albedo {:.4} ± {:.4}, expected {expected:.4}",
                wavelengths[k], estimate.mean, estimate.std_error
            );
            assert!(
                (estimate.mean - expected).abs() < 0.02 * expected + 4.0 * estimate.std_error,
                "{wo}, λ {}: {estimate:?} vs {expected}",
                wavelengths[k]
            );
        }
        let expected = expected_r[1] * fraction;
        assert!(
            (quadrature - expected).abs() < 0.02 * expected,
            "{wo}: quadrature {quadrature} vs {expected}"
        );
    }
}

/// Not a check: writes the synthetic files into the folder
/// `$RPBRT_MEASURED_OUT`, to render them with pbrt-v4 beside rpbrt
/// (`RPBRT_MEASURED_OUT=/tmp/x cargo test --release --lib
/// write_synthetic_files -- --ignored`).
#[test]
#[ignore]
fn write_synthetic_files() {
    let Some(dir) = std::env::var_os("RPBRT_MEASURED_OUT") else {
        eprintln!("RPBRT_MEASURED_OUT not set: nothing written");
        return;
    };
    let dir = std::path::PathBuf::from(dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut constant = Synthetic::ggx(0.25);
    constant.values = vec![0.2, 0.5, 0.9, 0.4];
    let mut files = files();
    files.push(("constant", constant));
    for (name, file) in files {
        std::fs::write(dir.join(format!("{name}.bsdf")), file.bytes()).unwrap();
    }
}
