//! The contract every BxDF keeps (pbrt-v4's `BxDF` interface): its value,
//! a sample of ωi, the density of that sampling, the value and density at
//! once, and its flags. Each scattering model implements it; the layered
//! BxDF is generic over it (its two interfaces are any BxDFs); the closed
//! enum [`super::BxDF`] implements it too, by a `match` over the models, so
//! a path vertex calls it without indirection.

use super::{BSDFSample, BxDFFlags, BxDFReflTransFlags, TransportMode};
use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};

/// All methods work in the local shading frame (z is the shading normal)
/// with ωo and ωi both pointing away from the surface.
pub trait BxDFInterface {
    /// The BxDF's value for the pair (zero for delta lobes; a stochastic
    /// but deterministic estimate for layered BxDFs).
    fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum;

    /// Samples ωi given ωo, a 1D sample `uc` (lobe choice) and a 2D sample
    /// `u` (direction), restricted to the requested hemispheres.
    fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<BSDFSample>;

    /// Solid-angle density with which `sample_f` returns ωi (zero for delta
    /// lobes).
    fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode, sample_flags: BxDFReflTransFlags)
        -> f32;

    /// f, and with it the pdf over all lobes where that costs next to
    /// nothing more (hair: the value and the density share each lobe's
    /// terms); `None` asks the caller to call [`Self::pdf`] if it needs it,
    /// which is what the models whose pdf costs as much as f do.
    fn f_and_pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> (SampledSpectrum, Option<f32>) {
        (self.f(wo, wi, mode), None)
    }

    /// Which lobes the BxDF has (reflection, transmission; diffuse,
    /// glossy, specular): integrators skip what they cannot use.
    fn flags(&self) -> BxDFFlags;

    /// Roughens near-specular lobes (pbrt-v4's `regularize` option).
    fn regularize(&mut self);
}
