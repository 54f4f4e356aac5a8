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
            ShadingNormal::Bump(height) => {
                Some(super::bump_map::displaced_tangents(height, si, ctx))
            }
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
        assert!(
            (si.shading.n.abs() - below.abs()).length() < 1e-5,
            "{}",
            si.shading.n
        );
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

/// Whole scenes: which materials take the maps, their errors, and the
/// images they give.
#[cfg(test)]
mod scene_tests {
    use super::*;
    use crate::image::Image;
    use crate::scene::build::{build, BuiltScene, RenderOverrides};
    use crate::scene::load_text;
    use glam::Vec3;
    use std::path::{Path, PathBuf};

    /// An empty folder for one test's files.
    fn fresh_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "rpbrt-shading-normal-{}-{name}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A 1 × 1 EXR normal map encoding the tangent-space normal `local`.
    fn write_normal_map(path: &Path, local: Vec3) {
        let rgb = (local.normalize() + Vec3::ONE) * 0.5;
        Image::new(1, 1, &["R", "G", "B"], rgb.to_array().to_vec())
            .unwrap()
            .write_exr(path, false)
            .unwrap();
    }

    /// The scene `world` (after a camera and `WorldBegin`), read as the
    /// file `dir`/scene.pbrt and built.
    fn built(dir: &Path, world: &str) -> crate::error::Result<BuiltScene> {
        let text = format!("Camera \"perspective\"\nWorldBegin\n{world}");
        let loaded = load_text(&dir.join("scene.pbrt"), &text)?;
        build(loaded.scene, &RenderOverrides::default())
    }

    fn build_error(dir: &Path, world: &str) -> String {
        match built(dir, world) {
            Ok(_) => panic!("expected an error for {world}"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn materials_without_maps_are_not_wrapped() {
        let dir = fresh_dir("plain");
        let scene = built(&dir, "Material \"conductor\"\nShape \"sphere\"\n").unwrap();
        assert!(matches!(
            scene.materials.last(),
            Some(Material::Conductor { .. })
        ));
    }

    #[test]
    fn hair_and_mix_take_no_displacement() {
        let dir = fresh_dir("unused");
        let message = build_error(
            &dir,
            "Material \"hair\" \"float displacement\" 0.1\nShape \"sphere\"\n",
        );
        assert!(
            message.contains("unused parameter") && message.contains("displacement"),
            "{message}"
        );
        assert!(message.contains("3:17"), "{message}");
        let message = build_error(
            &dir,
            "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n\
             MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"a\" \"a\"] \"float displacement\" 0.1\n",
        );
        assert!(
            message.contains("unused parameter") && message.contains("displacement"),
            "{message}"
        );
    }

    #[test]
    fn every_other_material_takes_both() {
        let dir = fresh_dir("takes");
        write_normal_map(&dir.join("n.exr"), Vec3::Z);
        for kind in [
            "diffuse",
            "diffusetransmission",
            "conductor",
            "dielectric",
            "thindielectric",
            "coateddiffuse",
            "coatedconductor",
        ] {
            for (map, is_normal_map) in [
                ("\"float displacement\" 0.1", false),
                ("\"string normalmap\" \"n.exr\"", true),
                (
                    "\"string normalmap\" \"n.exr\" \"float displacement\" 0.1",
                    true,
                ),
            ] {
                let world = format!("Material \"{kind}\" {map}\nShape \"sphere\"\n");
                let scene = built(&dir, &world).unwrap_or_else(|e| panic!("{world}: {e}"));
                let Some(Material::Bumped(bumped)) = scene.materials.last() else {
                    panic!("{world}: not wrapped");
                };
                assert_eq!(
                    matches!(bumped.shading_normal, ShadingNormal::NormalMap(_)),
                    is_normal_map,
                    "{world}"
                );
            }
        }
    }

    #[test]
    fn a_missing_normal_map_is_a_located_error() {
        let dir = fresh_dir("missing");
        let message = build_error(
            &dir,
            "Material \"diffuse\" \"string normalmap\" \"nothere.png\"\nShape \"sphere\"\n",
        );
        assert!(message.contains("cannot read \""), "{message}");
        assert!(message.contains("nothere.png"), "{message}");
        assert!(message.contains("3:20"), "{message}");
        // Read also where the material then takes none (hair), as pbrt-v4.
        let message = build_error(
            &dir,
            "Material \"hair\" \"string normalmap\" \"nothere.png\"\nShape \"sphere\"\n",
        );
        assert!(message.contains("cannot read \""), "{message}");
    }

    #[test]
    fn a_normal_map_needs_colour_channels() {
        let dir = fresh_dir("grey");
        Image::new(1, 1, &["Y"], vec![0.5])
            .unwrap()
            .write_exr(dir.join("grey.exr"), false)
            .unwrap();
        let message = build_error(
            &dir,
            "Material \"diffuse\" \"string normalmap\" \"grey.exr\"\nShape \"sphere\"\n",
        );
        assert!(message.contains("R, G and B"), "{message}");
    }

    #[test]
    fn materials_naming_one_file_share_its_image() {
        let dir = fresh_dir("shared");
        write_normal_map(&dir.join("n.exr"), Vec3::Z);
        let scene = built(
            &dir,
            "MakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"string normalmap\" \"n.exr\"\n\
             MakeNamedMaterial \"b\" \"string type\" \"conductor\" \"string normalmap\" \"n.exr\"\n",
        )
        .unwrap();
        let map = |m: &Material| match m {
            Material::Bumped(b) => match &b.shading_normal {
                ShadingNormal::NormalMap(map) => Arc::clone(map),
                other => panic!("{other:?}"),
            },
            other => panic!("{other:?}"),
        };
        // Materials 1 and 2: the named ones, after the default one.
        assert!(Arc::ptr_eq(
            &map(&scene.materials[1]),
            &map(&scene.materials[2])
        ));
    }

    /// The pixels of `material` on the plane z = 0 (a 20 × 20 quad, u
    /// along x and v along y) filling the view of a narrow camera looking
    /// down −z, lit by a white point light 1414 away at 45° towards −x
    /// (nearly a distant light; BDPT takes no distant lights) whose scale
    /// makes its irradiance at the origin 1, direct light only, with
    /// `integrator`.
    fn render_plane(dir: &Path, name: &str, integrator: &str, material: &str) -> Vec<f32> {
        let scene = format!(
"LookAt 0 0 50  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 10\n\
             Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8 \"string filename\" \"{name}.exr\"\n\
             Sampler \"zsobol\" \"integer pixelsamples\" 16\n\
             Integrator \"{integrator}\" \"integer maxdepth\" 1\nWorldBegin\n\
             LightSource \"point\" \"point3 from\" [-1000 0 1000] \"rgb I\" [1 1 1] \"float scale\" 2e6\n\
             {material}\n\
             Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n\
             \"point3 P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\n\
             \"point2 uv\" [0 0  1 0  1 1  0 1]\n"
        );
        let path = dir.join(format!("{name}.pbrt"));
        std::fs::write(&path, scene).unwrap();
        let overrides = RenderOverrides {
            outfile: Some(dir.join(format!("{name}.exr"))),
            ..Default::default()
        };
        crate::pipeline::render_file(&path, &overrides, 1, false).unwrap();
        Image::read(dir.join(format!("{name}.exr")))
            .unwrap()
            .rgb_data()
    }

    fn mean(values: &[f32]) -> f64 {
        values.iter().map(|&v| v as f64).sum::<f64>() / values.len() as f64
    }

    /// A diffuse plane whose height rises 20·tan 30° over u (the quad is
    /// 20 wide, so its slope is tan 30°) reflects as if turned 30° towards
    /// the light: cos 15° instead of cos 45°, and a normal map encoding
    /// the same tilt gives the same image.
    #[test]
    fn a_sloped_height_lights_the_plane_as_its_tilt() {
        let dir = fresh_dir("render");
        let tilt = 30f32.to_radians();
        write_normal_map(
            &dir.join("tilt.exr"),
            Vec3::new(-tilt.sin(), 0.0, tilt.cos()),
        );
        let slope = 20.0 * tilt.tan();
        let bump = format!(
            "Texture \"height\" \"float\" \"bilerp\" \"float v00\" 0 \"float v01\" 0 \"float v10\" {slope} \"float v11\" {slope}\n\
             Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5] \"texture displacement\" \"height\""
        );
        let normal_map =
            "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5] \"string normalmap\" \"tilt.exr\"";
        let flat = "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]";
        let expected_ratio = (15f64.to_radians().cos()) / (45f64.to_radians().cos());
        for integrator in ["path", "volpath", "bdpt"] {
            let flat = render_plane(&dir, &format!("{integrator}-flat"), integrator, flat);
            let bumped = render_plane(&dir, &format!("{integrator}-bump"), integrator, &bump);
            let mapped = render_plane(&dir, &format!("{integrator}-map"), integrator, normal_map);
            // Radiance R/π · E cos θ: a white light of unit luminance on a
            // grey 0.5 surface (the light's distance varies by 0.2° over
            // the view).
            let analytic_flat = 0.5 / std::f64::consts::PI * 45f64.to_radians().cos();
            let (flat, bumped, mapped) = (mean(&flat), mean(&bumped), mean(&mapped));
            // The light is sampled exactly (a point light, a diffuse
            // surface): only the wavelengths vary, the same in all three.
            let tolerance = 0.005;
            eprintln!("{integrator}: flat {flat:.5} (analytic {analytic_flat:.5}), bump {bumped:.5}, map {mapped:.5}");
            assert!(
                (flat / analytic_flat - 1.0).abs() < tolerance,
                "{integrator}: flat {flat} vs {analytic_flat}"
            );
            assert!(
                (bumped / flat / expected_ratio - 1.0).abs() < tolerance,
                "{integrator}: bump/flat {} vs {expected_ratio}",
                bumped / flat
            );
            assert!(
                (mapped / flat / expected_ratio - 1.0).abs() < tolerance,
                "{integrator}: map/flat {} vs {expected_ratio}",
                mapped / flat
            );
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
