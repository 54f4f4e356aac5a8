//! The stratified sampler: one jittered sample per stratum, with the strata
//! of each dimension visited in an independent random order ("padding").

use super::permutation::permutation_element;
use crate::math::hash::hash_words;
use crate::math::pcg32::Pcg32;
use glam::{IVec2, Vec2};

/// Jittered stratified samples (pbrt-v4's `StratifiedSampler`).
///
/// | parameter    | type    | default             |
/// |--------------|---------|---------------------|
/// | `"xsamples"` | integer | 4                   |
/// | `"ysamples"` | integer | 4                   |
/// | `"jitter"`   | bool    | true                |
/// | `"seed"`     | integer | the `--seed` option |
///
/// Samples per pixel are `xsamples · ysamples`. A 1D value falls in one of
/// that many strata of [0, 1), a 2D value in one cell of the
/// `xsamples × ysamples` grid; which stratum a sample index gets is a
/// permutation chosen by hashing pixel, dimension and seed. Without jitter
/// values are stratum centres.
#[derive(Clone, Debug)]
pub struct StratifiedSampler {
    x_samples: u32,
    y_samples: u32,
    jitter: bool,
    seed: i32,
    rng: Pcg32,
    pixel: IVec2,
    sample_index: u32,
    dimension: u32,
}

impl StratifiedSampler {
    /// `x_samples` and `y_samples` must be at least 1.
    pub fn new(x_samples: u32, y_samples: u32, jitter: bool, seed: i32) -> Self {
        StratifiedSampler {
            x_samples: x_samples.max(1),
            y_samples: y_samples.max(1),
            jitter,
            seed,
            rng: Pcg32::default(),
            pixel: IVec2::ZERO,
            sample_index: 0,
            dimension: 0,
        }
    }

    pub fn samples_per_pixel(&self) -> u32 {
        self.x_samples * self.y_samples
    }

    pub fn start_pixel_sample(&mut self, pixel: IVec2, sample_index: u32, dimension: u32) {
        self.pixel = pixel;
        self.sample_index = sample_index;
        self.dimension = dimension;
        self.rng.set_sequence(hash_words(&[
            pixel.x as u32,
            pixel.y as u32,
            self.seed as u32,
        ]));
        self.rng
            .advance((u64::from(sample_index) * 65536 + u64::from(dimension)) as i64);
    }

    /// This sample's stratum in the current dimension.
    fn stratum(&self) -> u32 {
        let hash = hash_words(&[
            self.pixel.x as u32,
            self.pixel.y as u32,
            self.dimension,
            self.seed as u32,
        ]);
        permutation_element(self.sample_index, self.samples_per_pixel(), hash as u32)
    }

    fn offset_in_stratum(&mut self) -> f32 {
        if self.jitter {
            self.rng.uniform_f32()
        } else {
            0.5
        }
    }

    pub fn get_1d(&mut self) -> f32 {
        let stratum = self.stratum();
        self.dimension += 1;
        let delta = self.offset_in_stratum();
        (stratum as f32 + delta) / self.samples_per_pixel() as f32
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let stratum = self.stratum();
        self.dimension += 2;
        let x = stratum % self.x_samples;
        let y = stratum / self.x_samples;
        let dx = self.offset_in_stratum();
        let dy = self.offset_in_stratum();
        Vec2::new(
            (x as f32 + dx) / self.x_samples as f32,
            (y as f32 + dy) / self.y_samples as f32,
        )
    }

    pub fn get_pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}
