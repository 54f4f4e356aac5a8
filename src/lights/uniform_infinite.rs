//! Infinitely distant uniform light (`infinite` with `L` and no file).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `L` | spectrum | colour space illuminant | radiance |
//! | `scale` | float | 1 | scale |
//! | `illuminance` | float | — | if given: illuminance in lux at an upward-facing surface |

use super::{LightLiSample, LightSampleContext, Radiance};
use crate::math::sampling::{sample_uniform_sphere, UNIFORM_SPHERE_PDF};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

pub struct UniformInfiniteLight {
    pub radiance: Spectrum,
    pub scale: f32,
    pub scene_center: Vec3,
    pub scene_radius: f32,
}

impl UniformInfiniteLight {
    pub fn preprocess(&mut self, center: Vec3, radius: f32) {
        self.scene_center = center;
        self.scene_radius = radius;
    }

    pub fn le(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.radiance.sample(lambda) * self.scale
    }

    /// pbrt-v4: when the BSDF is also sampled (MIS), a uniform light
    /// leaves all directions to it and is not sampled.
    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
        allow_incomplete_pdf: bool,
    ) -> Option<LightLiSample<'_>> {
        if allow_incomplete_pdf {
            return None;
        }
        let wi = sample_uniform_sphere(u);
        Some(LightLiSample {
            l: Radiance::Value(self.le(lambda)),
            wi,
            pdf: UNIFORM_SPHERE_PDF,
            p_light: ctx.p + wi * (2.0 * self.scene_radius),
            p_light_error: Vec3::ZERO,
            n_light: Vec3::ZERO,
        })
    }

    pub fn pdf_li(&self, allow_incomplete_pdf: bool) -> f32 {
        if allow_incomplete_pdf {
            0.0
        } else {
            UNIFORM_SPHERE_PDF
        }
    }

    pub fn phi(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.le(lambda) * (4.0 * PI * PI * self.scene_radius * self.scene_radius)
    }
}
