//! pbrt-v4's `homogeneous` medium: the same coefficients everywhere.
//!
//! | parameter | type | default | meaning |
//! |-----------|------|---------|---------|
//! | `sigma_a` | spectrum | 1 | absorption coefficient σa (per unit length) |
//! | `sigma_s` | spectrum | 1 | scattering coefficient σs |
//! | `scale`   | float | 1 | multiplies σa and σs |
//! | `preset`  | string | none | named measured σa, σs (replace the two above) |
//! | `g`       | float | 0 | Henyey–Greenstein asymmetry |
//! | `Le`      | spectrum | 0 | emitted radiance (an illuminant spectrum, divided by its luminance as a light's) |
//! | `Lescale` | float | 1 | multiplies `Le` |

use super::{
    emission_norm, extinction, scattering_coefficients, MajorantSegment, MediumProperties,
};
use crate::error::{scene_error, Result};
use crate::scene_description::Entity;
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::parameter::spectrum_param;
use crate::spectrum::{SampledWavelengths, Spectrum};
use std::path::Path;

#[derive(Clone, Debug)]
pub struct HomogeneousMedium {
    sigma_a: Spectrum,
    sigma_s: Spectrum,
    /// `scale`, applied to σa and σs.
    scale: f32,
    le: Spectrum,
    le_scale: f32,
    g: f32,
}

impl HomogeneousMedium {
    pub fn create(entity: &Entity, base: &Path) -> Result<Self> {
        let p = &entity.params;
        let (mut sigma_a, mut sigma_s, scale) = scattering_coefficients(entity, base)?;
        if let Some((name, loc)) = p.string_at("preset")? {
            match super::presets::named_coefficients(&name) {
                Some((a, s)) => (sigma_a, sigma_s) = (a, s),
                None => return scene_error(format!("unknown medium preset \"{name}\""), &loc),
            }
        }
        let le = spectrum_param(p, "Le", SpectrumKind::Illuminant, entity.color_space, base)?
            .unwrap_or(Spectrum::Constant(0.0));
        // As a light's: `Le` is divided by its luminance, so that the
        // `Lescale` says how bright it is.
        let le_scale = p.float("Lescale", 1.0)? as f32 / emission_norm(&le);
        Ok(HomogeneousMedium {
            sigma_a,
            sigma_s,
            scale,
            le,
            le_scale,
            g: p.float("g", 0.0)? as f32,
        })
    }

    pub fn is_emissive(&self) -> bool {
        self.le_scale * self.le.max_value() > 0.0
    }

    pub fn sample_point(&self, lambda: &SampledWavelengths) -> MediumProperties {
        MediumProperties::at_density(
            &self.sigma_a,
            &self.sigma_s,
            self.scale,
            self.le.sample(lambda) * self.le_scale,
            self.g,
            lambda,
        )
    }

    /// σt itself, along the whole ray.
    pub fn majorant(&self, t_max: f32, lambda: &SampledWavelengths) -> MajorantSegment {
        MajorantSegment {
            t_min: 0.0,
            t_max,
            sigma_maj: extinction(&self.sigma_a, &self.sigma_s, lambda) * self.scale,
        }
    }
}
