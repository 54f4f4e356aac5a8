//! The `imagemap` texture: an image file looked up through a MIP map
//! (pbrt-v4's `FloatImageTexture` / `SpectrumImageTexture`).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `filename` | string | required | PNG, EXR, PFM, TGA (or JPEG) file, relative to the scene file |
//! | `wrap` | string | `repeat` | outside [0,1]²: `repeat`, `black`, `clamp`, `octahedralsphere` |
//! | `filter` | string | `bilinear` | `point`, `bilinear`, `trilinear`, `ewa` (MIP level from the ray differentials) |
//! | `maxanisotropy` | float | 8 | EWA ellipse eccentricity limit |
//! | `encoding` | string | `sRGB` for PNG, else `linear` | `sRGB`, `linear` or `gamma G` (8-bit PNG only, as pbrt-v4) |
//! | `scale` | float | 1 | multiplies the looked-up value |
//! | `invert` | bool | false | 1 − value (after `scale`), clamped at 0 |
//! | `mapping` … | | `uv` | see [`super::mapping`] |
//!
//! As in pbrt-v4, t is flipped (t = 1 − t) so v = 0 is the image's bottom
//! row, and a spectrum texture turns the RGB into a spectrum of the kind
//! its use asks for (albedo RGB clamped to [0, 1]) in sRGB, the colour
//! space pbrt-v4 assumes for image textures. Images with the same file and
//! settings are loaded once ([`ImageCache`]).

use super::mapping::{TexCoord2D, TextureMapping2D};
use super::TextureEvalContext;
use crate::error::{image_file_error, scene_error, Result};
use crate::image::mipmap::DEFAULT_MAX_ANISOTROPY;
use crate::image::{ColorEncoding, FilterFunction, MIPMap, WrapMode};
use crate::scene_description::ColorSpaceName;
use crate::scene_description::ParamSet;
use crate::spectrum::color_space::{self, SpectrumKind};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Mat4, Vec2, Vec3};
use pbrt_parser::Location;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// MIP maps already built, by file and the settings that shape them.
#[derive(Default)]
pub struct ImageCache {
    mipmaps: HashMap<(PathBuf, String), Arc<MIPMap>>,
}

impl ImageCache {
    pub fn len(&self) -> usize {
        self.mipmaps.len()
    }

    pub fn is_empty(&self) -> bool {
        self.mipmaps.is_empty()
    }

    fn get(
        &mut self,
        path: &Path,
        wrap: WrapMode,
        filter: FilterFunction,
        encoding: Option<ColorEncoding>,
        max_anisotropy: f32,
        location: &Location,
    ) -> Result<Arc<MIPMap>> {
        let key = (
            path.to_path_buf(),
            format!("{wrap:?} {filter:?} {encoding:?} {max_anisotropy}"),
        );
        if let Some(m) = self.mipmaps.get(&key) {
            return Ok(Arc::clone(m));
        }
        let mipmap = match MIPMap::from_file(path, wrap, filter, encoding) {
            Ok(m) => Arc::new(m.with_max_anisotropy(max_anisotropy)),
            Err(e) => return Err(image_file_error("imagemap texture", e, location)),
        };
        self.mipmaps.insert(key, Arc::clone(&mipmap));
        Ok(mipmap)
    }
}

#[derive(Clone, Debug)]
pub struct ImageTexture {
    mipmap: Arc<MIPMap>,
    mapping: TextureMapping2D,
    scale: f32,
    invert: bool,
}

impl ImageTexture {
    pub fn create(
        params: &ParamSet,
        render_from_texture: Mat4,
        base_directory: &Path,
        cache: &mut ImageCache,
        location: &Location,
    ) -> Result<ImageTexture> {
        let mapping = TextureMapping2D::create(params, render_from_texture, location)?;
        let max_anisotropy = params.float("maxanisotropy", DEFAULT_MAX_ANISOTROPY as f64)? as f32;
        let filter_name = params.string("filter", "bilinear")?;
        let Some(filter) = FilterFunction::parse(&filter_name) else {
            return scene_error(
                format!("\"{filter_name}\": filter function unknown (expected point, bilinear, trilinear or ewa)"),
                location,
            );
        };
        let wrap_name = params.string("wrap", "repeat")?;
        let Some(wrap) = WrapMode::parse(&wrap_name) else {
            return scene_error(
                format!("\"{wrap_name}\": wrap mode unknown (expected repeat, black, clamp or octahedralsphere)"),
                location,
            );
        };
        let scale = params.float("scale", 1.0)? as f32;
        let invert = params.bool("invert", false)?;
        let (filename, filename_at) = params
            .string_at("filename")?
            .unwrap_or_else(|| (String::new(), location.clone()));
        if filename.is_empty() {
            return scene_error("imagemap texture: \"filename\" must be given", location);
        }
        let encoding = match params.find("encoding", &[pbrt_parser::ParamType::String])? {
            None => None,
            Some(_) => {
                let text = params.string("encoding", "")?;
                match ColorEncoding::parse(&text) {
                    Some(e) => Some(e),
                    None => {
                        return scene_error(
                            format!("\"{text}\": unknown color encoding (expected sRGB, linear or \"gamma G\")"),
                            location,
                        )
                    }
                }
            }
        };
        let path = pbrt_parser::resolve_path(base_directory, &filename);
        let mipmap = cache.get(&path, wrap, filter, encoding, max_anisotropy, &filename_at)?;
        Ok(ImageTexture::new(mipmap, mapping, scale, invert))
    }

    pub fn new(mipmap: Arc<MIPMap>, mapping: TextureMapping2D, scale: f32, invert: bool) -> Self {
        ImageTexture {
            mipmap,
            mapping,
            scale,
            invert,
        }
    }

    /// Texture coordinates with t flipped, as pbrt-v4 looks images up.
    fn coords(&self, ctx: &TextureEvalContext) -> TexCoord2D {
        let mut c = self.mapping.map(ctx);
        c.st.y = 1.0 - c.st.y;
        c
    }

    pub fn evaluate_float(&self, ctx: &TextureEvalContext) -> f32 {
        let c = self.coords(ctx);
        let v = self.scale
            * self
                .mipmap
                .lookup_float(c.st, Vec2::new(c.dsdx, c.dtdx), Vec2::new(c.dsdy, c.dtdy));
        if self.invert {
            (1.0 - v).max(0.0)
        } else {
            v
        }
    }

    pub fn evaluate_rgb(&self, ctx: &TextureEvalContext) -> Vec3 {
        let c = self.coords(ctx);
        let rgb = self.scale
            * Vec3::from(self.mipmap.lookup_rgb(
                c.st,
                Vec2::new(c.dsdx, c.dtdx),
                Vec2::new(c.dsdy, c.dtdy),
            ));
        let rgb = if self.invert { Vec3::ONE - rgb } else { rgb };
        rgb.max(Vec3::ZERO)
    }

    pub fn evaluate_spectrum(
        &self,
        ctx: &TextureEvalContext,
        kind: SpectrumKind,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        color_space::get(ColorSpaceName::Srgb)
            .rgb_to_spectrum(self.evaluate_rgb(ctx), kind)
            .sample(lambda)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;

    /// A 4×4 grey image whose texel (x, y) (y = 0 the top row) is x + 4y.
    fn ramp(wrap: WrapMode, filter: FilterFunction) -> ImageTexture {
        let data = (0..16).map(|i| i as f32).collect();
        let image = Image::new(4, 4, &["Y"], data).unwrap();
        let mipmap = MIPMap::new(image, wrap, filter).unwrap();
        let mapping = TextureMapping2D::Uv {
            scale: Vec2::ONE,
            delta: Vec2::ZERO,
        };
        ImageTexture::new(Arc::new(mipmap), mapping, 1.0, false)
    }

    fn at(u: f32, v: f32, footprint: f32) -> TextureEvalContext {
        TextureEvalContext {
            uv: Vec2::new(u, v),
            dudx: footprint,
            dvdy: footprint,
            ..Default::default()
        }
    }

    const WRAPS: [WrapMode; 4] = [
        WrapMode::Repeat,
        WrapMode::Black,
        WrapMode::Clamp,
        WrapMode::OctahedralSphere,
    ];
    const FILTERS: [FilterFunction; 4] = [
        FilterFunction::Point,
        FilterFunction::Bilinear,
        FilterFunction::Trilinear,
        FilterFunction::Ewa,
    ];

    #[test]
    fn texel_centres_read_their_texel_with_v_up() {
        // v = 0.875 is the top row (t = 1 − v), u = 0.375 the second column.
        for wrap in WRAPS {
            for filter in FILTERS {
                let t = ramp(wrap, filter);
                assert_eq!(
                    t.evaluate_float(&at(0.375, 0.875, 0.0)),
                    1.0,
                    "{wrap:?} {filter:?}"
                );
                assert_eq!(
                    t.evaluate_float(&at(0.875, 0.125, 0.0)),
                    15.0,
                    "{wrap:?} {filter:?}"
                );
                assert_eq!(t.evaluate_rgb(&at(0.125, 0.625, 0.0)), Vec3::splat(4.0));
            }
        }
    }

    #[test]
    fn bilinear_interpolates_between_texel_centres() {
        let t = ramp(WrapMode::Clamp, FilterFunction::Bilinear);
        // Halfway between texels 0 and 1 of the top row, and a quarter of
        // the way down towards row 1.
        assert_eq!(t.evaluate_float(&at(0.25, 0.875, 0.0)), 0.5);
        assert_eq!(t.evaluate_float(&at(0.125, 0.8125, 0.0)), 1.0);
        // The point filter takes the nearest texel instead.
        let point = ramp(WrapMode::Clamp, FilterFunction::Point);
        assert_eq!(point.evaluate_float(&at(0.3, 0.875, 0.0)), 1.0);
    }

    #[test]
    fn each_wrap_mode_reads_outside_the_image_its_own_way() {
        // Row 1 (values 4…7), one texel left of the image, then at the
        // left edge (halfway between texel −1 and texel 0).
        let outside = |wrap| {
            let t = ramp(wrap, FilterFunction::Point);
            t.evaluate_float(&at(-0.125, 0.625, 0.0))
        };
        assert_eq!(outside(WrapMode::Repeat), 7.0);
        assert_eq!(outside(WrapMode::Black), 0.0);
        assert_eq!(outside(WrapMode::Clamp), 4.0);
        // Across the left edge of the octahedral square, as pbrt-v4 wraps
        // it: texel (1, 4 − 1 − 1) = 9.
        assert_eq!(outside(WrapMode::OctahedralSphere), 9.0);
        let edge = |wrap| {
            let t = ramp(wrap, FilterFunction::Bilinear);
            t.evaluate_float(&at(0.0, 0.625, 0.0))
        };
        assert_eq!(edge(WrapMode::Repeat), 5.5);
        assert_eq!(edge(WrapMode::Black), 2.0);
        assert_eq!(edge(WrapMode::Clamp), 4.0);
        assert_eq!(edge(WrapMode::OctahedralSphere), 6.5);
    }

    #[test]
    fn footprints_choose_coarser_levels() {
        for filter in FILTERS {
            // A footprint as wide as the image reads the 1×1 level: the mean.
            let t = ramp(WrapMode::Repeat, filter);
            let v = t.evaluate_float(&at(0.375, 0.875, 1.0));
            assert!((v - 7.5).abs() < 1e-5, "{filter:?}: {v}");
        }
        // A one-texel footprint (filter width 2 × ¼) reads level 1, whose
        // texel (0, 0) averages texels 0, 1, 4, 5.
        let point = ramp(WrapMode::Repeat, FilterFunction::Point);
        assert_eq!(point.evaluate_float(&at(0.125, 0.875, 0.25)), 2.5);
        // Trilinear filtering of the same footprint blends levels 1 and 2
        // by the level's fraction (0 here): level 1 bilinearly.
        let trilinear = ramp(WrapMode::Clamp, FilterFunction::Trilinear);
        assert_eq!(trilinear.evaluate_float(&at(0.25, 0.75, 0.25)), 2.5);
    }

    #[test]
    fn scale_and_invert_apply_after_the_lookup() {
        let mut t = ramp(WrapMode::Clamp, FilterFunction::Bilinear);
        t.scale = 0.25;
        assert_eq!(t.evaluate_float(&at(0.375, 0.875, 0.0)), 0.25);
        t.invert = true;
        assert_eq!(t.evaluate_float(&at(0.375, 0.875, 0.0)), 0.75);
        // Inverted values below zero are clamped.
        assert_eq!(t.evaluate_float(&at(0.875, 0.125, 0.0)), 0.0);
        assert_eq!(t.evaluate_rgb(&at(0.875, 0.125, 0.0)), Vec3::ZERO);
    }

    #[test]
    fn the_cache_loads_an_image_once_per_setting() {
        let dir = std::env::temp_dir().join(format!("rpbrt-imagemap-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("ramp.pfm");
        let data = (0..12).map(|i| i as f32 / 12.0).collect();
        Image::new(2, 2, &["R", "G", "B"], data)
            .unwrap()
            .write(&path)
            .unwrap();
        let location = Location::nowhere();
        let mut cache = ImageCache::default();
        let (wrap, filter) = (WrapMode::Repeat, FilterFunction::Bilinear);
        let a = cache
            .get(&path, wrap, filter, None, 8.0, &location)
            .unwrap();
        let b = cache
            .get(&path, wrap, filter, None, 8.0, &location)
            .unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        cache
            .get(&path, WrapMode::Clamp, filter, None, 8.0, &location)
            .unwrap();
        assert_eq!(cache.len(), 2);
        let missing = cache.get(&dir.join("absent.png"), wrap, filter, None, 8.0, &location);
        assert!(missing.is_err());
        std::fs::remove_dir_all(&dir).ok();
    }
}
