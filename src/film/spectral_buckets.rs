//! The wavelength buckets of the `spectral` film: where a wavelength
//! falls, how the buckets' channels are named, and how its samples'
//! wavelengths are drawn (uniformly over the buckets' range).

use crate::spectrum::SampledWavelengths;

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
