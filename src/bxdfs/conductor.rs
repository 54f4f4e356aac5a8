//! Metals: all light not absorbed is reflected, by a perfect mirror or by
//! a Torrance–Sparrow microfacet lobe, with complex-index Fresnel.

use super::fresnel::fr_complex_spectrum;
use super::geometry::{abs_cos_theta, face_forward, reflect, same_hemisphere};
use super::microfacet::TrowbridgeReitzDistribution;
use super::{BSDFSample, BxDFFlags, BxDFInterface, BxDFReflTransFlags, TransportMode};
use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};

/// A conductor with complex index of refraction η + i k (per wavelength,
/// relative to the outside medium).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConductorBxDF {
    distribution: TrowbridgeReitzDistribution,
    eta: SampledSpectrum,
    k: SampledSpectrum,
}

impl ConductorBxDF {
    pub fn new(
        distribution: TrowbridgeReitzDistribution,
        eta: SampledSpectrum,
        k: SampledSpectrum,
    ) -> Self {
        ConductorBxDF {
            distribution,
            eta,
            k,
        }
    }

    pub fn distribution(&self) -> TrowbridgeReitzDistribution {
        self.distribution
    }
}

impl BxDFInterface for ConductorBxDF {
    fn flags(&self) -> BxDFFlags {
        if self.distribution.effectively_smooth() {
            BxDFFlags::SPECULAR_REFLECTION
        } else {
            BxDFFlags::GLOSSY_REFLECTION
        }
    }

    /// The Torrance–Sparrow BRDF D(ωm) F G / (4 |cos θo| |cos θi|); zero for
    /// a smooth conductor (a delta lobe has no finite value).
    fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) || self.distribution.effectively_smooth() {
            return SampledSpectrum::ZERO;
        }
        let cos_theta_o = abs_cos_theta(wo);
        let cos_theta_i = abs_cos_theta(wi);
        if cos_theta_i == 0.0 || cos_theta_o == 0.0 {
            return SampledSpectrum::ZERO;
        }
        let wm = wi + wo;
        if wm.length_squared() == 0.0 {
            return SampledSpectrum::ZERO;
        }
        let wm = wm.normalize();
        let fresnel = fr_complex_spectrum(wo.dot(wm).abs(), self.eta, self.k);
        fresnel
            * (self.distribution.d(wm) * self.distribution.g(wo, wi)
                / (4.0 * cos_theta_i * cos_theta_o))
    }

    /// Smooth: the mirror direction with probability 1. Rough: a visible
    /// microfacet normal, reflected about; samples that end up below the
    /// surface are rejected (that energy is lost, as in pbrt-v4).
    fn sample_f(
        &self,
        wo: Vec3,
        _uc: f32,
        u: Vec2,
        _mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<BSDFSample> {
        if !sample_flags.includes_reflection() {
            return None;
        }
        if self.distribution.effectively_smooth() {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            let cos_theta_i = abs_cos_theta(wi);
            let f = fr_complex_spectrum(cos_theta_i, self.eta, self.k) / cos_theta_i;
            return Some(BSDFSample::new(f, wi, 1.0, BxDFFlags::SPECULAR_REFLECTION));
        }
        if wo.z == 0.0 {
            return None;
        }
        let wm = self.distribution.sample_wm(wo, u);
        let wi = reflect(wo, wm);
        if !same_hemisphere(wo, wi) {
            return None;
        }
        // The reflection Jacobian dωm/dωi = 1/(4 |ωo·ωm|).
        let pdf = self.distribution.pdf(wo, wm) / (4.0 * wo.dot(wm).abs());
        let cos_theta_o = abs_cos_theta(wo);
        let cos_theta_i = abs_cos_theta(wi);
        if cos_theta_i == 0.0 || cos_theta_o == 0.0 {
            return None;
        }
        let fresnel = fr_complex_spectrum(wo.dot(wm).abs(), self.eta, self.k);
        let f = fresnel
            * (self.distribution.d(wm) * self.distribution.g(wo, wi)
                / (4.0 * cos_theta_i * cos_theta_o));
        Some(BSDFSample::new(f, wi, pdf, BxDFFlags::GLOSSY_REFLECTION))
    }

    fn pdf(
        &self,
        wo: Vec3,
        wi: Vec3,
        _mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> f32 {
        if !sample_flags.includes_reflection()
            || !same_hemisphere(wo, wi)
            || self.distribution.effectively_smooth()
        {
            return 0.0;
        }
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = face_forward(wm.normalize(), Vec3::Z);
        self.distribution.pdf(wo, wm) / (4.0 * wo.dot(wm).abs())
    }

    fn regularize(&mut self) {
        self.distribution.regularize();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::test_support::*;
    use crate::bxdfs::BxDF;

    /// Copper-like constants (η, k at four wavelengths).
    fn copper(alpha_x: f32, alpha_y: f32) -> BxDF {
        BxDF::Conductor(ConductorBxDF::new(
            TrowbridgeReitzDistribution::new(alpha_x, alpha_y),
            SampledSpectrum([1.1, 0.95, 0.27, 0.21]),
            SampledSpectrum([2.6, 2.5, 2.9, 4.2]),
        ))
    }

    /// A (nearly) perfect reflector: |F| → 1 at all angles.
    fn perfect_mirror_material(alpha_x: f32, alpha_y: f32) -> BxDF {
        BxDF::Conductor(ConductorBxDF::new(
            TrowbridgeReitzDistribution::new(alpha_x, alpha_y),
            SampledSpectrum::splat(0.0),
            SampledSpectrum::splat(1e4),
        ))
    }

    const ROUGHNESSES: [(f32, f32); 5] =
        [(0.1, 0.1), (0.3, 0.3), (0.6, 0.6), (1.0, 1.0), (0.15, 0.6)];

    #[test]
    fn smooth_conductor_reflects_fresnel_into_the_mirror_direction() {
        let bxdf = copper(0.0, 0.0);
        assert_eq!(bxdf.flags(), BxDFFlags::SPECULAR_REFLECTION);
        let wo = Vec3::new(0.3, 0.4, 0.866_025_4);
        let bs = bxdf
            .sample_f(
                wo,
                0.5,
                Vec2::splat(0.5),
                TransportMode::Radiance,
                BxDFReflTransFlags::All,
            )
            .unwrap();
        assert_eq!(bs.wi, Vec3::new(-0.3, -0.4, 0.866_025_4));
        assert_eq!(bs.pdf, 1.0);
        let weight = bs.f * bs.wi.z / bs.pdf;
        let expected = fr_complex_spectrum(
            wo.z,
            SampledSpectrum([1.1, 0.95, 0.27, 0.21]),
            SampledSpectrum([2.6, 2.5, 2.9, 4.2]),
        );
        assert!((weight - expected).max_component().abs() < 1e-6);
        assert!(bxdf.f(wo, bs.wi, TransportMode::Radiance).is_zero());
        assert_eq!(
            bxdf.pdf(wo, bs.wi, TransportMode::Radiance, BxDFReflTransFlags::All),
            0.0
        );
    }

    #[test]
    fn rough_white_conductor_loses_energy_only_to_single_scattering() {
        // With |F| = 1 the only loss is masking–shadowing (single
        // scattering), so the albedo is ≤ 1, near 1 when smooth, and
        // decreasing with roughness. Measured figures are printed.
        let mut rng = Pcg32Source::new(31);
        let wo = Vec3::new(0.5, 0.0, 0.866_025_4);
        let mut previous = 1.0;
        for alpha in [0.05, 0.3, 0.6, 1.0] {
            let bxdf = perfect_mirror_material(alpha, alpha);
            let mut albedo = Accumulator::default();
            for _ in 0..100_000 {
                let weight = bxdf
                    .sample_f(
                        wo,
                        rng.next_f32(),
                        rng.next_vec2(),
                        TransportMode::Radiance,
                        BxDFReflTransFlags::All,
                    )
                    .map_or(0.0, |bs| bs.f.average() * bs.wi.z.abs() / bs.pdf);
                albedo.add(weight as f64);
            }
            let albedo = albedo.estimate();
            eprintln!(
                "white rough conductor α = {alpha}: albedo {:.4} ± {:.4}",
                albedo.mean, albedo.std_error
            );
            assert!(albedo.mean <= 1.0 + 3.0 * albedo.std_error, "{albedo:?}");
            assert!(albedo.mean <= previous + 1e-3, "{albedo:?}");
            previous = albedo.mean;
            if alpha == 0.05 {
                assert!(albedo.mean > 0.99, "{albedo:?}");
            }
        }
    }

    fn assert_sampling_consistent(roughnesses: &[(f32, f32)], seed: u64) {
        let mut rng = Pcg32Source::new(seed);
        for &(ax, ay) in roughnesses {
            let bxdf = copper(ax, ay);
            for wo in test_directions(&mut rng, 3, true) {
                let report = sampling_consistency(
                    &bxdf,
                    wo,
                    TransportMode::Radiance,
                    40_000,
                    300_000,
                    &mut rng,
                );
                let case = format!("α = ({ax}, {ay}), wo = {wo}");
                eprintln!(
                    "conductor {case}: sampled {:.4} ± {:.4}, uniform {:.4} ± {:.4}, z = {:.2}, max pdf rel. err {:.1e} ({} > 1e-3), max f rel. err {:.1e}",
                    report.importance.mean, report.importance.std_error, report.uniform.mean, report.uniform.std_error,
                    report.z_score(), report.max_pdf_relative_error, report.pdf_mismatches, report.max_f_relative_error
                );
                assert!(report.z_score() < 4.5, "{case}: {report:?}");
                // Rough lobes never produce delta samples.
                assert_eq!(report.specular.mean, 0.0, "{case}");
                assert!(
                    report.pdf_mismatches * 1000 <= report.samples,
                    "{case}: {report:?}"
                );
                assert!(report.max_f_relative_error < 1e-2, "{case}: {report:?}");
            }
        }
    }

    #[test]
    fn sampling_is_consistent_with_f_and_pdf_isotropic() {
        assert_sampling_consistent(&ROUGHNESSES[..4], 32);
    }

    #[test]
    fn sampling_is_consistent_with_f_and_pdf_anisotropic() {
        assert_sampling_consistent(&[(0.15, 0.6), (0.5, 0.2)], 37);
    }

    #[test]
    fn chi2_isotropic() {
        let bsdf = tilted_bsdf(copper(0.7, 0.7));
        let mut rng = Pcg32Source::new(33);
        let wos = test_directions(&mut rng, 2, true);
        assert_chi2_passes("conductor α 0.7", &bsdf, &wos, &mut rng);
    }

    #[test]
    fn chi2_anisotropic() {
        let bsdf = tilted_bsdf(copper(0.55, 0.39));
        let mut rng = Pcg32Source::new(34);
        let wos = test_directions(&mut rng, 2, false);
        assert_chi2_passes("conductor α (0.55, 0.39)", &bsdf, &wos, &mut rng);
    }

    #[test]
    fn chi2_low_roughness() {
        let bsdf = tilted_bsdf(copper(0.15, 0.15));
        let mut rng = Pcg32Source::new(35);
        let wos = test_directions(&mut rng, 2, false);
        assert_chi2_passes("conductor α 0.15", &bsdf, &wos, &mut rng);
    }

    #[test]
    fn reciprocity() {
        let mut rng = Pcg32Source::new(36);
        for (ax, ay) in ROUGHNESSES {
            let bxdf = copper(ax, ay);
            let ws = test_directions(&mut rng, 12, true);
            for &a in &ws {
                for &b in &ws {
                    let fab = bxdf.f(a, b, TransportMode::Radiance);
                    let fba = bxdf.f(b, a, TransportMode::Radiance);
                    let scale = fab.max_component().max(1e-3);
                    assert!(
                        (fab - fba).max_component().abs() / scale < 1e-4,
                        "{a} {b}: {fab:?} {fba:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn regularize_turns_a_mirror_glossy() {
        let mut bxdf = copper(0.0, 0.0);
        bxdf.regularize();
        assert_eq!(bxdf.flags(), BxDFFlags::GLOSSY_REFLECTION);
        let BxDF::Conductor(c) = bxdf else {
            unreachable!()
        };
        assert_eq!(c.distribution().alpha_x(), 0.1);
    }
}
