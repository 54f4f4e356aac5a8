//! Normal maps (pbrt-v4's `"string normalmap"` material parameter): an RGB
//! image whose texels are tangent-space shading normals, and the shading
//! tangents they give at a hit.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `normalmap` | string | `""` (none) | image file, relative to the scene file; must have R, G and B channels |
//!
//! As pbrt-v4 reads them: the file's values are taken as they are stored
//! (linear, so an 8-bit PNG's 128 is 128/255, not sRGB-decoded; TGA and
//! JPEG files are still sRGB-decoded, as pbrt-v4 does for those formats),
//! looked up bilinearly at (u, 1 − v) with the image repeating, and an
//! RGB c is the normal normalize(2c − 1) in the frame whose x is the
//! shading ∂p/∂u and whose z is the shading normal. Every material that
//! names a file shares one copy of it ([`NormalMapCache`]).

use crate::error::{image_file_error, scene_error, Result};
use crate::image::{ColorEncoding, Image, WrapMode};
use crate::interaction::SurfaceInteraction;
use crate::math::frame::Frame;
use glam::{Vec2, Vec3};
use pbrt_parser::Location;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A normal map: a linear image with exactly the channels R, G, B.
#[derive(Debug)]
pub struct NormalMap {
    image: Image,
}

impl NormalMap {
    /// The map of an image that has R, G and B channels (others are
    /// dropped), its values taken as linear; `None` without them.
    pub fn from_image(image: Image) -> Option<NormalMap> {
        let rgb = image.select_channels(&["R", "G", "B"])?;
        // Decoded once here (a no-op for linear data), so lookups need not.
        Some(NormalMap {
            image: rgb.to_linear(),
        })
    }

    /// Reads the normal map in file `path`; errors point at `location`
    /// (where the scene names the file).
    pub fn read(path: &Path, location: &Location) -> Result<NormalMap> {
        let image = Image::read(path).map_err(|e| image_file_error("normal map", e, location))?;
        // pbrt-v4 asks for linear encoding, which its PNG reader obeys and
        // its TGA and JPEG readers do not (they stay sRGB).
        let is_png = path
            .extension()
            .is_some_and(|extension| extension.eq_ignore_ascii_case("png"));
        let image = if is_png {
            image.with_encoding(ColorEncoding::Linear)
        } else {
            image
        };
        let channels = image.channels().join(", ");
        match NormalMap::from_image(image) {
            Some(map) => Ok(map),
            None => scene_error(
                format!(
                    "normal map \"{}\": the image must have R, G and B channels (it has {channels})",
                    path.display()
                ),
                location,
            ),
        }
    }

    /// The tangent-space normal at texture coordinates `uv` (unit; z is
    /// the surface's normal), or `None` where the texel colour encodes no
    /// direction (2c − 1 = 0).
    pub fn tangent_space_normal(&self, uv: Vec2) -> Option<Vec3> {
        // Image rows run top to bottom, v bottom to top.
        let st = Vec2::new(uv.x, 1.0 - uv.y);
        let texel = |channel| self.image.bilerp_channel(st, channel, WrapMode::Repeat);
        let encoded = Vec3::new(texel(0), texel(1), texel(2));
        (2.0 * encoded - Vec3::ONE).try_normalize()
    }

    /// The shading ∂p/∂u and ∂p/∂v at `si` that make the mapped normal
    /// their cross product's direction, each as long as before (pbrt-v4's
    /// `NormalMap`); `None` where the map gives no direction.
    pub fn shading_tangents(&self, si: &SurfaceInteraction) -> Option<(Vec3, Vec3)> {
        let local = self.tangent_space_normal(si.uv)?;
        let shading = &si.shading;
        let frame = Frame::from_xz(shading.dpdu.try_normalize()?, shading.n);
        let normal = frame.from_local(local);
        let (u_length, v_length) = (shading.dpdu.length(), shading.dpdv.length());
        // ∂p/∂u made perpendicular to the new normal (one Gram–Schmidt
        // step), then ∂p/∂v perpendicular to both.
        let dpdu = (shading.dpdu - normal * shading.dpdu.dot(normal)).try_normalize()? * u_length;
        let dpdv = normal.cross(dpdu).try_normalize()? * v_length;
        Some((dpdu, dpdv))
    }
}

/// Normal maps already read, by resolved file name: materials naming the
/// same file share one image.
#[derive(Default)]
pub struct NormalMapCache {
    maps: HashMap<PathBuf, Arc<NormalMap>>,
}

impl NormalMapCache {
    /// How many files have been read.
    pub fn len(&self) -> usize {
        self.maps.len()
    }

    pub fn is_empty(&self) -> bool {
        self.maps.is_empty()
    }

    /// The map in file `path`, read the first time it is asked for.
    pub fn get(&mut self, path: &Path, location: &Location) -> Result<Arc<NormalMap>> {
        if let Some(map) = self.maps.get(path) {
            return Ok(Arc::clone(map));
        }
        let map = Arc::new(NormalMap::read(path, location)?);
        self.maps.insert(path.to_path_buf(), Arc::clone(&map));
        Ok(map)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interaction::Shading;

    /// A 2 × 2 map of one colour.
    fn constant_map(rgb: [f32; 3]) -> NormalMap {
        let data = (0..4).flat_map(|_| rgb).collect();
        NormalMap::from_image(Image::new(2, 2, &["R", "G", "B"], data).unwrap()).unwrap()
    }

    /// A hit on the plane z = 0 with ∂p/∂u = 2x̂, ∂p/∂v = 3ŷ, normal ẑ.
    fn flat_hit() -> SurfaceInteraction {
        let (dpdu, dpdv) = (Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0));
        SurfaceInteraction {
            n: Vec3::Z,
            uv: Vec2::new(0.3, 0.7),
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

    #[test]
    fn the_flat_colour_keeps_the_tangents() {
        let map = constant_map([0.5, 0.5, 1.0]);
        let si = flat_hit();
        let (dpdu, dpdv) = map.shading_tangents(&si).unwrap();
        assert!((dpdu - si.shading.dpdu).length() < 1e-6, "{dpdu}");
        assert!((dpdv - si.shading.dpdv).length() < 1e-6, "{dpdv}");
    }

    #[test]
    fn a_colour_gives_its_normal_in_the_tangent_frame() {
        // 2c − 1 = (0.6, −0.48, 0.64): a unit vector, tilted towards +x
        // (∂p/∂u) and −y.
        let local = Vec3::new(0.6, -0.48, 0.64);
        let map = constant_map(((local + Vec3::ONE) * 0.5).to_array());
        let si = flat_hit();
        let (dpdu, dpdv) = map.shading_tangents(&si).unwrap();
        let normal = dpdu.cross(dpdv).normalize();
        assert!((normal - local).length() < 1e-5, "{normal}");
        assert!((dpdu.length() - 2.0).abs() < 1e-5);
        assert!((dpdv.length() - 3.0).abs() < 1e-5);
        assert!(dpdu.dot(normal).abs() < 1e-5 && dpdv.dot(normal).abs() < 1e-5);
    }

    #[test]
    fn lookups_flip_v_and_repeat() {
        // Top row (v near 1) red-ish, bottom row (v near 0) blue.
        let top = [1.0, 0.5, 0.5];
        let bottom = [0.5, 0.5, 1.0];
        let data = [top, top, bottom, bottom].concat();
        let map = NormalMap::from_image(Image::new(2, 2, &["R", "G", "B"], data).unwrap()).unwrap();
        let near_top = map.tangent_space_normal(Vec2::new(0.25, 0.75)).unwrap();
        assert!((near_top - Vec3::X).length() < 1e-6, "{near_top}");
        let near_bottom = map.tangent_space_normal(Vec2::new(1.25, -0.75)).unwrap();
        assert!((near_bottom - Vec3::Z).length() < 1e-6, "{near_bottom}");
    }

    #[test]
    fn grey_gives_no_direction() {
        let map = constant_map([0.5, 0.5, 0.5]);
        assert!(map.tangent_space_normal(Vec2::splat(0.5)).is_none());
        assert!(map.shading_tangents(&flat_hit()).is_none());
    }

    #[test]
    fn an_image_without_colour_channels_is_refused() {
        let grey = Image::new(1, 1, &["Y"], vec![0.5]).unwrap();
        assert!(NormalMap::from_image(grey).is_none());
    }

    #[test]
    fn files_are_read_once_and_missing_ones_name_the_file() {
        let dir = std::env::temp_dir().join(format!("rpbrt-normal-map-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("flat.exr");
        Image::new(1, 1, &["R", "G", "B"], vec![0.5, 0.5, 1.0])
            .unwrap()
            .write_exr(&path, false)
            .unwrap();
        let at = Location::nowhere();
        let mut cache = NormalMapCache::default();
        let first = cache.get(&path, &at).unwrap();
        let second = cache.get(&path, &at).unwrap();
        assert!(Arc::ptr_eq(&first, &second));
        assert_eq!(cache.len(), 1);
        let missing = dir.join("missing.png");
        let message = cache.get(&missing, &at).unwrap_err().to_string();
        assert!(
            message.contains("cannot read") && message.contains("missing.png"),
            "{message}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
