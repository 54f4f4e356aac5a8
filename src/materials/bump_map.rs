//! Bump mapping (pbrt-v4's `BumpMap`): a material's `displacement` float
//! texture, read as a height along the shading normal, tilts the shading
//! tangents as the displaced surface would without moving the surface.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `displacement` | float texture | none | height along the shading normal (render-space units) |
//!
//! The height d's derivatives are forward differences: one step
//! du = ½(|∂u/∂x| + |∂u/∂y|) in u (0.0005 where the hit has no
//! screen-space differentials), likewise dv, the texture evaluated at the
//! point moved by du·∂p/∂u with u + du, and at the point moved by dv·∂p/∂v
//! with v + dv. The displaced surface p + d·n then has
//! ∂p/∂u' = ∂p/∂u + (∂d/∂u) n + d ∂n/∂u, and likewise in v, all in the
//! shading geometry.

use crate::interaction::SurfaceInteraction;
use crate::textures::{FloatTexture, TextureEvalContext};
use glam::{Vec2, Vec3};

/// The step in u or v where the hit has no screen-space differentials
/// (pbrt-v4's).
const FALLBACK_STEP: f32 = 0.0005;

/// Half the footprint of a pixel in one texture coordinate, or the
/// fallback step where it is zero.
fn step(d_dx: f32, d_dy: f32) -> f32 {
    let step = 0.5 * (d_dx.abs() + d_dy.abs());
    if step == 0.0 {
        FALLBACK_STEP
    } else {
        step
    }
}

/// The shading ∂p/∂u and ∂p/∂v of the surface at `si` displaced by
/// `displacement`, its textures looked up around `ctx` (the hit's context,
/// with its differentials).
pub fn displaced_tangents(
    displacement: &FloatTexture,
    si: &SurfaceInteraction,
    ctx: &TextureEvalContext,
) -> (Vec3, Vec3) {
    let shading = &si.shading;
    let du = step(ctx.dudx, ctx.dudy);
    let dv = step(ctx.dvdx, ctx.dvdy);
    let moved = |dp: Vec3, duv: Vec2| TextureEvalContext {
        p: ctx.p + dp,
        uv: ctx.uv + duv,
        ..*ctx
    };
    let u_height = displacement.evaluate(&moved(du * shading.dpdu, Vec2::new(du, 0.0)));
    let v_height = displacement.evaluate(&moved(dv * shading.dpdv, Vec2::new(0.0, dv)));
    let height = displacement.evaluate(ctx);
    let dpdu = shading.dpdu + (u_height - height) / du * shading.n + height * shading.dndu;
    let dpdv = shading.dpdv + (v_height - height) / dv * shading.n + height * shading.dndv;
    (dpdu, dpdv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interaction::Shading;
    use crate::textures::bilerp::BilerpTexture;
    use crate::textures::mapping::TextureMapping2D;

    /// A hit on the plane z = 0 with ∂p/∂u = `u_length`·x̂, ∂p/∂v = ŷ.
    fn flat_hit(u_length: f32) -> SurfaceInteraction {
        let (dpdu, dpdv) = (Vec3::new(u_length, 0.0, 0.0), Vec3::Y);
        SurfaceInteraction {
            n: Vec3::Z,
            uv: Vec2::new(0.4, 0.6),
            dpdu,
            dpdv,
            shading: Shading {
                n: Vec3::Z,
                dpdu,
                dpdv,
                ..Default::default()
            },
            ..Default::default()
        }
    }

    /// The height `slope`·u: a bilinear texture 0 at u = 0, `slope` at 1.
    fn ramp(slope: f32) -> FloatTexture {
        FloatTexture::Bilerp(Box::new(BilerpTexture {
            mapping: TextureMapping2D::Uv {
                scale: Vec2::ONE,
                delta: Vec2::ZERO,
            },
            // v00, v10, v01, v11.
            values: [0.0, slope, 0.0, slope],
        }))
    }

    #[test]
    fn a_slope_in_u_tilts_the_normal_against_u() {
        for (slope, u_length) in [(0.5, 1.0), (2.0, 4.0), (-1.0, 0.5)] {
            let si = flat_hit(u_length);
            let ctx = TextureEvalContext::at(&si);
            let (dpdu, dpdv) = displaced_tangents(&ramp(slope), &si, &ctx);
            let normal = dpdu.cross(dpdv).normalize();
            // The surface rises by `slope` per unit u, that is by
            // slope / |∂p/∂u| per unit length along x: the normal leans
            // back by atan of that.
            let tilt = (slope / u_length).atan();
            let expected = Vec3::new(-tilt.sin(), 0.0, tilt.cos());
            assert!(
                (normal - expected).length() < 1e-3,
                "slope {slope}, |dpdu| {u_length}: {normal} vs {expected}"
            );
            assert_eq!(dpdv, Vec3::Y);
        }
    }

    #[test]
    fn a_constant_height_leaves_a_plane_flat() {
        let si = flat_hit(2.0);
        let ctx = TextureEvalContext::at(&si);
        let (dpdu, dpdv) = displaced_tangents(&FloatTexture::Constant(0.3), &si, &ctx);
        assert_eq!((dpdu, dpdv), (si.shading.dpdu, si.shading.dpdv));
    }

    #[test]
    fn a_constant_height_follows_the_normal_s_change() {
        // On a curved surface a constant height still moves the tangents
        // by d·∂n/∂u (the offset surface is larger).
        let mut si = flat_hit(1.0);
        si.shading.dndu = Vec3::new(0.5, 0.0, 0.0);
        let ctx = TextureEvalContext::at(&si);
        let (dpdu, _) = displaced_tangents(&FloatTexture::Constant(2.0), &si, &ctx);
        assert_eq!(dpdu, Vec3::new(2.0, 0.0, 0.0));
    }

    #[test]
    fn steps_follow_the_differentials() {
        assert_eq!(step(0.0, 0.0), FALLBACK_STEP);
        assert_eq!(step(-0.01, 0.03), 0.02);
    }
}
