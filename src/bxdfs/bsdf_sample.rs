//! The result of sampling a BxDF.

use super::BxDFFlags;
use crate::spectrum::SampledSpectrum;
use glam::Vec3;

/// A sampled incident direction with the BxDF's value and the density
/// it was drawn with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BSDFSample {
    /// BxDF value for (wo, wi). For specular lobes, the delta's weight
    /// divided by |cos θi|, so that f·|cos θi|/pdf is the usual throughput.
    pub f: SampledSpectrum,
    /// The sampled incident direction (local frame for BxDFs, render
    /// space once the BSDF returns it).
    pub wi: Vec3,
    /// Solid-angle density of `wi`, or the discrete probability of the
    /// lobe for specular samples.
    pub pdf: f32,
    /// Which kind of scattering produced the sample.
    pub flags: BxDFFlags,
    /// Relative index of refraction across the boundary for transmission
    /// (η inside / η outside, inverted when leaving), 1 otherwise. The
    /// integrator tracks its product for Russian roulette.
    pub eta: f32,
    /// Set by the layered BxDF: `pdf` is only proportional to the true
    /// density (the walk's path density), so MIS must call `pdf()` instead.
    pub pdf_is_proportional: bool,
}

impl BSDFSample {
    pub fn new(f: SampledSpectrum, wi: Vec3, pdf: f32, flags: BxDFFlags) -> Self {
        BSDFSample {
            f,
            wi,
            pdf,
            flags,
            eta: 1.0,
            pdf_is_proportional: false,
        }
    }

    /// A transmission sample across a boundary of relative index `eta`.
    pub fn with_eta(mut self, eta: f32) -> Self {
        self.eta = eta;
        self
    }

    pub fn is_reflection(&self) -> bool {
        self.flags.is_reflective()
    }

    pub fn is_transmission(&self) -> bool {
        self.flags.is_transmissive()
    }

    pub fn is_specular(&self) -> bool {
        self.flags.is_specular()
    }

    /// Whether the sample can be used: non-zero value and density, and a
    /// direction off the tangent plane. Mirrors the checks pbrt applies
    /// before trusting a sample.
    pub fn is_usable(&self) -> bool {
        self.f.is_nonzero() && self.pdf > 0.0 && self.wi.z != 0.0
    }
}
