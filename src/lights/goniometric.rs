//! Goniometric light: a point light whose intensity varies with direction
//! as a greyscale image in pbrt-v4's equal-area octahedral mapping of the
//! sphere describes.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `I` | spectrum | colour space illuminant | spectral shape of the intensity |
//! | `scale` | float | 1 | scale |
//! | `power` | float | — | if given: total power in W (photometric normalisation) |
//! | `filename` | string | — (required) | square image (EXR, PFM, PNG) of the relative intensity: its `Y` channel, or the average of R, G and B |
//!
//! The light sits at the origin of its coordinate system. pbrt-v4 swaps
//! the light's y and z axes before looking directions up, so the image's
//! "poles" (its centre and corners) lie along the light's ±y axis: a
//! goniometric diagram's vertical axis is y in pbrt's convention.

use super::{LightLiSample, LightSampleContext};
use crate::math::equal_area::equal_area_sphere_to_square;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Mat3, Vec3};
use std::f32::consts::PI;

pub struct GoniometricLight {
    pub position: Vec3,
    /// Render-space direction → the image's frame (the light's inverse
    /// transform followed by pbrt-v4's y/z swap).
    pub image_from_render: Mat3,
    pub intensity: Spectrum,
    pub scale: f32,
    /// Relative intensity, row-major, top row first; `resolution`².
    pub image: Vec<f32>,
    pub resolution: usize,
}

impl GoniometricLight {
    /// The image's mean: its integral over the sphere is 4π × this, since
    /// every pixel of the equal-area map covers the same solid angle.
    pub fn image_mean(&self) -> f32 {
        let sum: f64 = self.image.iter().map(|&v| v as f64).sum();
        (sum / self.image.len().max(1) as f64) as f32
    }

    /// Intensity towards the render-space direction `w` (need not be unit).
    pub fn intensity_towards(&self, w: Vec3, lambda: &SampledWavelengths) -> SampledSpectrum {
        let Some(w_image) = (self.image_from_render * w).try_normalize() else {
            return SampledSpectrum::ZERO;
        };
        let uv = equal_area_sphere_to_square(w_image);
        // pbrt-v4's nearest lookup with clamped coordinates.
        let n = self.resolution as i64;
        let x = ((uv.x * n as f32) as i64).clamp(0, n - 1) as usize;
        let y = ((uv.y * n as f32) as i64).clamp(0, n - 1) as usize;
        let value = self
            .image
            .get(y * self.resolution + x)
            .copied()
            .unwrap_or(0.0);
        self.intensity.sample(lambda) * (self.scale * value)
    }

    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample<'_>> {
        super::sample_point_source(self.position, ctx, |w| self.intensity_towards(w, lambda))
    }

    pub fn phi(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.intensity.sample(lambda) * (self.scale * 4.0 * PI * self.image_mean())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::PointLight;
    use crate::math::equal_area::equal_area_square_to_sphere;
    use glam::Vec2;

    fn context(p: Vec3) -> LightSampleContext {
        LightSampleContext {
            p,
            p_error: Vec3::ZERO,
            n: Vec3::ZERO,
            ns: Vec3::ZERO,
            time: 0.0,
        }
    }

    /// The light-space direction at the centre of pixel (x, y).
    fn pixel_direction(x: usize, y: usize, n: usize) -> Vec3 {
        equal_area_square_to_sphere(Vec2::new(
            (x as f32 + 0.5) / n as f32,
            (y as f32 + 0.5) / n as f32,
        ))
    }

    #[test]
    fn equal_area_mapping_round_trips_pixel_centres() {
        let n = 64;
        for y in 0..n {
            for x in 0..n {
                let uv = Vec2::new((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32);
                let w = equal_area_square_to_sphere(uv);
                assert!((w.length() - 1.0).abs() < 1e-5);
                let back = equal_area_sphere_to_square(w);
                assert!(
                    (back - uv).abs().max_element() < 1e-4,
                    "{uv} → {w} → {back}"
                );
            }
        }
    }

    /// Uniformly distributed directions land equally often in every pixel:
    /// each covers 4π / n² steradians.
    #[test]
    fn equal_area_pixels_have_equal_solid_angle() {
        let n = 8;
        let mut counts = vec![0u32; n * n];
        let samples = 640_000;
        // A deterministic uniform sphere sampling (Fibonacci lattice).
        let golden = (1.0 + 5f64.sqrt()) / 2.0;
        for i in 0..samples {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / samples as f64;
            let phi = 2.0 * std::f64::consts::PI * (i as f64 / golden).fract();
            let r = (1.0 - z * z).sqrt();
            let w = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
            let uv = equal_area_sphere_to_square(w);
            let x = ((uv.x * n as f32) as usize).min(n - 1);
            let y = ((uv.y * n as f32) as usize).min(n - 1);
            counts[y * n + x] += 1;
        }
        let expected = samples as f32 / (n * n) as f32;
        for (i, &c) in counts.iter().enumerate() {
            assert!(
                (c as f32 / expected - 1.0).abs() < 0.01,
                "pixel {i}: {c} vs {expected}"
            );
        }
    }

    fn light(
        image: Vec<f32>,
        resolution: usize,
        position: Vec3,
        rotation: Mat3,
    ) -> GoniometricLight {
        // As create.rs does: the light's inverse rotation, then the y/z swap.
        let swap = Mat3::from_cols(Vec3::X, Vec3::Z, Vec3::Y);
        GoniometricLight {
            position,
            image_from_render: swap * rotation.transpose(),
            intensity: Spectrum::Constant(2.5),
            scale: 1.5,
            image,
            resolution,
        }
    }

    /// A constant image makes it a point light of intensity I × scale ×
    /// the image's value, whatever the transform.
    #[test]
    fn constant_image_equals_point_light() {
        let rotation = Mat3::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let position = Vec3::new(0.5, -1.0, 2.0);
        let gonio = light(vec![0.8; 32 * 32], 32, position, rotation);
        let point = PointLight {
            position,
            intensity: Spectrum::Constant(2.5),
            scale: 1.5 * 0.8,
        };
        let lambda = SampledWavelengths::sample_visible(0.3);
        for i in 0..200 {
            let t = i as f32 * 0.37;
            let p = Vec3::new(t.sin() * 3.0, (t * 1.7).cos() * 2.0, (t * 0.3).sin() * 4.0);
            let a = gonio
                .sample_li(&context(p), &lambda)
                .map(|s| (s.l.value(&lambda), s.wi));
            let b = point
                .sample_li(&context(p), &lambda)
                .map(|s| (s.l.value(&lambda), s.wi));
            let ((la, wa), (lb, wb)) = (a.unwrap(), b.unwrap());
            assert!((wa - wb).length() < 1e-6);
            for k in 0..4 {
                assert!((la[k] / lb[k] - 1.0).abs() < 1e-5, "{} vs {}", la[k], lb[k]);
            }
        }
        let (pa, pb) = (gonio.phi(&lambda), point.phi(&lambda));
        assert!((pa[0] / pb[0] - 1.0).abs() < 1e-5);
    }

    /// The image's y axis (after pbrt-v4's swap, the light's z) is where
    /// the map's centre is: a single bright pixel at a known direction is
    /// seen from that direction only.
    #[test]
    fn pixels_map_to_their_directions_through_the_swap() {
        let n = 16;
        let (px, py) = (11, 3);
        let mut image = vec![0.0; n * n];
        image[py * n + px] = 1.0;
        let gonio = light(image, n, Vec3::ZERO, Mat3::IDENTITY);
        let lambda = SampledWavelengths::sample_visible(0.5);
        let d_image = pixel_direction(px, py, n);
        // Image frame (x, y, z) is the light's (x, z, y).
        let d_light = Vec3::new(d_image.x, d_image.z, d_image.y);
        let lit = gonio.sample_li(&context(d_light * 3.0), &lambda).unwrap();
        assert!((lit.l.value(&lambda)[0] - 2.5 * 1.5 / 9.0).abs() < 1e-5);
        // The unswapped direction falls in another pixel.
        assert!(gonio.sample_li(&context(d_image * 3.0), &lambda).is_none());
    }

    /// φ = ∫ I dω: an image holding |cos θ| about the map's pole axis
    /// integrates to 2π.
    #[test]
    fn power_is_the_integral_of_intensity() {
        let n = 256;
        let image: Vec<f32> = (0..n * n)
            .map(|i| pixel_direction(i % n, i / n, n).z.abs())
            .collect();
        let mut gonio = light(image, n, Vec3::ZERO, Mat3::IDENTITY);
        gonio.scale = 1.0;
        let lambda = SampledWavelengths::sample_visible(0.5);
        let phi = gonio.phi(&lambda)[0] / 2.5;
        assert!((phi / (2.0 * PI) - 1.0).abs() < 1e-3, "{phi}");
    }
}
