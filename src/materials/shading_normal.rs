//! A material's bump or normal map: what changes the shading normal at a
//! hit before the material's BSDF is made there (pbrt-v4's step in
//! `SurfaceInteraction::GetBSDF`).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `displacement` | float texture | none | bump map: see [`super::bump_map`] |
//! | `normalmap` | string | `""` | normal map file: see [`super::normal_map`]; wins over `displacement` |
//!
//! As pbrt-v4: `diffuse`, `diffusetransmission`, `conductor`, `dielectric`,
//! `thindielectric`, `coateddiffuse` and `coatedconductor` take both; `hair`
//! and `mix` take neither (a `displacement` there is an unused parameter; a
//! `normalmap` file is still read, and its errors reported, but not used).
//! The map applies to the material a `mix` chooses, after the choice.
//!
//! The new shading ∂p/∂u and ∂p/∂v give the shading normal (their cross
//! product, turned to the geometric normal's side), and the hit keeps
//! them: the BSDF's frame and everything the integrator later does with
//! the shading normal (cosines, light sampling) see the mapped one.
//! Materials without a map are not wrapped and pay nothing.

use super::normal_map::NormalMap;
use super::Material;
use crate::interaction::SurfaceInteraction;
use crate::textures::{FloatTexture, TextureEvalContext};
use std::sync::Arc;

/// Where a material's shading normal comes from, when not the shape's.
#[derive(Clone, Debug)]
pub enum ShadingNormal {
    /// A bump map: the `displacement` height texture.
    Bump(FloatTexture),
    /// A normal map image.
    NormalMap(Arc<NormalMap>),
}

impl ShadingNormal {
    /// The map of a material that takes one: the normal map if it names
    /// one (pbrt-v4 then ignores the displacement), else the bump map.
    pub fn choose(
        normal_map: Option<Arc<NormalMap>>,
        displacement: Option<FloatTexture>,
    ) -> Option<ShadingNormal> {
        match (normal_map, displacement) {
            (Some(map), _) => Some(ShadingNormal::NormalMap(map)),
            (None, Some(height)) => Some(ShadingNormal::Bump(height)),
            (None, None) => None,
        }
    }

    /// Replaces the shading geometry of `si` by the mapped one (textures
    /// looked up in `ctx`). Where the map gives no direction (a degenerate
    /// texel, tangents that cancel or are not finite) the shape's shading
    /// geometry is kept rather than made NaN.
    pub fn apply(&self, si: &mut SurfaceInteraction, ctx: &TextureEvalContext) {
        let tangents = match self {
            ShadingNormal::Bump(height) => Some(super::bump_map::displaced_tangents(height, si, ctx)),
            ShadingNormal::NormalMap(map) => map.shading_tangents(si),
        };
        let Some((dpdu, dpdv)) = tangents else {
            return;
        };
        let Some(normal) = dpdu.cross(dpdv).try_normalize() else {
            return;
        };
        let (dndu, dndv) = (si.shading.dndu, si.shading.dndv);
        si.set_shading_geometry(normal, dpdu, dpdv, dndu, dndv, false);
    }
}

/// A material whose hits take their shading normal from a map.
#[derive(Clone, Debug)]
pub struct Bumped {
    pub shading_normal: ShadingNormal,
    pub material: Material,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interaction::Shading;
    use glam::{Vec2, Vec3};

    /// A hit on the plane z = 0 seen from above, ∂p/∂u = x̂, ∂p/∂v = ŷ.
    fn flat_hit() -> SurfaceInteraction {
        SurfaceInteraction {
            n: Vec3::Z,
            uv: Vec2::splat(0.5),
            dpdu: Vec3::X,
            dpdv: Vec3::Y,
            shading: Shading {
                n: Vec3::Z,
                dpdu: Vec3::X,
                dpdv: Vec3::Y,
                ..Default::default()
            },
            ..Default::default()
        }
    }

    #[test]
    fn the_normal_map_wins_over_the_displacement() {
        let map = NormalMap::from_image(
            crate::image::Image::new(1, 1, &["R", "G", "B"], vec![0.5, 0.5, 1.0]).unwrap(),
        )
        .unwrap();
        let chosen = ShadingNormal::choose(Some(Arc::new(map)), Some(FloatTexture::Constant(1.0)));
        assert!(matches!(chosen, Some(ShadingNormal::NormalMap(_))));
        let chosen = ShadingNormal::choose(None, Some(FloatTexture::Constant(1.0)));
        assert!(matches!(chosen, Some(ShadingNormal::Bump(_))));
        assert!(ShadingNormal::choose(None, None).is_none());
    }

    #[test]
    fn a_mapped_normal_facing_away_is_turned_to_the_geometric_side() {
        // A normal map can only tilt the normal; a tangent-space normal
        // below the surface is turned back (SetShadingGeometry, not
        // authoritative), and the geometric normal is left alone.
        let below = Vec3::new(0.0, 0.6, -0.8);
        let map = NormalMap::from_image(
            crate::image::Image::new(
                1,
                1,
                &["R", "G", "B"],
                ((below + Vec3::ONE) * 0.5).to_array().to_vec(),
            )
            .unwrap(),
        )
        .unwrap();
        let mut si = flat_hit();
        let ctx = TextureEvalContext::at(&si);
        ShadingNormal::NormalMap(Arc::new(map)).apply(&mut si, &ctx);
        assert_eq!(si.n, Vec3::Z);
        assert!(si.shading.n.dot(si.n) > 0.0);
        assert!((si.shading.n.abs() - below.abs()).length() < 1e-5, "{}", si.shading.n);
    }

    #[test]
    fn a_degenerate_map_keeps_the_shape_s_shading() {
        let grey = NormalMap::from_image(
            crate::image::Image::new(1, 1, &["R", "G", "B"], vec![0.5; 3]).unwrap(),
        )
        .unwrap();
        let mut si = flat_hit();
        let before = si;
        let ctx = TextureEvalContext::at(&si);
        ShadingNormal::NormalMap(Arc::new(grey)).apply(&mut si, &ctx);
        assert_eq!(si, before);
        ShadingNormal::Bump(FloatTexture::Constant(f32::NAN)).apply(&mut si, &ctx);
        assert_eq!(si, before);
    }
}
