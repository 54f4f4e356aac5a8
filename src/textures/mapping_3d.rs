//! The 3D texture mapping (pbrt-v4's `TextureMapping3D`, whose only kind
//! is `PointTransformMapping`): the point, and its per-pixel differentials,
//! in texture space — the coordinate system in force at the `Texture`
//! directive. Solid textures (`fbm`, `wrinkled`, `windy`, `marble`, the 3D
//! `checkerboard`) read it; it takes no parameters, so scaling or rotating
//! a solid texture is done with transforms before its `Texture` directive.

use super::TextureEvalContext;
use glam::{Mat4, Vec3};

/// A texture-space point and how it moves per pixel in x and y.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TexCoord3D {
    pub p: Vec3,
    pub dpdx: Vec3,
    pub dpdy: Vec3,
}

#[derive(Clone, Debug, PartialEq)]
pub struct TextureMapping3D {
    texture_from_render: Mat4,
}

impl TextureMapping3D {
    /// The mapping for a texture whose `Texture` directive had
    /// `render_from_texture` in force.
    pub fn new(render_from_texture: Mat4) -> Self {
        TextureMapping3D {
            texture_from_render: render_from_texture.inverse(),
        }
    }

    pub fn map(&self, ctx: &TextureEvalContext) -> TexCoord3D {
        let m = &self.texture_from_render;
        TexCoord3D {
            p: m.transform_point3(ctx.p),
            dpdx: m.transform_vector3(ctx.dpdx),
            dpdy: m.transform_vector3(ctx.dpdy),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_and_differentials_go_to_texture_space() {
        // Texture space scaled by 2 and moved by (1, 0, 0) from render space.
        let render_from_texture =
            Mat4::from_translation(Vec3::X) * Mat4::from_scale(Vec3::splat(2.0));
        let mapping = TextureMapping3D::new(render_from_texture);
        let ctx = TextureEvalContext {
            p: Vec3::new(3.0, 4.0, -2.0),
            dpdx: Vec3::new(0.2, 0.0, 0.0),
            dpdy: Vec3::new(0.0, 0.0, 0.4),
            ..Default::default()
        };
        let c = mapping.map(&ctx);
        assert!(
            (c.p - Vec3::new(1.0, 2.0, -1.0)).length() < 1e-6,
            "{:?}",
            c.p
        );
        // Differentials are vectors: scaled, not translated.
        assert!((c.dpdx - Vec3::new(0.1, 0.0, 0.0)).length() < 1e-6);
        assert!((c.dpdy - Vec3::new(0.0, 0.0, 0.2)).length() < 1e-6);
    }
}
