//! The film: pixel sums of filtered, sensor-converted radiance samples.
//!
//! [`RgbFilm`] holds the settings every film shares (resolution, bounds,
//! sensor, output); a pixel's accumulator is a [`FilmPixel`]: RGB sums
//! ([`rgb::Pixel`]) for the `rgb` film, RGB and wavelength buckets
//! ([`spectral::SpectralPixel`]) for the `spectral` one, RGB and what the
//! camera sees first ([`gbuffer::GBufferPixel`]) for the `gbuffer` one.

pub mod gbuffer;
pub mod rgb;
pub mod spectral;
pub mod spectral_buckets;
pub mod splat;
pub mod visible_surface;

pub use rgb::RgbFilm;

use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use visible_surface::VisibleSurface;

/// What a film keeps per pixel, summing one filtered sample at a time.
pub trait FilmPixel: Clone + Send + Sync {
    /// Whether samples need the surface the camera ray sees first.
    const USES_VISIBLE_SURFACE: bool = false;

    fn add_sample(
        &mut self,
        film: &RgbFilm,
        l: SampledSpectrum,
        lambda: &SampledWavelengths,
        weight: f32,
        visible: Option<&VisibleSurface>,
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
        _visible: Option<&VisibleSurface>,
    ) {
        film.add_sample(self, l, lambda, weight);
    }

    fn rgb(&self) -> &rgb::Pixel {
        self
    }
}
