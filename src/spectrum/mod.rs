//! Spectral rendering: sampled wavelengths and the spectra evaluated at
//! them, the CIE observer, RGB colour spaces and RGB → spectrum conversion.

pub mod blackbody;
pub mod cie;
pub mod color_space;
pub mod data;
pub mod daylight;
pub mod densely_sampled;
pub mod named;
pub mod parameter;
pub mod piecewise_linear;
pub mod rgb_spectra;
pub mod rgb_to_spectrum;
pub mod rgb_to_spectrum_cache;
pub mod rgb_to_spectrum_fit;
pub mod sampled;
pub mod sigmoid_polynomial;
#[allow(clippy::module_inception)]
pub mod spectrum;
pub mod xyz;

pub use blackbody::{blackbody, BlackbodySpectrum};
pub use cie::{cie_x, cie_xyz, cie_y, cie_z, CIE_Y_INTEGRAL};
pub use color_space::{convert_rgb_color_space, RgbColorSpace, SpectrumKind};
pub use daylight::daylight_spectrum;
pub use densely_sampled::DenselySampled;
pub use named::named_spectrum;
pub use piecewise_linear::{read_spectrum_file, PiecewiseLinear};
pub use rgb_spectra::{RgbAlbedoSpectrum, RgbIlluminantSpectrum, RgbUnboundedSpectrum};
pub use rgb_to_spectrum::RgbToSpectrumTable;
pub use sampled::{
    SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN, N_SPECTRUM_SAMPLES,
};
pub use sigmoid_polynomial::RgbSigmoidPolynomial;
pub use spectrum::Spectrum;
pub use xyz::{
    inner_product, spectrum_to_photometric, spectrum_to_xyz, spectrum_to_y, white_balance,
    xyy_to_xyz, xyz_to_xy,
};
