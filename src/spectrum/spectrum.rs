//! The spectrum of any kind a scene can give: one enum, so evaluation is
//! a match rather than a virtual call, and cheap to clone (large tables sit
//! behind `Arc`).

use std::sync::Arc;

use super::blackbody::BlackbodySpectrum;
use super::densely_sampled::DenselySampled;
use super::piecewise_linear::PiecewiseLinear;
use super::rgb_spectra::{RgbAlbedoSpectrum, RgbIlluminantSpectrum, RgbUnboundedSpectrum};
use super::sampled::{SampledSpectrum, SampledWavelengths};

/// A function of wavelength (nm), in one of pbrt-v4's representations.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f32),
    PiecewiseLinear(Arc<PiecewiseLinear>),
    DenselySampled(Arc<DenselySampled>),
    Blackbody(BlackbodySpectrum),
    RgbAlbedo(RgbAlbedoSpectrum),
    RgbUnbounded(RgbUnboundedSpectrum),
    RgbIlluminant(RgbIlluminantSpectrum),
}

impl Spectrum {
    /// The value at `lambda` nm.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        match self {
            Spectrum::Constant(c) => *c,
            Spectrum::PiecewiseLinear(s) => s.eval(lambda),
            Spectrum::DenselySampled(s) => s.eval(lambda),
            Spectrum::Blackbody(s) => s.eval(lambda),
            Spectrum::RgbAlbedo(s) => s.eval(lambda),
            Spectrum::RgbUnbounded(s) => s.eval(lambda),
            Spectrum::RgbIlluminant(s) => s.eval(lambda),
        }
    }

    /// The values at a path's wavelengths.
    #[inline]
    pub fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Spectrum::Constant(c) => SampledSpectrum::splat(*c),
            Spectrum::PiecewiseLinear(s) => s.sample(w),
            Spectrum::DenselySampled(s) => s.sample(w),
            Spectrum::Blackbody(s) => s.sample(w),
            Spectrum::RgbAlbedo(s) => s.sample(w),
            Spectrum::RgbUnbounded(s) => s.sample(w),
            Spectrum::RgbIlluminant(s) => s.sample(w),
        }
    }

    /// An upper bound of the values over the visible range (exact for all
    /// but the tabulated kinds, where it is the largest sample).
    pub fn max_value(&self) -> f32 {
        match self {
            Spectrum::Constant(c) => *c,
            Spectrum::PiecewiseLinear(s) => s.max_value(),
            Spectrum::DenselySampled(s) => s.max_value(),
            Spectrum::Blackbody(s) => s.max_value(),
            Spectrum::RgbAlbedo(s) => s.max_value(),
            Spectrum::RgbUnbounded(s) => s.max_value(),
            Spectrum::RgbIlluminant(s) => s.max_value(),
        }
    }

    /// This spectrum tabulated at each whole nanometre over 360–830 nm,
    /// for spectra evaluated often (lights).
    pub fn to_densely_sampled(&self) -> DenselySampled {
        DenselySampled::from_fn(|l| self.eval(l))
    }
}

impl From<PiecewiseLinear> for Spectrum {
    fn from(s: PiecewiseLinear) -> Self {
        Spectrum::PiecewiseLinear(Arc::new(s))
    }
}

impl From<DenselySampled> for Spectrum {
    fn from(s: DenselySampled) -> Self {
        Spectrum::DenselySampled(Arc::new(s))
    }
}

impl From<BlackbodySpectrum> for Spectrum {
    fn from(s: BlackbodySpectrum) -> Self {
        Spectrum::Blackbody(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::sigmoid_polynomial::RgbSigmoidPolynomial;

    #[test]
    fn every_kind_samples_as_it_evaluates() {
        let w = SampledWavelengths::sample_visible(0.37);
        let polynomial = RgbSigmoidPolynomial::new(-1e-4, 0.1, -24.0);
        let spectra = [
            Spectrum::Constant(0.25),
            PiecewiseLinear::new(vec![300.0, 900.0], vec![0.0, 6.0])
                .unwrap()
                .into(),
            DenselySampled::from_fn(|l| l / 1000.0).into(),
            BlackbodySpectrum::new(4000.0).into(),
            Spectrum::RgbAlbedo(RgbAlbedoSpectrum { polynomial }),
            Spectrum::RgbUnbounded(RgbUnboundedSpectrum {
                scale: 3.0,
                polynomial,
            }),
            Spectrum::RgbIlluminant(RgbIlluminantSpectrum {
                scale: 2.0,
                polynomial,
                illuminant: Arc::new(DenselySampled::from_fn(|_| 0.5)),
            }),
        ];
        for s in &spectra {
            let sampled = s.sample(&w);
            for i in 0..w.lambda.len() {
                assert_eq!(sampled[i], s.eval(w.lambda[i]), "{s:?}");
                assert!(sampled[i] <= s.max_value() + 1e-6, "{s:?}");
            }
        }
    }

    #[test]
    fn spectra_are_small_and_shareable_across_threads() {
        fn assert_sync_send<T: Sync + Send>() {}
        assert_sync_send::<Spectrum>();
        assert!(std::mem::size_of::<Spectrum>() <= 32);
    }
}
