//! The `fbm` texture (float): fractional Brownian motion of Perlin noise
//! at the texture-space point (see [`super::noise::fbm`]), a value of
//! about ±1 that varies smoothly at every scale down to the pixel.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `octaves` | integer | 8 | the most octaves summed |
//! | `roughness` | float | 0.5 | ω, each octave's amplitude relative to the previous one |
//!
//! The point is the one in texture space (the coordinate system of the
//! `Texture` directive, see [`super::mapping_3d`]).

use super::mapping_3d::TextureMapping3D;
use super::noise::fbm;
use super::TextureEvalContext;
use crate::error::{scene_error, Result};
use crate::scene_description::ParamSet;
use glam::Mat4;
use pbrt_parser::Location;

#[derive(Clone, Debug)]
pub struct FbmTexture {
    pub mapping: TextureMapping3D,
    pub octaves: i32,
    pub omega: f32,
}

/// The `octaves` and `roughness` parameters the noise textures share.
pub fn octave_parameters(params: &ParamSet, location: &Location) -> Result<(i32, f32)> {
    let octaves = params.int("octaves", 8)?;
    // More than ~30 octaves have features below f32 precision; a limit
    // keeps a mistyped count from making every lookup slow.
    if !(0..=64).contains(&octaves) {
        return scene_error(
            format!("\"octaves\" must be between 0 and 64, not {octaves}"),
            location,
        );
    }
    let omega = params.float("roughness", 0.5)? as f32;
    if !omega.is_finite() {
        return scene_error("\"roughness\" must be finite", location);
    }
    Ok((octaves, omega))
}

impl FbmTexture {
    pub fn create(
        params: &ParamSet,
        render_from_texture: Mat4,
        location: &Location,
    ) -> Result<Self> {
        let (octaves, omega) = octave_parameters(params, location)?;
        Ok(FbmTexture {
            mapping: TextureMapping3D::new(render_from_texture),
            octaves,
            omega,
        })
    }

    pub fn evaluate(&self, ctx: &TextureEvalContext) -> f32 {
        let c = self.mapping.map(ctx);
        fbm(c.p, c.dpdx, c.dpdy, self.omega, self.octaves)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::textures::noise::noise;
    use glam::Vec3;

    /// Without a footprint, fbm is Σ ωⁱ noise(1.99ⁱ p) over all octaves,
    /// at the texture-space point (here render space scaled by 3).
    #[test]
    fn fbm_is_the_octave_sum_in_texture_space() {
        let render_from_texture = Mat4::from_scale(Vec3::splat(3.0));
        let texture = FbmTexture {
            mapping: TextureMapping3D::new(render_from_texture),
            octaves: 5,
            omega: 0.6,
        };
        for p in [Vec3::new(0.3, 1.7, -2.2), Vec3::new(10.1, -4.4, 0.05)] {
            let q = p / 3.0;
            let expected: f32 = (0..5)
                .map(|i| 0.6f32.powi(i) * noise(1.99f32.powi(i) * q))
                .sum();
            let ctx = TextureEvalContext {
                p,
                ..Default::default()
            };
            assert!((texture.evaluate(&ctx) - expected).abs() < 1e-5);
        }
    }
}
