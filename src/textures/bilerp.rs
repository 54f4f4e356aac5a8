//! The `bilerp` texture: bilinear interpolation of four values over the 2D
//! texture coordinates, v00 at (s, t) = (0, 0), v10 at (1, 0), v01 at
//! (0, 1), v11 at (1, 1) (extrapolated outside the unit square, as pbrt-v4).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `v00` | float/spectrum | 0 | value at (0, 0) |
//! | `v01` | float/spectrum | 1 | value at (0, 1) |
//! | `v10` | float/spectrum | 0 | value at (1, 0) |
//! | `v11` | float/spectrum | 1 | value at (1, 1) |
//! | `mapping` … | | `uv` | the 2D mapping (see [`super::mapping`]) |
//!
//! The values are constants, not textures.

use super::mapping::TextureMapping2D;
use super::TextureEvalContext;
use crate::error::Result;
use crate::scene_description::ParamSet;
use glam::Mat4;
use pbrt_parser::Location;

/// Four corner values (f32 for a float texture, a spectrum for a spectrum
/// one) and the mapping that places them.
#[derive(Clone, Debug)]
pub struct BilerpTexture<V> {
    pub mapping: TextureMapping2D,
    /// v00, v10, v01, v11: in the order of [`BilerpTexture::weights`].
    pub values: [V; 4],
}

impl<V> BilerpTexture<V> {
    /// The texture with corner values read by `value(name, default)`.
    pub fn create(
        params: &ParamSet,
        render_from_texture: Mat4,
        location: &Location,
        mut value: impl FnMut(&str, f32) -> Result<V>,
    ) -> Result<Self> {
        let mapping = TextureMapping2D::create(params, render_from_texture, location)?;
        Ok(BilerpTexture {
            mapping,
            values: [
                value("v00", 0.0)?,
                value("v10", 0.0)?,
                value("v01", 1.0)?,
                value("v11", 1.0)?,
            ],
        })
    }

    /// The weights of v00, v10, v01, v11 at `ctx`.
    pub fn weights(&self, ctx: &TextureEvalContext) -> [f32; 4] {
        let st = self.mapping.map(ctx).st;
        let (s, t) = (st.x, st.y);
        [(1.0 - s) * (1.0 - t), s * (1.0 - t), (1.0 - s) * t, s * t]
    }
}

impl BilerpTexture<f32> {
    pub fn evaluate(&self, ctx: &TextureEvalContext) -> f32 {
        self.weights(ctx)
            .iter()
            .zip(&self.values)
            .map(|(w, v)| w * v)
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn texture(values: [f32; 4]) -> BilerpTexture<f32> {
        BilerpTexture {
            mapping: TextureMapping2D::Uv {
                scale: Vec2::ONE,
                delta: Vec2::ZERO,
            },
            values,
        }
    }

    fn at(u: f32, v: f32) -> TextureEvalContext {
        TextureEvalContext {
            uv: Vec2::new(u, v),
            ..Default::default()
        }
    }

    #[test]
    fn corners_centre_and_edges() {
        // v00 = 1, v10 = 2, v01 = 3, v11 = 4.
        let t = texture([1.0, 2.0, 3.0, 4.0]);
        assert_eq!(t.evaluate(&at(0.0, 0.0)), 1.0);
        assert_eq!(t.evaluate(&at(1.0, 0.0)), 2.0);
        assert_eq!(t.evaluate(&at(0.0, 1.0)), 3.0);
        assert_eq!(t.evaluate(&at(1.0, 1.0)), 4.0);
        assert_eq!(t.evaluate(&at(0.5, 0.5)), 2.5);
        assert_eq!(t.evaluate(&at(0.25, 0.0)), 1.25);
        assert_eq!(t.evaluate(&at(0.0, 0.75)), 2.5);
        // pbrt-v4's defaults (0, 0, 1, 1) make a ramp in t.
        let ramp = texture([0.0, 0.0, 1.0, 1.0]);
        assert_eq!(ramp.evaluate(&at(0.9, 0.3)), 0.3);
    }
}
