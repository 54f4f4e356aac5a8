//! Diffuse area light: a shape that emits uniformly (`AreaLightSource
//! "diffuse"`), as pbrt-v4's `DiffuseAreaLight`.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `L` | spectrum | colour space illuminant | emitted radiance |
//! | `scale` | float | 1 | scale |
//! | `twosided` | bool | false | emit from both sides |
//! | `power` | float | — | if given: total power in W (photometric) |
//! | `filename` | string | — | RGB image of emitted radiance over the shape's (u, v) (not with `L`) |
//!
//! The shape's own `alpha` (float or float texture) masks the emission as
//! pbrt-v4 does: where alpha a < 1 at a point, the point emits nothing
//! when a hash of the point exceeds a (always when a ≤ 0). A shape whose
//! alpha is the constant 0 is never hit; pbrt-v4 then drops the mask and
//! keeps the light, reached by light sampling alone (its type becomes
//! `DeltaPosition`, so its samples are not weighted against the BSDF's):
//! an invisible emitter.
//!
//! With `filename`, the radiance at (u, v) is the image's bilinearly
//! interpolated RGB at (u, 1 − v) (clamped at the edges) as an RGB
//! illuminant spectrum. The image's colour space is linear sRGB (the image
//! readers carry none; pbrt-v4's default when a file names none).

use super::{LightLiSample, LightSampleContext, Radiance};
use crate::image::{Image, WrapMode};
use crate::math::hash::hash_floats;
use crate::shapes::{Shape, ShapeSampleContext, ShapeStorage};
use crate::spectrum::color_space::{RgbColorSpace, SpectrumKind};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use crate::textures::{FloatTexture, TextureEvalContext};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::Arc;

pub struct DiffuseAreaLight {
    /// The emitting shape.
    pub shape: Shape,
    /// Emitted radiance (without an image).
    pub radiance: Spectrum,
    /// Emitted radiance over (u, v), replacing `radiance`.
    pub image: Option<Arc<EmissionImage>>,
    pub scale: f32,
    pub two_sided: bool,
    pub area: f32,
    /// The shape's alpha, masking the emission (none when opaque, and none
    /// for an invisible emitter).
    pub alpha: Option<Arc<FloatTexture>>,
    /// The shape is never hit (constant alpha 0): reached only by light
    /// sampling.
    pub invisible: bool,
}

/// An area light's RGB emission image, linear.
pub struct EmissionImage {
    /// Linear R, G, B.
    pub image: Image,
    pub color_space: &'static RgbColorSpace,
}

impl EmissionImage {
    /// The RGB at (u, v) (pbrt-v4 flips v so that the image's top row is at
    /// v = 1).
    pub fn rgb(&self, uv: Vec2) -> Vec3 {
        let st = Vec2::new(uv.x, 1.0 - uv.y);
        Vec3::from_array([0, 1, 2].map(|c| self.image.bilerp_channel(st, c, WrapMode::Clamp)))
    }

    /// The mean over pixels of each pixel's spectrum.
    fn mean_spectrum(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        let mut sum = SampledSpectrum::ZERO;
        let data = self.image.data();
        for c in data.chunks_exact(3) {
            sum += self
                .color_space
                .rgb_to_spectrum(Vec3::new(c[0], c[1], c[2]), SpectrumKind::Illuminant)
                .sample(lambda);
        }
        sum / (data.len() / 3).max(1) as f32
    }

    /// The mean of all channel values (pbrt-v4's φ for the light bounds).
    pub fn mean_channel(&self) -> f32 {
        let data = self.image.data();
        data.iter().sum::<f32>() / data.len().max(1) as f32
    }
}

/// The same point, as the shapes' sampling takes it.
fn shape_context(ctx: &LightSampleContext) -> ShapeSampleContext {
    ShapeSampleContext {
        p: ctx.p,
        p_error: ctx.p_error,
        n: ctx.n,
        ns: ctx.ns,
        time: ctx.time,
    }
}

impl DiffuseAreaLight {
    /// Whether alpha masks the emission at `p` (uv `uv`): pbrt-v4's
    /// stochastic test, with a hash of the point alone.
    fn alpha_masked(&self, p: Vec3, uv: Vec2) -> bool {
        let Some(alpha) = &self.alpha else {
            return false;
        };
        // pbrt-v4 evaluates it at an interaction with only p and uv.
        let ctx = TextureEvalContext {
            p,
            uv,
            ..Default::default()
        };
        let a = alpha.evaluate(&ctx);
        if a >= 1.0 {
            return false;
        }
        if a <= 0.0 {
            return true;
        }
        let u = (hash_floats(&[p.x, p.y, p.z]) as u32) as f32 * (1.0 / 4_294_967_296.0);
        u > a
    }

    /// Radiance leaving the surface point `p` (normal `n`, surface
    /// coordinates `uv`) in direction `w`.
    pub fn l(
        &self,
        p: Vec3,
        n: Vec3,
        uv: Vec2,
        w: Vec3,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        if !self.two_sided && n.dot(w) < 0.0 {
            return SampledSpectrum::ZERO;
        }
        if self.alpha_masked(p, uv) {
            return SampledSpectrum::ZERO;
        }
        match &self.image {
            None => self.radiance.sample(lambda) * self.scale,
            Some(image) => {
                image
                    .color_space
                    .rgb_to_spectrum(image.rgb(uv), SpectrumKind::Illuminant)
                    .sample(lambda)
                    * self.scale
            }
        }
    }

    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
        shapes: &ShapeStorage,
    ) -> Option<LightLiSample<'_>> {
        let shape_ctx = shape_context(ctx);
        let ss = self.shape.sample_from(shapes, &shape_ctx, u)?;
        if ss.pdf == 0.0 || (ss.p - ctx.p).length_squared() == 0.0 {
            return None;
        }
        let wi = (ss.p - ctx.p).normalize();
        let l = self.l(ss.p, ss.n, ss.uv, -wi, lambda);
        if l.is_zero() {
            return None;
        }
        Some(LightLiSample {
            l: Radiance::Value(l),
            wi,
            pdf: ss.pdf,
            p_light: ss.p,
            p_light_error: ss.p_error,
            n_light: ss.n,
        })
    }

    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, shapes: &ShapeStorage) -> f32 {
        let shape_ctx = shape_context(ctx);
        self.shape.pdf_from(shapes, &shape_ctx, wi)
    }

    pub fn phi(&self, lambda: &SampledWavelengths, _shapes: &ShapeStorage) -> SampledSpectrum {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        let l = match &self.image {
            None => self.radiance.sample(lambda),
            Some(image) => image.mean_spectrum(lambda),
        };
        l * (PI * sides * self.area * self.scale)
    }

    /// The emission's largest value, as the light bounds take it (pbrt-v4:
    /// the spectrum's maximum, or an image's mean channel value).
    pub fn bounds_radiance(&self) -> f32 {
        match &self.image {
            None => self.radiance.max_value(),
            Some(image) => image.mean_channel(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Transform;
    use crate::scene_description::ColorSpaceName;
    use crate::shapes::mesh::{MeshData, TriangleMesh};
    use crate::shapes::Triangle;
    use crate::spectrum::color_space;
    use crate::textures::bilerp::BilerpTexture;
    use crate::textures::mapping::TextureMapping2D;

    /// A unit square in z = 0 facing +z as two triangles, with uv = (x, y).
    fn square() -> (ShapeStorage, Vec<Shape>) {
        let mut storage = ShapeStorage::default();
        let data = MeshData {
            vertex_indices: vec![0, 1, 2, 0, 2, 3],
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            uvs: vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 1.0),
            ],
            ..Default::default()
        };
        storage
            .triangle_meshes
            .push(TriangleMesh::new(&Transform::IDENTITY, false, data));
        let shapes = (0..2)
            .map(|i| Shape::Triangle(Triangle::new(0, i)))
            .collect();
        (storage, shapes)
    }

    fn light(
        shape: Shape,
        storage: &ShapeStorage,
        alpha: Option<FloatTexture>,
    ) -> DiffuseAreaLight {
        DiffuseAreaLight {
            area: shape.area(storage),
            shape,
            radiance: Spectrum::Constant(2.0),
            image: None,
            scale: 1.5,
            two_sided: false,
            alpha: alpha.map(Arc::new),
            invisible: false,
        }
    }

    fn context(p: Vec3) -> LightSampleContext {
        LightSampleContext {
            p,
            p_error: Vec3::ZERO,
            n: Vec3::ZERO,
            ns: Vec3::ZERO,
            time: 0.0,
        }
    }

    /// With alpha a, the fraction of the light's samples that carry
    /// radiance is a (the hash of the point is uniform), and those carry
    /// the unmasked radiance.
    #[test]
    fn alpha_masks_that_fraction_of_the_emission() {
        let (storage, shapes) = square();
        let lambda = SampledWavelengths::sample_visible(0.3);
        for a in [0.0f32, 0.25, 0.6, 1.0] {
            let light = light(shapes[0].clone(), &storage, Some(FloatTexture::Constant(a)));
            let n = 40_000;
            let mut lit = 0;
            for i in 0..n {
                let u = Vec2::new(
                    (i as f32 + 0.5) / n as f32,
                    ((i * 7919) % n) as f32 / n as f32,
                );
                if let Some(s) =
                    light.sample_li(&context(Vec3::new(0.3, 0.3, 2.0)), u, &lambda, &storage)
                {
                    lit += 1;
                    let l = s.l.value(&lambda);
                    assert!((l[0] - 3.0).abs() < 1e-6, "{}", l[0]);
                }
            }
            let fraction = lit as f32 / n as f32;
            assert!(
                (fraction - a).abs() < 0.01,
                "alpha {a}: {fraction} of the samples lit"
            );
        }
    }

    /// A textured alpha is evaluated at the point's (u, v): alpha = u
    /// masks everything at u = 0 and nothing at u = 1, and half of the
    /// points along a line at u = ½.
    #[test]
    fn alpha_texture_is_evaluated_at_the_point_uv() {
        let (storage, shapes) = square();
        let lambda = SampledWavelengths::sample_visible(0.5);
        let texture = FloatTexture::Bilerp(Box::new(BilerpTexture {
            mapping: TextureMapping2D::Uv {
                scale: Vec2::ONE,
                delta: Vec2::ZERO,
            },
            values: [0.0, 1.0, 0.0, 1.0],
        }));
        let light = light(shapes[0].clone(), &storage, Some(texture));
        let w = Vec3::Z;
        let mut lit_at_half = 0;
        for i in 0..1000 {
            let y = i as f32 / 1000.0;
            let at = |u: f32| light.l(Vec3::new(u, y, 0.0), Vec3::Z, Vec2::new(u, y), w, &lambda);
            assert!(at(0.0).is_zero());
            assert!((at(1.0)[0] - 3.0).abs() < 1e-6);
            lit_at_half += at(0.5).is_nonzero() as u32;
        }
        assert!((450..=550).contains(&lit_at_half), "{lit_at_half}");
    }

    /// The image's pixel at (u, 1 − v), and φ from the mean pixel.
    #[test]
    fn image_emission_reads_the_pixel_at_u_one_minus_v() {
        let (storage, shapes) = square();
        let lambda = SampledWavelengths::sample_visible(0.5);
        let cs = color_space::get(ColorSpaceName::Srgb);
        // Top row (y = 0) red, green; bottom row blue, white.
        let pixels = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
        ];
        let image = Image::new(2, 2, &["R", "G", "B"], pixels.as_flattened().to_vec()).unwrap();
        let mut light = light(shapes[0].clone(), &storage, None);
        light.image = Some(Arc::new(EmissionImage {
            image,
            color_space: cs,
        }));
        let expected = |rgb: [f32; 3]| {
            cs.rgb_to_spectrum(Vec3::from(rgb), SpectrumKind::Illuminant)
                .sample(&lambda)
                * 1.5
        };
        // (u, v) = (¼, ¾) is the top-left pixel's centre: red.
        for (uv, pixel) in [
            (Vec2::new(0.25, 0.75), 0),
            (Vec2::new(0.75, 0.75), 1),
            (Vec2::new(0.25, 0.25), 2),
            (Vec2::new(0.75, 0.25), 3),
        ] {
            let got = light.l(Vec3::ZERO, Vec3::Z, uv, Vec3::Z, &lambda);
            let want = expected(pixels[pixel]);
            for k in 0..4 {
                assert!(
                    (got[k] - want[k]).abs() <= 1e-5 * want[k].abs().max(1.0),
                    "{uv}: {got:?} vs {want:?}"
                );
            }
        }
        // φ: π × area × scale × the mean of the pixels' spectra.
        let phi = light.phi(&lambda, &storage);
        let mut mean = SampledSpectrum::ZERO;
        for p in pixels {
            mean += expected(p) / 1.5;
        }
        let want = mean / 4.0 * (PI * 0.5 * 1.5);
        for k in 0..4 {
            assert!((phi[k] - want[k]).abs() <= 1e-5 * want[k].max(1.0));
        }
        // Six channel values of 1 among twelve.
        assert!((light.bounds_radiance() - 0.5).abs() < 1e-6);
    }
}
