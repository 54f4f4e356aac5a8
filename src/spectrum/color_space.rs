//! RGB colour spaces: primaries and white, the matrices to and from XYZ,
//! and turning a scene's RGB values into spectra.

use std::sync::{Arc, OnceLock};
use std::time::Instant;

use glam::{DMat3, Mat3, Vec2, Vec3};

use super::densely_sampled::DenselySampled;
use super::named::named_spectrum;
use super::rgb_spectra::{RgbAlbedoSpectrum, RgbIlluminantSpectrum, RgbUnboundedSpectrum};
use super::rgb_to_spectrum::{RgbToSpectrumTable, TABLE_RESOLUTION};
use super::rgb_to_spectrum_cache::{self as cache, Fnv1a, FIT_VERSION};
use super::rgb_to_spectrum_fit::FitProblem;
use super::sampled::{SampledSpectrum, SampledWavelengths};
use super::sigmoid_polynomial::RgbSigmoidPolynomial;
use super::spectrum::Spectrum;
use super::xyz::{spectrum_to_xyz, xyy_to_xyz, xyz_to_xy};
use crate::scene_description::ColorSpaceName;

/// What an RGB value stands for, which decides how it becomes a spectrum
/// (pbrt-v4's `SpectrumType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumKind {
    /// A reflectance or transmittance: components must lie in [0, 1].
    Albedo,
    /// Any non-negative quantity (e.g. a scattering coefficient).
    Unbounded,
    /// Emitted light: relative to the colour space's illuminant.
    Illuminant,
}

/// An RGB colour space as pbrt-v4 defines one: chromaticities of its
/// primaries and a standard illuminant whose chromaticity is its white.
#[derive(Debug)]
pub struct RgbColorSpace {
    pub name: ColorSpaceName,
    /// Chromaticities (xy) of the red, green and blue primaries.
    pub r: Vec2,
    pub g: Vec2,
    pub b: Vec2,
    /// Chromaticity of the illuminant, computed from its spectrum.
    pub whitepoint: Vec2,
    /// The illuminant spectrum, normalised to unit luminance: what RGB
    /// (1, 1, 1) emits.
    pub illuminant: Spectrum,
    illuminant_densely_sampled: Arc<DenselySampled>,
    /// Linear RGB → XYZ; maps (1, 1, 1) to the illuminant's XYZ.
    pub xyz_from_rgb: Mat3,
    pub rgb_from_xyz: Mat3,
    /// Fitted at first use (see [`RgbColorSpace::rgb_to_spectrum_table`]).
    table: OnceLock<RgbToSpectrumTable>,
}

impl RgbColorSpace {
    /// A colour space from primaries and an illuminant. `None` if the
    /// primaries are degenerate (collinear) or the illuminant is black.
    pub fn new(
        name: ColorSpaceName,
        r: Vec2,
        g: Vec2,
        b: Vec2,
        illuminant: &Spectrum,
    ) -> Option<Self> {
        let dense = Arc::new(illuminant.to_densely_sampled());
        let illuminant = Spectrum::DenselySampled(Arc::clone(&dense));
        let white = spectrum_to_xyz(&illuminant).as_dvec3();
        if !(white.y > 0.0) {
            return None;
        }
        let primary = |xy: Vec2| xyy_to_xyz(xy, 1.0).as_dvec3();
        let primaries = DMat3::from_cols(primary(r), primary(g), primary(b));
        let det = primaries.determinant();
        if !(det.abs() > 1e-12) {
            return None;
        }
        // Scale each primary so that together they make the white.
        let weights = primaries.inverse() * white;
        let xyz_from_rgb = primaries * DMat3::from_diagonal(weights);
        let rgb_from_xyz = xyz_from_rgb.inverse();
        Some(RgbColorSpace {
            name,
            r,
            g,
            b,
            whitepoint: xyz_to_xy(white.as_vec3()),
            illuminant,
            illuminant_densely_sampled: dense,
            xyz_from_rgb: xyz_from_rgb.as_mat3(),
            rgb_from_xyz: rgb_from_xyz.as_mat3(),
            table: OnceLock::new(),
        })
    }

    /// The illuminant as the densely sampled table it is stored as.
    pub fn illuminant_densely_sampled(&self) -> &Arc<DenselySampled> {
        &self.illuminant_densely_sampled
    }

    pub fn to_xyz(&self, rgb: Vec3) -> Vec3 {
        self.xyz_from_rgb * rgb
    }

    pub fn to_rgb(&self, xyz: Vec3) -> Vec3 {
        self.rgb_from_xyz * xyz
    }

    /// Weights giving luminance Y from this space's linear RGB.
    pub fn luminance_vector(&self) -> Vec3 {
        self.xyz_from_rgb.row(1)
    }

    /// The sigmoid polynomial of an RGB with components in [0, 1]
    /// (clamped into it otherwise).
    pub fn to_rgb_coefficients(&self, rgb: Vec3) -> RgbSigmoidPolynomial {
        self.rgb_to_spectrum_table().lookup(rgb)
    }

    /// The spectrum a scene's RGB stands for, by pbrt-v4's rules:
    /// - `Albedo`: the fitted reflectance itself;
    /// - `Unbounded`: the RGB divided by 2·max is fitted, and the spectrum
    ///   scaled back up by 2·max;
    /// - `Illuminant`: as `Unbounded`, times this space's illuminant.
    ///
    /// Out-of-range input is clamped rather than refused (negative or NaN
    /// components count as 0, albedo components above 1 as 1); use
    /// [`RgbColorSpace::try_rgb_to_spectrum`] to report it instead.
    pub fn rgb_to_spectrum(&self, rgb: Vec3, kind: SpectrumKind) -> Spectrum {
        let rgb = Vec3::new(
            non_negative(rgb.x),
            non_negative(rgb.y),
            non_negative(rgb.z),
        );
        match kind {
            SpectrumKind::Albedo => Spectrum::RgbAlbedo(RgbAlbedoSpectrum {
                polynomial: self.to_rgb_coefficients(rgb.min(Vec3::ONE)),
            }),
            SpectrumKind::Unbounded => {
                let (scale, polynomial) = self.scaled_coefficients(rgb);
                Spectrum::RgbUnbounded(RgbUnboundedSpectrum { scale, polynomial })
            }
            SpectrumKind::Illuminant => {
                let (scale, polynomial) = self.scaled_coefficients(rgb);
                Spectrum::RgbIlluminant(RgbIlluminantSpectrum {
                    scale,
                    polynomial,
                    illuminant: Arc::clone(&self.illuminant_densely_sampled),
                })
            }
        }
    }

    /// As [`RgbColorSpace::rgb_to_spectrum`], but an RGB outside the kind's
    /// domain (negative or non-finite components; albedo above 1) is an
    /// error naming the value, as pbrt-v4 reports it.
    pub fn try_rgb_to_spectrum(&self, rgb: Vec3, kind: SpectrumKind) -> Result<Spectrum, String> {
        if !rgb.is_finite() {
            return Err(format!(
                "RGB value ({}, {}, {}) is not finite",
                rgb.x, rgb.y, rgb.z
            ));
        }
        if rgb.min_element() < 0.0 {
            return Err(format!(
                "RGB value ({}, {}, {}) has a negative component",
                rgb.x, rgb.y, rgb.z
            ));
        }
        if kind == SpectrumKind::Albedo && rgb.max_element() > 1.0 {
            return Err(format!(
                "RGB reflectance ({}, {}, {}) has a component above 1",
                rgb.x, rgb.y, rgb.z
            ));
        }
        Ok(self.rgb_to_spectrum(rgb, kind))
    }

    /// (2·max, coefficients of rgb / (2·max)), or black for black.
    /// The scale and sigmoid polynomial of the illuminant spectrum
    /// [`RgbColorSpace::rgb_to_spectrum`] gives for `rgb` (the spectrum is
    /// scale × polynomial(λ) × the colour space's illuminant(λ)), for
    /// callers that store them per texel instead of building a spectrum
    /// per lookup.
    pub fn illuminant_coefficients(&self, rgb: Vec3) -> (f32, RgbSigmoidPolynomial) {
        self.scaled_coefficients(Vec3::new(
            non_negative(rgb.x),
            non_negative(rgb.y),
            non_negative(rgb.z),
        ))
    }

    fn scaled_coefficients(&self, rgb: Vec3) -> (f32, RgbSigmoidPolynomial) {
        let scale = 2.0 * rgb.max_element();
        if scale > 0.0 && scale.is_finite() {
            (scale, self.to_rgb_coefficients(rgb / scale))
        } else {
            (0.0, self.to_rgb_coefficients(Vec3::ZERO))
        }
    }

    /// The fitted RGB → spectrum table, computed (or read from the disk
    /// cache) on first use.
    pub fn rgb_to_spectrum_table(&self) -> &RgbToSpectrumTable {
        self.table.get_or_init(|| self.load_or_fit_table())
    }

    fn fit_problem(&self) -> FitProblem {
        FitProblem::new(
            &self.illuminant_densely_sampled,
            self.xyz_from_rgb.as_dmat3(),
        )
    }

    /// Everything the fitted table depends on, hashed.
    fn table_fingerprint(&self) -> u64 {
        let mut hash = Fnv1a::default();
        hash.write(&FIT_VERSION.to_le_bytes());
        hash.write(&(TABLE_RESOLUTION as u32).to_le_bytes());
        for v in self.xyz_from_rgb.to_cols_array() {
            hash.write(&v.to_le_bytes());
        }
        for v in self.illuminant_densely_sampled.values() {
            hash.write(&v.to_le_bytes());
        }
        for l in 360..=830 {
            let cmf = super::cie::cie_xyz(l as f32);
            hash.write_f64(f64::from(cmf.x) + 2.0 * f64::from(cmf.y) + 4.0 * f64::from(cmf.z));
        }
        hash.finish()
    }

    fn load_or_fit_table(&self) -> RgbToSpectrumTable {
        let fingerprint = self.table_fingerprint();
        let path = cache::cache_directory()
            .map(|dir| cache::cache_file(&dir, color_space_file_name(self.name), fingerprint));
        // Rows are read from the file as lookups need them.
        if let Some(table) = path
            .as_deref()
            .and_then(|p| cache::CachedRows::open(p, fingerprint))
            .filter(|cached| cached.resolution() == TABLE_RESOLUTION)
            .and_then(|cached| RgbToSpectrumTable::from_cache(cached, self.fit_problem()))
        {
            return table;
        }
        let start = Instant::now();
        let table = RgbToSpectrumTable::compute(&self.fit_problem(), TABLE_RESOLUTION);
        log_fit_time(self.name, start.elapsed().as_secs_f64());
        if let Some(path) = path {
            // Not being able to cache only costs time on the next run.
            let _ = cache::store(
                &path,
                table.resolution(),
                table.z_nodes(),
                table.rows(),
                fingerprint,
            );
        }
        table
    }
}

fn log_fit_time(name: ColorSpaceName, seconds: f64) {
    if std::env::var_os("RPBRT_LOG_SPECTRUM_FIT").is_some() {
        eprintln!("rpbrt: fitted the {name:?} RGB-to-spectrum table in {seconds:.2} s");
    }
}

fn non_negative(v: f32) -> f32 {
    // max sends NaN to 0 as well.
    v.max(0.0)
}

fn color_space_file_name(name: ColorSpaceName) -> &'static str {
    ColorSpaceName::ALL
        .iter()
        .find(|(_, n)| *n == name)
        .map_or("unnamed", |(s, _)| *s)
}

impl SampledSpectrum {
    /// RGB in `cs` of this spectrum's Monte Carlo XYZ estimate.
    pub fn to_rgb(&self, w: &SampledWavelengths, cs: &RgbColorSpace) -> Vec3 {
        cs.to_rgb(self.to_xyz(w))
    }
}

/// The matrix taking linear RGB in `from` to linear RGB in `to`, through
/// XYZ (no chromatic adaptation, as pbrt-v4's `ConvertRGBColorSpace`).
pub fn convert_rgb_color_space(from: &RgbColorSpace, to: &RgbColorSpace) -> Mat3 {
    if std::ptr::eq(from, to) {
        return Mat3::IDENTITY;
    }
    (to.rgb_from_xyz.as_dmat3() * from.xyz_from_rgb.as_dmat3()).as_mat3()
}

/// pbrt-v4's colour spaces by name, built on first use and shared.
pub fn get(name: ColorSpaceName) -> &'static RgbColorSpace {
    static SRGB: OnceLock<RgbColorSpace> = OnceLock::new();
    static DCI_P3: OnceLock<RgbColorSpace> = OnceLock::new();
    static REC2020: OnceLock<RgbColorSpace> = OnceLock::new();
    static ACES2065_1: OnceLock<RgbColorSpace> = OnceLock::new();
    let cell = match name {
        ColorSpaceName::Srgb => &SRGB,
        ColorSpaceName::DciP3 => &DCI_P3,
        ColorSpaceName::Rec2020 => &REC2020,
        ColorSpaceName::Aces2065_1 => &ACES2065_1,
    };
    cell.get_or_init(|| build_standard(name))
}

/// The primaries and illuminants pbrt-v4 uses.
fn build_standard(name: ColorSpaceName) -> RgbColorSpace {
    let xy = Vec2::new;
    let (r, g, b, illuminant) = match name {
        // ITU-R BT.709 primaries, D65.
        ColorSpaceName::Srgb => (
            xy(0.64, 0.33),
            xy(0.30, 0.60),
            xy(0.15, 0.06),
            "stdillum-D65",
        ),
        // P3-D65 (Display P3): DCI-P3 primaries with a D65 white.
        ColorSpaceName::DciP3 => (
            xy(0.68, 0.32),
            xy(0.265, 0.69),
            xy(0.15, 0.06),
            "stdillum-D65",
        ),
        // ITU-R BT.2020, D65.
        ColorSpaceName::Rec2020 => (
            xy(0.708, 0.292),
            xy(0.170, 0.797),
            xy(0.131, 0.046),
            "stdillum-D65",
        ),
        // SMPTE ST 2065-1 (ACES AP0), ACES D60 white.
        ColorSpaceName::Aces2065_1 => (
            xy(0.7347, 0.2653),
            xy(0.0, 1.0),
            xy(0.0001, -0.077),
            "illum-acesD60",
        ),
    };
    // Both are compiled-in tables covered by the tests; failing here would
    // be a build defect, not something a scene can cause.
    let illuminant = named_spectrum(illuminant).expect("compiled-in illuminant exists");
    RgbColorSpace::new(name, r, g, b, &illuminant).expect("standard primaries are independent")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::xyz::spectrum_to_xyz;

    #[test]
    fn srgb_matrices_are_inverse_and_map_white_to_d65() {
        let cs = get(ColorSpaceName::Srgb);
        let product = cs.rgb_from_xyz * cs.xyz_from_rgb;
        assert!(product.abs_diff_eq(Mat3::IDENTITY, 1e-5), "{product}");
        let white = cs.to_xyz(Vec3::ONE);
        let d65 = spectrum_to_xyz(&named_spectrum("stdillum-D65").unwrap());
        assert!((white - d65).abs().max_element() < 1e-5, "{white} vs {d65}");
        assert!(
            (cs.whitepoint - Vec2::new(0.3127, 0.3290))
                .abs()
                .max_element()
                < 2e-4
        );
        // The familiar sRGB matrix (IEC 61966-2-1), to the precision the
        // illuminant's tabulation allows.
        let expected = Mat3::from_cols(
            Vec3::new(0.4124, 0.2126, 0.0193),
            Vec3::new(0.3576, 0.7152, 0.1192),
            Vec3::new(0.1805, 0.0722, 0.9505),
        );
        assert!(
            cs.xyz_from_rgb.abs_diff_eq(expected, 2e-3),
            "{}",
            cs.xyz_from_rgb
        );
        assert!(
            (cs.luminance_vector() - Vec3::new(0.2126, 0.7152, 0.0722))
                .abs()
                .max_element()
                < 2e-3
        );
    }

    #[test]
    fn every_standard_space_is_consistent() {
        for (_, name) in ColorSpaceName::ALL {
            let cs = get(name);
            assert!((cs.rgb_from_xyz * cs.xyz_from_rgb).abs_diff_eq(Mat3::IDENTITY, 1e-4));
            assert!((cs.to_xyz(Vec3::ONE).y - 1.0).abs() < 1e-4);
            // Each primary's chromaticity is where its column points.
            for (column, primary) in [(0, cs.r), (1, cs.g), (2, cs.b)] {
                let xy = xyz_to_xy(cs.xyz_from_rgb.col(column));
                assert!((xy - primary).abs().max_element() < 1e-4, "{name:?} {xy}");
            }
        }
        let aces = get(ColorSpaceName::Aces2065_1);
        assert!(
            (aces.whitepoint - Vec2::new(0.32168, 0.33767))
                .abs()
                .max_element()
                < 3e-4
        );
        let p3 = get(ColorSpaceName::DciP3);
        assert!((p3.whitepoint - get(ColorSpaceName::Srgb).whitepoint).length() < 1e-6);
        let m = convert_rgb_color_space(get(ColorSpaceName::Srgb), p3);
        // sRGB white stays white in P3 (same illuminant).
        assert!((m * Vec3::ONE - Vec3::ONE).abs().max_element() < 1e-4);
    }

    #[test]
    fn colour_spaces_can_be_shared_between_render_threads() {
        fn assert_sync_send<T: Sync + Send>() {}
        assert_sync_send::<RgbColorSpace>();
        assert_sync_send::<RgbToSpectrumTable>();
    }

    #[test]
    fn degenerate_primaries_are_refused() {
        let d65 = named_spectrum("stdillum-D65").unwrap();
        let p = Vec2::new(0.3, 0.3);
        assert!(RgbColorSpace::new(ColorSpaceName::Srgb, p, p, p, &d65).is_none());
        let black = Spectrum::Constant(0.0);
        let cs = get(ColorSpaceName::Srgb);
        assert!(RgbColorSpace::new(ColorSpaceName::Srgb, cs.r, cs.g, cs.b, &black).is_none());
    }

    #[test]
    fn out_of_range_rgb_is_reported_or_clamped() {
        let cs = get(ColorSpaceName::Srgb);
        assert!(cs
            .try_rgb_to_spectrum(Vec3::new(1.2, 0.5, 0.5), SpectrumKind::Albedo)
            .is_err());
        assert!(cs
            .try_rgb_to_spectrum(Vec3::new(-0.1, 0.5, 0.5), SpectrumKind::Unbounded)
            .is_err());
        assert!(cs
            .try_rgb_to_spectrum(Vec3::new(f32::NAN, 0.5, 0.5), SpectrumKind::Illuminant)
            .is_err());
        assert!(cs
            .try_rgb_to_spectrum(Vec3::new(3.0, 0.5, 0.5), SpectrumKind::Unbounded)
            .is_ok());
        let clamped = cs.rgb_to_spectrum(Vec3::new(1.2, f32::NAN, -3.0), SpectrumKind::Albedo);
        assert!((0.0..=1.0).contains(&clamped.eval(600.0)));
        let black = cs.rgb_to_spectrum(Vec3::ZERO, SpectrumKind::Illuminant);
        assert_eq!(black.eval(550.0), 0.0);
        assert_eq!(black.max_value(), 0.0);
    }
}
