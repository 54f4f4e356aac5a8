//! Lambertian reflection: light leaves equally in all directions of the
//! hemisphere it arrived in.

use super::geometry::{abs_cos_theta, same_hemisphere};
use super::{BSDFSample, BxDFFlags, BxDFInterface, BxDFReflTransFlags, TransportMode};
use crate::math::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// f = R/π on both sides of the surface (the BxDF reflects on whichever
/// side ωo is), so R is the directional–hemispherical reflectance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseBxDF {
    reflectance: SampledSpectrum,
}

impl DiffuseBxDF {
    pub fn new(reflectance: SampledSpectrum) -> Self {
        DiffuseBxDF { reflectance }
    }

    pub fn reflectance(&self) -> SampledSpectrum {
        self.reflectance
    }
}

impl BxDFInterface for DiffuseBxDF {
    fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) {
            return SampledSpectrum::ZERO;
        }
        self.reflectance * FRAC_1_PI
    }

    /// Cosine-weighted sampling, which makes f·cos/pdf = R exactly.
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
        let mut wi = sample_cosine_hemisphere(u);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = cosine_hemisphere_pdf(abs_cos_theta(wi));
        Some(BSDFSample::new(
            self.reflectance * FRAC_1_PI,
            wi,
            pdf,
            BxDFFlags::DIFFUSE_REFLECTION,
        ))
    }

    fn pdf(
        &self,
        wo: Vec3,
        wi: Vec3,
        _mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> f32 {
        if !sample_flags.includes_reflection() || !same_hemisphere(wo, wi) {
            return 0.0;
        }
        cosine_hemisphere_pdf(abs_cos_theta(wi))
    }

    /// A black diffuse surface scatters nothing (flags unset), which lets
    /// integrators skip it.
    fn flags(&self) -> BxDFFlags {
        if self.reflectance.is_nonzero() {
            BxDFFlags::DIFFUSE_REFLECTION
        } else {
            BxDFFlags::UNSET
        }
    }

    /// Nothing to widen: the lobe is already as broad as it gets.
    fn regularize(&mut self) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::test_support::*;
    use crate::bxdfs::BxDF;

    fn white() -> BxDF {
        BxDF::Diffuse(DiffuseBxDF::new(SampledSpectrum::ONE))
    }

    #[test]
    fn white_furnace_reflects_exactly_everything() {
        // Expected 1 for every sample (f cos/pdf = R), from either side.
        let bxdf = white();
        let mut rng = Pcg32Source::new(11);
        for wo in test_directions(&mut rng, 8, true) {
            for _ in 0..10_000 {
                let bs = bxdf
                    .sample_f(
                        wo,
                        rng.next_f32(),
                        rng.next_vec2(),
                        TransportMode::Radiance,
                        BxDFReflTransFlags::All,
                    )
                    .expect("diffuse sampling cannot fail");
                let weight = bs.f.average() * bs.wi.z.abs() / bs.pdf;
                assert!((weight - 1.0).abs() < 1e-5, "{weight}");
                assert!(same_hemisphere(wo, bs.wi));
            }
        }
    }

    #[test]
    fn sampling_is_consistent_with_f_and_pdf() {
        let bxdf = BxDF::Diffuse(DiffuseBxDF::new(SampledSpectrum([0.2, 0.5, 0.7, 0.9])));
        let mut rng = Pcg32Source::new(12);
        for wo in test_directions(&mut rng, 4, true) {
            let report = sampling_consistency(
                &bxdf,
                wo,
                TransportMode::Radiance,
                20_000,
                200_000,
                &mut rng,
            );
            assert!(report.z_score() < 4.5, "{report:?}");
            assert!((report.uniform.mean - 0.575).abs() < 0.01, "{report:?}");
            assert_eq!(report.pdf_mismatches, 0, "{report:?}");
        }
    }

    #[test]
    fn chi2_sampling_matches_pdf() {
        let bsdf = tilted_bsdf(white());
        let mut rng = Pcg32Source::new(13);
        let wos = test_directions(&mut rng, 2, true);
        assert_chi2_passes("diffuse", &bsdf, &wos, &mut rng);
    }

    #[test]
    fn reciprocal_and_one_sided_per_hemisphere() {
        let bxdf = white();
        let mut rng = Pcg32Source::new(14);
        let ws = test_directions(&mut rng, 6, true);
        for &a in &ws {
            for &b in &ws {
                assert_eq!(
                    bxdf.f(a, b, TransportMode::Radiance),
                    bxdf.f(b, a, TransportMode::Radiance)
                );
            }
        }
        assert!(bxdf.f(Vec3::Z, -Vec3::Z, TransportMode::Radiance).is_zero());
        assert!(bxdf
            .sample_f(
                Vec3::Z,
                0.5,
                Vec2::splat(0.5),
                TransportMode::Radiance,
                BxDFReflTransFlags::Transmission
            )
            .is_none());
        assert!(BxDF::Diffuse(DiffuseBxDF::new(SampledSpectrum::ZERO))
            .flags()
            .is_unset());
    }
}
