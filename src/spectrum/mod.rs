//! Spectral rendering: sampled wavelengths and the spectra evaluated at
//! them, the CIE observer, RGB colour spaces and RGB → spectrum conversion.

pub mod cie;
pub mod data;
pub mod sampled;

pub use cie::{cie_x, cie_xyz, cie_y, cie_z, CIE_Y_INTEGRAL};
pub use sampled::{
    SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES,
};
