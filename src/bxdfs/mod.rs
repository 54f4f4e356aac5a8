//! Scattering functions (BxDFs) with pbrt-v4's semantics, and the BSDF that
//! places one in a surface's shading frame.
//!
//! Every BxDF keeps one contract, [`BxDFInterface`], in the local shading
//! frame (z is the shading normal) with ωo and ωi both pointing away from
//! the surface. The family is a closed enum dispatched by `match`, so a
//! BxDF is created per intersection by value, with no heap allocation.

mod bsdf;
mod bsdf_sample;
mod bxdf_interface;
mod conductor;
mod dielectric;
mod diffuse;
mod diffuse_transmission;
pub mod dual_hair;
mod flags;
pub mod fresnel;
pub mod geometry;
pub mod hair;
pub mod hair_diffraction;
pub mod hair_ellipse;
#[cfg(test)]
mod hair_ellipse_oracle;
mod henyey_greenstein;
mod layered;
pub mod measured;
mod microfacet;
mod thin_dielectric;
mod transport_mode;

#[cfg(test)]
pub(crate) mod test_support;

pub use bsdf::BSDF;
pub use bsdf_sample::BSDFSample;
pub use bxdf_interface::BxDFInterface;
pub use conductor::ConductorBxDF;
pub use dielectric::DielectricBxDF;
pub use diffuse::DiffuseBxDF;
pub use diffuse_transmission::DiffuseTransmissionBxDF;
pub use flags::{BxDFFlags, BxDFReflTransFlags};
pub use henyey_greenstein::{henyey_greenstein, HenyeyGreenstein, PhaseFunctionSample};
pub use layered::{CoatedConductorBxDF, CoatedDiffuseBxDF, LayeredBxDF};
pub use measured::MeasuredBxDF;
pub use microfacet::TrowbridgeReitzDistribution;
pub use thin_dielectric::ThinDielectricBxDF;
pub use transport_mode::TransportMode;

use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};

/// The BxDFs pbrt-v4's materials create (and the dual hair model).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BxDF {
    Diffuse(DiffuseBxDF),
    Conductor(ConductorBxDF),
    Dielectric(DielectricBxDF),
    ThinDielectric(ThinDielectricBxDF),
    CoatedDiffuse(CoatedDiffuseBxDF),
    CoatedConductor(CoatedConductorBxDF),
    DiffuseTransmission(DiffuseTransmissionBxDF),
    Hair(hair::CircularHairBxDF),
    DualHair(dual_hair::DualHairBxDF),
    Measured(MeasuredBxDF),
}

/// Expands to a `match` calling `$method` on whichever BxDF `$self` holds.
macro_rules! dispatch {
    ($self:expr, $bxdf:ident => $call:expr) => {
        match $self {
            BxDF::Diffuse($bxdf) => $call,
            BxDF::Conductor($bxdf) => $call,
            BxDF::Dielectric($bxdf) => $call,
            BxDF::ThinDielectric($bxdf) => $call,
            BxDF::CoatedDiffuse($bxdf) => $call,
            BxDF::CoatedConductor($bxdf) => $call,
            BxDF::DiffuseTransmission($bxdf) => $call,
            BxDF::Hair($bxdf) => $call,
            BxDF::DualHair($bxdf) => $call,
            BxDF::Measured($bxdf) => $call,
        }
    };
}

/// The contract is the trait's; the enum keeps it by a `match` over the
/// models (no indirection per call, and each arm inlines its model).
impl BxDFInterface for BxDF {
    fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        dispatch!(self, b => b.f(wo, wi, mode))
    }

    fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<BSDFSample> {
        dispatch!(self, b => b.sample_f(wo, uc, u, mode, sample_flags))
    }

    fn pdf(
        &self,
        wo: Vec3,
        wi: Vec3,
        mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> f32 {
        dispatch!(self, b => b.pdf(wo, wi, mode, sample_flags))
    }

    fn f_and_pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (SampledSpectrum, Option<f32>) {
        dispatch!(self, b => b.f_and_pdf(wo, wi, mode))
    }

    fn flags(&self) -> BxDFFlags {
        dispatch!(self, b => b.flags())
    }

    fn regularize(&mut self) {
        dispatch!(self, b => b.regularize())
    }
}

impl From<DiffuseBxDF> for BxDF {
    fn from(b: DiffuseBxDF) -> Self {
        BxDF::Diffuse(b)
    }
}

impl From<ConductorBxDF> for BxDF {
    fn from(b: ConductorBxDF) -> Self {
        BxDF::Conductor(b)
    }
}

impl From<DielectricBxDF> for BxDF {
    fn from(b: DielectricBxDF) -> Self {
        BxDF::Dielectric(b)
    }
}

impl From<ThinDielectricBxDF> for BxDF {
    fn from(b: ThinDielectricBxDF) -> Self {
        BxDF::ThinDielectric(b)
    }
}

impl From<CoatedDiffuseBxDF> for BxDF {
    fn from(b: CoatedDiffuseBxDF) -> Self {
        BxDF::CoatedDiffuse(b)
    }
}

impl From<CoatedConductorBxDF> for BxDF {
    fn from(b: CoatedConductorBxDF) -> Self {
        BxDF::CoatedConductor(b)
    }
}

impl From<MeasuredBxDF> for BxDF {
    fn from(b: MeasuredBxDF) -> Self {
        BxDF::Measured(b)
    }
}

impl From<DiffuseTransmissionBxDF> for BxDF {
    fn from(b: DiffuseTransmissionBxDF) -> Self {
        BxDF::DiffuseTransmission(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_enum_stays_small_enough_to_pass_by_value() {
        // Per-intersection values: keep them in a few cache lines. The
        // largest are the hair models, which carry their state for the
        // hit's ωo (the dual model's trace results, tilts and lobe
        // probabilities, ~130 bytes; the circular model's A_p and angles,
        // ~150 bytes) so that f, pdf and sample do not compute it again
        // (benches/hair.rs, "vertex"); five cache lines.
        let size = std::mem::size_of::<BxDF>();
        eprintln!(
            "BxDF {size} bytes (circular hair {}, dual hair {})",
            std::mem::size_of::<hair::CircularHairBxDF>(),
            std::mem::size_of::<dual_hair::DualHairBxDF>()
        );
        assert!(size <= 320, "{size}");
    }
}
