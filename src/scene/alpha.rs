//! Alpha cutouts: the `alpha` shape parameter (a float or a float
//! texture, default 1) makes parts of a surface absent, as pbrt-v4's
//! `GeometricPrimitive` does.
//!
//! At a hit with alpha a < 1 the hit is ignored when u > a, u being a hash
//! of the ray's origin and direction in [0, 1) (1 when a = 0), so a
//! fractional alpha lets that fraction of rays through, the same rays on
//! every run; the ray then continues from the hit. Shadow rays test alpha
//! the same way. A constant alpha ≤ 0 removes the shape at build time (it
//! could never be hit); a constant alpha ≥ 1 is no cutout. On an area
//! light's shape alpha also masks the emission (`lights::diffuse_area`),
//! and a shape of constant alpha 0 still emits, unseen.

use crate::error::Result;
use crate::interaction::SurfaceInteraction;
use crate::math::hash::hash_words;
use crate::math::Ray;
use crate::scene_description::Shape;
use crate::textures::{FloatTexture, NamedTextures, TextureEvalContext, TextureParams};
use std::path::Path;

/// What a shape's `alpha` parameter asks for.
pub enum Alpha {
    /// No cutout.
    Opaque,
    /// Never hit: the shape is left out.
    Invisible,
    Cutout(FloatTexture),
}

impl Alpha {
    pub fn create(shape: &Shape, textures: &NamedTextures, base_directory: &Path) -> Result<Alpha> {
        let tp = TextureParams {
            params: &shape.entity.params,
            color_space: shape.entity.color_space,
            textures,
            base_directory,
        };
        let alpha = match tp.float_texture_opt("alpha")? {
            None => return Ok(Alpha::Opaque),
            Some(t) => match t.constant() {
                Some(a) if a >= 1.0 => Alpha::Opaque,
                Some(a) if a <= 0.0 => Alpha::Invisible,
                _ => Alpha::Cutout(t),
            },
        };
        Ok(alpha)
    }
}

/// Whether the hit `si` of `ray` is cut out by `alpha`.
pub fn cut_out(alpha: &FloatTexture, si: &SurfaceInteraction, ray: &Ray) -> bool {
    let a = alpha.evaluate(&TextureEvalContext::at(si));
    if a >= 1.0 {
        return false;
    }
    let u = if a <= 0.0 {
        1.0
    } else {
        let (o, d) = (ray.origin, ray.direction);
        let words = [o.x, o.y, o.z, d.x, d.y, d.z].map(f32::to_bits);
        (hash_words(&words) as u32) as f32 * (1.0 / 4_294_967_296.0)
    };
    u > a
}
