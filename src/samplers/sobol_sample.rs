//! Points of the Sobol' sequence: the sample index multiplied by a
//! dimension's generator matrix over GF(2), then scrambled.

use super::randomize_strategy::BinaryScrambler;
use super::sobol_matrices::{SOBOL_DIMENSIONS, SOBOL_MATRICES_32, SOBOL_MATRIX_SIZE};
use crate::math::pcg32::TWO_TO_MINUS_32;
use crate::math::ONE_MINUS_EPSILON;

/// Coordinate `dimension` (below [`SOBOL_DIMENSIONS`]; larger ones wrap) of
/// Sobol' point `index` (below 2^52; higher bits are ignored), scrambled.
pub fn sobol_sample(index: u64, dimension: usize, scrambler: BinaryScrambler) -> f32 {
    let bits = scrambler.scramble(sobol_bits(index, dimension % SOBOL_DIMENSIONS));
    (bits as f32 * TWO_TO_MINUS_32).min(ONE_MINUS_EPSILON)
}

/// The unscrambled product of the index with the dimension's matrix. It
/// is the sampler's hottest loop (a quarter of a render's time before it
/// skipped the index's zero bits), so: dimension 0's matrix is the bit
/// reversal (van der Corput; its columns past the 32nd are zero), and for
/// the others only the index's set bits are visited.
#[inline]
fn sobol_bits(index: u64, dimension: usize) -> u32 {
    let mut remaining = index & ((1u64 << SOBOL_MATRIX_SIZE) - 1);
    if dimension == 0 {
        return (remaining as u32).reverse_bits();
    }
    let first_column = dimension * SOBOL_MATRIX_SIZE;
    let columns = &SOBOL_MATRICES_32[first_column..first_column + SOBOL_MATRIX_SIZE];
    let mut bits = 0u32;
    while remaining != 0 {
        bits ^= columns[remaining.trailing_zeros() as usize];
        remaining &= remaining - 1;
    }
    bits
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The matrix product as the definition states it, column by column.
    #[test]
    fn fast_product_is_the_matrix_product() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..20000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let index = state >> (state % 40);
            let dimension = (state % 1031) as usize % SOBOL_DIMENSIONS;
            let dimension = if state % 5 == 0 { 0 } else { dimension };
            let mut expected = 0u32;
            for j in 0..SOBOL_MATRIX_SIZE {
                if index >> j & 1 == 1 {
                    expected ^= column(dimension, j);
                }
            }
            assert_eq!(
                sobol_bits(index, dimension),
                expected,
                "index {index:#x} dimension {dimension}"
            );
        }
    }

    fn column(dimension: usize, j: usize) -> u32 {
        SOBOL_MATRICES_32[dimension * SOBOL_MATRIX_SIZE + j]
    }

    /// Spot checks against pbrt-v4's table (built from the same Joe–Kuo
    /// numbers), including columns past the 32nd.
    #[test]
    fn table_matches_known_generator_columns() {
        assert_eq!(column(0, 0), 0x8000_0000);
        assert_eq!(column(0, 31), 1);
        assert_eq!(column(0, 32), 0);
        assert_eq!(column(1, 3), 0xf000_0000);
        assert_eq!(column(1, 31), 0xffff_ffff);
        assert_eq!(column(1, 33), 0xc000_0000);
        assert_eq!(
            (0..8).map(|j| column(2, j)).collect::<Vec<_>>(),
            [
                0x8000_0000,
                0xc000_0000,
                0x6000_0000,
                0x9000_0000,
                0xe800_0000,
                0x5c00_0000,
                0x8e00_0000,
                0xc500_0000
            ]
        );
        assert_eq!(column(1023, 9), 0xfec0_0000);
        assert_eq!(column(1023, 50), 0x34a3_2b93);
        assert_eq!(column(1023, 51), 0x1397_876e);
    }

    /// Each dimension's first 2^k points put one point in each interval of
    /// length 2^-k, and every pair among the first dimensions is a
    /// (0, m, 2)-net for small m in elementary intervals of equal sides.
    #[test]
    fn unscrambled_points_are_stratified() {
        for dimension in [0, 1, 2, 5, 100, 1023] {
            let mut seen = [false; 64];
            for index in 0..64 {
                let u = sobol_sample(index, dimension, BinaryScrambler::None);
                let cell = (u * 64.0) as usize;
                assert!(!seen[cell], "dimension {dimension}");
                seen[cell] = true;
            }
        }
        let mut seen = [false; 16];
        for index in 0..16 {
            let x = sobol_sample(index, 0, BinaryScrambler::None);
            let y = sobol_sample(index, 1, BinaryScrambler::None);
            let cell = (x * 4.0) as usize + 4 * (y * 4.0) as usize;
            assert!(!seen[cell]);
            seen[cell] = true;
        }
    }

    #[test]
    fn first_point_is_zero_and_values_stay_below_one() {
        assert_eq!(sobol_sample(0, 3, BinaryScrambler::None), 0.0);
        assert!(sobol_sample(5, 3, BinaryScrambler::XorMask(u32::MAX)) < 1.0);
    }
}
