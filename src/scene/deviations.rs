//! Warnings for what rpbrt does differently from pbrt-v4 in a given scene
//! (docs/compatibility.md lists them all): each deviation the scene
//! actually meets is named once, at the file:line:col of the first thing
//! that meets it, so no image differs from pbrt-v4's without saying so.
//!
//! - **Named metal spectra** (`metal-Cu-eta`, …, and the default copper
//!   of `conductor` and `coatedconductor`): rpbrt's n, k come from published measurements, not pbrt-v4's
//!   tables; close, not identical.
//! - **Texture filtering after specular bounces**: pbrt-v4 carries ray
//!   differentials through perfectly smooth reflection and refraction;
//!   rpbrt filters textures seen after them with the camera's approximate
//!   differentials. Met when a texture varies (so it is filtered) and some
//!   material can scatter specularly.
//! - **EXR chromaticities**: pbrt-v4 reads an EXR image's primaries and
//!   converts; rpbrt reads every EXR texture or environment map as sRGB.
//!   Met when an EXR a texture or light names (`filename`) declares
//!   primaries other than sRGB's (only the file's header is read here).

use crate::materials::Material;
use crate::scene_description::{Entity, SceneDescription};
use pbrt_parser::{Values, Warning};
use std::path::Path;

/// sRGB's (Rec. 709's) primaries and D65 white, CIE xy: red, green, blue,
/// white.
const SRGB_PRIMARIES: [[f32; 2]; 4] = [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06], [0.3127, 0.3290]];

/// The primaries an EXR file declares (red, green, blue, white), when it
/// declares some; `None` also when the header cannot be read (the image
/// reader reports that).
fn exr_primaries(path: &Path) -> Option<[[f32; 2]; 4]> {
    let meta = exr::meta::MetaData::read_from_file(path, false).ok()?;
    let c = meta.headers.first()?.shared_attributes.chromaticities?;
    Some([c.red, c.green, c.blue, c.white].map(|v| [v.0, v.1]))
}

/// The warnings for `scene`, whose materials were made as `materials`
/// (anonymous then named, as `build` makes them); `texture_filtering`:
/// whether textures are filtered (some texture varies, filtering is on);
/// `base_directory`: where the scene's file names resolve.
pub fn warnings(
    scene: &SceneDescription,
    materials: &[Material],
    texture_filtering: bool,
    base_directory: &Path,
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
    let mut exr_warned = false;
    for entity in &entities {
        for p in entity.params.own() {
            if let (false, "filename", Values::Strings(names)) =
                (exr_warned, p.name.as_str(), &p.values)
            {
                let exr = names
                    .first()
                    .filter(|n| n.to_ascii_lowercase().ends_with(".exr"));
                if let Some(name) = exr {
                    let path = pbrt_parser::resolve_path(base_directory, name);
                    let differs = exr_primaries(&path).is_some_and(|primaries| {
                        primaries
                            .iter()
                            .zip(&SRGB_PRIMARIES)
                            .any(|(a, b)| (a[0] - b[0]).abs() > 1e-3 || (a[1] - b[1]).abs() > 1e-3)
                    });
                    if differs {
                        exr_warned = true;
                        out.push(Warning {
                            message: format!(
                                "\"{name}\" declares primaries other than sRGB's: pbrt-v4 converts from them, rpbrt reads the image as sRGB"
                            ),
                            location: p.location.clone(),
                        });
                    }
                }
            }
            let Values::Strings(names) = &p.values else {
                continue;
            };
            for name in names.iter().filter(|n| n.starts_with("metal-")) {
                if !named_metals.iter().any(|m| name == m) {
                    named_metals.push(name.to_string());
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
        .find_map(|m| {
            let names = match m.kind.as_str() {
                "conductor" => ["eta", "k", "reflectance"],
                "coatedconductor" => ["conductor.eta", "conductor.k", "reflectance"],
                _ => return None,
            };
            names
                .iter()
                .all(|n| m.params.own().all(|p| p.name != *n))
                .then_some((m, names))
        });
    if let Some((m, [eta, k, reflectance])) = default_copper {
        out.push(Warning {
            message: format!("{} without \"{eta}\", \"{k}\" or \"{reflectance}\" is copper: rpbrt's copper n, k are published measurements, not pbrt-v4's tables (close, not identical)", m.kind),
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
        let mut normal_maps = crate::materials::normal_map::NormalMapCache::default();
        let materials: Vec<Material> = scene
            .materials
            .iter()
            .chain(scene.named_materials.values())
            .map(|m| {
                Material::create(
                    m,
                    &crate::textures::NamedTextures::default(),
                    Path::new("."),
                    &mut normal_maps,
                )
                .unwrap()
            })
            .collect();
        let filtering = scene.textures.iter().any(|t| t.entity.kind != "constant");
        warnings(scene, &materials, filtering, Path::new("."))
            .iter()
            .map(|w| w.to_string())
            .collect()
    }

    /// A 1 × 1 EXR with the given primaries (or none).
    fn write_exr(path: &Path, primaries: Option<[[f32; 2]; 4]>) {
        use exr::prelude::*;
        let mut attributes = ImageAttributes::new(IntegerBounds::from_dimensions((1, 1)));
        attributes.chromaticities =
            primaries.map(|[r, g, b, w]| exr::meta::attribute::Chromaticities {
                red: Vec2(r[0], r[1]),
                green: Vec2(g[0], g[1]),
                blue: Vec2(b[0], b[1]),
                white: Vec2(w[0], w[1]),
            });
        let channels = SpecificChannels::rgb(|_: Vec2<usize>| (0.5f32, 0.5f32, 0.5f32));
        let layer = Layer::new(
            (1, 1),
            LayerAttributes::default(),
            Encoding::UNCOMPRESSED,
            channels,
        );
        Image::new(attributes, layer).write().to_file(path).unwrap();
    }

    #[test]
    fn exr_primaries_other_than_srgb_are_named() {
        let dir = std::env::temp_dir().join(format!("rpbrt-deviations-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let rec2020 = [
            [0.708, 0.292],
            [0.170, 0.797],
            [0.131, 0.046],
            [0.3127, 0.3290],
        ];
        write_exr(&dir.join("wide.exr"), Some(rec2020));
        write_exr(&dir.join("srgb.exr"), Some(SRGB_PRIMARIES));
        write_exr(&dir.join("plain.exr"), None);
        let scene_with = |file: &str| {
            let text = format!(
                "Camera \"perspective\"\nWorldBegin\nLightSource \"infinite\" \"string filename\" \"{file}\"\n"
            );
            let loaded = load_text(&dir.join("s.pbrt"), &text).unwrap();
            warnings(&loaded.scene, &[], false, &dir)
                .iter()
                .map(|w| w.to_string())
                .collect::<Vec<_>>()
        };
        let w = scene_with("wide.exr");
        assert!(
            w.len() == 1 && w[0].contains("s.pbrt:3:") && w[0].contains("wide.exr"),
            "{w:?}"
        );
        assert!(scene_with("srgb.exr").is_empty());
        assert!(scene_with("plain.exr").is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn named_metals_are_named_once_where_first_used() {
        let w = warnings_of(
            "Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\n\
             Shape \"sphere\"\n\
             Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\n",
        );
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].contains("w.pbrt:3:") && w[0].contains("metal-Au-eta"),
            "{w:?}"
        );
        assert!(w[1].contains("metal-Au-k"), "{w:?}");
    }

    #[test]
    fn default_copper_is_named() {
        let w = warnings_of("Material \"conductor\" \"float roughness\" 0.2\n");
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("w.pbrt:3:1") && w[0].contains("copper"),
            "{w:?}"
        );
        assert!(
            warnings_of("Material \"conductor\" \"rgb reflectance\" [0.9 0.9 0.9]\n").is_empty()
        );
    }

    #[test]
    fn texture_filtering_after_specular_only_when_both_are_there() {
        let texture = "Texture \"c\" \"spectrum\" \"checkerboard\"\n";
        let glass = "Material \"dielectric\"\n";
        let rough = "Material \"dielectric\" \"float roughness\" 0.3\n";
        let w = warnings_of(&format!("{texture}{glass}"));
        assert!(
            w.len() == 1 && w[0].contains("w.pbrt:3:1") && w[0].contains("specular"),
            "{w:?}"
        );
        assert!(warnings_of(&format!("{texture}{rough}")).is_empty());
        assert!(warnings_of(glass).is_empty());
    }
}
