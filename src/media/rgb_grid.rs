//! pbrt-v4's `rgbgrid` medium: σa, σs and Le given per cell as RGB, each
//! turned into a spectrum (unbounded for σ, illuminant for Le) and the
//! sampled spectra interpolated trilinearly.
//!
//! | parameter | type | default | meaning |
//! |-----------|------|---------|---------|
//! | `sigma_a` | rgb[nx·ny·nz] | 1 everywhere | absorption per cell (x fastest) |
//! | `sigma_s` | rgb[nx·ny·nz] | 1 everywhere | scattering per cell |
//! | `Le`      | rgb[nx·ny·nz] | none | emitted radiance per cell |
//! | `nx`, `ny`, `nz` | integer | 1 | grid resolution |
//! | `p0`, `p1` | point3 | (0,0,0), (1,1,1) | the box, in the medium's space |
//! | `scale`   | float | 1 | multiplies σa and σs |
//! | `Lescale` | float | 1 | multiplies Le |
//! | `g`       | float | 0 | Henyey–Greenstein asymmetry |
//!
//! One of `sigma_a` and `sigma_s` must be given.

use super::cuboid::Cuboid;
use super::grid::{cuboid, resolution};
use super::sampled_grid::SampledGrid;
use super::{MajorantSegment, MediumProperties};
use crate::error::{scene_error, Result};
use crate::math::{Ray, Transform};
use crate::scene_description::Entity;
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec3;
use pbrt_parser::ParamType;
use std::path::Path;

#[derive(Clone, Debug)]
pub struct RgbGridMedium {
    cuboid: Cuboid,
    /// Indices into `spectra` per cell (a grid of spectra is not `Copy`).
    sigma_a: Option<SampledGrid<u32>>,
    sigma_s: Option<SampledGrid<u32>>,
    le: Option<SampledGrid<u32>>,
    /// The per-cell spectra; index 0 is black (outside the grid).
    spectra: Vec<Spectrum>,
    scale: f32,
    le_scale: f32,
    g: f32,
    /// The largest σa + σs at any wavelength, before `scale`.
    max_sigma_t: f32,
}

impl RgbGridMedium {
    pub fn create(entity: &Entity, render_from_medium: &Transform, _base: &Path) -> Result<Self> {
        let p = &entity.params;
        let (dims, n) = resolution(entity)?;
        let color_space = crate::spectrum::color_space::get(entity.color_space);
        let mut spectra = vec![Spectrum::Constant(0.0)];
        let mut max_of = [0.0f32; 2];
        let read = |name: &str, kind: SpectrumKind, spectra: &mut Vec<Spectrum>| {
            let Some(param) = p.find(name, &[ParamType::Rgb])? else {
                return Ok(None);
            };
            let v = param.numbers();
            if v.len() != 3 * n {
                return scene_error(
                    format!(
                        "\"rgb {name}\" has {} values; expected 3·nx·ny·nz = {}",
                        v.len(),
                        3 * n
                    ),
                    &param.location,
                );
            }
            let mut cells = Vec::with_capacity(n);
            let mut max = 0.0f32;
            for c in v.chunks_exact(3) {
                let rgb = Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
                if !(rgb.is_finite() && rgb.min_element() >= 0.0) {
                    return scene_error(
                        format!("\"rgb {name}\" values must be finite and ≥ 0"),
                        &param.location,
                    );
                }
                let s = color_space.rgb_to_spectrum(rgb, kind);
                max = max.max(s.max_value());
                cells.push(spectra.len() as u32);
                spectra.push(s);
            }
            Ok(Some((
                SampledGrid::new(cells, dims[0], dims[1], dims[2]),
                max,
            )))
        };
        let sigma_a = read("sigma_a", SpectrumKind::Unbounded, &mut spectra)?;
        let sigma_s = read("sigma_s", SpectrumKind::Unbounded, &mut spectra)?;
        let le = read("Le", SpectrumKind::Illuminant, &mut spectra)?;
        if sigma_a.is_none() && sigma_s.is_none() {
            return scene_error(
                "medium \"rgbgrid\" needs \"rgb sigma_a\" or \"rgb sigma_s\" values",
                &entity.location.0,
            );
        }
        for (i, g) in [&sigma_a, &sigma_s].into_iter().enumerate() {
            max_of[i] = g.as_ref().map_or(1.0, |(_, m)| *m);
        }
        Ok(RgbGridMedium {
            cuboid: cuboid(entity, render_from_medium)?,
            sigma_a: sigma_a.map(|(g, _)| g),
            sigma_s: sigma_s.map(|(g, _)| g),
            le: le.map(|(g, _)| g),
            spectra,
            scale: p.float("scale", 1.0)? as f32,
            le_scale: p.float("Lescale", 1.0)? as f32,
            g: p.float("g", 0.0)? as f32,
            max_sigma_t: max_of[0] + max_of[1],
        })
    }

    pub fn is_emissive(&self) -> bool {
        self.le.is_some() && self.le_scale > 0.0
    }

    fn lookup(
        &self,
        grid: &Option<SampledGrid<u32>>,
        u: Vec3,
        lambda: &SampledWavelengths,
        absent: f32,
    ) -> SampledSpectrum {
        match grid {
            Some(g) => g.lookup(u, |i| self.spectra[i as usize].sample(lambda)),
            None => SampledSpectrum::splat(absent),
        }
    }

    pub fn sample_point(&self, p: Vec3, lambda: &SampledWavelengths) -> MediumProperties {
        let u = self.cuboid.unit(p);
        let le = if self.is_emissive() {
            self.lookup(&self.le, u, lambda, 0.0) * self.le_scale
        } else {
            SampledSpectrum::ZERO
        };
        MediumProperties {
            sigma_a: self.lookup(&self.sigma_a, u, lambda, 1.0) * self.scale,
            sigma_s: self.lookup(&self.sigma_s, u, lambda, 1.0) * self.scale,
            le,
            g: self.g,
        }
    }

    pub fn majorant(
        &self,
        ray: &Ray,
        t_max: f32,
        _lambda: &SampledWavelengths,
    ) -> Option<MajorantSegment> {
        self.cuboid.majorant(ray, t_max, || {
            SampledSpectrum::splat(self.max_sigma_t * self.scale)
        })
    }
}
