//! The `windy` texture (float): waves on water under gusts of wind, the
//! product of a low-frequency "wind strength" |fbm(p/10)| (3 octaves, ω ½)
//! and a "wave height" fbm(p) (6 octaves, ω ½), at the texture-space point.
//! It has no parameters of its own.

use super::mapping_3d::TextureMapping3D;
use super::noise::fbm;
use super::TextureEvalContext;
use glam::Mat4;

#[derive(Clone, Debug)]
pub struct WindyTexture {
    pub mapping: TextureMapping3D,
}

impl WindyTexture {
    pub fn create(render_from_texture: Mat4) -> Self {
        WindyTexture {
            mapping: TextureMapping3D::new(render_from_texture),
        }
    }

    pub fn evaluate(&self, ctx: &TextureEvalContext) -> f32 {
        let c = self.mapping.map(ctx);
        let wind_strength = fbm(0.1 * c.p, 0.1 * c.dpdx, 0.1 * c.dpdy, 0.5, 3);
        let wave_height = fbm(c.p, c.dpdx, c.dpdy, 0.5, 6);
        wind_strength.abs() * wave_height
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::textures::noise::noise;
    use glam::Vec3;

    fn octaves(p: Vec3, count: i32) -> f32 {
        (0..count)
            .map(|i| 0.5f32.powi(i) * noise(1.99f32.powi(i) * p))
            .sum()
    }

    #[test]
    fn windy_is_wind_strength_times_wave_height() {
        let texture = WindyTexture::create(Mat4::IDENTITY);
        for p in [
            Vec3::new(0.3, 1.7, -2.2),
            Vec3::new(12.5, -3.3, 40.0),
            Vec3::new(-0.9, 0.1, 0.45),
        ] {
            let expected = octaves(0.1 * p, 3).abs() * octaves(p, 6);
            let ctx = TextureEvalContext {
                p,
                ..Default::default()
            };
            let value = texture.evaluate(&ctx);
            assert!((value - expected).abs() < 1e-5, "{value} vs {expected}");
        }
    }
}
