//! The `marble` texture (spectrum): veins along y perturbed by noise.
//! With p the texture-space point times `scale`, t = ½ + ½ sin(p.y +
//! variation · fbm(p)) picks a colour on a fixed spline of greys and a
//! blue-grey vein colour (pbrt-v4's nine control points, taken four at a
//! time as cubic Bézier segments), times 1.5, as an sRGB reflectance.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `octaves` | integer | 8 | the most octaves of the perturbing fbm |
//! | `roughness` | float | 0.5 | ω of the fbm |
//! | `scale` | float | 1 | frequency of the veins in texture space |
//! | `variation` | float | 0.2 | strength of the perturbation |
//!
//! pbrt-v4 has it as a spectrum texture only.

use super::fbm::octave_parameters;
use super::mapping_3d::TextureMapping3D;
use super::noise::fbm;
use super::TextureEvalContext;
use crate::error::{scene_error, Result};
use crate::scene_description::ColorSpaceName;
use crate::scene_description::ParamSet;
use crate::spectrum::color_space::{self, SpectrumKind};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Mat4, Vec3};
use pbrt_parser::Location;

#[derive(Clone, Debug)]
pub struct MarbleTexture {
    pub mapping: TextureMapping3D,
    pub octaves: i32,
    pub omega: f32,
    pub scale: f32,
    pub variation: f32,
}

/// The marble's colour spline's control points (linear sRGB).
const MARBLE_COLORS: [Vec3; 9] = [
    Vec3::new(0.58, 0.58, 0.6),
    Vec3::new(0.58, 0.58, 0.6),
    Vec3::new(0.58, 0.58, 0.6),
    Vec3::new(0.5, 0.5, 0.5),
    Vec3::new(0.6, 0.59, 0.58),
    Vec3::new(0.58, 0.58, 0.6),
    Vec3::new(0.58, 0.58, 0.6),
    Vec3::new(0.2, 0.2, 0.33),
    Vec3::new(0.58, 0.58, 0.6),
];

/// The cubic Bézier curve with control points `p` at `u` ∈ [0, 1], by
/// repeated linear interpolation (de Casteljau).
pub fn cubic_bezier(p: &[Vec3], u: f32) -> Vec3 {
    let a = [p[0].lerp(p[1], u), p[1].lerp(p[2], u), p[2].lerp(p[3], u)];
    let b = [a[0].lerp(a[1], u), a[1].lerp(a[2], u)];
    b[0].lerp(b[1], u)
}

impl MarbleTexture {
    pub fn create(
        params: &ParamSet,
        render_from_texture: Mat4,
        location: &Location,
    ) -> Result<Self> {
        let (octaves, omega) = octave_parameters(params, location)?;
        let scale = params.float("scale", 1.0)? as f32;
        let variation = params.float("variation", 0.2)? as f32;
        if !scale.is_finite() || !variation.is_finite() {
            return scene_error("\"scale\" and \"variation\" must be finite", location);
        }
        Ok(MarbleTexture {
            mapping: TextureMapping3D::new(render_from_texture),
            octaves,
            omega,
            scale,
            variation,
        })
    }

    /// The marble's linear sRGB colour at `ctx`.
    pub fn evaluate_rgb(&self, ctx: &TextureEvalContext) -> Vec3 {
        let c = self.mapping.map(ctx);
        let p = c.p * self.scale;
        let marble = p.y
            + self.variation
                * fbm(
                    p,
                    self.scale * c.dpdx,
                    self.scale * c.dpdy,
                    self.omega,
                    self.octaves,
                );
        let t = 0.5 + 0.5 * marble.sin();
        // Six segments, each starting at the next control point.
        let segments = MARBLE_COLORS.len() - 3;
        let first = ((t * segments as f32).floor() as usize).min(segments - 1);
        let u = t * segments as f32 - first as f32;
        1.5 * cubic_bezier(&MARBLE_COLORS[first..first + 4], u)
    }

    pub fn evaluate(
        &self,
        ctx: &TextureEvalContext,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        // As pbrt-v4: an sRGB reflectance whatever the scene's colour space.
        color_space::get(ColorSpaceName::Srgb)
            .rgb_to_spectrum(self.evaluate_rgb(ctx), SpectrumKind::Albedo)
            .sample(lambda)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::textures::noise::noise;

    /// The Bernstein form (1−u)³p₀ + 3(1−u)²u p₁ + 3(1−u)u² p₂ + u³p₃.
    fn bernstein(p: &[Vec3], u: f32) -> Vec3 {
        let v = 1.0 - u;
        v * v * v * p[0] + 3.0 * v * v * u * p[1] + 3.0 * v * u * u * p[2] + u * u * u * p[3]
    }

    #[test]
    fn de_casteljau_matches_bernstein() {
        let p = [Vec3::X, Vec3::Y * 2.0, Vec3::new(0.5, -1.0, 3.0), Vec3::ONE];
        for u in [0.0, 0.2, 0.5, 0.9, 1.0] {
            assert!((cubic_bezier(&p, u) - bernstein(&p, u)).length() < 1e-6);
        }
    }

    /// The marble's colour by pbrt-v4's formula, evaluated from scratch.
    #[test]
    fn marble_colour_by_its_formula() {
        let texture = MarbleTexture {
            mapping: TextureMapping3D::new(Mat4::IDENTITY),
            octaves: 8,
            omega: 0.5,
            scale: 2.5,
            variation: 0.2,
        };
        for p in [
            Vec3::new(0.3, 1.7, -2.2),
            Vec3::new(0.1, 0.05, 0.7),
            Vec3::new(-3.0, 0.4, 1.0),
        ] {
            let q = 2.5 * p;
            let fbm: f32 = (0..8)
                .map(|i| 0.5f32.powi(i) * noise(1.99f32.powi(i) * q))
                .sum();
            let t = 0.5 + 0.5 * (q.y + 0.2 * fbm).sin();
            let first = ((t * 6.0).floor() as usize).min(5);
            let expected = 1.5 * bernstein(&MARBLE_COLORS[first..], t * 6.0 - first as f32);
            let ctx = TextureEvalContext {
                p,
                ..Default::default()
            };
            let rgb = texture.evaluate_rgb(&ctx);
            assert!((rgb - expected).length() < 1e-5, "{rgb} vs {expected}");
            // Within the colours' convex hull, times 1.5: a valid reflectance.
            assert!(rgb.max_element() <= 0.9 + 1e-6 && rgb.min_element() >= 0.3 - 1e-6);
        }
    }
}
