//! The Halton sampler: dimension d is the radical inverse in the d-th prime
//! base, with the first two dimensions scaled so that consecutive runs of
//! indices land in each pixel.

use super::digit_permutation::RadicalInversePermutations;
use super::primes::PRIME_TABLE_SIZE;
use super::radical_inverse::{
    inverse_radical_inverse, owen_scrambled_radical_inverse, radical_inverse,
    scrambled_radical_inverse,
};
use super::randomize_strategy::RandomizeStrategy;
use crate::math::hash::mix_bits;
use glam::{IVec2, Vec2};

/// The Halton sequence's first two dimensions repeat over tiles of at most
/// this many pixels a side.
const MAX_HALTON_RESOLUTION: i32 = 128;

/// Randomized Halton points (pbrt-v4's `HaltonSampler`).
///
/// | parameter         | type    | default           | values                                |
/// |-------------------|---------|-------------------|---------------------------------------|
/// | `"pixelsamples"`  | integer | 16                |                                       |
/// | `"seed"`          | integer | `--seed`          |                                       |
/// | `"randomization"` | string  | `"permutedigits"` | `"none"`, `"permutedigits"`, `"owen"` |
///
/// The pixel's film position uses dimensions 0 and 1 (bases 2 and 3),
/// scaled by 2^j ≥ min(width, 128) and 3^k ≥ min(height, 128): the Halton
/// points whose first j base-2 and k base-3 digits reversed equal a pixel's
/// coordinates (modulo the tile) are that pixel's samples, found through the
/// Chinese remainder theorem. Those two dimensions are never scrambled.
/// Other requests start at dimension 2 and wrap back to 2 after the last
/// prime base (dimension 999). As in pbrt-v4, `"owen"` scrambling is seeded
/// by the dimension alone: the seed only affects `"permutedigits"`.
#[derive(Clone, Debug)]
pub struct HaltonSampler {
    samples_per_pixel: u32,
    randomize: RandomizeStrategy,
    digit_permutations: Option<RadicalInversePermutations>,
    /// 2^j and 3^k.
    base_scales: [i64; 2],
    /// j and k.
    base_exponents: [u32; 2],
    /// 3^k's inverse modulo 2^j and 2^j's inverse modulo 3^k.
    multiplicative_inverses: [i64; 2],
    halton_index: u64,
    dimension: usize,
}

/// `a`'s inverse modulo `n` (they must be coprime), in [0, n).
fn multiplicative_inverse(a: i64, n: i64) -> i64 {
    // Extended Euclid: x with a·x + n·y = 1.
    let (mut old_r, mut r) = (a, n);
    let (mut old_x, mut x) = (1i64, 0i64);
    while r != 0 {
        let q = old_r / r;
        (old_r, r) = (r, old_r - q * r);
        (old_x, x) = (x, old_x - q * x);
    }
    old_x.rem_euclid(n.max(1))
}

impl HaltonSampler {
    pub fn new(
        samples_per_pixel: u32,
        full_resolution: IVec2,
        randomize: RandomizeStrategy,
        seed: i32,
    ) -> Self {
        let digit_permutations = (randomize == RandomizeStrategy::PermuteDigits)
            .then(|| RadicalInversePermutations::new(seed as u32));
        let mut base_scales = [1i64; 2];
        let mut base_exponents = [0u32; 2];
        for (i, base) in [2i64, 3].into_iter().enumerate() {
            let limit = i64::from(full_resolution[i].min(MAX_HALTON_RESOLUTION));
            while base_scales[i] < limit {
                base_scales[i] *= base;
                base_exponents[i] += 1;
            }
        }
        let multiplicative_inverses = [
            multiplicative_inverse(base_scales[1], base_scales[0]),
            multiplicative_inverse(base_scales[0], base_scales[1]),
        ];
        HaltonSampler {
            samples_per_pixel,
            randomize,
            digit_permutations,
            base_scales,
            base_exponents,
            multiplicative_inverses,
            halton_index: 0,
            dimension: 0,
        }
    }

    pub fn samples_per_pixel(&self) -> u32 {
        self.samples_per_pixel
    }

    pub fn start_pixel_sample(&mut self, pixel: IVec2, sample_index: u32, dimension: u32) {
        let sample_stride = self.base_scales[0] * self.base_scales[1];
        let mut index = 0i64;
        if sample_stride > 1 {
            let pixel_in_tile = [
                pixel.x.rem_euclid(MAX_HALTON_RESOLUTION),
                pixel.y.rem_euclid(MAX_HALTON_RESOLUTION),
            ];
            for (i, base) in [2u64, 3].into_iter().enumerate() {
                let offset =
                    inverse_radical_inverse(pixel_in_tile[i] as u64, base, self.base_exponents[i])
                        as i64;
                index += offset
                    * (sample_stride / self.base_scales[i])
                    * self.multiplicative_inverses[i];
            }
            index %= sample_stride;
        }
        index += i64::from(sample_index) * sample_stride;
        self.halton_index = index as u64;
        self.dimension = (dimension as usize).max(2);
    }

    fn sample_dimension(&self, dimension: usize) -> f32 {
        match (self.randomize, &self.digit_permutations) {
            (RandomizeStrategy::PermuteDigits, Some(permutations)) => {
                scrambled_radical_inverse(dimension, self.halton_index, permutations.get(dimension))
            }
            (RandomizeStrategy::Owen, _) => owen_scrambled_radical_inverse(
                dimension,
                self.halton_index,
                mix_bits(1 + ((dimension as u64) << 4)) as u32,
            ),
            _ => radical_inverse(dimension, self.halton_index),
        }
    }

    /// See `Sampler::skip`.
    pub fn skip(&mut self, count: usize) {
        super::take_dimensions(&mut self.dimension, count, PRIME_TABLE_SIZE);
    }

    pub fn get_1d(&mut self) -> f32 {
        let dimension = super::take_dimensions(&mut self.dimension, 1, PRIME_TABLE_SIZE);
        self.sample_dimension(dimension)
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let dimension = super::take_dimensions(&mut self.dimension, 2, PRIME_TABLE_SIZE);
        Vec2::new(
            self.sample_dimension(dimension),
            self.sample_dimension(dimension + 1),
        )
    }

    pub fn get_pixel_2d(&mut self) -> Vec2 {
        Vec2::new(
            radical_inverse(0, self.halton_index >> self.base_exponents[0]),
            radical_inverse(1, self.halton_index / self.base_scales[1] as u64),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multiplicative_inverses() {
        assert_eq!(multiplicative_inverse(3, 8), 3);
        assert_eq!(multiplicative_inverse(243, 128), 59);
        assert_eq!((243 * 59) % 128, 1);
        assert_eq!(multiplicative_inverse(1, 1), 0);
    }

    /// The pixel-sample points of consecutive sample indices, mapped back
    /// through the base scales, land in the pixel they were asked for.
    #[test]
    fn first_two_dimensions_find_the_pixel() {
        let sampler = HaltonSampler::new(4, IVec2::new(100, 50), RandomizeStrategy::None, 0);
        assert_eq!(sampler.base_scales, [128, 81]);
        for (px, py) in [(0, 0), (5, 7), (99, 49), (130, 3)] {
            let mut s = sampler.clone();
            for index in 0..4 {
                s.start_pixel_sample(IVec2::new(px, py), index, 0);
                let x = radical_inverse(0, s.halton_index) * 128.0;
                let y = radical_inverse(1, s.halton_index) * 81.0;
                assert_eq!(x.floor() as i32, px % 128);
                assert_eq!(y.floor() as i32, py % 128);
            }
        }
    }
}
