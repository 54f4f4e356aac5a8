//! From spectra to CIE XYZ and chromaticity, and chromatic adaptation
//! between whites.

use glam::{Mat3, Vec2, Vec3};

use super::cie::{cie_xyz, cie_y, sample_cie_xyz, sample_cie_y, CIE_Y_INTEGRAL};
use super::sampled::{SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};
use super::spectrum::Spectrum;

impl SampledSpectrum {
    /// Monte Carlo estimate of this spectrum's XYZ from its values at the
    /// path's wavelengths: the average of value · (x̄, ȳ, z̄) / pdf, over
    /// ∫ȳ so that a constant 1 has Y = 1. Wavelengths with zero density
    /// (terminated secondaries) contribute nothing.
    pub fn to_xyz(&self, w: &SampledWavelengths) -> Vec3 {
        let (x, y, z) = sample_cie_xyz(w);
        let pdf = w.pdf();
        Vec3::new(
            (x * *self).safe_div(pdf).average(),
            (y * *self).safe_div(pdf).average(),
            (z * *self).safe_div(pdf).average(),
        ) / CIE_Y_INTEGRAL
    }

    /// The Y (luminance) part of [`SampledSpectrum::to_xyz`] alone.
    pub fn y(&self, w: &SampledWavelengths) -> f32 {
        (sample_cie_y(w) * *self).safe_div(w.pdf()).average() / CIE_Y_INTEGRAL
    }
}

/// ∫ a(λ) b(λ) dλ by a 1 nm sum over 360–830 nm (pbrt-v4's `InnerProduct`).
pub fn inner_product(a: &Spectrum, b: &Spectrum) -> f32 {
    (LAMBDA_MIN as i32..=LAMBDA_MAX as i32)
        .map(|l| a.eval(l as f32) * b.eval(l as f32))
        .sum()
}

/// A spectrum's XYZ by a 1 nm sum over 360–830 nm, scaled so that a
/// constant 1 has Y = 1 (pbrt-v4's `SpectrumToXYZ`).
pub fn spectrum_to_xyz(s: &Spectrum) -> Vec3 {
    let mut xyz = Vec3::ZERO;
    for l in LAMBDA_MIN as i32..=LAMBDA_MAX as i32 {
        let lambda = l as f32;
        xyz += cie_xyz(lambda) * s.eval(lambda);
    }
    xyz / CIE_Y_INTEGRAL
}

/// The Y of [`spectrum_to_xyz`] alone.
pub fn spectrum_to_y(s: &Spectrum) -> f32 {
    integrate_against_y(|l| s.eval(l)) / CIE_Y_INTEGRAL
}

/// ∫ s ȳ dλ, the quantity lights divide their scale by so that `scale`
/// and `power` set brightness independently of the spectrum's shape. For
/// an RGB illuminant only the colour space's illuminant counts, not the
/// RGB multiplier (pbrt-v4's `SpectrumToPhotometric`).
pub fn spectrum_to_photometric(s: &Spectrum) -> f32 {
    match s {
        Spectrum::RgbIlluminant(rgb) => integrate_against_y(|l| rgb.illuminant().eval(l)),
        other => integrate_against_y(|l| other.eval(l)),
    }
}

/// ∫ f ȳ dλ by a 1 nm sum over 360–830 nm.
fn integrate_against_y(f: impl Fn(f32) -> f32) -> f32 {
    (LAMBDA_MIN as i32..=LAMBDA_MAX as i32)
        .map(|l| cie_y(l as f32) * f(l as f32))
        .sum()
}

/// Chromaticity (x, y) of an XYZ; (0, 0) for black.
pub fn xyz_to_xy(xyz: Vec3) -> Vec2 {
    let sum = xyz.x + xyz.y + xyz.z;
    if sum == 0.0 || !sum.is_finite() {
        return Vec2::ZERO;
    }
    Vec2::new(xyz.x / sum, xyz.y / sum)
}

/// The XYZ with chromaticity `xy` and luminance `y`; black when xy.y is 0
/// (pbrt-v4's `XYZ::FromxyY`).
pub fn xyy_to_xyz(xy: Vec2, y: f32) -> Vec3 {
    if xy.y == 0.0 {
        return Vec3::ZERO;
    }
    Vec3::new(xy.x * y / xy.y, y, (1.0 - xy.x - xy.y) * y / xy.y)
}

/// The Bradford cone-response matrix (Lam 1985), XYZ → LMS.
pub const BRADFORD_LMS_FROM_XYZ: Mat3 = Mat3::from_cols_array(&[
    // Column-major: these are the matrix's columns.
    0.8951, -0.7502, 0.0389, //
    0.2664, 1.7135, -0.0685, //
    -0.1614, 0.0367, 1.0296,
]);

/// The von Kries adaptation in Bradford cone space that maps XYZ seen
/// under a light of chromaticity `src_xy` to how it appears under
/// `dst_xy`: scales each cone response by the ratio of the two whites'
/// (pbrt-v4's `WhiteBalance`, used by the film's sensor).
pub fn white_balance(src_xy: Vec2, dst_xy: Vec2) -> Mat3 {
    let src_lms = BRADFORD_LMS_FROM_XYZ * xyy_to_xyz(src_xy, 1.0);
    let dst_lms = BRADFORD_LMS_FROM_XYZ * xyy_to_xyz(dst_xy, 1.0);
    let gain = Vec3::new(
        safe_ratio(dst_lms.x, src_lms.x),
        safe_ratio(dst_lms.y, src_lms.y),
        safe_ratio(dst_lms.z, src_lms.z),
    );
    BRADFORD_LMS_FROM_XYZ.inverse() * Mat3::from_diagonal(gain) * BRADFORD_LMS_FROM_XYZ
}

fn safe_ratio(a: f32, b: f32) -> f32 {
    if b != 0.0 {
        a / b
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::named::named_spectrum;

    #[test]
    fn d65_has_the_standard_white_point() {
        let d65 = named_spectrum("stdillum-D65").unwrap();
        let xyz = spectrum_to_xyz(&d65);
        let xy = xyz_to_xy(xyz);
        assert!(
            (xy.x - 0.3127).abs() < 2e-4 && (xy.y - 0.3290).abs() < 2e-4,
            "{xy}"
        );
        // Named illuminants are normalised to unit luminance.
        assert!((xyz.y - 1.0).abs() < 1e-4, "{xyz}");
        assert!((spectrum_to_y(&d65) - xyz.y).abs() < 1e-6);
        assert!((spectrum_to_photometric(&d65) - CIE_Y_INTEGRAL).abs() < 1e-2);
    }

    #[test]
    fn sampled_xyz_of_a_constant_converges_to_the_matching_function_areas() {
        // The estimator of ∫ s (x̄, ȳ, z̄) / ∫ȳ for s = 1 is (∫x̄, ∫ȳ, ∫z̄) / ∫ȳ.
        let expected = spectrum_to_xyz(&Spectrum::Constant(1.0));
        assert!((expected.y - 1.0).abs() < 1e-5, "{expected}");
        let n = 20_000;
        let mut sum = Vec3::ZERO;
        let mut y_sum = 0.0;
        for i in 0..n {
            // A stratified stream of sample values.
            let u = (i as f32 + 0.5) / n as f32;
            let w = SampledWavelengths::sample_visible(u);
            sum += SampledSpectrum::ONE.to_xyz(&w);
            y_sum += SampledSpectrum::ONE.y(&w);
        }
        let mean = sum / n as f32;
        for axis in 0..3 {
            assert!(
                (mean[axis] / expected[axis] - 1.0).abs() < 5e-3,
                "{mean} vs {expected}"
            );
        }
        assert!((y_sum / n as f32 - mean.y).abs() < 1e-5);
        // Uniform sampling estimates the same thing.
        let mut uniform = Vec3::ZERO;
        for i in 0..n {
            let u = (i as f32 + 0.5) / n as f32;
            let w = SampledWavelengths::sample_uniform(u, LAMBDA_MIN, LAMBDA_MAX);
            uniform += SampledSpectrum::ONE.to_xyz(&w);
        }
        uniform /= n as f32;
        assert!((uniform - expected).abs().max_element() < 5e-3, "{uniform}");
    }

    #[test]
    fn terminated_wavelengths_do_not_contribute() {
        let mut w = SampledWavelengths::sample_visible(0.3);
        w.terminate_secondary();
        let s = SampledSpectrum([1.0, 100.0, 100.0, 100.0]);
        let only_first = SampledSpectrum([1.0, 0.0, 0.0, 0.0]);
        assert_eq!(s.to_xyz(&w), only_first.to_xyz(&w));
    }

    #[test]
    fn chromaticity_round_trips() {
        let xyz = Vec3::new(0.3, 0.5, 0.2);
        let back = xyy_to_xyz(xyz_to_xy(xyz), xyz.y);
        assert!((back - xyz).abs().max_element() < 1e-6);
        assert_eq!(xyz_to_xy(Vec3::ZERO), Vec2::ZERO);
        assert_eq!(xyy_to_xyz(Vec2::ZERO, 1.0), Vec3::ZERO);
    }

    #[test]
    fn white_balance_maps_one_white_onto_the_other() {
        let d65 = Vec2::new(0.3127, 0.3290);
        let a = Vec2::new(0.4476, 0.4074);
        let m = white_balance(a, d65);
        let mapped = m * xyy_to_xyz(a, 1.0);
        assert!(
            (mapped - xyy_to_xyz(d65, 1.0)).abs().max_element() < 1e-5,
            "{mapped}"
        );
        let identity = white_balance(d65, d65);
        assert!(identity.abs_diff_eq(Mat3::IDENTITY, 1e-5), "{identity}");
        // Bradford's matrix maps equal-energy white to equal cone responses
        // (its rows sum to 1).
        let e = BRADFORD_LMS_FROM_XYZ * Vec3::ONE;
        assert!((e - Vec3::ONE).abs().max_element() < 2e-4, "{e}");
    }
}
