//! Infinitely distant light from an environment image (`infinite` with
//! `filename`), in pbrt-v4's equal-area octahedral parameterisation.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `filename` | string | — | square RGB image (EXR, PFM, PNG) in equal-area octahedral mapping |
//! | `scale` | float | 1 | scale |
//! | `illuminance` | float | — | not supported yet with an image |
//!
//! Directions are sampled from the image's luminance; when the BSDF is also
//! sampled (MIS), from the *compensated* distribution (luminance minus its
//! average, clamped at 0), which leaves the dim parts to BSDF sampling
//! (pbrt-v4's approach).

use super::{LightLiSample, LightSampleContext, Radiance};
use crate::math::equal_area::{
    equal_area_sphere_to_square, equal_area_square_to_sphere, wrap_equal_area_square,
};
use crate::samplers::distribution::{Domain2D, PiecewiseConstant2D};
use crate::spectrum::color_space::RgbColorSpace;
use crate::spectrum::{DenselySampled, RgbSigmoidPolynomial, SampledSpectrum, SampledWavelengths};
use glam::{IVec2, Mat4, Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::Arc;

pub struct ImageInfiniteLight {
    pub render_from_light: Mat4,
    pub light_from_render: Mat4,
    /// Each texel's illuminant spectrum (row-major, top row first; width =
    /// height = resolution), all the light keeps of its image's RGB (scale and sigmoid polynomial of
    /// [`RgbColorSpace::illuminant_coefficients`]), computed once: a
    /// lookup evaluates it without building a spectrum (whose shared
    /// reference to the illuminant both render threads would count up
    /// and down on every lookup).
    texels: Vec<(f32, RgbSigmoidPolynomial)>,
    /// The colour space's illuminant, which the texels' spectra modulate.
    illuminant: Arc<DenselySampled>,
    pub resolution: i32,
    pub color_space: &'static RgbColorSpace,
    pub scale: f32,
    pub distribution: PiecewiseConstant2D,
    pub compensated: PiecewiseConstant2D,
    pub scene_center: Vec3,
    pub scene_radius: f32,
}

impl ImageInfiniteLight {
    /// The light of an image whose linear RGB is `rgb` (interleaved,
    /// row-major, top row first, `resolution` texels square).
    pub fn new(
        render_from_light: Mat4,
        rgb: &[f32],
        resolution: i32,
        color_space: &'static RgbColorSpace,
        scale: f32,
    ) -> Self {
        let n = resolution as usize;
        let d: Vec<f32> = rgb
            .chunks_exact(3)
            .map(|c| (c[0] + c[1] + c[2]) / 3.0)
            .collect();
        let domain = Domain2D::UNIT;
        let distribution = PiecewiseConstant2D::new(&d, n, n, domain);
        let average = d.iter().map(|&v| v as f64).sum::<f64>() / d.len().max(1) as f64;
        let mut comp = d;
        for v in &mut comp {
            *v = (*v - average as f32).max(0.0);
        }
        if comp.iter().all(|&v| v == 0.0) {
            comp.fill(1.0);
        }
        let compensated = PiecewiseConstant2D::new(&comp, n, n, domain);
        drop(comp);
        let texels = rgb
            .chunks_exact(3)
            .map(|c| color_space.illuminant_coefficients(Vec3::new(c[0], c[1], c[2])))
            .collect();
        ImageInfiniteLight {
            light_from_render: render_from_light.inverse(),
            render_from_light,
            texels,
            illuminant: Arc::clone(color_space.illuminant_densely_sampled()),
            resolution,
            color_space,
            scale,
            distribution,
            compensated,
            scene_center: Vec3::ZERO,
            scene_radius: 0.0,
        }
    }

    pub fn preprocess(&mut self, center: Vec3, radius: f32) {
        self.scene_center = center;
        self.scene_radius = radius;
    }

    /// Radiance of the image at (u, v) (nearest texel, octahedral wrap).
    fn image_le(&self, uv: Vec2, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.texel_le(self.texel_index(uv), lambda)
    }

    /// The texel holding `uv`.
    fn texel_index(&self, uv: Vec2) -> usize {
        let r = self.resolution;
        let p = IVec2::new((uv.x * r as f32) as i32, (uv.y * r as f32) as i32);
        let p = wrap_equal_area_square(p, IVec2::splat(r));
        (p.y * r + p.x) as usize
    }

    /// Starts loading texel `i`.
    pub(super) fn prefetch_texel(&self, i: usize) {
        if let Some(texel) = self.texels.get(i) {
            crate::accel::prefetch(texel);
        }
    }

    /// Radiance of texel `i`: pbrt-v4's RGB illuminant spectrum of its RGB,
    /// times the light's scale.
    pub(super) fn texel_le(&self, i: usize, lambda: &SampledWavelengths) -> SampledSpectrum {
        let (scale, polynomial) = &self.texels[i];
        SampledSpectrum::from_fn(|k| {
            let l = lambda.lambda[k];
            scale * polynomial.eval(l) * self.illuminant.eval(l)
        }) * self.scale
    }

    pub fn le(&self, direction: Vec3, lambda: &SampledWavelengths) -> SampledSpectrum {
        let w = self
            .light_from_render
            .transform_vector3(direction)
            .normalize();
        self.image_le(equal_area_sphere_to_square(w), lambda)
    }

    /// The sample's radiance is its texel, read only if the caller needs it
    /// (see [`Radiance`]).
    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        allow_incomplete_pdf: bool,
    ) -> Option<LightLiSample<'_>> {
        let dist = if allow_incomplete_pdf {
            &self.compensated
        } else {
            &self.distribution
        };
        let (uv, map_pdf) = dist.sample(u);
        if map_pdf == 0.0 {
            return None;
        }
        let wi = self
            .render_from_light
            .transform_vector3(equal_area_square_to_sphere(uv))
            .normalize();
        Some(LightLiSample {
            l: Radiance::Texel(self, self.texel_index(uv) as u32),
            wi,
            pdf: map_pdf / (4.0 * PI),
            p_light: ctx.p + wi * (2.0 * self.scene_radius),
            p_light_error: Vec3::ZERO,
            n_light: Vec3::ZERO,
        })
    }

    /// Starts loading what `sample_li(_, u, allow_incomplete_pdf)` will
    /// read first from its sampling tables.
    #[inline]
    pub fn prefetch_sample(&self, u: Vec2, allow_incomplete_pdf: bool) {
        if allow_incomplete_pdf {
            self.compensated.prefetch(u);
        } else {
            self.distribution.prefetch(u);
        }
    }

    pub fn pdf_li(&self, wi: Vec3, allow_incomplete_pdf: bool) -> f32 {
        let w = self.light_from_render.transform_vector3(wi).normalize();
        let uv = equal_area_sphere_to_square(w);
        let dist = if allow_incomplete_pdf {
            &self.compensated
        } else {
            &self.distribution
        };
        dist.pdf(uv) / (4.0 * PI)
    }

    /// Power: 4π² R² × the image's average radiance (over 4 wavelengths).
    pub fn phi(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        let mut sum = SampledSpectrum::ZERO;
        for i in 0..self.texels.len() {
            sum += self.texel_le(i, lambda);
        }
        sum * (4.0 * PI * PI * self.scene_radius * self.scene_radius
            / self.texels.len().max(1) as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_description::ColorSpaceName;
    use crate::spectrum::color_space::SpectrumKind;

    /// A 16 × 16 environment with smoothly varying colours and one bright
    /// texel, rotated so light space differs from render space.
    /// The test image's RGB.
    fn rgb() -> Vec<[f32; 3]> {
        let n = 16;
        (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f32 / n as f32, (i / n) as f32 / n as f32);
                if i == 37 {
                    [40.0, 30.0, 20.0]
                } else {
                    [0.2 + x, 0.1 + y, 0.3 + x * y]
                }
            })
            .collect()
    }

    fn light() -> ImageInfiniteLight {
        let rotation = Mat4::from_rotation_x(0.7) * Mat4::from_rotation_z(-1.1);
        let space = crate::spectrum::color_space::get(ColorSpaceName::Srgb);
        let mut light = ImageInfiniteLight::new(rotation, rgb().as_flattened(), 16, space, 2.0);
        light.preprocess(Vec3::ZERO, 1.0);
        light
    }

    fn texel_le(
        light: &ImageInfiniteLight,
        i: usize,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        let c = rgb()[i];
        light
            .color_space
            .rgb_to_spectrum(Vec3::from(c), SpectrumKind::Illuminant)
            .sample(lambda)
            * light.scale
    }

    /// Texel centre → direction (render space) → `le` returns that texel:
    /// the equal-area mapping and the light transform round-trip.
    #[test]
    fn every_texel_round_trips_through_its_direction() {
        let light = light();
        let lambda = SampledWavelengths::sample_visible(0.37);
        let n = light.resolution as usize;
        for i in 0..n * n {
            let uv = Vec2::new(
                ((i % n) as f32 + 0.5) / n as f32,
                ((i / n) as f32 + 0.5) / n as f32,
            );
            let d = light
                .render_from_light
                .transform_vector3(equal_area_square_to_sphere(uv));
            let got = light.le(d, &lambda);
            let want = texel_le(&light, i, &lambda);
            for k in 0..4 {
                assert!(
                    (got.0[k] - want.0[k]).abs() <= 1e-5 * want.0[k].max(1.0),
                    "texel {i}"
                );
            }
        }
    }

    /// Sampling directions by the image and dividing by the pdf integrates
    /// the environment: ∫ Le dω = 4π × mean texel radiance (equal-area
    /// texels). `pdf_li` agrees with the sampled pdf, and the compensated
    /// distribution samples only above-average texels.
    #[test]
    fn importance_sampling_integrates_the_environment() {
        let light = light();
        let rgb = rgb();
        let lambda = SampledWavelengths::sample_visible(0.61);
        let n = light.resolution as usize;
        let mean: f32 = (0..n * n)
            .map(|i| texel_le(&light, i, &lambda).0[0])
            .sum::<f32>()
            / (n * n) as f32;
        let expected = 4.0 * PI * mean;
        let ctx = LightSampleContext {
            p: Vec3::ZERO,
            p_error: Vec3::ZERO,
            n: Vec3::ZERO,
            ns: Vec3::ZERO,
            time: 0.0,
        };
        let m = 256;
        let mut sum = 0.0f64;
        for j in 0..m * m {
            // Stratified sample points.
            let u = Vec2::new(
                ((j % m) as f32 + 0.5) / m as f32,
                ((j / m) as f32 + 0.5) / m as f32,
            );
            let s = light.sample_li(&ctx, u, false).expect("a sample");
            let pdf = light.pdf_li(s.wi, false);
            assert!(
                (pdf - s.pdf).abs() <= 1e-3 * s.pdf,
                "pdf {pdf} vs {}",
                s.pdf
            );
            sum += (s.l.value(&lambda).0[0] / s.pdf) as f64;
            if let Some(c) = light.sample_li(&ctx, u, true) {
                let uv =
                    equal_area_sphere_to_square(light.light_from_render.transform_vector3(c.wi));
                let i = (uv.y * n as f32) as usize * n + (uv.x * n as f32) as usize;
                let luminance = rgb[i.min(n * n - 1)].iter().sum::<f32>() / 3.0;
                let average =
                    rgb.iter().map(|c| c.iter().sum::<f32>() / 3.0).sum::<f32>() / (n * n) as f32;
                assert!(
                    luminance >= average * 0.999,
                    "compensated sample in a dim texel"
                );
            }
        }
        let estimate = sum / (m * m) as f64;
        assert!(
            (estimate - expected as f64).abs() < 1e-3 * expected as f64,
            "{estimate} vs {expected}"
        );
    }
}
