//! Point light.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `I` | spectrum | colour space illuminant | radiant intensity (spectral shape) |
//! | `scale` | float | 1 | scale |
//! | `power` | float | — | if given: total power in W (photometric normalisation) |
//! | `from` | point3 | 0 0 0 | position |

use super::{LightLiSample, LightSampleContext, Radiance};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec3;
use std::f32::consts::PI;

pub struct PointLight {
    pub position: Vec3,
    pub intensity: Spectrum,
    pub scale: f32,
}

impl PointLight {
    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample<'_>> {
        let d = self.position - ctx.p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let l = self.intensity.sample(lambda) * (self.scale / dist2);
        Some(LightLiSample {
            l: Radiance::Value(l),
            wi: d / dist2.sqrt(),
            pdf: 1.0,
            p_light: self.position,
            p_light_error: Vec3::ZERO,
            n_light: Vec3::ZERO,
        })
    }

    pub fn phi(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.intensity.sample(lambda) * (4.0 * PI * self.scale)
    }
}
