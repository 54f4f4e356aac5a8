//! Lambertian reflection and transmission: a thin translucent sheet
//! (paper, leaves) that scatters diffusely to both sides.

use super::geometry::{abs_cos_theta, same_hemisphere};
use super::{BSDFSample, BxDFFlags, BxDFInterface, BxDFReflTransFlags, TransportMode};
use crate::math::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// f = R/π on ωo's side, T/π on the other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmissionBxDF {
    reflectance: SampledSpectrum,
    transmittance: SampledSpectrum,
}

impl DiffuseTransmissionBxDF {
    pub fn new(reflectance: SampledSpectrum, transmittance: SampledSpectrum) -> Self {
        DiffuseTransmissionBxDF {
            reflectance,
            transmittance,
        }
    }

    /// Probabilities of choosing reflection and transmission: proportional
    /// to the largest component of R and T, restricted to the requested
    /// hemispheres.
    fn lobe_probabilities(&self, sample_flags: BxDFReflTransFlags) -> Option<(f32, f32)> {
        let mut pr = self.reflectance.max_component();
        let mut pt = self.transmittance.max_component();
        if !sample_flags.includes_reflection() {
            pr = 0.0;
        }
        if !sample_flags.includes_transmission() {
            pt = 0.0;
        }
        if pr == 0.0 && pt == 0.0 {
            return None;
        }
        Some((pr / (pr + pt), pt / (pr + pt)))
    }
}

impl BxDFInterface for DiffuseTransmissionBxDF {
    fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if same_hemisphere(wo, wi) {
            self.reflectance * FRAC_1_PI
        } else {
            self.transmittance * FRAC_1_PI
        }
    }

    fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<BSDFSample> {
        let (pr, pt) = self.lobe_probabilities(sample_flags)?;
        let mut wi = sample_cosine_hemisphere(u);
        if uc < pr {
            if wo.z < 0.0 {
                wi.z = -wi.z;
            }
            let pdf = cosine_hemisphere_pdf(abs_cos_theta(wi)) * pr;
            Some(BSDFSample::new(
                self.f(wo, wi, mode),
                wi,
                pdf,
                BxDFFlags::DIFFUSE_REFLECTION,
            ))
        } else {
            if wo.z > 0.0 {
                wi.z = -wi.z;
            }
            let pdf = cosine_hemisphere_pdf(abs_cos_theta(wi)) * pt;
            Some(BSDFSample::new(
                self.f(wo, wi, mode),
                wi,
                pdf,
                BxDFFlags::DIFFUSE_TRANSMISSION,
            ))
        }
    }

    fn pdf(
        &self,
        wo: Vec3,
        wi: Vec3,
        _mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> f32 {
        let Some((pr, pt)) = self.lobe_probabilities(sample_flags) else {
            return 0.0;
        };
        let lobe = if same_hemisphere(wo, wi) { pr } else { pt };
        lobe * cosine_hemisphere_pdf(abs_cos_theta(wi))
    }

    fn flags(&self) -> BxDFFlags {
        let mut flags = BxDFFlags::UNSET;
        if self.reflectance.is_nonzero() {
            flags |= BxDFFlags::DIFFUSE_REFLECTION;
        }
        if self.transmittance.is_nonzero() {
            flags |= BxDFFlags::DIFFUSE_TRANSMISSION;
        }
        flags
    }

    fn regularize(&mut self) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::test_support::*;
    use crate::bxdfs::BxDF;

    fn sheet() -> BxDF {
        BxDF::DiffuseTransmission(DiffuseTransmissionBxDF::new(
            SampledSpectrum([0.3, 0.5, 0.1, 0.2]),
            SampledSpectrum([0.6, 0.2, 0.4, 0.25]),
        ))
    }

    #[test]
    fn white_furnace_is_r_plus_t() {
        // R + T = 0.275 + 0.3625 = 0.6375 averaged over wavelengths.
        let bxdf = sheet();
        let mut rng = Pcg32Source::new(21);
        for wo in test_directions(&mut rng, 4, true) {
            let report = sampling_consistency(
                &bxdf,
                wo,
                TransportMode::Radiance,
                50_000,
                200_000,
                &mut rng,
            );
            assert!(
                (report.importance.mean - 0.6375).abs() < 0.002,
                "{report:?}"
            );
            assert!(report.z_score() < 4.5, "{report:?}");
            assert_eq!(report.pdf_mismatches, 0, "{report:?}");
        }
    }

    #[test]
    fn chi2_sampling_matches_pdf() {
        let bsdf = tilted_bsdf(sheet());
        let mut rng = Pcg32Source::new(22);
        let wos = test_directions(&mut rng, 2, true);
        assert_chi2_passes("diffuse transmission", &bsdf, &wos, &mut rng);
    }

    #[test]
    fn restricted_sampling_stays_in_its_hemisphere() {
        let bxdf = sheet();
        let wo = Vec3::new(0.1, 0.2, 0.974_679_4);
        for i in 0..64 {
            let u = Vec2::new((i as f32 + 0.5) / 64.0, 0.3);
            let t = bxdf
                .sample_f(
                    wo,
                    u.x,
                    u,
                    TransportMode::Radiance,
                    BxDFReflTransFlags::Transmission,
                )
                .unwrap();
            assert!(t.wi.z < 0.0 && t.is_transmission());
            let r = bxdf
                .sample_f(
                    wo,
                    u.x,
                    u,
                    TransportMode::Radiance,
                    BxDFReflTransFlags::Reflection,
                )
                .unwrap();
            assert!(r.wi.z > 0.0 && r.is_reflection());
            assert_eq!(
                r.pdf,
                bxdf.pdf(
                    wo,
                    r.wi,
                    TransportMode::Radiance,
                    BxDFReflTransFlags::Reflection
                )
            );
        }
    }
}
