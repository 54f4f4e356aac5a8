//! Participating media (pbrt-v4's `MakeNamedMedium`): what a ray meets
//! between surfaces. Each medium gives its scattering and absorption
//! coefficients, emission and Henyey–Greenstein asymmetry at a point
//! ([`Medium::sample_point`]) and a majorant, an upper bound of σt along a
//! ray ([`Medium::majorant`]), for the null-scattering estimators of the
//! `volpath` integrator ([`sample_t_maj`]).
//!
//! | type          | file              | notes |
//! |---------------|-------------------|-------|
//! | `homogeneous` | `homogeneous.rs`  | constant coefficients everywhere |
//! | `uniformgrid` | `grid.rs`         | a density (and emission) grid in a box |
//! | `rgbgrid`     | `rgb_grid.rs`     | RGB σa, σs and Le grids in a box |
//! | `cloud`       | `cloud.rs`        | procedural noise cloud in a box |
//! | `nanovdb`     | `nanovdb.rs`      | density (and temperature) grids of a NanoVDB file (`nanovdb_file.rs` reads it) |
//!
//! Grid media use one majorant for their whole box (the largest σt in
//! it), not pbrt-v4's 16³ majorant grid: unbiased either way, only the
//! number of null collisions differs.
//!
//! Coefficients are per unit of render-space distance; the medium's
//! transform (the CTM at `MakeNamedMedium`) places a grid's box.

mod cloud;
mod cuboid;
mod grid;
mod homogeneous;
mod nanovdb;
pub(crate) mod nanovdb_file;
mod presets;
mod rgb_grid;
mod sampled_grid;

pub use cloud::CloudMedium;
pub use grid::GridMedium;
pub use homogeneous::HomogeneousMedium;
pub use nanovdb::NanoVdbMedium;
pub use rgb_grid::RgbGridMedium;

use crate::error::{scene_error, Result};
use crate::math::pcg32::Pcg32;
use crate::math::{Ray, Transform};
use crate::scene_description::Entity;
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::parameter::spectrum_param;
use crate::spectrum::{BlackbodySpectrum, SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec3;
use std::path::Path;

/// The medium's coefficients at a point, at the path's wavelengths.
#[derive(Clone, Copy, Debug)]
pub struct MediumProperties {
    /// Absorption coefficient σa.
    pub sigma_a: SampledSpectrum,
    /// Scattering coefficient σs.
    pub sigma_s: SampledSpectrum,
    /// Emitted radiance Le (multiplied by σa where it is gathered).
    pub le: SampledSpectrum,
    /// The Henyey–Greenstein asymmetry g.
    pub g: f32,
}

impl MediumProperties {
    /// The coefficients of a medium whose σa and σs spectra are scaled by
    /// `density` at this point (every medium here is one), emitting `le`.
    pub(crate) fn at_density(
        sigma_a: &Spectrum,
        sigma_s: &Spectrum,
        density: f32,
        le: SampledSpectrum,
        g: f32,
        lambda: &SampledWavelengths,
    ) -> Self {
        MediumProperties {
            sigma_a: sigma_a.sample(lambda) * density,
            sigma_s: sigma_s.sample(lambda) * density,
            le,
            g,
        }
    }
}

/// σt = σa + σs of the unscaled spectra at `lambda` (a majorant's base).
pub(crate) fn extinction(
    sigma_a: &Spectrum,
    sigma_s: &Spectrum,
    lambda: &SampledWavelengths,
) -> SampledSpectrum {
    sigma_a.sample(lambda) + sigma_s.sample(lambda)
}

/// A stretch `t_min..t_max` of a ray (unit direction) where σt ≤ `sigma_maj`.
#[derive(Clone, Copy, Debug)]
pub struct MajorantSegment {
    pub t_min: f32,
    pub t_max: f32,
    pub sigma_maj: SampledSpectrum,
}

/// The media on the two sides of a surface, by index into the built
/// scene's media (`None`: vacuum). Only surfaces where the two differ
/// carry one; elsewhere a ray keeps its medium. u16 keeps primitives small.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MediumInterface {
    pub inside: Option<u16>,
    pub outside: Option<u16>,
}

impl MediumInterface {
    /// The medium a ray leaving the surface (geometric normal `n`) in
    /// direction `w` enters: the outside one on the normal's side.
    pub fn towards(&self, w: Vec3, n: Vec3) -> Option<u16> {
        if w.dot(n) > 0.0 {
            self.outside
        } else {
            self.inside
        }
    }
}

/// A participating medium, by type.
#[derive(Clone, Debug)]
pub enum Medium {
    Homogeneous(HomogeneousMedium),
    Grid(GridMedium),
    RgbGrid(RgbGridMedium),
    Cloud(CloudMedium),
    NanoVdb(NanoVdbMedium),
}

impl Medium {
    /// The medium of a `MakeNamedMedium` directive (`"string type"` in
    /// `entity.kind`), placed by `render_from_medium`.
    pub fn create(entity: &Entity, render_from_medium: &Transform, base: &Path) -> Result<Self> {
        let loc = &entity.location.0;
        // The type is `entity.kind` (read from this parameter).
        entity.params.string("type", "")?;
        let medium = match entity.kind.as_str() {
            "homogeneous" => Medium::Homogeneous(HomogeneousMedium::create(entity, base)?),
            "uniformgrid" => Medium::Grid(GridMedium::create(entity, render_from_medium, base)?),
            "rgbgrid" => Medium::RgbGrid(RgbGridMedium::create(entity, render_from_medium, base)?),
            "cloud" => Medium::Cloud(CloudMedium::create(entity, render_from_medium, base)?),
            "nanovdb" => Medium::NanoVdb(NanoVdbMedium::create(entity, render_from_medium, base)?),
            other => return scene_error(format!("unknown medium type \"{other}\""), loc),
        };
        entity
            .params
            .report_unused(|| format!("medium \"{}\"", entity.kind))?;
        Ok(medium)
    }

    /// Whether the medium emits anywhere.
    pub fn is_emissive(&self) -> bool {
        match self {
            Medium::Homogeneous(m) => m.is_emissive(),
            Medium::Grid(m) => m.is_emissive(),
            Medium::RgbGrid(m) => m.is_emissive(),
            Medium::Cloud(_) => false,
            Medium::NanoVdb(m) => m.is_emissive(),
        }
    }

    /// The coefficients at render-space point `p`.
    pub fn sample_point(&self, p: Vec3, lambda: &SampledWavelengths) -> MediumProperties {
        match self {
            Medium::Homogeneous(m) => m.sample_point(lambda),
            Medium::Grid(m) => m.sample_point(p, lambda),
            Medium::RgbGrid(m) => m.sample_point(p, lambda),
            Medium::Cloud(m) => m.sample_point(p, lambda),
            Medium::NanoVdb(m) => m.sample_point(p, lambda),
        }
    }

    /// Where along `ray` (unit direction), before `t_max`, the medium may
    /// interact, with its majorant there; `None` where it cannot.
    pub fn majorant(
        &self,
        ray: &Ray,
        t_max: f32,
        lambda: &SampledWavelengths,
    ) -> Option<MajorantSegment> {
        match self {
            Medium::Homogeneous(m) => Some(m.majorant(t_max, lambda)),
            Medium::Grid(m) => m.majorant(ray, t_max, lambda),
            Medium::RgbGrid(m) => m.majorant(ray, t_max, lambda),
            Medium::Cloud(m) => m.majorant(ray, t_max, lambda),
            Medium::NanoVdb(m) => m.majorant(ray, t_max, lambda),
        }
    }
}

/// Below this many kelvin a blackbody's visible emission is negligible and
/// pbrt-v4's grid and nanovdb media emit nothing.
const MIN_GLOW_KELVIN: f32 = 100.0;

/// A medium's blackbody emission at `kelvin` times `scale` (nothing at or
/// below [`MIN_GLOW_KELVIN`]).
fn blackbody_glow(kelvin: f32, scale: f32, lambda: &SampledWavelengths) -> SampledSpectrum {
    if kelvin > MIN_GLOW_KELVIN {
        BlackbodySpectrum::new(kelvin).sample(lambda) * scale
    } else {
        SampledSpectrum::ZERO
    }
}

/// Reads σa and σs (`"sigma_a"`, `"sigma_s"`, each 1 by default, as
/// unbounded spectra) and the `"scale"` that multiplies both.
fn scattering_coefficients(entity: &Entity, base: &Path) -> Result<(Spectrum, Spectrum, f32)> {
    let p = &entity.params;
    let read = |name: &str| -> Result<Spectrum> {
        Ok(
            spectrum_param(p, name, SpectrumKind::Unbounded, entity.color_space, base)?
                .unwrap_or(Spectrum::Constant(1.0)),
        )
    };
    Ok((
        read("sigma_a")?,
        read("sigma_s")?,
        p.float("scale", 1.0)? as f32,
    ))
}

/// What an emission spectrum is divided by (its luminance, as pbrt-v4
/// does for lights and media); 1 for a black one.
fn emission_norm(le: &Spectrum) -> f32 {
    let y = crate::spectrum::spectrum_to_photometric(le);
    if y > 0.0 {
        y
    } else {
        1.0
    }
}

/// Samples the majorant transmittance along `ray` up to `t_max` (pbrt-v4's
/// `SampleT_maj`): tentative collisions are drawn with density
/// σmaj e^(−σmaj t) for the first wavelength, and `callback` gets each
/// collision's generator (for its own numbers), point, properties, σmaj
/// and the majorant transmittance
/// since the previous one; it returns whether to go on. Returns the
/// majorant transmittance from the last collision to the end (1 when the
/// callback stopped).
#[allow(clippy::too_many_arguments)]
pub fn sample_t_maj(
    medium: &Medium,
    ray: &Ray,
    t_max: f32,
    mut u: f32,
    rng: &mut Pcg32,
    lambda: &SampledWavelengths,
    mut callback: impl FnMut(
        &mut Pcg32,
        Vec3,
        &MediumProperties,
        SampledSpectrum,
        SampledSpectrum,
    ) -> bool,
) -> SampledSpectrum {
    let len = ray.direction.length();
    if len == 0.0 {
        return SampledSpectrum::ONE;
    }
    // Distances along a unit direction, so σ is per unit length.
    let t_max = t_max * len;
    let ray = Ray::new(ray.origin, ray.direction / len, ray.time);
    let Some(seg) = medium.majorant(&ray, t_max, lambda) else {
        return SampledSpectrum::ONE;
    };
    let mut t_maj = SampledSpectrum::ONE;
    let sigma_maj = seg.sigma_maj;
    let transmittance = |dt: f32| {
        // An infinite stretch with σ = 0 transmits everything (not NaN).
        let dt = dt.min(f32::MAX);
        (sigma_maj * -dt).exp()
    };
    if sigma_maj.0[0] == 0.0 {
        return transmittance(seg.t_max - seg.t_min);
    }
    let mut t_min = seg.t_min;
    loop {
        let t = t_min + sample_exponential(u, sigma_maj.0[0]);
        u = rng.uniform_f32();
        if t < seg.t_max {
            t_maj *= transmittance(t - t_min);
            let p = ray.at(t);
            let mp = medium.sample_point(p, lambda);
            if !callback(rng, p, &mp, sigma_maj, t_maj) {
                return SampledSpectrum::ONE;
            }
            t_maj = SampledSpectrum::ONE;
            t_min = t;
        } else {
            return t_maj * transmittance(seg.t_max - t_min);
        }
    }
}

/// A distance drawn with density a e^(−a x).
pub fn sample_exponential(u: f32, a: f32) -> f32 {
    -(1.0 - u).ln() / a
}

#[cfg(test)]
mod tests;
