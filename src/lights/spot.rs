//! Spot light.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `I` | spectrum | colour space illuminant | intensity |
//! | `scale` | float | 1 | scale |
//! | `power` | float | — | total power (photometric) |
//! | `from`, `to` | point3 | 0 0 0, 0 0 1 | position and aim |
//! | `coneangle` | float | 30 | total cone half-angle in degrees |
//! | `conedeltaangle` | float | 5 | angle of the smooth falloff at the cone's edge |

use super::{LightLiSample, LightSampleContext};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec3;
use std::f32::consts::PI;

pub struct SpotLight {
    pub position: Vec3,
    /// Unit axis of the cone, in render space.
    pub axis: Vec3,
    pub intensity: Spectrum,
    pub scale: f32,
    pub cos_falloff_start: f32,
    pub cos_falloff_end: f32,
}

fn smooth_step(x: f32, a: f32, b: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl SpotLight {
    fn emitted(&self, cos_theta: f32, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.intensity.sample(lambda)
            * (smooth_step(cos_theta, self.cos_falloff_end, self.cos_falloff_start) * self.scale)
    }

    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample<'_>> {
        super::sample_point_source(self.position, ctx, |w| {
            self.emitted(w.dot(self.axis), lambda)
        })
    }

    pub fn phi(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.intensity.sample(lambda)
            * (self.scale
                * 2.0
                * PI
                * ((1.0 - self.cos_falloff_start)
                    + (self.cos_falloff_start - self.cos_falloff_end) / 2.0))
    }
}
