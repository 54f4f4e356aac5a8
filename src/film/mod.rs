//! The film: pixel sums of filtered, sensor-converted radiance samples.
//!
//! [`RgbFilm`] holds the settings every film shares (resolution, bounds,
//! sensor, output); a pixel's accumulator is a [`FilmPixel`]: RGB sums
//! ([`rgb::Pixel`]) for the `rgb` film, RGB and wavelength buckets
//! ([`spectral::SpectralPixel`]) for the `spectral` one.

pub mod rgb;
pub mod spectral;
pub mod splat;

pub use rgb::RgbFilm;

use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// What a film keeps per pixel, summing one filtered sample at a time.
pub trait FilmPixel: Clone + Send + Sync {
    fn add_sample(
        &mut self,
        film: &RgbFilm,
        l: SampledSpectrum,
        lambda: &SampledWavelengths,
        weight: f32,
    );

    /// The RGB sums.
    fn rgb(&self) -> &rgb::Pixel;
}

impl FilmPixel for rgb::Pixel {
    fn add_sample(
        &mut self,
        film: &RgbFilm,
        l: SampledSpectrum,
        lambda: &SampledWavelengths,
        weight: f32,
    ) {
        film.add_sample(self, l, lambda, weight);
    }

    fn rgb(&self) -> &rgb::Pixel {
        self
    }
}
