//! pbrt-v4's `cloud` medium: a procedural cloud in a box, its density
//! from sums of Perlin noise that thin out with height (y, in the
//! medium's space: the box only bounds it).
//!
//! | parameter | type | default | meaning |
//! |-----------|------|---------|---------|
//! | `density` | float | 1 | overall density of the noise |
//! | `wispiness` | float | 1 | how much the lookup point is warped by noise |
//! | `frequency` | float | 5 | noise frequency per unit of the medium's space |
//! | `p0`, `p1` | point3 | (0,0,0), (1,1,1) | the box, in the medium's space |
//! | `sigma_a`, `sigma_s` | spectrum | 1 | coefficients at density 1 |
//! | `scale`   | float | 1 | multiplies σa and σs |
//! | `g`       | float | 0 | Henyey–Greenstein asymmetry |
//!
//! The warp moves the lookup point along the noise's gradient, taken by
//! forward differences as pbrt-v4 does.

use super::cuboid::Cuboid;
use super::grid::cuboid;
use super::{extinction, scattering_coefficients, MajorantSegment, MediumProperties};
use crate::error::Result;
use crate::math::{Ray, Transform};
use crate::scene_description::Entity;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use crate::textures::noise::noise;
use glam::Vec3;
use std::path::Path;

#[derive(Clone, Debug)]
pub struct CloudMedium {
    cuboid: Cuboid,
    sigma_a: Spectrum,
    sigma_s: Spectrum,
    scale: f32,
    g: f32,
    density: f32,
    wispiness: f32,
    frequency: f32,
}

/// The gradient of [`noise`] at `p`, by forward differences 0.01 long
/// (pbrt-v4's step: the warp, and so the cloud's shape, depends on it).
fn noise_gradient(p: Vec3) -> Vec3 {
    const H: f32 = 0.01;
    let n = noise(p);
    let d = |axis: Vec3| (noise(p + H * axis) - n) / H;
    Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z))
}

impl CloudMedium {
    pub fn create(entity: &Entity, render_from_medium: &Transform, base: &Path) -> Result<Self> {
        let p = &entity.params;
        let (sigma_a, sigma_s, scale) = scattering_coefficients(entity, base)?;
        Ok(CloudMedium {
            cuboid: cuboid(entity, render_from_medium)?,
            sigma_a,
            sigma_s,
            scale,
            g: p.float("g", 0.0)? as f32,
            density: p.float("density", 1.0)? as f32,
            wispiness: p.float("wispiness", 1.0)? as f32,
            frequency: p.float("frequency", 5.0)? as f32,
        })
    }

    /// The cloud's density at medium-space `p`, 0…1.
    fn density_at(&self, p: Vec3) -> f32 {
        let mut pp = self.frequency * p;
        if self.wispiness > 0.0 {
            let (mut omega, mut lambda) = (0.05 * self.wispiness, 10.0);
            for _ in 0..2 {
                pp += omega * noise_gradient(lambda * pp);
                omega *= 0.5;
                lambda *= 1.99;
            }
        }
        let mut d = 0.0;
        let (mut omega, mut lambda) = (0.5, 1.0);
        for _ in 0..5 {
            d += omega * noise(lambda * pp);
            omega *= 0.5;
            lambda *= 1.99;
        }
        let d = ((1.0 - p.y) * 4.5 * self.density * d).clamp(0.0, 1.0);
        (d + 2.0 * (0.5 - p.y).max(0.0)).clamp(0.0, 1.0)
    }

    pub fn sample_point(&self, p: Vec3, lambda: &SampledWavelengths) -> MediumProperties {
        // pbrt-v4 evaluates the cloud at the medium-space point itself, not
        // at its place in the box.
        let d = self.density_at(self.cuboid.medium_point(p)) * self.scale;
        MediumProperties::at_density(
            &self.sigma_a,
            &self.sigma_s,
            d,
            SampledSpectrum::ZERO,
            self.g,
            lambda,
        )
    }

    /// The density is at most 1: σt itself bounds the box.
    pub fn majorant(
        &self,
        ray: &Ray,
        t_max: f32,
        lambda: &SampledWavelengths,
    ) -> Option<MajorantSegment> {
        self.cuboid.majorant(ray, t_max, || {
            extinction(&self.sigma_a, &self.sigma_s, lambda) * self.scale
        })
    }
}
