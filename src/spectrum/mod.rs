//! Spectral rendering: sampled wavelengths and the spectra evaluated at
//! them.

pub mod sampled;

pub use sampled::{
    SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES,
};
