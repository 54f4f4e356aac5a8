//! The `pmj02bn` sampler: progressive multi-jittered (0,2) point sets
//! (Christensen, Kensler and Kilpatrick 2018) dealt to each pixel's
//! samples, one set per pair of dimensions, as pbrt-v4's `PMJ02BNSampler`.
//!
//! | parameter        | type    | default  | values                          |
//! |------------------|---------|----------|---------------------------------|
//! | `"pixelsamples"` | integer | 16       | best a power of four            |
//! | `"seed"`         | integer | `--seed` |                                 |
//!
//! Its structure is pbrt-v4's: a 2D request takes point `π(i)` of the
//! point set of its dimension pair (π a permutation per pixel, dimension
//! and seed), shifted toroidally by an offset per pixel and dimension; a
//! 1D request takes stratum `π(i)` of `spp` strata, offset within it the
//! same way. Its numbers are not pbrt-v4's: pbrt-v4 reads precomputed
//! pmj02bn tables and blue-noise offsets, which rpbrt does not ship.
//! Here each point set is an Owen-scrambled (0,2)-sequence of Sobol'
//! points — which Helmer, Christensen and Kensler (2021) show is the same
//! distribution as the pmj02 construction — and the offsets are hashed
//! (white noise across pixels, not blue).

use super::permutation::permutation_element;
use super::randomize_strategy::{BinaryScrambler, RandomizeStrategy};
use super::sobol_sample::sobol_sample;
use crate::math::hash::hash_words;
use crate::math::ONE_MINUS_EPSILON;
use glam::{IVec2, Vec2};

/// How many distinct point sets: later dimension pairs reuse them, picked
/// by hash (as pbrt-v4 cycles through its tables).
const POINT_SETS: u32 = 5;

#[derive(Clone, Debug)]
pub struct Pmj02bnSampler {
    samples_per_pixel: u32,
    seed: i32,
    pixel: IVec2,
    sample_index: u32,
    dimension: u32,
}

/// A hash as a number in [0, 1).
fn unit(hash: u64) -> f32 {
    ((hash >> 40) as f32 * (1.0 / (1u64 << 24) as f32)).min(ONE_MINUS_EPSILON)
}

impl Pmj02bnSampler {
    pub fn new(samples_per_pixel: u32, seed: i32) -> Self {
        Pmj02bnSampler {
            samples_per_pixel,
            seed,
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

    /// See `Sampler::skip`.
    pub fn skip(&mut self, count: usize) {
        self.dimension += count as u32;
    }

    /// A hash of pixel, `dimension`, seed and `salt`.
    fn hash(&self, dimension: u32, salt: u32) -> u64 {
        hash_words(&[
            self.pixel.x as u32,
            self.pixel.y as u32,
            dimension,
            self.seed as u32,
            salt,
        ])
    }

    /// The sample's place in this pixel's order at the current dimension.
    fn permuted_index(&self) -> u32 {
        permutation_element(
            self.sample_index,
            self.samples_per_pixel,
            self.hash(self.dimension, 0) as u32,
        )
    }

    pub fn get_1d(&mut self) -> f32 {
        let index = self.permuted_index();
        let offset = unit(self.hash(self.dimension, 1));
        self.dimension += 1;
        ((index as f32 + offset) / self.samples_per_pixel as f32).min(ONE_MINUS_EPSILON)
    }

    /// Point `index` of the (0,2) point set scrambled by `seed`.
    fn point(index: u32, seed: u64) -> Vec2 {
        let scrambled = |dimension, seed| {
            sobol_sample(
                u64::from(index),
                dimension,
                BinaryScrambler::new(RandomizeStrategy::Owen, seed),
            )
        };
        Vec2::new(scrambled(0, seed as u32), scrambled(1, (seed >> 32) as u32))
    }

    pub fn get_2d(&mut self) -> Vec2 {
        let index = self.permuted_index();
        let pair = self.dimension / 2;
        let set = if pair < POINT_SETS {
            pair
        } else {
            (self.hash(self.dimension, 2) % POINT_SETS as u64) as u32
        };
        // The same point set in every pixel (seeded by set and seed only).
        let point = Self::point(index, hash_words(&[set, self.seed as u32]));
        let shift = Vec2::new(
            unit(self.hash(self.dimension, 1)),
            unit(self.hash(self.dimension + 1, 1)),
        );
        self.dimension += 2;
        let wrap = |v: f32| if v >= 1.0 { v - 1.0 } else { v }.min(ONE_MINUS_EPSILON);
        let u = point + shift;
        Vec2::new(wrap(u.x), wrap(u.y))
    }

    /// The film position: a point set of the pixel's own, unshifted, so
    /// that its samples stay one per stratum of the pixel (pbrt-v4 deals
    /// a blue-noise table's points to the pixels of a tile instead).
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        let index = self.permuted_index();
        let point = Self::point(index, self.hash(self.dimension, 3));
        self.dimension += 2;
        point
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Within a pixel, 16 samples of a 2D dimension fill each of the
    /// 4 × 4 strata of a (0,2) net once, up to the pixel's shift: count
    /// strata of the unshifted points by undoing the shift.
    #[test]
    fn each_pixel_gets_a_stratified_point_set() {
        let spp = 16;
        let mut s = Pmj02bnSampler::new(spp, 7);
        for pixel in [IVec2::new(0, 0), IVec2::new(13, 4)] {
            for dimension in [0u32, 2, 6, 14] {
                let mut cells = [[0u32; 4]; 4];
                let mut columns = [0u32; 16];
                let mut strata_1d = [0u32; 16];
                for i in 0..spp {
                    s.start_pixel_sample(pixel, i, dimension);
                    let shift =
                        Vec2::new(unit(s.hash(dimension, 1)), unit(s.hash(dimension + 1, 1)));
                    let u = s.get_2d();
                    assert!(u.cmpge(Vec2::ZERO).all() && u.cmplt(Vec2::ONE).all());
                    let p = (u - shift + Vec2::ONE).fract();
                    cells[(p.x * 4.0) as usize][(p.y * 4.0) as usize] += 1;
                    columns[(p.x * 16.0) as usize] += 1;
                    s.start_pixel_sample(pixel, i, dimension);
                    strata_1d[(s.get_1d() * 16.0) as usize] += 1;
                }
                assert!(cells.iter().flatten().all(|&c| c == 1), "{cells:?}");
                assert!(columns.iter().all(|&c| c == 1), "{columns:?}");
                assert!(strata_1d.iter().all(|&c| c == 1), "{strata_1d:?}");
            }
        }
    }

    #[test]
    fn pixels_get_different_samples() {
        let mut s = Pmj02bnSampler::new(4, 0);
        s.start_pixel_sample(IVec2::new(0, 0), 1, 2);
        let a = s.get_2d();
        s.start_pixel_sample(IVec2::new(1, 0), 1, 2);
        assert_ne!(a, s.get_2d());
    }
}
