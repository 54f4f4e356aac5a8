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

use super::{LightLiSample, LightSampleContext};
use crate::math::equal_area::{
    equal_area_sphere_to_square, equal_area_square_to_sphere, wrap_equal_area_square,
};
use crate::samplers::distribution::{Domain2D, PiecewiseConstant2D};
use crate::spectrum::color_space::{RgbColorSpace, SpectrumKind};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{IVec2, Mat4, Vec2, Vec3};
use std::f32::consts::PI;

pub struct ImageInfiniteLight {
    pub render_from_light: Mat4,
    pub light_from_render: Mat4,
    /// Linear RGB, row-major, top row first; width = height = resolution.
    pub rgb: Vec<[f32; 3]>,
    pub resolution: i32,
    pub color_space: &'static RgbColorSpace,
    pub scale: f32,
    pub distribution: PiecewiseConstant2D,
    pub compensated: PiecewiseConstant2D,
    pub scene_center: Vec3,
    pub scene_radius: f32,
}

impl ImageInfiniteLight {
    pub fn new(
        render_from_light: Mat4,
        rgb: Vec<[f32; 3]>,
        resolution: i32,
        color_space: &'static RgbColorSpace,
        scale: f32,
    ) -> Self {
        let n = resolution as usize;
        let d: Vec<f32> = rgb.iter().map(|c| (c[0] + c[1] + c[2]) / 3.0).collect();
        let domain = Domain2D::UNIT;
        let distribution = PiecewiseConstant2D::new(&d, n, n, domain);
        let average = d.iter().map(|&v| v as f64).sum::<f64>() / d.len().max(1) as f64;
        let mut comp: Vec<f32> = d.iter().map(|&v| (v - average as f32).max(0.0)).collect();
        if comp.iter().all(|&v| v == 0.0) {
            comp.fill(1.0);
        }
        let compensated = PiecewiseConstant2D::new(&comp, n, n, domain);
        ImageInfiniteLight {
            light_from_render: render_from_light.inverse(),
            render_from_light,
            rgb,
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
        let r = self.resolution;
        let p = IVec2::new((uv.x * r as f32) as i32, (uv.y * r as f32) as i32);
        let p = wrap_equal_area_square(p, IVec2::splat(r));
        let c = self.rgb[(p.y * r + p.x) as usize];
        let rgb = Vec3::new(c[0].max(0.0), c[1].max(0.0), c[2].max(0.0));
        self.color_space
            .rgb_to_spectrum(rgb, SpectrumKind::Illuminant)
            .sample(lambda)
            * self.scale
    }

    pub fn le(&self, direction: Vec3, lambda: &SampledWavelengths) -> SampledSpectrum {
        let w = self
            .light_from_render
            .transform_vector3(direction)
            .normalize();
        self.image_le(equal_area_sphere_to_square(w), lambda)
    }

    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
        allow_incomplete_pdf: bool,
    ) -> Option<LightLiSample> {
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
            l: self.image_le(uv, lambda),
            wi,
            pdf: map_pdf / (4.0 * PI),
            p_light: ctx.p + wi * (2.0 * self.scene_radius),
            p_light_error: Vec3::ZERO,
            n_light: Vec3::ZERO,
        })
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
        for c in &self.rgb {
            let rgb = Vec3::new(c[0].max(0.0), c[1].max(0.0), c[2].max(0.0));
            sum += self
                .color_space
                .rgb_to_spectrum(rgb, SpectrumKind::Illuminant)
                .sample(lambda);
        }
        sum * (4.0 * PI * PI * self.scene_radius * self.scene_radius * self.scale
            / self.rgb.len().max(1) as f32)
    }
}
