//! pbrt-v4's `spectral` film: the `rgb` film's image plus the radiance
//! averaged in wavelength buckets, written as one OpenEXR file in the
//! spectral layout of Fichet et al. 2021 ("An OpenEXR Layout for Spectral
//! Images"): channels `R`, `G`, `B`, then `S0.<λ>nm` per bucket (λ its
//! centre, with ',' for the decimal point, as '.' separates layers),
//! and the header's `spectralLayoutVersion` and `emissiveUnits`.
//!
//! Wavelengths are sampled uniformly over [`lambdamin`, `lambdamax`]
//! (stratified, one per bucket range), so every bucket's sum divided by
//! its weight is an average of radiance over that bucket, times the CIE
//! Y integral (which cancels the photometric normalisation of lights).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `nbuckets` | integer | 16 | wavelength buckets |
//! | `lambdamin`, `lambdamax` | float | 360, 830 | wavelength range in nm (within 360–830) |
//!
//! and every parameter of the `rgb` film; the file name must end in `.exr`.

use super::rgb::{Pixel, RgbFilm};
use super::spectral_buckets::SpectralBuckets;
use super::visible_surface::VisibleSurface;
use super::FilmPixel;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, CIE_Y_INTEGRAL, N_SPECTRUM_SAMPLES};

/// A spectral film's pixel: the RGB sums and, per bucket, the sum of
/// weighted radiance and of weights.
#[derive(Clone, Debug)]
pub struct SpectralPixel {
    pub rgb: Pixel,
    /// `count` radiance sums, then `count` weight sums.
    sums: Box<[f64]>,
}

impl SpectralPixel {
    pub fn new(buckets: &SpectralBuckets) -> Self {
        SpectralPixel {
            rgb: Pixel::default(),
            sums: vec![0.0; 2 * buckets.count].into_boxed_slice(),
        }
    }

    /// The average radiance in each bucket (0 where no sample fell).
    pub fn bucket_values(&self) -> impl Iterator<Item = f32> + '_ {
        let (radiance, weight) = self.sums.split_at(self.sums.len() / 2);
        radiance
            .iter()
            .zip(weight)
            .map(|(&r, &w)| if w > 0.0 { (r / w) as f32 } else { 0.0 })
    }
}

impl FilmPixel for SpectralPixel {
    fn add_sample(
        &mut self,
        film: &RgbFilm,
        l: SampledSpectrum,
        lambda: &SampledWavelengths,
        weight: f32,
        _visible: Option<&VisibleSurface>,
    ) {
        film.add_sample(&mut self.rgb, l, lambda, weight);
        let Some(buckets) = film.spectral else {
            return;
        };
        // Clamped as the RGB is, by its largest wavelength. The density
        // is uniform, so each bucket's weighted mean is its average
        // radiance as it stands (pbrt-v4 does not divide by it). Where a
        // dispersive surface kept only the first wavelength, that one
        // carries the others' share (its density fell by as much) and the
        // others carry nothing: pbrt-v4 adds them as they are.
        let mut l = l;
        let m = l.max_component();
        if m > film.max_component_value() {
            l *= film.max_component_value() / m;
        }
        let uniform = 1.0 / (buckets.lambda_max - buckets.lambda_min);
        let count = buckets.count;
        for i in 0..N_SPECTRUM_SAMPLES {
            let b = buckets.bucket(lambda.lambda[i]);
            let share = if lambda.pdf[i] > 0.0 {
                uniform / lambda.pdf[i]
            } else {
                0.0
            };
            self.sums[b] += (weight * CIE_Y_INTEGRAL * l[i] * share) as f64;
            self.sums[count + b] += weight as f64;
        }
    }

    fn rgb(&self) -> &Pixel {
        &self.rgb
    }
}
