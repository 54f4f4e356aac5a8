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

use super::gbuffer::VisibleSurface;
use super::rgb::{Pixel, RgbFilm};
use super::FilmPixel;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, CIE_Y_INTEGRAL, N_SPECTRUM_SAMPLES};

/// The wavelength buckets of a spectral film.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpectralBuckets {
    pub lambda_min: f32,
    pub lambda_max: f32,
    pub count: usize,
}

impl SpectralBuckets {
    /// The bucket wavelength `lambda` falls in (the ends clamped in).
    pub fn bucket(&self, lambda: f32) -> usize {
        let b =
            self.count as f32 * (lambda - self.lambda_min) / (self.lambda_max - self.lambda_min);
        (b.max(0.0) as usize).min(self.count - 1)
    }

    /// The channel names of the buckets, `S0.<centre>nm` (3 decimals,
    /// decimal comma).
    pub fn channel_names(&self) -> Vec<String> {
        (0..self.count)
            .map(|i| {
                let t = (i as f32 + 0.5) / self.count as f32;
                let centre = (1.0 - t) * self.lambda_min + t * self.lambda_max;
                format!("S0.{}nm", format!("{centre:.3}").replace('.', ","))
            })
            .collect()
    }

    /// Wavelengths for a sample: uniform over the buckets' range.
    pub fn sample_wavelengths(&self, u: f32) -> SampledWavelengths {
        SampledWavelengths::sample_uniform(u, self.lambda_min, self.lambda_max)
    }
}

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
            l = l * (film.max_component_value() / m);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buckets_split_the_range_evenly_and_name_their_centres() {
        let b = SpectralBuckets {
            lambda_min: 400.0,
            lambda_max: 700.0,
            count: 3,
        };
        assert_eq!(b.bucket(400.0), 0);
        assert_eq!(b.bucket(499.9), 0);
        assert_eq!(b.bucket(500.1), 1);
        assert_eq!(b.bucket(699.9), 2);
        assert_eq!(b.bucket(700.0), 2);
        assert_eq!(b.bucket(350.0), 0);
        assert_eq!(
            b.channel_names(),
            ["S0.450,000nm", "S0.550,000nm", "S0.650,000nm"]
        );
        // Uniform wavelengths stay in the range, one in each quarter.
        let lambda = b.sample_wavelengths(0.3);
        for (i, l) in lambda.lambda.iter().enumerate() {
            assert!((400.0..700.0).contains(l), "{i}: {l}");
        }
    }
}
