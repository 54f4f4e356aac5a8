//! The padded Sobol' sampler: each pair of dimensions is a 2D Sobol' point
//! set of its own, its points dealt to the pixel's samples in a random
//! order per pixel and dimension.

use super::permutation::permutation_element;
use super::randomize_strategy::{BinaryScrambler, RandomizeStrategy};
use super::sobol_sample::sobol_sample;
use crate::math::hash::hash_words;
use glam::{IVec2, Vec2};

/// Per-pixel Sobol' points, padded across dimensions (pbrt-v4's
/// `PaddedSobolSampler`).
///
/// | parameter         | type    | default      | values                                              |
/// |-------------------|---------|--------------|-----------------------------------------------------|
/// | `"pixelsamples"`  | integer | 16           | best a power of two                                 |
/// | `"seed"`          | integer | `--seed`     |                                                     |
/// | `"randomization"` | string  | `"fastowen"` | `"none"`, `"permutedigits"`, `"fastowen"`, `"owen"` |
///
/// A 1D request uses Sobol' dimension 0, a 2D one dimensions 0 and 1; the
/// sample index is permuted, and the scrambling seeded, by a hash of pixel,
/// dimension and seed.
#[derive(Clone, Debug)]
pub struct PaddedSobolSampler {
    samples_per_pixel: u32,
    seed: i32,
    randomize: RandomizeStrategy,
    pixel: IVec2,
    sample_index: u32,
    dimension: u32,
}

impl PaddedSobolSampler {
    pub fn new(samples_per_pixel: u32, randomize: RandomizeStrategy, seed: i32) -> Self {
        PaddedSobolSampler {
            samples_per_pixel,
            seed,
            randomize,
            pixel: IVec2::ZERO,
            sample_index: 0,
            dimension: 0,
        }
    }

    pub fn samples_per_pixel(&self) -> u32 {
        self.samples_per_pixel
    }

    pub fn start_pixel_sample(&mut self, pixel: IVec2, sample_index: u32, dimension: u32) {
        self.pixel = pixel;
        self.sample_index = sample_index;
        self.dimension = dimension;
    }

    /// The hash of pixel, dimension and seed, and the permuted index.
    fn hash_and_index(&self) -> (u64, u64) {
        let hash = hash_words(&[
            self.pixel.x as u32,
            self.pixel.y as u32,
            self.dimension,
            self.seed as u32,
        ]);
        let index = permutation_element(self.sample_index, self.samples_per_pixel, hash as u32);
        (hash, u64::from(index))
    }

    /// See `Sampler::skip`.
    pub fn skip(&mut self, count: usize) {
        self.dimension += count as u32;
    }

    pub fn get_1d(&mut self) -> f32 {
        let (hash, index) = self.hash_and_index();
        self.dimension += 1;
        let scrambler = BinaryScrambler::new(self.randomize, (hash >> 32) as u32);
        sobol_sample(index, 0, scrambler)
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let (hash, index) = self.hash_and_index();
        self.dimension += 2;
        Vec2::new(
            sobol_sample(index, 0, BinaryScrambler::new(self.randomize, hash as u32)),
            sobol_sample(
                index,
                1,
                BinaryScrambler::new(self.randomize, (hash >> 32) as u32),
            ),
        )
    }

    pub fn get_pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}
