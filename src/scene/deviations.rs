//! Warnings for what rpbrt does differently from pbrt-v4 in a given scene
//! (docs/compatibility.md lists them all): each deviation the scene
//! actually meets is named once, at the file:line:col of the first thing
//! that meets it, so no image differs from pbrt-v4's without saying so.
//!
//! - **Named metal spectra** (`metal-Cu-eta`, …, and `conductor`'s default
//!   copper): rpbrt's n, k come from published measurements, not pbrt-v4's
//!   tables; close, not identical.
//! - **Texture filtering after specular bounces**: pbrt-v4 carries ray
//!   differentials through perfectly smooth reflection and refraction;
//!   rpbrt filters textures seen after them with the camera's approximate
//!   differentials. Met when a texture varies (so it is filtered) and some
//!   material can scatter specularly.
//!
//! The third deviation, EXR chromaticities, is warned about where EXR
//! images are read (`image::exr_file`).

use super::description::{Entity, SceneDescription};
use crate::materials::Material;
use pbrt_parser::{Values, Warning};

/// The warnings for `scene`, whose materials were made as `materials`
/// (anonymous then named, as `build` makes them); `texture_filtering`:
/// whether textures are filtered (some texture varies, filtering is on).
pub fn warnings(
    scene: &SceneDescription,
    materials: &[Material],
    texture_filtering: bool,
) -> Vec<Warning> {
    let mut out = Vec::new();
    let entities: Vec<&Entity> = scene
        .materials
        .iter()
        .chain(scene.named_materials.values())
        .chain(scene.lights.iter().map(|l| &l.entity))
        .chain(scene.textures.iter().map(|t| &t.entity))
        .collect();
    let mut named_metals: Vec<String> = Vec::new();
    for entity in &entities {
        for p in entity.params.own() {
            let Values::Strings(names) = &p.values else {
                continue;
            };
            for name in names.iter().filter(|n| n.starts_with("metal-")) {
                if !named_metals.contains(name) {
                    named_metals.push(name.clone());
                    out.push(Warning {
                        message: format!(
                            "spectrum \"{name}\": rpbrt's metal n, k are published measurements, not pbrt-v4's tables (close, not identical)"
                        ),
                        location: p.location.clone(),
                    });
                }
            }
        }
    }
    let default_copper = scene
        .materials
        .iter()
        .chain(scene.named_materials.values())
        .find(|m| {
            m.kind == "conductor"
                && ["eta", "k", "reflectance"]
                    .iter()
                    .all(|n| m.params.own().all(|p| p.name != *n))
        });
    if let Some(m) = default_copper {
        out.push(Warning {
            message: "conductor without \"eta\", \"k\" or \"reflectance\" is copper: rpbrt's copper n, k are published measurements, not pbrt-v4's tables (close, not identical)".into(),
            location: m.location.0.clone(),
        });
    }
    if texture_filtering && materials.iter().any(Material::can_be_specular) {
        let varying = scene
            .textures
            .iter()
            .find(|t| !matches!(t.entity.kind.as_str(), "constant"));
        if let Some(t) = varying {
            out.push(Warning {
                message: "textures seen after a perfectly specular reflection or refraction are filtered with the camera's approximate differentials (pbrt-v4 carries the differentials through the bounce): they may be filtered differently".into(),
                location: t.entity.location.0.clone(),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load_text;
    use std::path::Path;

    fn warnings_of(world: &str) -> Vec<String> {
        let text = format!("Camera \"perspective\"\nWorldBegin\n{world}");
        let loaded = load_text(Path::new("w.pbrt"), &text).unwrap();
        let scene = &loaded.scene;
        let materials: Vec<Material> = scene
            .materials
            .iter()
            .chain(scene.named_materials.values())
            .map(|m| {
                Material::create(m, &crate::textures::NamedTextures::default(), Path::new("."))
                    .unwrap()
            })
            .collect();
        let filtering = scene.textures.iter().any(|t| t.entity.kind != "constant");
        warnings(scene, &materials, filtering)
            .iter()
            .map(|w| w.to_string())
            .collect()
    }

    #[test]
    fn named_metals_are_named_once_where_first_used() {
        let w = warnings_of(
            "Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\n\
             Shape \"sphere\"\n\
             Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\n",
        );
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].contains("w.pbrt:3:") && w[0].contains("metal-Au-eta"), "{w:?}");
        assert!(w[1].contains("metal-Au-k"), "{w:?}");
    }

    #[test]
    fn default_copper_is_named() {
        let w = warnings_of("Material \"conductor\" \"float roughness\" 0.2\n");
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("w.pbrt:3:1") && w[0].contains("copper"), "{w:?}");
        assert!(warnings_of("Material \"conductor\" \"rgb reflectance\" [0.9 0.9 0.9]\n").is_empty());
    }

    #[test]
    fn texture_filtering_after_specular_only_when_both_are_there() {
        let texture = "Texture \"c\" \"spectrum\" \"checkerboard\"\n";
        let glass = "Material \"dielectric\"\n";
        let rough = "Material \"dielectric\" \"float roughness\" 0.3\n";
        let w = warnings_of(&format!("{texture}{glass}"));
        assert!(w.len() == 1 && w[0].contains("w.pbrt:3:1") && w[0].contains("specular"), "{w:?}");
        assert!(warnings_of(&format!("{texture}{rough}")).is_empty());
        assert!(warnings_of(glass).is_empty());
    }
}
