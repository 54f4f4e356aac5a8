//! Published spectral measurements, compiled in.
//!
//! The tables in the sibling files are written by `tools/gen_spectral_data.py`
//! from the CIE standards and the refractiveindex.info database (see that
//! script for sources and licences); this file holds only the shapes they
//! come in, so that regenerating the data never touches code.

// Generated files keep the generator's layout.
#[rustfmt::skip]
pub mod cie_1931;
#[rustfmt::skip]
pub mod glasses;
#[rustfmt::skip]
#[allow(clippy::approx_constant)] // tabulated measurements, not constants
pub mod illuminants;
#[rustfmt::skip]
#[allow(clippy::approx_constant)] // tabulated measurements, not constants
pub mod metals;

/// Values sampled at evenly spaced wavelengths: the form the CIE publishes
/// its observers and illuminants in.
#[derive(Debug)]
pub struct UniformTable {
    /// Wavelength of `values[0]`, in nm.
    pub first_lambda: f32,
    /// Spacing between samples, in nm.
    pub step: f32,
    pub values: &'static [f32],
}

impl UniformTable {
    /// The samples as interleaved (λ, value) pairs, the form
    /// [`crate::spectrum::PiecewiseLinear::from_interleaved`] takes.
    pub fn interleaved(&self) -> Vec<f64> {
        self.values
            .iter()
            .enumerate()
            .flat_map(|(i, &v)| {
                [
                    f64::from(self.first_lambda) + i as f64 * f64::from(self.step),
                    f64::from(v),
                ]
            })
            .collect()
    }
}

/// A glass's refractive index in the three-term Sellmeier form optical
/// catalogues publish: n² − 1 = Σᵢ Bᵢ λ² / (λ² − Cᵢ), with λ in µm.
#[derive(Debug)]
pub struct SellmeierGlass {
    pub b: [f32; 3],
    /// The Cᵢ, in µm².
    pub c_square_micrometres: [f32; 3],
}

impl SellmeierGlass {
    /// The refractive index at `lambda_nm`.
    pub fn refractive_index(&self, lambda_nm: f64) -> f64 {
        let l2 = (lambda_nm / 1000.0).powi(2);
        let sum: f64 = (0..3)
            .map(|i| f64::from(self.b[i]) * l2 / (l2 - f64::from(self.c_square_micrometres[i])))
            .sum();
        (1.0 + sum).sqrt()
    }
}
