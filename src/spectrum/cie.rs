//! The CIE 1931 2° standard observer: the colour matching functions x̄, ȳ,
//! z̄ that turn a spectrum into XYZ.
//!
//! pbrt-v4 holds them as densely sampled spectra over 360–830 nm at 1 nm
//! and looks them up at the nearest whole nanometre; these functions do the
//! same straight from the compiled table, so the per-sample path needs no
//! allocation and no lazy initialisation.

use glam::Vec3;

use super::data::cie_1931::{CIE_1931_X, CIE_1931_Y, CIE_1931_Z};
use super::sampled::{nanometre_index, SampledSpectrum, SampledWavelengths, LAMBDA_MIN};

/// ∫ ȳ(λ) dλ over 360–830 nm (1 nm sum of the table): the Y of a constant
/// spectrum of 1. pbrt-v4 divides by this so that such a spectrum has Y = 1.
pub const CIE_Y_INTEGRAL: f32 = 106.856895;

/// Number of 1 nm samples in the tables (360..=830).
pub const CIE_SAMPLE_COUNT: usize = 471;

/// Index of the whole nanometre nearest `lambda` in the 360–830 nm tables,
/// or `None` outside them (where the observer is taken to be blind).
#[inline]
fn table_index(lambda: f32) -> Option<usize> {
    nanometre_index(lambda, LAMBDA_MIN as i32, CIE_SAMPLE_COUNT)
}

/// x̄(λ) at the nearest whole nanometre; 0 outside 360–830 nm.
#[inline]
pub fn cie_x(lambda: f32) -> f32 {
    table_index(lambda).map_or(0.0, |i| CIE_1931_X.values[i])
}

/// ȳ(λ) (the photopic luminous efficiency) at the nearest whole nanometre.
#[inline]
pub fn cie_y(lambda: f32) -> f32 {
    table_index(lambda).map_or(0.0, |i| CIE_1931_Y.values[i])
}

/// z̄(λ) at the nearest whole nanometre.
#[inline]
pub fn cie_z(lambda: f32) -> f32 {
    table_index(lambda).map_or(0.0, |i| CIE_1931_Z.values[i])
}

/// (x̄, ȳ, z̄)(λ) with one range check.
#[inline]
pub fn cie_xyz(lambda: f32) -> Vec3 {
    match table_index(lambda) {
        Some(i) => Vec3::new(
            CIE_1931_X.values[i],
            CIE_1931_Y.values[i],
            CIE_1931_Z.values[i],
        ),
        None => Vec3::ZERO,
    }
}

/// The three matching functions at a path's wavelengths.
#[inline]
pub fn sample_cie_xyz(
    w: &SampledWavelengths,
) -> (SampledSpectrum, SampledSpectrum, SampledSpectrum) {
    let mut x = SampledSpectrum::ZERO;
    let mut y = SampledSpectrum::ZERO;
    let mut z = SampledSpectrum::ZERO;
    for (i, &lambda) in w.lambda.iter().enumerate() {
        let v = cie_xyz(lambda);
        x[i] = v.x;
        y[i] = v.y;
        z[i] = v.z;
    }
    (x, y, z)
}

/// ȳ at a path's wavelengths.
#[inline]
pub fn sample_cie_y(w: &SampledWavelengths) -> SampledSpectrum {
    SampledSpectrum::from_fn(|i| cie_y(w.lambda[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn integral(values: &[f32]) -> f64 {
        values.iter().map(|&v| f64::from(v)).sum()
    }

    #[test]
    fn matching_functions_integrate_to_the_y_integral() {
        // The CIE normalised x̄, ȳ, z̄ to equal areas (equal-energy white
        // at x = y = 1/3); the 1 nm tables keep that to within 0.1 %.
        for (name, table) in [("x", &CIE_1931_X), ("y", &CIE_1931_Y), ("z", &CIE_1931_Z)] {
            assert_eq!(table.values.len(), CIE_SAMPLE_COUNT);
            let area = integral(table.values);
            let relative = (area / f64::from(CIE_Y_INTEGRAL) - 1.0).abs();
            assert!(relative < 1e-3, "∫{name}̄ = {area}");
        }
        let y_area = integral(CIE_1931_Y.values);
        assert!(
            (y_area - f64::from(CIE_Y_INTEGRAL)).abs() < 1e-3,
            "{y_area}"
        );
    }

    #[test]
    fn lookup_rounds_to_the_nearest_nanometre_and_is_zero_outside() {
        assert_eq!(cie_y(555.0), CIE_1931_Y.values[195]);
        assert_eq!(cie_y(555.4), CIE_1931_Y.values[195]);
        assert_eq!(cie_y(555.5), CIE_1931_Y.values[196]);
        assert!((cie_y(555.0) - 1.0).abs() < 1e-3, "ȳ peaks at 555 nm");
        assert_eq!(cie_x(359.4), 0.0);
        assert_eq!(cie_z(830.6), 0.0);
        assert_eq!(cie_xyz(f32::NAN), Vec3::ZERO);
        assert!(cie_x(830.4) > 0.0);
    }
}
