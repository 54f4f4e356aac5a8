//! The independent sampler: uniform random values with no stratification.

use crate::math::hash::hash_words;
use crate::math::pcg32::Pcg32;
use glam::{IVec2, Vec2};

/// Independent uniform random samples (pbrt-v4's `IndependentSampler`).
///
/// | parameter        | type    | default               |
/// |------------------|---------|-----------------------|
/// | `"pixelsamples"` | integer | 4                     |
/// | `"seed"`         | integer | the `--seed` option   |
///
/// Each pixel sample reads its own stretch of one PCG32 stream: the stream
/// is chosen by hashing the pixel and seed, and sample `i` starts
/// `i · 65536 + dimension` values in, so values never depend on which
/// thread or in what order pixels are rendered.
#[derive(Clone, Debug)]
pub struct IndependentSampler {
    samples_per_pixel: u32,
    seed: i32,
    rng: Pcg32,
}

impl IndependentSampler {
    pub fn new(samples_per_pixel: u32, seed: i32) -> Self {
        IndependentSampler {
            samples_per_pixel,
            seed,
            rng: Pcg32::default(),
        }
    }

    pub fn samples_per_pixel(&self) -> u32 {
        self.samples_per_pixel
    }

    pub fn start_pixel_sample(&mut self, pixel: IVec2, sample_index: u32, dimension: u32) {
        self.rng.set_sequence(hash_words(&[
            pixel.x as u32,
            pixel.y as u32,
            self.seed as u32,
        ]));
        self.rng
            .advance((u64::from(sample_index) * 65536 + u64::from(dimension)) as i64);
    }

    pub fn get_1d(&mut self) -> f32 {
        self.rng.uniform_f32()
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let x = self.rng.uniform_f32();
        let y = self.rng.uniform_f32();
        Vec2::new(x, y)
    }

    pub fn get_pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}
