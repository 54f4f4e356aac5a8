//! The global Sobol' sampler: one Sobol' sequence over the whole image, its
//! first two dimensions spread over the pixels.

use super::randomize_strategy::{BinaryScrambler, RandomizeStrategy};
use super::sobol_interval::{sobol_frame_index, sobol_pixel_index};
use super::sobol_matrices::SOBOL_DIMENSIONS;
use super::sobol_sample::sobol_sample;
use crate::math::hash::hash_words;
use crate::math::ONE_MINUS_EPSILON;
use glam::{IVec2, Vec2};
use std::sync::Arc;

/// Samples from one image-wide Sobol' sequence (pbrt-v4's `SobolSampler`).
///
/// | parameter         | type    | default      | values                                              |
/// |-------------------|---------|--------------|-----------------------------------------------------|
/// | `"pixelsamples"`  | integer | 16           | best a power of two                                 |
/// | `"seed"`          | integer | `--seed`     |                                                     |
/// | `"randomization"` | string  | `"fastowen"` | `"none"`, `"permutedigits"`, `"fastowen"`, `"owen"` |
///
/// Dimensions 0 and 1, over a square of 2^m pixels a side covering the
/// image, are the film position: a pixel's samples are the Sobol' points
/// that fall in it, and they are never scrambled. Other requests start at
/// dimension 2 and wrap back to 2 after dimension 1023. Images wider or
/// taller than 2^25 pixels are not supported.
#[derive(Clone, Debug)]
pub struct SobolSampler {
    samples_per_pixel: u32,
    /// The power of two at least the image's larger side.
    scale: i32,
    log2_scale: u32,
    randomize: RandomizeStrategy,
    /// The scrambling hash of each dimension, (dimension, seed) hashed
    /// once per sampler rather than per sample.
    dimension_hashes: Arc<[u32]>,
    pixel: IVec2,
    /// The pixel's part of the Sobol' index (see `sobol_pixel_index`),
    /// kept while the pixel's samples are taken.
    pixel_index: u64,
    dimension: usize,
    sobol_index: u64,
}

impl SobolSampler {
    /// `full_resolution`'s sides must be between 1 and 2^25.
    pub fn new(
        samples_per_pixel: u32,
        full_resolution: IVec2,
        randomize: RandomizeStrategy,
        seed: i32,
    ) -> Self {
        let largest_side = full_resolution.x.max(full_resolution.y).max(1) as u32;
        let scale = largest_side.next_power_of_two();
        SobolSampler {
            samples_per_pixel,
            scale: scale as i32,
            log2_scale: scale.trailing_zeros(),
            randomize,
            dimension_hashes: (0..SOBOL_DIMENSIONS)
                .map(|d| hash_words(&[d as u32, seed as u32]) as u32)
                .collect(),
            pixel: IVec2::ZERO,
            pixel_index: sobol_pixel_index(scale.trailing_zeros(), IVec2::ZERO),
            dimension: 0,
            sobol_index: 0,
        }
    }

    pub fn samples_per_pixel(&self) -> u32 {
        self.samples_per_pixel
    }

    pub fn start_pixel_sample(&mut self, pixel: IVec2, sample_index: u32, dimension: u32) {
        if pixel != self.pixel {
            self.pixel = pixel;
            self.pixel_index = sobol_pixel_index(self.log2_scale, pixel);
        }
        self.dimension = (dimension as usize).max(2);
        self.sobol_index =
            sobol_frame_index(self.log2_scale, u64::from(sample_index)) ^ self.pixel_index;
    }

    fn sample_dimension(&self, dimension: usize) -> f32 {
        let scrambler = match self.randomize {
            RandomizeStrategy::None => BinaryScrambler::None,
            strategy => BinaryScrambler::new(strategy, self.dimension_hashes[dimension]),
        };
        sobol_sample(self.sobol_index, dimension, scrambler)
    }

    /// See `Sampler::skip`.
    pub fn skip(&mut self, count: usize) {
        super::take_dimensions(&mut self.dimension, count, SOBOL_DIMENSIONS);
    }

    pub fn get_1d(&mut self) -> f32 {
        let dimension = super::take_dimensions(&mut self.dimension, 1, SOBOL_DIMENSIONS);
        self.sample_dimension(dimension)
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let dimension = super::take_dimensions(&mut self.dimension, 2, SOBOL_DIMENSIONS);
        Vec2::new(
            self.sample_dimension(dimension),
            self.sample_dimension(dimension + 1),
        )
    }

    pub fn get_pixel_2d(&mut self) -> Vec2 {
        let scale = self.scale as f32;
        let to_pixel =
            |u: f32, pixel: i32| (u * scale - pixel as f32).clamp(0.0, ONE_MINUS_EPSILON);
        Vec2::new(
            to_pixel(
                sobol_sample(self.sobol_index, 0, BinaryScrambler::None),
                self.pixel.x,
            ),
            to_pixel(
                sobol_sample(self.sobol_index, 1, BinaryScrambler::None),
                self.pixel.y,
            ),
        )
    }
}
