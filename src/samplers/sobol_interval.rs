//! Finding the Sobol' points that fall in a given pixel: with the image
//! covered by a 2^m × 2^m grid laid over the first two Sobol' dimensions,
//! the `frame`-th point of the sequence inside pixel `p` (pbrt-v4's
//! `SobolIntervalToIndex`, after Grünschloß et al.).
//!
//! The first m binary digits of the point's x and y coordinates are the
//! pixel. They are a linear function over GF(2) of the index's bits: the low
//! 2m bits through an invertible 2m × 2m matrix M, the bits above (the
//! `frame`) through further columns D. So the index is `frame << 2m` with
//! low bits M⁻¹ (pixel ⊕ D·frame). M⁻¹ and D are computed here from the
//! generator matrices, for every m up to [`MAX_LOG2_RESOLUTION`].

use super::sobol_matrices::{SOBOL_MATRICES_32, SOBOL_MATRIX_SIZE};
use std::sync::OnceLock;

/// The largest m (a 2^m × 2^m pixel grid) supported: pbrt-v4's limit.
pub const MAX_LOG2_RESOLUTION: u32 = 25;

/// M⁻¹ and D for one m, with pixel bits packed as `(x << m) | y`.
struct PixelGridMatrices {
    /// Column c: the index bits to XOR in for bit c of the packed pixel.
    inverse_columns: Vec<u64>,
    /// Column c: M⁻¹ of [`frame_columns`]' column c, the low index bits that frame
    /// bit c XORs in (the map is linear, so the pixel's and the frame's
    /// parts of the index can be computed apart).
    frame_index_columns: Vec<u64>,
}

/// The packed pixel bits (`(x << m) | y`, each the top m bits of its
/// coordinate) that index bit `k` contributes.
fn pixel_bits_of_index_bit(m: u32, k: usize) -> u64 {
    let x = SOBOL_MATRICES_32[k] >> (32 - m);
    let y = SOBOL_MATRICES_32[SOBOL_MATRIX_SIZE + k] >> (32 - m);
    (u64::from(x) << m) | u64::from(y)
}

impl PixelGridMatrices {
    fn new(m: u32) -> Self {
        let size = 2 * m as usize;
        // Gauss–Jordan elimination over GF(2) on (column, index bit) pairs
        // until each column is a single pixel bit.
        let mut rows: Vec<(u64, u64)> = (0..size)
            .map(|k| (pixel_bits_of_index_bit(m, k), 1u64 << k))
            .collect();
        for bit in 0..size {
            let mask = 1u64 << bit;
            if let Some(pivot) = (bit..size).find(|&r| rows[r].0 & mask != 0) {
                rows.swap(bit, pivot);
                let (pivot_value, pivot_combination) = rows[bit];
                for (r, row) in rows.iter_mut().enumerate() {
                    if r != bit && row.0 & mask != 0 {
                        row.0 ^= pivot_value;
                        row.1 ^= pivot_combination;
                    }
                }
            }
        }
        let inverse_columns: Vec<u64> = rows.iter().map(|&(_, combination)| combination).collect();
        let frame_index_columns = frame_columns(m)
            .iter()
            .map(|&bits| xor_columns(&inverse_columns, bits))
            .collect();
        PixelGridMatrices {
            inverse_columns,
            frame_index_columns,
        }
    }
}

/// D: column c is the packed pixel bits that index bit 2m + c contributes.
fn frame_columns(m: u32) -> Vec<u64> {
    (2 * m as usize..SOBOL_MATRIX_SIZE)
        .map(|k| pixel_bits_of_index_bit(m, k))
        .collect()
}

/// The XOR of the `columns` picked by the set bits of `bits` (a matrix
/// times a vector over GF(2)).
fn xor_columns(columns: &[u64], mut bits: u64) -> u64 {
    let mut sum = 0;
    for column in columns {
        if bits == 0 {
            break;
        }
        if bits & 1 != 0 {
            sum ^= column;
        }
        bits >>= 1;
    }
    sum
}

fn pixel_grid_matrices(m: u32) -> &'static PixelGridMatrices {
    static TABLES: OnceLock<Vec<PixelGridMatrices>> = OnceLock::new();
    let tables = TABLES.get_or_init(|| {
        (1..=MAX_LOG2_RESOLUTION)
            .map(PixelGridMatrices::new)
            .collect()
    });
    &tables[(m.clamp(1, MAX_LOG2_RESOLUTION) - 1) as usize]
}

/// The index of the `frame`-th Sobol' point whose first two coordinates fall
/// in cell `pixel` of the 2^`log2_resolution` square grid over [0,1)².
/// `log2_resolution` must not exceed [`MAX_LOG2_RESOLUTION`] and the pixel
/// must lie in the grid.
#[cfg(test)]
fn sobol_interval_to_index(log2_resolution: u32, frame: u64, pixel: glam::IVec2) -> u64 {
    sobol_frame_index(log2_resolution, frame) ^ sobol_pixel_index(log2_resolution, pixel)
}

/// The part of the index of a pixel's `frame`-th point (see
/// `sobol_interval_to_index`) that depends on the pixel alone (M⁻¹ of its
/// bits): a sampler computes it once per pixel.
pub fn sobol_pixel_index(log2_resolution: u32, pixel: glam::IVec2) -> u64 {
    let m = log2_resolution;
    if m == 0 {
        return 0;
    }
    let pixel_bits = (u64::from(pixel.x as u32) << m) | u64::from(pixel.y as u32);
    xor_columns(&pixel_grid_matrices(m).inverse_columns, pixel_bits)
}

/// The part of the same index that depends on the frame alone: the frame
/// above the low 2m bits, and M⁻¹ D of the frame in them.
pub fn sobol_frame_index(log2_resolution: u32, frame: u64) -> u64 {
    let m = log2_resolution;
    if m == 0 {
        return frame;
    }
    let matrices = pixel_grid_matrices(m);
    (frame << (2 * m)) ^ xor_columns(&matrices.frame_index_columns, frame)
}

#[cfg(test)]
mod tests {
    use super::super::randomize_strategy::BinaryScrambler;
    use super::super::sobol_sample::sobol_sample;
    use super::*;
    use glam::IVec2;

    /// The same matrices as pbrt-v4's `VdCSobolMatricesInv` and
    /// `VdCSobolMatrices` tables for small m.
    #[test]
    fn matrices_match_known_values() {
        assert_eq!(PixelGridMatrices::new(1).inverse_columns, [0x2, 0x3]);
        assert_eq!(
            PixelGridMatrices::new(2).inverse_columns,
            [0xc, 0x4, 0xa, 0x5]
        );
        assert_eq!(
            PixelGridMatrices::new(3).inverse_columns,
            [0x28, 0x30, 0x10, 0x3c, 0x22, 0x11]
        );
        assert_eq!(&frame_columns(3)[..4], &[0x5, 0x7, 0x4, 0x6]);
        assert_eq!(&frame_columns(17)[..3], &[0x14000, 0x1e000, 0x11000]);
        assert_eq!(
            &PixelGridMatrices::new(19).inverse_columns[..4],
            &[
                0x28_0028_0000,
                0x30_0030_0000,
                0x10_0010_0000,
                0xf_fff0_0000
            ]
        );
        assert_eq!(frame_columns(25), [0x140_0140, 0x1e0_01e0]);
    }

    #[test]
    fn found_points_lie_in_their_pixel_and_are_distinct() {
        for m in [1u32, 3, 6] {
            let resolution = 1 << m;
            let mut seen = std::collections::HashSet::new();
            let mut pixels = vec![
                (0, 0),
                (1, 0),
                (resolution - 1, resolution - 1),
                (resolution / 2, 1),
            ];
            pixels.sort();
            pixels.dedup();
            for (px, py) in pixels {
                for frame in 0..16 {
                    let index = sobol_interval_to_index(m, frame, IVec2::new(px, py));
                    assert!(seen.insert(index));
                    let x = sobol_sample(index, 0, BinaryScrambler::None) * resolution as f32;
                    let y = sobol_sample(index, 1, BinaryScrambler::None) * resolution as f32;
                    assert_eq!(
                        (x.floor() as i32, y.floor() as i32),
                        (px, py),
                        "m {m} frame {frame}"
                    );
                }
            }
        }
    }
}
