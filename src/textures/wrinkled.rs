//! The `wrinkled` texture (float): turbulence of Perlin noise at the
//! texture-space point (see [`super::noise::turbulence`]), a non-negative
//! value with creases where the noise crosses zero.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `octaves` | integer | 8 | the most octaves summed |
//! | `roughness` | float | 0.5 | ω, each octave's amplitude relative to the previous one |

use super::fbm::octave_parameters;
use super::mapping_3d::TextureMapping3D;
use super::noise::turbulence;
use super::TextureEvalContext;
use crate::error::Result;
use crate::scene_description::ParamSet;
use glam::Mat4;
use pbrt_parser::Location;

#[derive(Clone, Debug)]
pub struct WrinkledTexture {
    pub mapping: TextureMapping3D,
    pub octaves: i32,
    pub omega: f32,
}

impl WrinkledTexture {
    pub fn create(
        params: &ParamSet,
        render_from_texture: Mat4,
        location: &Location,
    ) -> Result<Self> {
        let (octaves, omega) = octave_parameters(params, location)?;
        Ok(WrinkledTexture {
            mapping: TextureMapping3D::new(render_from_texture),
            octaves,
            omega,
        })
    }

    pub fn evaluate(&self, ctx: &TextureEvalContext) -> f32 {
        let c = self.mapping.map(ctx);
        turbulence(c.p, c.dpdx, c.dpdy, self.omega, self.octaves)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::textures::noise::noise;
    use glam::Vec3;

    /// Without a footprint: Σ ωⁱ |noise(1.99ⁱ p)| over the octaves, plus
    /// 0.2 ωⁿ for the partial octave that pbrt-v4 always adds.
    #[test]
    fn wrinkled_is_turbulence_by_its_formula() {
        let texture = WrinkledTexture {
            mapping: TextureMapping3D::new(Mat4::IDENTITY),
            octaves: 8,
            omega: 0.5,
        };
        for p in [Vec3::new(0.3, 1.7, -2.2), Vec3::new(-7.25, 0.5, 3.125)] {
            let sum: f32 = (0..8)
                .map(|i| 0.5f32.powi(i) * noise(1.99f32.powi(i) * p).abs())
                .sum();
            let expected = sum + 0.2 * 0.5f32.powi(8);
            let ctx = TextureEvalContext {
                p,
                ..Default::default()
            };
            let value = texture.evaluate(&ctx);
            assert!((value - expected).abs() < 1e-5, "{value} vs {expected}");
            assert!(value >= 0.0);
        }
    }
}
