//! A BxDF placed at a surface point: converts render-space directions to
//! the local shading frame and back.

use super::hair::Longitudinal;
use super::{BSDFSample, BxDF, BxDFFlags, BxDFInterface, BxDFReflTransFlags, TransportMode};
use crate::math::Frame;
use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BSDF {
    bxdf: BxDF,
    shading_frame: Frame,
}

impl BSDF {
    /// Shading frame with z = `shading_normal` and x along `dpdus` (the
    /// shading ∂p/∂u, which orients anisotropic roughness). `dpdus` is made
    /// orthogonal to the normal first; if it is degenerate, any tangent is
    /// used.
    pub fn new(shading_normal: Vec3, dpdus: Vec3, bxdf: BxDF) -> Self {
        BSDF {
            bxdf,
            shading_frame: Self::frame(shading_normal, dpdus),
        }
    }

    /// The shading frame [`BSDF::new`] builds (for a material that needs
    /// local directions before it has made its BxDF).
    pub fn frame(shading_normal: Vec3, dpdus: Vec3) -> Frame {
        let z = shading_normal.normalize();
        let x = dpdus - z * z.dot(dpdus);
        if x.length_squared() > 1e-12 {
            Frame::from_xz(x.normalize(), z)
        } else {
            Frame::from_z(z)
        }
    }

    pub fn bxdf(&self) -> &BxDF {
        &self.bxdf
    }

    pub fn shading_frame(&self) -> &Frame {
        &self.shading_frame
    }

    /// At a hit in the dual hair model's diffracting ring: the fibre's
    /// tangent (render space, unit) and the ring's longitudinal lobe
    /// M_diff; `None` anywhere else.
    pub(crate) fn diffracting_ring(&self) -> Option<(Vec3, Longitudinal)> {
        match &self.bxdf {
            BxDF::DualHair(b) => b
                .ring_longitudinal()
                .map(|m| (self.shading_frame.from_local(Vec3::X), m)),
            _ => None,
        }
    }

    pub fn flags(&self) -> BxDFFlags {
        self.bxdf.flags()
    }

    pub fn render_to_local(&self, v: Vec3) -> Vec3 {
        self.shading_frame.to_local(v)
    }

    pub fn local_to_render(&self, v: Vec3) -> Vec3 {
        self.shading_frame.from_local(v)
    }

    /// Zero when ωo lies in the shading tangent plane (no well-defined
    /// side), as in pbrt-v4.
    pub fn f(&self, wo_render: Vec3, wi_render: Vec3, mode: TransportMode) -> SampledSpectrum {
        let wi = self.render_to_local(wi_render);
        let wo = self.render_to_local(wo_render);
        if wo.z == 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.bxdf.f(wo, wi, mode)
    }

    /// [`Self::f`], and [`Self::pdf`] over all lobes when the BxDF gives it
    /// with the value ([`BxDF::f_and_pdf`]).
    pub fn f_and_pdf(
        &self,
        wo_render: Vec3,
        wi_render: Vec3,
        mode: TransportMode,
    ) -> (SampledSpectrum, Option<f32>) {
        let wi = self.render_to_local(wi_render);
        let wo = self.render_to_local(wo_render);
        if wo.z == 0.0 {
            return (SampledSpectrum::ZERO, Some(0.0));
        }
        self.bxdf.f_and_pdf(wo, wi, mode)
    }

    /// Samples ωi in render space. Unusable samples (zero value or density,
    /// or tangent to the surface) are dropped here, so callers can trust
    /// any sample they get.
    pub fn sample_f(
        &self,
        wo_render: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<BSDFSample> {
        let wo = self.render_to_local(wo_render);
        if wo.z == 0.0 || !self.bxdf.flags().allows(sample_flags) {
            return None;
        }
        let mut bs = self
            .bxdf
            .sample_f(wo, uc, u, mode, sample_flags)
            .filter(BSDFSample::is_usable)?;
        bs.wi = self.local_to_render(bs.wi);
        Some(bs)
    }

    pub fn pdf(
        &self,
        wo_render: Vec3,
        wi_render: Vec3,
        mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> f32 {
        let wo = self.render_to_local(wo_render);
        let wi = self.render_to_local(wi_render);
        if wo.z == 0.0 {
            return 0.0;
        }
        self.bxdf.pdf(wo, wi, mode, sample_flags)
    }

    pub fn regularize(&mut self) {
        self.bxdf.regularize();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::{ConductorBxDF, DiffuseBxDF, TrowbridgeReitzDistribution};

    #[test]
    fn frame_follows_normal_and_tangent() {
        let n = Vec3::new(0.0, 1.0, 0.0);
        let bsdf = BSDF::new(
            n,
            Vec3::new(1.0, 0.5, 0.0),
            BxDF::Diffuse(DiffuseBxDF::new(SampledSpectrum::ONE)),
        );
        assert!((bsdf.render_to_local(n) - Vec3::Z).length() < 1e-6);
        assert!((bsdf.render_to_local(Vec3::X) - Vec3::X).length() < 1e-6);
        let v = Vec3::new(0.3, -0.2, 0.9).normalize();
        assert!((bsdf.local_to_render(bsdf.render_to_local(v)) - v).length() < 1e-6);
    }

    #[test]
    fn tangent_outgoing_direction_gives_nothing() {
        let n = Vec3::Z;
        let bsdf = BSDF::new(
            n,
            Vec3::X,
            BxDF::Diffuse(DiffuseBxDF::new(SampledSpectrum::ONE)),
        );
        let grazing = Vec3::X;
        assert!(bsdf.f(grazing, Vec3::Z, TransportMode::Radiance).is_zero());
        assert_eq!(
            bsdf.pdf(
                grazing,
                Vec3::Z,
                TransportMode::Radiance,
                BxDFReflTransFlags::All
            ),
            0.0
        );
        assert!(bsdf
            .sample_f(
                grazing,
                0.5,
                Vec2::splat(0.5),
                TransportMode::Radiance,
                BxDFReflTransFlags::All
            )
            .is_none());
        // Asking a reflector for transmission only gives nothing.
        assert!(bsdf
            .sample_f(
                Vec3::Z,
                0.5,
                Vec2::splat(0.5),
                TransportMode::Radiance,
                BxDFReflTransFlags::Transmission
            )
            .is_none());
    }

    #[test]
    fn anisotropy_is_oriented_by_the_tangent() {
        // Roughness along x is larger: the lobe spreads more along dpdu.
        let bxdf = BxDF::Conductor(ConductorBxDF::new(
            TrowbridgeReitzDistribution::new(0.6, 0.1),
            SampledSpectrum::splat(0.2),
            SampledSpectrum::splat(3.0),
        ));
        let n = Vec3::new(0.0, 0.0, 1.0);
        let along = BSDF::new(n, Vec3::X, bxdf);
        let across = BSDF::new(n, Vec3::Y, bxdf);
        let wo = Vec3::Z;
        let wi = Vec3::new(0.5, 0.0, 0.866_025_4);
        let f_along = along.f(wo, wi, TransportMode::Radiance).average();
        let f_across = across.f(wo, wi, TransportMode::Radiance).average();
        assert!(f_along > 10.0 * f_across, "{f_along} vs {f_across}");
    }
}
