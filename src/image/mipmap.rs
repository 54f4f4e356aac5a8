//! MIP maps: filtered image-texture lookups as pbrt-v4 performs them.
//!
//! A lookup gets texture coordinates `st` ∈ [0, 1]² and their screen-space
//! differentials `dst0`, `dst1` (how `st` changes from one pixel to the
//! next). Those choose how much of the texture one pixel covers, hence which
//! pyramid level(s) to read and how to filter them:
//!
//! * `Point`, `Bilinear`, `Trilinear` pick a level from the largest
//!   differential component (filter width = 2·max |component|; level =
//!   levels − 1 + log₂ width) and read it by nearest texel, bilinearly, or
//!   bilinearly in two adjacent levels blended by the level's fraction.
//! * `Ewa` filters an elliptical footprint: the differentials are the
//!   ellipse's axes (the minor one lengthened so the eccentricity is at most
//!   `max_anisotropy`), the level comes from the minor axis, and texels in
//!   the ellipse are summed with Gaussian weights, in two levels blended.
//!
//! pbrt-v4's quirks are kept on purpose, so textures look the same:
//! trilinear filtering does not blend between levels 0 and 1 (any level
//! below 1 reads level 0 alone), a float lookup of a point texel or an EWA
//! footprint reads the first channel while a bilinear float lookup averages
//! R, G, B (or reads A of an RGBA image).

use super::ewa_weights::ewa_weight;
use super::pyramid::build_pyramid;
use super::{ColorEncoding, Image, ImageError, WrapMode};
use glam::{IVec2, Vec2, Vec3};
use std::ops::{Add, Mul};
use std::path::Path;

/// How a MIP map filters (pbrt-v4's `filter` texture parameter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterFunction {
    Point,
    Bilinear,
    Trilinear,
    Ewa,
}

impl FilterFunction {
    /// Parses pbrt-v4's `filter` parameter values.
    pub fn parse(text: &str) -> Option<FilterFunction> {
        match text {
            "point" => Some(FilterFunction::Point),
            "bilinear" => Some(FilterFunction::Bilinear),
            "trilinear" => Some(FilterFunction::Trilinear),
            "ewa" | "EWA" => Some(FilterFunction::Ewa),
            _ => None,
        }
    }
}

/// pbrt-v4's default limit on EWA ellipse eccentricity (`maxanisotropy`).
pub const DEFAULT_MAX_ANISOTROPY: f32 = 8.0;

/// An image pyramid with its wrap mode and filter.
#[derive(Clone, Debug)]
pub struct MIPMap {
    /// Level 0 is the full-resolution (power-of-two) image, the last is 1×1;
    /// all linear, with 1, 3 (RGB) or 4 (RGBA) channels.
    levels: Vec<Image>,
    wrap: WrapMode,
    filter: FilterFunction,
    max_anisotropy: f32,
}

impl MIPMap {
    /// Builds the pyramid of `image` (decoded to linear with its encoding).
    ///
    /// As pbrt-v4 does for image textures, a multi-channel image keeps its
    /// R, G, B channels, plus A unless alpha is 1 everywhere; an image with
    /// neither R, G, B nor a single channel is an error.
    pub fn new(image: Image, wrap: WrapMode, filter: FilterFunction) -> Result<MIPMap, ImageError> {
        let image = texture_channels(image)?;
        let levels = build_pyramid(&image, wrap)?;
        Ok(MIPMap {
            levels,
            wrap,
            filter,
            max_anisotropy: DEFAULT_MAX_ANISOTROPY,
        })
    }

    /// Reads an image file and builds its MIP map. `encoding` (pbrt-v4's
    /// `encoding` texture parameter) overrides the sRGB decoding of PNG
    /// files only: pbrt-v4 always decodes TGA and JPEG as sRGB, and
    /// floating-point files are linear. Errors name the file.
    pub fn from_file(
        path: impl AsRef<Path>,
        wrap: WrapMode,
        filter: FilterFunction,
        encoding: Option<ColorEncoding>,
    ) -> Result<MIPMap, ImageError> {
        let path = path.as_ref();
        let mut image = Image::read(path)?;
        let is_png = path
            .extension()
            .is_some_and(|extension| extension.eq_ignore_ascii_case("png"));
        if let (Some(encoding), true) = (encoding, is_png) {
            image = image.with_encoding(encoding);
        }
        MIPMap::new(image, wrap, filter).map_err(|error| match error {
            ImageError::TextureChannels(_) | ImageError::Invalid(_) => ImageError::Malformed {
                path: path.into(),
                message: error.to_string(),
            },
            other => other,
        })
    }

    /// Limits EWA ellipse eccentricity (pbrt-v4's `maxanisotropy`, default 8).
    pub fn with_max_anisotropy(mut self, max_anisotropy: f32) -> MIPMap {
        self.max_anisotropy = max_anisotropy;
        self
    }

    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Resolution of `level` (clamped to the existing levels).
    pub fn level_resolution(&self, level: usize) -> IVec2 {
        self.level(level).resolution()
    }

    /// The linear image of `level` (clamped to the existing levels).
    pub fn level(&self, level: usize) -> &Image {
        &self.levels[level.min(self.levels.len() - 1)]
    }

    pub fn wrap_mode(&self) -> WrapMode {
        self.wrap
    }

    pub fn filter(&self) -> FilterFunction {
        self.filter
    }

    /// Filtered RGB at `st` for a pixel footprint with differentials
    /// `dst0`, `dst1`. Single-channel images give grey.
    pub fn lookup_rgb(&self, st: Vec2, dst0: Vec2, dst1: Vec2) -> [f32; 3] {
        self.filtered::<Vec3>(st, dst0, dst1).to_array()
    }

    /// Filtered scalar at `st` (see the module description for which
    /// channel a multi-channel image gives).
    pub fn lookup_float(&self, st: Vec2, dst0: Vec2, dst1: Vec2) -> f32 {
        self.filtered::<f32>(st, dst0, dst1)
    }

    /// RGB of texel `p` of `level`, outside the image as the wrap mode says.
    pub fn texel(&self, level: usize, p: IVec2) -> [f32; 3] {
        Vec3::texel(self.level(level), p, self.wrap).to_array()
    }

    /// First channel of texel `p` of `level`.
    pub fn texel_float(&self, level: usize, p: IVec2) -> f32 {
        f32::texel(self.level(level), p, self.wrap)
    }

    /// Bilinearly interpolated RGB of `level` at `st` (texel centres at
    /// half-integers over the level's resolution).
    pub fn bilerp(&self, level: usize, st: Vec2) -> [f32; 3] {
        Vec3::bilerp(self.level(level), st, self.wrap).to_array()
    }

    /// Bilinearly interpolated scalar of `level` at `st`: the channel of a
    /// single-channel image, the RGB average, or A of an RGBA image.
    pub fn bilerp_float(&self, level: usize, st: Vec2) -> f32 {
        f32::bilerp(self.level(level), st, self.wrap)
    }

    fn filtered<T: TexelValue>(&self, st: Vec2, mut dst0: Vec2, mut dst1: Vec2) -> T {
        let top_level = self.levels.len() - 1;
        if self.filter != FilterFunction::Ewa {
            let width = 2.0 * dst0.abs().max_element().max(dst1.abs().max_element());
            // Level at which the filter width covers about one texel.
            let level = top_level as f32 + width.max(1e-8).log2();
            if level >= top_level as f32 {
                return T::texel(&self.levels[top_level], IVec2::ZERO, self.wrap);
            }
            // `as` maps NaN (from NaN differentials) to 0.
            let level_index = (level.floor().max(0.0) as usize).min(top_level);
            return match self.filter {
                FilterFunction::Point => {
                    let image = &self.levels[level_index];
                    let resolution = image.resolution().as_vec2();
                    let texel = (st * resolution - Vec2::splat(0.5)).round();
                    T::texel(image, IVec2::new(texel.x as i32, texel.y as i32), self.wrap)
                }
                FilterFunction::Bilinear => T::bilerp(&self.levels[level_index], st, self.wrap),
                _ if level_index == 0 => T::bilerp(&self.levels[0], st, self.wrap),
                _ => {
                    let fraction = level - level_index as f32;
                    let lower = T::bilerp(&self.levels[level_index], st, self.wrap);
                    let upper = T::bilerp(&self.levels[level_index + 1], st, self.wrap);
                    lower * (1.0 - fraction) + upper * fraction
                }
            };
        }

        // EWA: dst0 becomes the major axis, dst1 the minor.
        if dst0.length_squared() < dst1.length_squared() {
            std::mem::swap(&mut dst0, &mut dst1);
        }
        let major_length = dst0.length();
        let mut minor_length = dst1.length();
        if minor_length * self.max_anisotropy < major_length && minor_length > 0.0 {
            let scale = major_length / (minor_length * self.max_anisotropy);
            dst1 *= scale;
            minor_length *= scale;
        }
        if minor_length == 0.0 {
            return T::bilerp(&self.levels[0], st, self.wrap);
        }
        let lod = (top_level as f32 + minor_length.log2()).max(0.0);
        let lod_floor = lod.floor();
        let fraction = lod - lod_floor;
        let level_index = lod_floor as usize; // saturating; NaN → 0
        self.ewa::<T>(level_index, st, dst0, dst1) * (1.0 - fraction)
            + self.ewa::<T>(level_index.saturating_add(1), st, dst0, dst1) * fraction
    }

    /// Gaussian-weighted sum over the texels of `level` inside the ellipse
    /// with axes `dst0`, `dst1` (in [0, 1]² units) centred at `st`.
    fn ewa<T: TexelValue>(&self, level: usize, st: Vec2, dst0: Vec2, dst1: Vec2) -> T {
        if level >= self.levels.len() {
            return T::texel(&self.levels[self.levels.len() - 1], IVec2::ZERO, self.wrap);
        }
        let image = &self.levels[level];
        // To this level's texel units, with texel centres at integers.
        let resolution = image.resolution().as_vec2();
        let centre = st * resolution - Vec2::splat(0.5);
        let axis0 = dst0 * resolution;
        let axis1 = dst1 * resolution;

        // Implicit ellipse A s² + B s t + C t² < 1 through the axes, grown by
        // one texel so it always covers some texel centre.
        let mut a = axis0.y * axis0.y + axis1.y * axis1.y + 1.0;
        let mut b = -2.0 * (axis0.x * axis0.y + axis1.x * axis1.y);
        let mut c = axis0.x * axis0.x + axis1.x * axis1.x + 1.0;
        let inverse_f = 1.0 / (a * c - b * b * 0.25);
        a *= inverse_f;
        b *= inverse_f;
        c *= inverse_f;

        // The ellipse's bounding box in texels.
        let determinant = -b * b + 4.0 * a * c;
        let inverse_determinant = 1.0 / determinant;
        let s_extent = 2.0 * inverse_determinant * (determinant * c).max(0.0).sqrt();
        let t_extent = 2.0 * inverse_determinant * (a * determinant).max(0.0).sqrt();
        // Saturating casts keep degenerate (huge or NaN) footprints finite;
        // the box is also limited to a few times the level's size, beyond
        // which every texel has been visited anyway (wrapping repeats them).
        let limit = |extent: f32| 4.0 * extent + 4.0;
        let s0 = (centre.x - s_extent)
            .ceil()
            .max(centre.x - limit(resolution.x)) as i32;
        let s1 = (centre.x + s_extent)
            .floor()
            .min(centre.x + limit(resolution.x)) as i32;
        let t0 = (centre.y - t_extent)
            .ceil()
            .max(centre.y - limit(resolution.y)) as i32;
        let t1 = (centre.y + t_extent)
            .floor()
            .min(centre.y + limit(resolution.y)) as i32;

        let mut sum = T::default();
        let mut weight_sum = 0.0;
        for t in t0..=t1 {
            let tt = t as f32 - centre.y;
            for s in s0..=s1 {
                let ss = s as f32 - centre.x;
                let radius_squared = a * ss * ss + b * ss * tt + c * tt * tt;
                if radius_squared < 1.0 {
                    let weight = ewa_weight(radius_squared);
                    sum = sum + T::texel(image, IVec2::new(s, t), self.wrap) * weight;
                    weight_sum += weight;
                }
            }
        }
        if weight_sum > 0.0 {
            sum * (1.0 / weight_sum)
        } else {
            // Only reachable with degenerate input; pbrt-v4 would divide by 0.
            T::bilerp(image, st, self.wrap)
        }
    }
}

/// The channels pbrt-v4 keeps for an image texture (see [`MIPMap::new`]).
fn texture_channels(image: Image) -> Result<Image, ImageError> {
    if image.channel_count() == 1 {
        return Ok(image);
    }
    if let Some(rgba) = image.select_channels(&["R", "G", "B", "A"]) {
        let encoding = rgba.encoding();
        let alpha_is_one = rgba
            .data()
            .chunks_exact(4)
            .all(|pixel| encoding.to_linear(pixel[3]) == 1.0);
        if !alpha_is_one {
            return Ok(rgba);
        }
    }
    image
        .select_channels(&["R", "G", "B"])
        .ok_or_else(|| ImageError::TextureChannels(image.channels().to_vec()))
}

/// What a lookup returns: RGB (`Vec3`) or a scalar (`f32`), with pbrt-v4's
/// rules for reading each from 1-, 3- or 4-channel levels.
trait TexelValue: Copy + Default + Add<Output = Self> + Mul<f32, Output = Self> {
    fn texel(image: &Image, p: IVec2, wrap: WrapMode) -> Self;
    fn bilerp(image: &Image, st: Vec2, wrap: WrapMode) -> Self;
}

impl TexelValue for Vec3 {
    fn texel(image: &Image, p: IVec2, wrap: WrapMode) -> Vec3 {
        if image.channel_count() >= 3 {
            Vec3::new(
                image.channel(p, 0, wrap),
                image.channel(p, 1, wrap),
                image.channel(p, 2, wrap),
            )
        } else {
            Vec3::splat(image.channel(p, 0, wrap))
        }
    }

    fn bilerp(image: &Image, st: Vec2, wrap: WrapMode) -> Vec3 {
        if image.channel_count() >= 3 {
            Vec3::new(
                image.bilerp_channel(st, 0, wrap),
                image.bilerp_channel(st, 1, wrap),
                image.bilerp_channel(st, 2, wrap),
            )
        } else {
            Vec3::splat(image.bilerp_channel(st, 0, wrap))
        }
    }
}

impl TexelValue for f32 {
    fn texel(image: &Image, p: IVec2, wrap: WrapMode) -> f32 {
        image.channel(p, 0, wrap)
    }

    fn bilerp(image: &Image, st: Vec2, wrap: WrapMode) -> f32 {
        match image.channel_count() {
            3 => {
                (image.bilerp_channel(st, 0, wrap)
                    + image.bilerp_channel(st, 1, wrap)
                    + image.bilerp_channel(st, 2, wrap))
                    / 3.0
            }
            4 => image.bilerp_channel(st, 3, wrap),
            _ => image.bilerp_channel(st, 0, wrap),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::PixelFormat;
    use super::*;

    const ALL_FILTERS: [FilterFunction; 4] = [
        FilterFunction::Point,
        FilterFunction::Bilinear,
        FilterFunction::Trilinear,
        FilterFunction::Ewa,
    ];

    /// Footprints from tiny to wider than the texture, isotropic and not.
    fn footprints() -> Vec<(Vec2, Vec2)> {
        let mut footprints = Vec::new();
        for scale in [0.0, 1e-4, 1.0 / 300.0, 0.01, 0.07, 0.3, 2.0] {
            footprints.push((Vec2::new(scale, 0.0), Vec2::new(0.0, scale)));
            footprints.push((
                Vec2::new(scale, scale * 0.5),
                Vec2::new(-scale * 0.05, scale * 0.1),
            ));
        }
        footprints
    }

    #[test]
    fn constant_image_looks_up_as_the_constant_everywhere() {
        let rgb = [0.2, 0.5, 0.9];
        for (width, height) in [(64, 32), (37, 20), (1, 1)] {
            let image = Image::filled(width, height, &["R", "G", "B"], &rgb).unwrap();
            for wrap in [
                WrapMode::Repeat,
                WrapMode::Clamp,
                WrapMode::OctahedralSphere,
            ] {
                for filter in ALL_FILTERS {
                    let mipmap = MIPMap::new(image.clone(), wrap, filter).unwrap();
                    for level in 0..mipmap.level_count() {
                        let texel = mipmap.texel(level, IVec2::new(1, 0));
                        let bilerp = mipmap.bilerp(level, Vec2::new(0.3, 0.8));
                        for (value, expected) in texel.iter().chain(&bilerp).zip(rgb.iter().cycle())
                        {
                            assert!((value - expected).abs() < 1e-5, "level {level}: {value}");
                        }
                    }
                    for (dst0, dst1) in footprints() {
                        for st in [
                            Vec2::new(0.5, 0.5),
                            Vec2::new(0.01, 0.99),
                            Vec2::new(0.7, 0.2),
                        ] {
                            let looked_up = mipmap.lookup_rgb(st, dst0, dst1);
                            for (value, expected) in looked_up.iter().zip(rgb) {
                                assert!(
                                    (value - expected).abs() < 1e-5,
                                    "{filter:?} {wrap:?} {width}×{height} at {st} {dst0} {dst1}: {looked_up:?}"
                                );
                            }
                            let scalar = mipmap.lookup_float(st, dst0, dst1);
                            // Point texels and EWA read R; bilinear reads the average.
                            assert!(
                                (scalar - rgb[0]).abs() < 1e-5 || (scalar - 1.6 / 3.0).abs() < 1e-5,
                                "{filter:?}: {scalar}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn level_count_and_resolution_for_256_by_128() {
        let image = Image::filled(256, 128, &["Y"], &[1.0]).unwrap();
        let mipmap = MIPMap::new(image, WrapMode::Repeat, FilterFunction::Bilinear).unwrap();
        assert_eq!(mipmap.level_count(), 9);
        assert_eq!(mipmap.level_resolution(0), IVec2::new(256, 128));
        assert_eq!(mipmap.level_resolution(7), IVec2::new(2, 1));
        assert_eq!(mipmap.level_resolution(8), IVec2::new(1, 1));
    }

    #[test]
    fn bilinear_of_a_checker_at_centres_and_midpoints() {
        let checker = Image::new(2, 2, &["Y"], vec![0.0, 1.0, 1.0, 0.0]).unwrap();
        let mipmap = MIPMap::new(checker, WrapMode::Repeat, FilterFunction::Bilinear).unwrap();
        let at = |s, t| mipmap.bilerp_float(0, Vec2::new(s, t));
        assert_eq!(at(0.25, 0.25), 0.0);
        assert_eq!(at(0.75, 0.25), 1.0);
        assert_eq!(at(0.25, 0.75), 1.0);
        assert_eq!(at(0.75, 0.75), 0.0);
        assert_eq!(at(0.5, 0.25), 0.5);
        assert_eq!(at(0.75, 0.5), 0.5);
        assert_eq!(at(0.5, 0.5), 0.5);
        // Repeat wrap: the image's edge is between the last and first texel.
        assert_eq!(at(0.0, 0.25), 0.5);
        assert_eq!(mipmap.bilerp(0, Vec2::new(0.75, 0.25)), [1.0; 3]);
        assert_eq!(mipmap.bilerp(1, Vec2::new(0.1, 0.6)), [0.5; 3]);
        // A tiny footprint reads level 0 bilinearly.
        let tiny = Vec2::new(1e-4, 0.0);
        assert_eq!(
            mipmap.lookup_float(Vec2::new(0.75, 0.25), tiny, tiny.perp()),
            1.0
        );
    }

    #[test]
    fn filters_choose_levels_like_pbrt() {
        // 8×8 with distinct level averages: left half 0, right half 1 at
        // level 0 means level 3 (1×1) is 0.5.
        let data: Vec<f32> = (0..64).map(|i| if i % 8 < 4 { 0.0 } else { 1.0 }).collect();
        let image = Image::new(8, 8, &["Y"], data).unwrap();
        let st = Vec2::new(0.9, 0.5);
        let lookup = |filter, width: f32| {
            let mipmap = MIPMap::new(image.clone(), WrapMode::Clamp, filter).unwrap();
            mipmap.lookup_float(st, Vec2::new(width / 2.0, 0.0), Vec2::ZERO)
        };
        // Width ≥ 1 covers the whole texture: the 1×1 level.
        assert_eq!(lookup(FilterFunction::Point, 1.0), 0.5);
        assert_eq!(lookup(FilterFunction::Bilinear, 4.0), 0.5);
        // Width 1/8 → level 0 exactly: texel (7, 4) is 1.
        assert_eq!(lookup(FilterFunction::Point, 1.0 / 8.0), 1.0);
        // Trilinear between levels 0 and 1 does not blend (pbrt-v4 quirk).
        let mipmap =
            MIPMap::new(image.clone(), WrapMode::Clamp, FilterFunction::Trilinear).unwrap();
        let level_0_to_1 = 1.0 / 8.0 * 2f32.powf(0.5);
        assert_eq!(
            mipmap.lookup_float(st, Vec2::new(level_0_to_1 / 2.0, 0.0), Vec2::ZERO),
            mipmap.bilerp_float(0, st)
        );
        // Between levels 1 and 2 it blends by the fraction.
        let level_one_and_a_quarter = 1.0 / 8.0 * 2f32.powf(1.25);
        let blended = mipmap.lookup_float(
            st,
            Vec2::new(level_one_and_a_quarter / 2.0, 0.0),
            Vec2::ZERO,
        );
        let expected = 0.75 * mipmap.bilerp_float(1, st) + 0.25 * mipmap.bilerp_float(2, st);
        assert!((blended - expected).abs() < 1e-5, "{blended} vs {expected}");
    }

    #[test]
    fn ewa_averages_a_wide_footprint_and_stays_within_range() {
        // Stripes of 0 and 1 along x: a footprint spanning many stripes
        // averages them, a footprint along a stripe keeps its value.
        let data: Vec<f32> = (0..64 * 64).map(|i| (i % 2) as f32).collect();
        let image = Image::new(64, 64, &["Y"], data).unwrap();
        let mipmap = MIPMap::new(image, WrapMode::Repeat, FilterFunction::Ewa).unwrap();
        let across = mipmap.lookup_float(
            Vec2::new(0.5, 0.5),
            Vec2::new(0.2, 0.0),
            Vec2::new(0.0, 0.2),
        );
        assert!((across - 0.5).abs() < 0.02, "{across}");
        // Long and thin along y, thinner than a texel across: no blurring
        // across stripes at level 0 beyond the one-texel minimum.
        let centre_of_texel_3 = Vec2::new(3.5 / 64.0, 0.5);
        let along =
            mipmap.lookup_float(centre_of_texel_3, Vec2::new(0.0, 0.1), Vec2::new(1e-6, 0.0));
        assert!(along > 0.5, "{along}");
        for (dst0, dst1) in footprints() {
            let value = mipmap.lookup_float(Vec2::new(0.3, 0.6), dst0, dst1);
            assert!((0.0..=1.0).contains(&value), "{dst0} {dst1}: {value}");
        }
        // Degenerate footprints neither panic nor loop for long.
        let _ = mipmap.lookup_float(
            Vec2::new(0.5, 0.5),
            Vec2::new(1e30, 1.0),
            Vec2::new(0.0, 1e-30),
        );
        let _ = mipmap.lookup_float(Vec2::new(f32::NAN, 0.5), Vec2::splat(f32::NAN), Vec2::ZERO);
        let _ = mipmap.lookup_rgb(Vec2::new(0.5, 0.5), Vec2::splat(f32::INFINITY), Vec2::ONE);
    }

    #[test]
    fn keeps_texture_channels_like_pbrt() {
        let opaque = Image::filled(2, 2, &["R", "G", "B", "A"], &[0.1, 0.2, 0.3, 1.0]).unwrap();
        let mipmap = MIPMap::new(opaque, WrapMode::Clamp, FilterFunction::Bilinear).unwrap();
        assert_eq!(mipmap.level(0).channels(), ["R", "G", "B"]);
        assert!(
            (mipmap.bilerp_float(0, Vec2::splat(0.5)) - 0.2).abs() < 1e-6,
            "RGB average"
        );

        let translucent =
            Image::filled(2, 2, &["R", "G", "B", "A"], &[0.1, 0.2, 0.3, 0.5]).unwrap();
        let mipmap = MIPMap::new(translucent, WrapMode::Clamp, FilterFunction::Bilinear).unwrap();
        assert_eq!(mipmap.level(0).channels(), ["R", "G", "B", "A"]);
        assert_eq!(mipmap.bilerp_float(0, Vec2::splat(0.5)), 0.5, "alpha");
        assert_eq!(mipmap.bilerp(0, Vec2::splat(0.5)), [0.1, 0.2, 0.3]);

        let unusable = Image::filled(1, 1, &["U", "V"], &[0.0, 0.0]).unwrap();
        assert!(matches!(
            MIPMap::new(unusable, WrapMode::Clamp, FilterFunction::Point),
            Err(ImageError::TextureChannels(_))
        ));
    }

    #[test]
    fn from_file_applies_the_encoding_parameter_to_png_only() {
        use super::super::atomic_write::test_directory::TestDirectory;
        let directory = TestDirectory::new("mipmap-file");
        let grey = [128u8; 4];
        for (name, format) in [
            ("grey.png", ::image::ImageFormat::Png),
            ("grey.tga", ::image::ImageFormat::Tga),
        ] {
            ::image::save_buffer_with_format(
                directory.join(name),
                &grey,
                2,
                2,
                ::image::ExtendedColorType::L8,
                format,
            )
            .unwrap();
        }
        let texel = |name: &str, encoding| {
            MIPMap::from_file(
                directory.join(name),
                WrapMode::Repeat,
                FilterFunction::Point,
                encoding,
            )
            .unwrap()
            .texel_float(0, IVec2::ZERO)
        };
        let srgb_grey = super::super::color_encoding::srgb_to_linear(128.0 / 255.0);
        assert_eq!(texel("grey.png", None), srgb_grey);
        assert_eq!(
            texel("grey.png", Some(ColorEncoding::Linear)),
            128.0 / 255.0
        );
        assert_eq!(texel("grey.tga", Some(ColorEncoding::Linear)), srgb_grey);
        let missing = MIPMap::from_file(
            directory.join("none.png"),
            WrapMode::Clamp,
            FilterFunction::Ewa,
            None,
        );
        assert!(missing.is_err_and(|error| error.to_string().contains("none.png")));
    }

    #[test]
    fn eight_bit_textures_are_decoded_to_linear() {
        let image = Image::filled(2, 2, &["Y"], &[128.0 / 255.0])
            .unwrap()
            .with_encoding(ColorEncoding::Srgb)
            .with_format(PixelFormat::U8);
        let mipmap =
            MIPMap::new(image.clone(), WrapMode::Repeat, FilterFunction::Trilinear).unwrap();
        let value = mipmap.lookup_float(Vec2::splat(0.5), Vec2::splat(0.2), Vec2::ZERO);
        assert!((value - 0.215_860_5).abs() < 1e-6, "{value}");
        let linear = MIPMap::new(
            image.with_encoding(ColorEncoding::Linear),
            WrapMode::Repeat,
            FilterFunction::Point,
        )
        .unwrap();
        assert_eq!(linear.texel_float(0, IVec2::ZERO), 128.0 / 255.0);
    }
}
