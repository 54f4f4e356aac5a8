//! Projection light: a point light that projects an image through a
//! perspective frustum, like a slide projector.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `filename` | string | — (required) | RGB image (EXR, PFM, PNG) to project |
//! | `fov` | float | 90 | field of view in degrees, across the image's shorter side |
//! | `scale` | float | 1 | scale |
//! | `power` | float | — | if given: total power in W (photometric normalisation) |
//!
//! The light sits at the origin of its coordinate system and projects
//! along +z. The image's top row goes towards the light's +y (pbrt-v4
//! flips y so that images, stored top row first, come out upright) and its
//! first column towards −x. Each pixel's RGB becomes pbrt-v4's RGB
//! illuminant spectrum in the image's colour space (linear sRGB: the
//! image readers here carry no colour space, and that is pbrt-v4's default).

use super::{LightLiSample, LightSampleContext};
use crate::spectrum::color_space::RgbColorSpace;
use crate::spectrum::{DenselySampled, RgbSigmoidPolynomial, SampledSpectrum, SampledWavelengths};
use glam::{Mat3, Vec2, Vec3};
use std::sync::Arc;

/// pbrt-v4's near plane: directions closer than this to the light's
/// xy-plane (light-space z below it) receive nothing.
pub const HITHER: f32 = 1e-3;

pub struct ProjectionLight {
    pub position: Vec3,
    /// Unit projection axis (the light's +z) in render space.
    pub axis: Vec3,
    /// Render-space direction → the light's frame, y already flipped.
    pub light_from_render: Mat3,
    /// Linear RGB, row-major, top row first.
    pub rgb: Vec<[f32; 3]>,
    /// Each pixel's illuminant spectrum (scale and sigmoid polynomial),
    /// computed once.
    texels: Vec<(f32, RgbSigmoidPolynomial)>,
    illuminant: Arc<DenselySampled>,
    pub width: usize,
    pub height: usize,
    pub color_space: &'static RgbColorSpace,
    pub scale: f32,
    pub frustum: Frustum,
}

/// The screen window of a perspective projection: a direction (x, y, z)
/// with z > 0 lands at (x, y) / (z · tan(fov / 2)), and the window spans
/// ±1 across the image's shorter side and ±aspect across the longer.
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    pub tan_half_fov: f32,
    pub screen_min: Vec2,
    pub screen_max: Vec2,
}

impl Frustum {
    pub fn new(fov_degrees: f32, width: usize, height: usize) -> Frustum {
        let aspect = width as f32 / height as f32;
        let half = if aspect > 1.0 {
            Vec2::new(aspect, 1.0)
        } else {
            Vec2::new(1.0, 1.0 / aspect)
        };
        Frustum {
            tan_half_fov: (fov_degrees.to_radians() / 2.0).tan(),
            screen_min: -half,
            screen_max: half,
        }
    }

    /// Area of the window on the plane z = 1 (pbrt-v4's `A`).
    pub fn plane_area(&self) -> f32 {
        let size = self.screen_max - self.screen_min;
        size.x * size.y * self.tan_half_fov * self.tan_half_fov
    }

    /// The light-space direction's point of [0, 1]² in the image (top
    /// left at the origin), or `None` outside the frustum.
    pub fn image_uv(&self, w: Vec3) -> Option<Vec2> {
        if w.z < HITHER {
            return None;
        }
        let screen = Vec2::new(w.x, w.y) / (w.z * self.tan_half_fov);
        let inside = screen.cmpge(self.screen_min).all() && screen.cmple(self.screen_max).all();
        inside.then(|| (screen - self.screen_min) / (self.screen_max - self.screen_min))
    }

    /// The unit light-space direction through a point of [0, 1]² of the
    /// image (the inverse of [`Frustum::image_uv`]).
    pub fn direction(&self, uv: Vec2) -> Vec3 {
        let screen = self.screen_min + uv * (self.screen_max - self.screen_min);
        Vec3::new(
            screen.x * self.tan_half_fov,
            screen.y * self.tan_half_fov,
            1.0,
        )
        .normalize()
    }

    /// Solid angle per unit of image area at `uv`, over the whole image's
    /// plane area: dω/dA = cos³θ on the plane z = 1.
    pub fn cos3(&self, uv: Vec2) -> f32 {
        self.direction(uv).z.powi(3)
    }
}

impl ProjectionLight {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        position: Vec3,
        axis: Vec3,
        light_from_render: Mat3,
        rgb: Vec<[f32; 3]>,
        width: usize,
        height: usize,
        color_space: &'static RgbColorSpace,
        scale: f32,
        fov_degrees: f32,
    ) -> ProjectionLight {
        let texels = rgb
            .iter()
            .map(|&c| color_space.illuminant_coefficients(Vec3::from(c)))
            .collect();
        ProjectionLight {
            position,
            axis,
            light_from_render,
            rgb,
            texels,
            illuminant: Arc::clone(color_space.illuminant_densely_sampled()),
            width,
            height,
            color_space,
            scale,
            frustum: Frustum::new(fov_degrees, width, height),
        }
    }

    /// The image's pixel at `uv` (pbrt-v4's nearest lookup, clamped).
    fn pixel_index(&self, uv: Vec2) -> usize {
        let x = ((uv.x * self.width as f32) as i64).clamp(0, self.width as i64 - 1) as usize;
        let y = ((uv.y * self.height as f32) as i64).clamp(0, self.height as i64 - 1) as usize;
        y * self.width + x
    }

    fn texel_spectrum(&self, i: usize, lambda: &SampledWavelengths) -> SampledSpectrum {
        let Some((scale, polynomial)) = self.texels.get(i) else {
            return SampledSpectrum::ZERO;
        };
        SampledSpectrum::from_fn(|k| {
            let l = lambda.lambda[k];
            scale * polynomial.eval(l) * self.illuminant.eval(l)
        })
    }

    /// Intensity towards the render-space direction `w` (need not be unit).
    pub fn intensity_towards(&self, w: Vec3, lambda: &SampledWavelengths) -> SampledSpectrum {
        match self.frustum.image_uv(self.light_from_render * w) {
            Some(uv) => self.texel_spectrum(self.pixel_index(uv), lambda) * self.scale,
            None => SampledSpectrum::ZERO,
        }
    }

    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample<'_>> {
        super::sample_point_source(self.position, ctx, |w| self.intensity_towards(w, lambda))
    }

    /// Pixel centres in image order, with their uv.
    fn pixel_centres(&self) -> impl Iterator<Item = (usize, Vec2)> + '_ {
        (0..self.height).flat_map(move |y| {
            (0..self.width).map(move |x| {
                let uv = Vec2::new(
                    (x as f32 + 0.5) / self.width as f32,
                    (y as f32 + 0.5) / self.height as f32,
                );
                (y * self.width + x, uv)
            })
        })
    }

    /// Total power: ∫ I dω over the frustum, as the sum over pixels of
    /// I × cos³θ × (plane area / pixel count) (pbrt-v4's `Phi`).
    pub fn phi(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        let mut sum = SampledSpectrum::ZERO;
        for (i, uv) in self.pixel_centres() {
            sum += self.texel_spectrum(i, lambda) * self.frustum.cos3(uv);
        }
        sum * (self.scale * self.frustum.plane_area() / self.rgb.len().max(1) as f32)
    }

    /// The photometric k_e of pbrt-v4's `power` normalisation: the same
    /// sum as [`ProjectionLight::phi`] with each pixel's luminance (of its
    /// unclamped RGB) in place of its spectrum.
    pub fn luminance_power(&self) -> f32 {
        let luminance = self.color_space.luminance_vector();
        let mut sum = 0.0f32;
        for (i, uv) in self.pixel_centres() {
            let dwda = self.frustum.cos3(uv);
            for (c, value) in self.rgb[i].iter().enumerate() {
                sum += value * luminance[c] * dwda;
            }
        }
        self.frustum.plane_area() * sum / self.rgb.len().max(1) as f32
    }

    /// pbrt-v4's `ProjectionLight::Bounds` φ: scale × the image's mean of
    /// each pixel's largest channel (no solid-angle factor, as there).
    pub fn bounds_phi(&self) -> f32 {
        let sum: f32 = self.rgb.iter().map(|c| c[0].max(c[1]).max(c[2])).sum();
        self.scale * sum / self.rgb.len().max(1) as f32
    }

    /// Cosine of the angle between the axis and the frustum's corner.
    pub fn cos_total_width(&self) -> f32 {
        self.frustum.direction(Vec2::ONE).z
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_description::ColorSpaceName;
    use crate::spectrum::color_space::{self, SpectrumKind};

    fn context(p: Vec3) -> LightSampleContext {
        LightSampleContext {
            p,
            p_error: Vec3::ZERO,
            n: Vec3::ZERO,
            ns: Vec3::ZERO,
            time: 0.0,
        }
    }

    /// 4×2 pixels, each a different colour, fov 90°: the screen spans
    /// x ∈ [−2, 2], y ∈ [−1, 1] at unit distance. Identity transform, so
    /// light_from_render is pbrt-v4's y flip.
    fn light(scale: f32) -> ProjectionLight {
        let rgb: Vec<[f32; 3]> = (0..8)
            .map(|i| [0.1 + i as f32 * 0.1, 0.5, 1.0 - i as f32 * 0.1])
            .collect();
        ProjectionLight::new(
            Vec3::ZERO,
            Vec3::Z,
            Mat3::from_diagonal(Vec3::new(1.0, -1.0, 1.0)),
            rgb,
            4,
            2,
            color_space::get(ColorSpaceName::Srgb),
            scale,
            90.0,
        )
    }

    /// A point of the plane z = 2 that lies on the ray through pixel
    /// (x, y)'s centre gets I(pixel)/d²: the top row is at +y, the first
    /// column at −x.
    #[test]
    fn plane_radiance_matches_the_projected_pixel() {
        let light = light(1.7);
        let lambda = SampledWavelengths::sample_visible(0.4);
        let cs = color_space::get(ColorSpaceName::Srgb);
        for (x, y) in [(0, 0), (3, 0), (1, 1), (2, 1)] {
            let screen = Vec2::new(-2.0 + x as f32 + 0.5, 1.0 - (y as f32 + 0.5));
            // Off-centre within the pixel too: nearest lookup.
            let p = Vec3::new(screen.x + 0.3, screen.y - 0.2, 1.0) * 2.0;
            let sample = light.sample_li(&context(p), &lambda).unwrap();
            let rgb = light.rgb[y * 4 + x];
            let expected = cs
                .rgb_to_spectrum(Vec3::from(rgb), SpectrumKind::Illuminant)
                .sample(&lambda)
                * (1.7 / p.length_squared());
            let got = sample.l.value(&lambda);
            for k in 0..4 {
                assert!(
                    (got[k] / expected[k] - 1.0).abs() < 1e-4,
                    "pixel ({x}, {y}): {} vs {}",
                    got[k],
                    expected[k]
                );
            }
            assert!((sample.wi + p.normalize()).length() < 1e-6);
        }
    }

    #[test]
    fn nothing_outside_the_frustum() {
        let light = light(1.0);
        let lambda = SampledWavelengths::sample_visible(0.4);
        for p in [
            Vec3::new(4.2, 0.0, 2.0),  // beyond x = 2 at unit distance
            Vec3::new(0.0, -2.1, 2.0), // below y = −1
            Vec3::new(0.0, 0.0, -1.0), // behind
            Vec3::new(1.0, 0.0, 0.0),  // in the light's plane
        ] {
            assert!(light.sample_li(&context(p), &lambda).is_none(), "{p}");
        }
        assert!(light
            .sample_li(&context(Vec3::new(3.9, 1.9, 2.0)), &lambda)
            .is_some());
    }

    /// A white image's power is scale × the frustum's solid angle ×
    /// the illuminant: Ω = 4 asin(ab / √((1 + a²)(1 + b²))) for a window
    /// of half-widths a, b at unit distance.
    #[test]
    fn power_matches_the_frustum_solid_angle() {
        let (w, h) = (300, 150);
        let cs = color_space::get(ColorSpaceName::Srgb);
        let light = ProjectionLight::new(
            Vec3::ZERO,
            Vec3::Z,
            Mat3::IDENTITY,
            vec![[1.0; 3]; w * h],
            w,
            h,
            cs,
            1.0,
            60.0,
        );
        let t = (30f32).to_radians().tan();
        let (a, b) = (2.0 * t, t);
        let omega = 4.0 * (a * b / ((1.0 + a * a) * (1.0 + b * b)).sqrt()).asin();
        // Luminance of white is 1: the normalisation's k_e is Ω.
        assert!(
            (light.luminance_power() / omega - 1.0).abs() < 1e-4,
            "{} vs {omega}",
            light.luminance_power()
        );
        let lambda = SampledWavelengths::sample_visible(0.6);
        let white = cs
            .rgb_to_spectrum(Vec3::ONE, SpectrumKind::Illuminant)
            .sample(&lambda);
        let phi = light.phi(&lambda);
        for k in 0..4 {
            assert!((phi[k] / (white[k] * omega) - 1.0).abs() < 1e-4);
        }
    }
}
