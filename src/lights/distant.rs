//! Distant (directional) light.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `L` | spectrum | colour space illuminant | radiance |
//! | `scale` | float | 1 | scale |
//! | `from`, `to` | point3 | 0 0 0, 0 0 1 | light arrives travelling from `from` to `to` |
//! | `illuminance` | float | — | if given: illuminance in lux at a surface facing the light |

use super::{LightLiSample, LightSampleContext, Radiance};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec3;
use std::f32::consts::PI;

pub struct DistantLight {
    /// Unit direction towards the light, in render space.
    pub towards_light: Vec3,
    pub radiance: Spectrum,
    pub scale: f32,
    pub scene_radius: f32,
}

impl DistantLight {
    pub fn preprocess(&mut self, _center: Vec3, radius: f32) {
        self.scene_radius = radius;
    }

    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample<'_>> {
        let wi = self.towards_light;
        Some(LightLiSample {
            l: Radiance::Value(self.radiance.sample(lambda) * self.scale),
            wi,
            pdf: 1.0,
            p_light: ctx.p + wi * (2.0 * self.scene_radius),
            p_light_error: Vec3::ZERO,
            n_light: Vec3::ZERO,
        })
    }

    pub fn phi(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.radiance.sample(lambda) * (self.scale * PI * self.scene_radius * self.scene_radius)
    }
}
