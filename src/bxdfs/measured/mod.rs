//! pbrt-v4's `MeasuredBxDF`: a BRDF interpolated from the RGL material
//! database's measurements (Dupuy & Jakob 2018, "An adaptive
//! parameterization for efficient material acquisition and rendering";
//! pbrt-v4 book §9.8). Reflection only, glossy.
//!
//! Directions map to the unit square by θ ↦ u = √(2θ/π) (a finer grid near
//! the normal, where glossy peaks are) and φ ↦ u = φ/2π + ½; the
//! microfacet normal ωm of a pair is its half vector, whose azimuth is
//! taken relative to ωo's in an isotropic file. With D the tabulated NDF, σ
//! the projected area and S the spectral table at the point R⁻¹(ωm) of the
//! warped domain (the visible-normal warp inverted),
//!
//!   f(ωo, ωi) = S(R⁻¹(ωm); φo, θo, λ) D(ωm) / (4 σ(ωo) cos θi),
//!
//! at each of the path's wavelengths. Sampling draws a point of the
//! warped domain from the luminance table, warps it to ωm by the
//! visible-normal table and reflects ωo; its density is the product of
//! the two tables' densities over the Jacobian 4 (ωo · ωm) · 2π² u_θ sin θm
//! from the unit square to ωi. Everything is conditioned on ωo; below the
//! surface both directions are mirrored first, as pbrt-v4 does.

pub mod data;
pub mod tensor_file;

#[cfg(test)]
pub(crate) mod synthetic;
#[cfg(test)]
mod tests;

pub use data::{DataError, MeasuredBxDFData};

use super::geometry::{abs_cos_theta, cos_theta, reflect, same_hemisphere};
use super::{BSDFSample, BxDFFlags, BxDFInterface, BxDFReflTransFlags, TransportMode};
use crate::math::safe_acos;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, N_SPECTRUM_SAMPLES};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// θ ∈ [0, π/2] ↦ [0, 1].
fn theta_to_u(theta: f32) -> f32 {
    (theta * (2.0 / PI)).sqrt()
}

/// φ ∈ [−π, π] ↦ [0, 1].
fn phi_to_u(phi: f32) -> f32 {
    phi * (1.0 / (2.0 * PI)) + 0.5
}

fn u_to_theta(u: f32) -> f32 {
    u * u * (PI / 2.0)
}

fn u_to_phi(u: f32) -> f32 {
    (2.0 * u - 1.0) * PI
}

/// The measured BRDF at one hit: the file's tables and the path's
/// wavelengths.
#[derive(Clone, Copy, Debug)]
pub struct MeasuredBxDF {
    /// Shared by every hit of every material naming the file, for the
    /// whole run, as pbrt-v4 keeps them (a BxDF is a plain value, so it
    /// holds a `'static` reference: see `materials::measured`).
    data: &'static MeasuredBxDFData,
    lambda: [f32; N_SPECTRUM_SAMPLES],
}

impl PartialEq for MeasuredBxDF {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self.data, other.data) && self.lambda == other.lambda
    }
}

/// ωo's spherical coordinates, the conditioning of every table.
struct Outgoing {
    theta: f32,
    phi: f32,
}

impl Outgoing {
    fn new(wo: Vec3) -> Self {
        Outgoing {
            theta: safe_acos(wo.z),
            phi: wo.y.atan2(wo.x),
        }
    }

    fn params(&self) -> [f32; 2] {
        [self.phi, self.theta]
    }

    fn unit(&self) -> Vec2 {
        Vec2::new(theta_to_u(self.theta), phi_to_u(self.phi))
    }
}

impl MeasuredBxDF {
    pub fn new(data: &'static MeasuredBxDFData, lambda: &SampledWavelengths) -> Self {
        MeasuredBxDF {
            data,
            lambda: lambda.lambda,
        }
    }

    /// The half vector of a pair above the surface on the unit square
    /// (azimuth relative to ωo's in an isotropic file, wrapped to [0, 1)).
    fn half_vector_unit(&self, wm: Vec3, o: &Outgoing) -> Vec2 {
        let theta_m = safe_acos(wm.z);
        let phi_m = wm.y.atan2(wm.x);
        let phi = if self.data.isotropic {
            phi_m - o.phi
        } else {
            phi_m
        };
        let v = phi_to_u(phi);
        Vec2::new(theta_to_u(theta_m), v - v.floor())
    }

    /// The spectral table at `sample` (a point of the warped domain) at
    /// each wavelength, negative interpolants clamped to zero as pbrt-v4.
    fn spectra(&self, sample: Vec2, o: &Outgoing) -> SampledSpectrum {
        let mut values = [0.0; N_SPECTRUM_SAMPLES];
        for (v, &lambda) in values.iter_mut().zip(&self.lambda) {
            *v = self
                .data
                .spectra
                .evaluate(sample, [o.phi, o.theta, lambda])
                .max(0.0);
        }
        SampledSpectrum(values)
    }

    /// Both directions above the surface (mirrored together when ωo is
    /// below), or `None` for a pair on opposite sides.
    fn upper(wo: Vec3, wi: Vec3) -> Option<(Vec3, Vec3)> {
        if !same_hemisphere(wo, wi) {
            return None;
        }
        Some(if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) })
    }

    /// The Jacobian from the unit square of ωm to ωi's solid angle.
    fn jacobian(wo: Vec3, wm: Vec3, u_wm: Vec2, sin_theta_m: f32) -> f32 {
        4.0 * wo.dot(wm) * (2.0 * PI * PI * u_wm.x * sin_theta_m).max(1e-6)
    }
}

impl BxDFInterface for MeasuredBxDF {
    fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        let Some((wo, wi)) = Self::upper(wo, wi) else {
            return SampledSpectrum::ZERO;
        };
        let wm = wi + wo;
        if wm.length_squared() == 0.0 {
            return SampledSpectrum::ZERO;
        }
        let wm = wm.normalize();
        let o = Outgoing::new(wo);
        let u_wm = self.half_vector_unit(wm, &o);
        let sample = self.data.vndf.invert(u_wm, o.params()).p;
        let fr = self.spectra(sample, &o);
        fr * (self.data.ndf.evaluate(u_wm, [])
            / (4.0 * self.data.sigma.evaluate(o.unit(), []) * cos_theta(wi)))
    }

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
        let flip = wo.z <= 0.0;
        let wo = if flip { -wo } else { wo };
        let o = Outgoing::new(wo);
        // The luminance warp first (the sample's two values in order, as
        // pbrt-v4 now passes them; its first release swapped them).
        let lum = self.data.luminance.sample(u, o.params());
        let vndf = self.data.vndf.sample(lum.p, o.params());
        let u_wm = vndf.p;

        let mut phi_m = u_to_phi(u_wm.y);
        if self.data.isotropic {
            phi_m += o.phi;
        }
        let theta_m = u_to_theta(u_wm.x);
        let (sin_theta_m, cos_theta_m) = theta_m.sin_cos();
        let wm = Vec3::new(
            sin_theta_m.clamp(-1.0, 1.0) * phi_m.cos(),
            sin_theta_m.clamp(-1.0, 1.0) * phi_m.sin(),
            cos_theta_m.clamp(-1.0, 1.0),
        );
        let wi = reflect(wo, wm);
        if wi.z <= 0.0 {
            return None;
        }
        let fr = self.spectra(lum.p, &o)
            * (self.data.ndf.evaluate(u_wm, [])
                / (4.0 * self.data.sigma.evaluate(o.unit(), []) * abs_cos_theta(wi)));
        let pdf = vndf.pdf * lum.pdf / Self::jacobian(wo, wm, u_wm, sin_theta_m);
        Some(BSDFSample::new(
            fr,
            if flip { -wi } else { wi },
            pdf,
            BxDFFlags::GLOSSY_REFLECTION,
        ))
    }

    fn pdf(
        &self,
        wo: Vec3,
        wi: Vec3,
        _mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> f32 {
        if !sample_flags.includes_reflection() {
            return 0.0;
        }
        let Some((wo, wi)) = Self::upper(wo, wi) else {
            return 0.0;
        };
        let wm = wi + wo;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = wm.normalize();
        let o = Outgoing::new(wo);
        let u_wm = self.half_vector_unit(wm, &o);
        let inverted = self.data.vndf.invert(u_wm, o.params());
        let lum_pdf = self.data.luminance.evaluate(inverted.p, o.params());
        let sin_theta_m = (wm.x * wm.x + wm.y * wm.y).sqrt();
        inverted.pdf * lum_pdf / Self::jacobian(wo, wm, u_wm, sin_theta_m)
    }

    fn flags(&self) -> BxDFFlags {
        BxDFFlags::GLOSSY_REFLECTION
    }

    /// Nothing to roughen: measured data (pbrt-v4 leaves it as is).
    fn regularize(&mut self) {}
}
