//! A thin dielectric slab (a window pane, a soap film without
//! interference): light reflects or passes straight through, having
//! bounced any number of times between the slab's two parallel faces.

use super::fresnel::fr_dielectric;
use super::geometry::abs_cos_theta;
use super::{BSDFSample, BxDFFlags, BxDFInterface, BxDFReflTransFlags, TransportMode};
use crate::math::sqr;
use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};

/// Both faces are smooth, so both lobes are deltas; transmitted light
/// leaves parallel to how it came in (the slab has no thickness to offset
/// it), so no η' scaling applies either.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectricBxDF {
    eta: f32,
}

impl ThinDielectricBxDF {
    pub fn new(eta: f32) -> Self {
        ThinDielectricBxDF { eta }
    }

    /// Total reflectance and transmittance of the slab: the single-face R
    /// plus the geometric series of inter-reflections, T²R/(1 − R²).
    fn reflectance_and_transmittance(&self, wo: Vec3) -> (f32, f32) {
        let mut reflectance = fr_dielectric(abs_cos_theta(wo), self.eta);
        let mut transmittance = 1.0 - reflectance;
        if reflectance < 1.0 {
            reflectance += sqr(transmittance) * reflectance / (1.0 - sqr(reflectance));
            transmittance = 1.0 - reflectance;
        }
        (reflectance, transmittance)
    }
}

impl BxDFInterface for ThinDielectricBxDF {
    /// Delta lobes only: never non-zero for a given direction pair.
    fn f(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        SampledSpectrum::ZERO
    }

    fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        _u: Vec2,
        _mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<BSDFSample> {
        let (reflectance, transmittance) = self.reflectance_and_transmittance(wo);
        let pr = if sample_flags.includes_reflection() {
            reflectance
        } else {
            0.0
        };
        let pt = if sample_flags.includes_transmission() {
            transmittance
        } else {
            0.0
        };
        if pr == 0.0 && pt == 0.0 {
            return None;
        }
        if uc < pr / (pr + pt) {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            let f = SampledSpectrum::splat(reflectance / abs_cos_theta(wi));
            Some(BSDFSample::new(
                f,
                wi,
                pr / (pr + pt),
                BxDFFlags::SPECULAR_REFLECTION,
            ))
        } else {
            let wi = -wo;
            let f = SampledSpectrum::splat(transmittance / abs_cos_theta(wi));
            Some(BSDFSample::new(
                f,
                wi,
                pt / (pr + pt),
                BxDFFlags::SPECULAR_TRANSMISSION,
            ))
        }
    }

    fn pdf(
        &self,
        _wo: Vec3,
        _wi: Vec3,
        _mode: TransportMode,
        _sample_flags: BxDFReflTransFlags,
    ) -> f32 {
        0.0
    }

    fn flags(&self) -> BxDFFlags {
        BxDFFlags::REFLECTION | BxDFFlags::TRANSMISSION | BxDFFlags::SPECULAR
    }

    /// pbrt-v4 leaves the thin dielectric unregularized.
    fn regularize(&mut self) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::test_support::*;
    use crate::bxdfs::BxDF;

    #[test]
    fn white_furnace_is_exactly_one_and_reflection_exceeds_one_face() {
        let bxdf = BxDF::ThinDielectric(ThinDielectricBxDF::new(1.5));
        let mut rng = Pcg32Source::new(51);
        for wo in test_directions(&mut rng, 10, true) {
            let mut reflected = 0.0;
            let n = 10_000;
            for _ in 0..n {
                let bs = bxdf
                    .sample_f(
                        wo,
                        rng.next_f32(),
                        rng.next_vec2(),
                        TransportMode::Radiance,
                        BxDFReflTransFlags::All,
                    )
                    .unwrap();
                let weight = bs.f.average() * bs.wi.z.abs() / bs.pdf;
                assert!((weight - 1.0).abs() < 1e-5, "{weight}");
                if bs.is_reflection() {
                    assert_eq!(bs.wi, Vec3::new(-wo.x, -wo.y, wo.z));
                    reflected += 1.0;
                } else {
                    assert_eq!(bs.wi, -wo);
                }
            }
            // Two faces reflect more than one: at normal incidence
            // 2R/(1 + R) = 0.0769 vs 0.04.
            let single_face = fr_dielectric(wo.z.abs(), 1.5);
            let double = 2.0 * single_face / (1.0 + single_face);
            let fraction = reflected / n as f32;
            assert!((fraction - double).abs() < 0.02, "{fraction} vs {double}");
        }
        assert!(bxdf.f(Vec3::Z, -Vec3::Z, TransportMode::Radiance).is_zero());
    }
}
