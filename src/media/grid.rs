//! pbrt-v4's `uniformgrid` medium: σa and σs scaled by a density grid
//! over a box, with emission scaled by a grid or given by temperature.
//!
//! | parameter | type | default | meaning |
//! |-----------|------|---------|---------|
//! | `density` | float[nx·ny·nz] | required | density at the cell centres (x fastest) |
//! | `nx`, `ny`, `nz` | integer | 1 | grid resolution |
//! | `p0`, `p1` | point3 | (0,0,0), (1,1,1) | the box, in the medium's space |
//! | `sigma_a`, `sigma_s` | spectrum | 1 | coefficients at density 1 |
//! | `scale`   | float | 1 | multiplies σa and σs |
//! | `g`       | float | 0 | Henyey–Greenstein asymmetry |
//! | `Le`      | spectrum | 0 | emitted radiance (illuminant spectrum, divided by its luminance) |
//! | `Lescale` | float or float[nx·ny·nz] | 1 | multiplies `Le` (or the blackbody) |
//! | `temperature` | float[nx·ny·nz] | none | blackbody emission instead of `Le` |
//! | `temperatureoffset`, `temperaturescale` | float | 0, 1 | kelvin = (T − offset)·scale |
//! | `temperaturecutoff` | float | 0 | no emission at or below this many kelvin |

use super::cuboid::Cuboid;
use super::sampled_grid::SampledGrid;
use super::{
    blackbody_glow, extinction, scattering_coefficients, MajorantSegment, MediumProperties,
};
use crate::error::{scene_error, Result};
use crate::math::{Ray, Transform};
use crate::scene_description::Entity;
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::parameter::spectrum_param;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{DVec3, Vec3};
use std::path::Path;

#[derive(Clone, Debug)]
pub struct GridMedium {
    cuboid: Cuboid,
    sigma_a: Spectrum,
    sigma_s: Spectrum,
    scale: f32,
    g: f32,
    density: SampledGrid<f32>,
    max_density: f32,
    emission: Option<Emission>,
}

#[derive(Clone, Debug)]
enum EmissionSource {
    /// The spectrum and its normalisation.
    Spectrum(Spectrum, f32),
    Temperature {
        grid: SampledGrid<f32>,
        offset: f32,
        scale: f32,
        cutoff: f32,
    },
}

#[derive(Clone, Debug)]
struct Emission {
    source: EmissionSource,
    le_scale: SampledGrid<f32>,
}

/// A per-cell float array of `n` values, or `None` when absent.
fn grid_values(
    entity: &Entity,
    name: &str,
    n: usize,
    dims: [i32; 3],
) -> Result<Option<SampledGrid<f32>>> {
    let Some(p) = entity.params.find(name, &[pbrt_parser::ParamType::Float])? else {
        return Ok(None);
    };
    let v = p.numbers();
    let [nx, ny, nz] = dims;
    if v.len() == n {
        Ok(Some(SampledGrid::new(
            v.iter().map(|&x| x as f32).collect(),
            nx,
            ny,
            nz,
        )))
    } else if v.len() == 1 && name == "Lescale" {
        Ok(Some(SampledGrid::new(vec![v[0] as f32; n], nx, ny, nz)))
    } else {
        scene_error(
            format!("\"{name}\" has {} values; expected nx·ny·nz = {n}", v.len()),
            &p.location,
        )
    }
}

/// The grid resolution (`nx`, `ny`, `nz`) and its cell count.
pub(super) fn resolution(entity: &Entity) -> Result<([i32; 3], usize)> {
    let p = &entity.params;
    let dims = [p.int("nx", 1)?, p.int("ny", 1)?, p.int("nz", 1)?];
    if dims.iter().any(|&d| d < 1) {
        return scene_error(
            format!(
                "grid resolution {} × {} × {} must be at least 1 in each axis",
                dims[0], dims[1], dims[2]
            ),
            &entity.location.0,
        );
    }
    let n = dims
        .iter()
        .try_fold(1usize, |acc, &d| acc.checked_mul(d as usize))
        .filter(|&n| n <= i32::MAX as usize);
    match n {
        Some(n) => Ok((dims, n)),
        None => scene_error("grid resolution is too large", &entity.location.0),
    }
}

/// The box `p0`–`p1`.
pub(super) fn cuboid(entity: &Entity, render_from_medium: &Transform) -> Result<Cuboid> {
    let p = &entity.params;
    let p0 = p.point3("p0", DVec3::ZERO)?;
    let p1 = p.point3("p1", DVec3::ONE)?;
    Ok(Cuboid::new(render_from_medium, p0, p1))
}

impl GridMedium {
    pub fn create(entity: &Entity, render_from_medium: &Transform, base: &Path) -> Result<Self> {
        let p = &entity.params;
        let loc = &entity.location.0;
        let (dims, n) = resolution(entity)?;
        let Some(density) = grid_values(entity, "density", n, dims)? else {
            return scene_error("medium \"uniformgrid\" needs \"float density\" values", loc);
        };
        if density
            .values()
            .iter()
            .any(|d| !(d.is_finite() && *d >= 0.0))
        {
            return scene_error("\"density\" values must be finite and ≥ 0", loc);
        }
        let max_density = density.values().iter().fold(0.0f32, |m, &d| m.max(d));
        let (sigma_a, sigma_s, scale) = scattering_coefficients(entity, base)?;
        let le = spectrum_param(p, "Le", SpectrumKind::Illuminant, entity.color_space, base)?;
        let temperature = grid_values(entity, "temperature", n, dims)?;
        let t_offset = p.float("temperatureoffset", 0.0)? as f32;
        let t_scale = p.float("temperaturescale", 1.0)? as f32;
        let t_cutoff = p.float("temperaturecutoff", 0.0)? as f32;
        let le_scale = grid_values(entity, "Lescale", n, dims)?
            .unwrap_or_else(|| SampledGrid::new(vec![1.0; n], dims[0], dims[1], dims[2]));
        let source = match (le, temperature) {
            (Some(_), Some(_)) => {
                return scene_error("both \"Le\" and \"temperature\" were given", loc);
            }
            (Some(le), None) if le.max_value() > 0.0 => {
                // Divided by its luminance, as a light's.
                let norm = super::emission_norm(&le);
                Some(EmissionSource::Spectrum(le, 1.0 / norm))
            }
            (None, Some(grid)) => Some(EmissionSource::Temperature {
                grid,
                offset: t_offset,
                scale: t_scale,
                cutoff: t_cutoff,
            }),
            _ => None,
        };
        let emission = source
            .filter(|_| le_scale.values().iter().any(|&s| s > 0.0))
            .map(|source| Emission { source, le_scale });
        Ok(GridMedium {
            cuboid: cuboid(entity, render_from_medium)?,
            sigma_a,
            sigma_s,
            scale,
            g: p.float("g", 0.0)? as f32,
            density,
            max_density,
            emission,
        })
    }

    pub fn is_emissive(&self) -> bool {
        self.emission.is_some()
    }

    pub fn sample_point(&self, p: Vec3, lambda: &SampledWavelengths) -> MediumProperties {
        let u = self.cuboid.unit(p);
        let d = self.density.lookup(u, |v| v) * self.scale;
        let le = match &self.emission {
            None => SampledSpectrum::ZERO,
            Some(e) => {
                let s = e.le_scale.lookup(u, |v| v);
                if s <= 0.0 {
                    SampledSpectrum::ZERO
                } else {
                    match &e.source {
                        EmissionSource::Spectrum(le, norm) => le.sample(lambda) * (s * norm),
                        EmissionSource::Temperature {
                            grid,
                            offset,
                            scale,
                            cutoff,
                        } => {
                            let t = (grid.lookup(u, |v| v) - offset) * scale;
                            if t > *cutoff {
                                blackbody_glow(t, s, lambda)
                            } else {
                                SampledSpectrum::ZERO
                            }
                        }
                    }
                }
            }
        };
        MediumProperties::at_density(&self.sigma_a, &self.sigma_s, d, le, self.g, lambda)
    }

    pub fn majorant(
        &self,
        ray: &Ray,
        t_max: f32,
        lambda: &SampledWavelengths,
    ) -> Option<MajorantSegment> {
        self.cuboid.majorant(ray, t_max, || {
            extinction(&self.sigma_a, &self.sigma_s, lambda) * (self.scale * self.max_density)
        })
    }
}
