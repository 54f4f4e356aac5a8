//! Spectra standing for RGB values of a colour space, in the three roles
//! pbrt-v4 distinguishes: reflectances bounded by 1, unbounded quantities
//! (scattering coefficients, IOR-like values), and light emission.

use std::sync::Arc;

use super::densely_sampled::DenselySampled;
use super::sampled::{SampledSpectrum, SampledWavelengths};
use super::sigmoid_polynomial::RgbSigmoidPolynomial;

/// A reflectance with RGB components in [0, 1]: the sigmoid polynomial
/// itself, which never leaves [0, 1] (pbrt-v4's `RGBAlbedoSpectrum`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbAlbedoSpectrum {
    pub polynomial: RgbSigmoidPolynomial,
}

impl RgbAlbedoSpectrum {
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        self.polynomial.eval(lambda)
    }

    pub fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::from_fn(|i| self.eval(w.lambda[i]))
    }

    pub fn max_value(&self) -> f32 {
        self.polynomial.max_value()
    }
}

/// An RGB with components of any non-negative size: the RGB is divided by
/// twice its largest component (so the fitted spectrum sits at half
/// brightness, away from the sigmoid's flat ends, with room to vary) and
/// that factor, `scale`, multiplies the spectrum back (pbrt-v4's
/// `RGBUnboundedSpectrum`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbUnboundedSpectrum {
    pub scale: f32,
    pub polynomial: RgbSigmoidPolynomial,
}

impl RgbUnboundedSpectrum {
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        self.scale * self.polynomial.eval(lambda)
    }

    pub fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::from_fn(|i| self.eval(w.lambda[i]))
    }

    pub fn max_value(&self) -> f32 {
        self.scale * self.polynomial.max_value()
    }
}

/// An emitted RGB: an unbounded RGB spectrum multiplied by the colour
/// space's illuminant, so that RGB (1, 1, 1) emits the space's white (D65
/// for sRGB) rather than an equal-energy spectrum (pbrt-v4's
/// `RGBIlluminantSpectrum`).
#[derive(Clone, Debug, PartialEq)]
pub struct RgbIlluminantSpectrum {
    pub scale: f32,
    pub polynomial: RgbSigmoidPolynomial,
    pub illuminant: Arc<DenselySampled>,
}

impl RgbIlluminantSpectrum {
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        self.scale * self.polynomial.eval(lambda) * self.illuminant.eval(lambda)
    }

    pub fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::from_fn(|i| self.eval(w.lambda[i]))
    }

    pub fn max_value(&self) -> f32 {
        self.scale * self.polynomial.max_value() * self.illuminant.max_value()
    }

    /// The colour space illuminant this spectrum modulates. Lights
    /// normalise their power by its luminance alone (pbrt-v4's
    /// `SpectrumToPhotometric`).
    pub fn illuminant(&self) -> &Arc<DenselySampled> {
        &self.illuminant
    }
}
