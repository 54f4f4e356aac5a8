//! The Z-order Sobol' sampler (Ahmed and Wonka's "screen-space blue noise
//! from a Sobol' sequence"): pixels visited along a Morton curve each take
//! the next run of a 2D Sobol' sequence, with randomly permuted base-4
//! digits so neighbouring pixels' error decorrelates as blue noise.

use super::bits::encode_morton_2;
use super::randomize_strategy::{BinaryScrambler, RandomizeStrategy};
use super::sobol_sample::sobol_sample;
use crate::math::hash::{hash_words, mix_bits};
use glam::{IVec2, Vec2};

/// All 24 permutations of the four base-4 digit values.
const BASE_4_PERMUTATIONS: [[u8; 4]; 24] = [
    [0, 1, 2, 3],
    [0, 1, 3, 2],
    [0, 2, 1, 3],
    [0, 2, 3, 1],
    [0, 3, 2, 1],
    [0, 3, 1, 2],
    [1, 0, 2, 3],
    [1, 0, 3, 2],
    [1, 2, 0, 3],
    [1, 2, 3, 0],
    [1, 3, 2, 0],
    [1, 3, 0, 2],
    [2, 1, 0, 3],
    [2, 1, 3, 0],
    [2, 0, 1, 3],
    [2, 0, 3, 1],
    [2, 3, 0, 1],
    [2, 3, 1, 0],
    [3, 1, 2, 0],
    [3, 1, 0, 2],
    [3, 2, 1, 0],
    [3, 2, 0, 1],
    [3, 0, 2, 1],
    [3, 0, 1, 2],
];

/// Blue-noise Sobol' samples along a Morton curve (pbrt-v4's
/// `ZSobolSampler`, its default sampler).
///
/// | parameter         | type    | default      | values                                              |
/// |-------------------|---------|--------------|-----------------------------------------------------|
/// | `"pixelsamples"`  | integer | 16           | rounded down to a power of two                      |
/// | `"seed"`          | integer | `--seed`     |                                                     |
/// | `"randomization"` | string  | `"fastowen"` | `"none"`, `"permutedigits"`, `"fastowen"`, `"owen"` |
///
/// Sample `i` of a pixel has Morton index `morton(pixel) · spp + i`; each
/// dimension permutes its base-4 digits (each digit's permutation chosen by
/// a hash of the digits above it and the dimension) to get a Sobol' index.
/// A 1D request uses Sobol' dimension 0, a 2D one dimensions 0 and 1,
/// scrambled with a hash of dimension and seed.
#[derive(Clone, Debug)]
pub struct ZSobolSampler {
    randomize: RandomizeStrategy,
    seed: i32,
    log2_samples_per_pixel: u32,
    base_4_digit_count: u32,
    morton_index: u64,
    dimension: u32,
}

impl ZSobolSampler {
    /// `samples_per_pixel` (at least 1) is rounded down to a power of two,
    /// as pbrt-v4 does.
    pub fn new(
        samples_per_pixel: u32,
        full_resolution: IVec2,
        randomize: RandomizeStrategy,
        seed: i32,
    ) -> Self {
        let log2_samples_per_pixel = samples_per_pixel.max(1).ilog2();
        let largest_side = full_resolution.x.max(full_resolution.y).max(1) as u32;
        let resolution = largest_side.next_power_of_two();
        let log4_samples_per_pixel = log2_samples_per_pixel.div_ceil(2);
        ZSobolSampler {
            randomize,
            seed,
            log2_samples_per_pixel,
            base_4_digit_count: resolution.ilog2() + log4_samples_per_pixel,
            morton_index: 0,
            dimension: 0,
        }
    }

    pub fn samples_per_pixel(&self) -> u32 {
        1 << self.log2_samples_per_pixel
    }

    pub fn start_pixel_sample(&mut self, pixel: IVec2, sample_index: u32, dimension: u32) {
        self.dimension = dimension;
        self.morton_index = (encode_morton_2(pixel.x as u32, pixel.y as u32)
            << self.log2_samples_per_pixel)
            | u64::from(sample_index);
    }

    /// The Sobol' index for the current dimension: the Morton index with
    /// its base-4 digits randomly permuted (and, for an odd power of two
    /// samples per pixel, its last binary digit flipped at random).
    fn sample_index(&self) -> u64 {
        let dimension_salt = u64::from(0x5555_5555u32.wrapping_mul(self.dimension));
        let odd_power_of_two = self.log2_samples_per_pixel & 1 == 1;
        let last_digit = u32::from(odd_power_of_two);
        let mut sample_index = 0u64;
        for i in (last_digit..self.base_4_digit_count).rev() {
            let digit_shift = 2 * i - last_digit;
            let digit = (self.morton_index.checked_shr(digit_shift).unwrap_or(0) & 3) as usize;
            let higher_digits = self.morton_index.checked_shr(digit_shift + 2).unwrap_or(0);
            let permutation = ((mix_bits(higher_digits ^ dimension_salt) >> 24) % 24) as usize;
            let digit = u64::from(BASE_4_PERMUTATIONS[permutation][digit]);
            sample_index |= digit.checked_shl(digit_shift).unwrap_or(0);
        }
        if odd_power_of_two {
            let digit = self.morton_index & 1;
            sample_index |= digit ^ (mix_bits((self.morton_index >> 1) ^ dimension_salt) & 1);
        }
        sample_index
    }

    fn scrambler(&self, seed: u32) -> BinaryScrambler {
        BinaryScrambler::new(self.randomize, seed)
    }

    /// See `Sampler::skip`.
    pub fn skip(&mut self, count: usize) {
        self.dimension += count as u32;
    }

    pub fn get_1d(&mut self) -> f32 {
        let sample_index = self.sample_index();
        self.dimension += 1;
        let hash = hash_words(&[self.dimension, self.seed as u32]) as u32;
        sobol_sample(sample_index, 0, self.scrambler(hash))
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let sample_index = self.sample_index();
        self.dimension += 2;
        let bits = hash_words(&[self.dimension, self.seed as u32]);
        Vec2::new(
            sobol_sample(sample_index, 0, self.scrambler(bits as u32)),
            sobol_sample(sample_index, 1, self.scrambler((bits >> 32) as u32)),
        )
    }

    pub fn get_pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_table_holds_every_permutation_once() {
        let mut seen = std::collections::HashSet::new();
        for p in BASE_4_PERMUTATIONS {
            let mut sorted = p;
            sorted.sort();
            assert_eq!(sorted, [0, 1, 2, 3]);
            assert!(seen.insert(p));
        }
    }

    /// Within one pixel and dimension, the spp sample indices are a
    /// permutation of one aligned block of spp Sobol' indices.
    #[test]
    fn a_pixels_samples_take_one_aligned_block_of_indices() {
        for spp in [1u32, 2, 8, 16, 32] {
            let mut sampler =
                ZSobolSampler::new(spp, IVec2::new(64, 48), RandomizeStrategy::FastOwen, 3);
            for pixel in [IVec2::new(0, 0), IVec2::new(13, 7), IVec2::new(63, 47)] {
                let mut indices: Vec<u64> = (0..spp)
                    .map(|i| {
                        sampler.start_pixel_sample(pixel, i, 5);
                        sampler.sample_index()
                    })
                    .collect();
                indices.sort();
                let block = indices[0] / u64::from(spp);
                let expected: Vec<u64> = (0..u64::from(spp))
                    .map(|i| block * u64::from(spp) + i)
                    .collect();
                assert_eq!(indices, expected, "spp {spp} pixel {pixel}");
            }
        }
    }
}
