//! The `directionmix` texture: a blend of two textures by the surface's
//! orientation, |n · dir|·tex1 + (1 − |n · dir|)·tex2 with n the geometric
//! normal: `tex1` where the surface faces along `dir` (either way), `tex2`
//! where it lies parallel to it.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `tex1` | float/spectrum texture | 0 | the value facing `dir` |
//! | `tex2` | float/spectrum texture | 1 | the value edge-on to `dir` |
//! | `dir` | vector3 | (0, 1, 0) | the direction, in the coordinate system of the `Texture` directive |

use super::{TextureEvalContext, TextureOf, TextureParams};
use crate::error::{scene_error, Result};
use crate::spectrum::color_space::SpectrumKind;
use glam::{Mat4, Vec3};
use pbrt_parser::Location;

#[derive(Clone, Debug)]
pub struct DirectionMixTexture<T> {
    pub tex1: Box<T>,
    pub tex2: Box<T>,
    /// Unit direction, in render space.
    pub dir: Vec3,
}

impl<T: TextureOf> DirectionMixTexture<T> {
    pub fn create(
        tp: &TextureParams,
        render_from_texture: Mat4,
        kind: SpectrumKind,
        location: &Location,
    ) -> Result<Self> {
        let dir = match tp.params.vector3s("dir")?.as_slice() {
            [] => Vec3::Y,
            [v] => v.as_vec3(),
            _ => return scene_error("\"dir\": expected one vector", location),
        };
        let dir = render_from_texture
            .transform_vector3(dir)
            .normalize_or_zero();
        if dir == Vec3::ZERO {
            return scene_error("\"dir\" must be a non-zero vector", location);
        }
        Ok(DirectionMixTexture {
            tex1: Box::new(T::parameter(tp, "tex1", 0.0, kind)?),
            tex2: Box::new(T::parameter(tp, "tex2", 1.0, kind)?),
            dir,
        })
    }

    /// The weights of `tex1` and `tex2` at `ctx`.
    pub fn weights(&self, ctx: &TextureEvalContext) -> (f32, f32) {
        let amount = ctx.n.dot(self.dir).abs();
        (amount, 1.0 - amount)
    }
}
