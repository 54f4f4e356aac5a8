//! The Gaussian weights of pbrt-v4's EWA texture filter.
//!
//! EWA weights each texel inside the filter ellipse by a Gaussian of its
//! squared elliptical radius r² ∈ [0, 1): e^(−α r²) − e^(−α) with α = 2,
//! offset so it falls to zero at the ellipse's edge. pbrt-v4 looks the weight
//! up in a 128-entry table indexed by ⌊r² · 128⌋ rather than evaluating the
//! exponential; the table is computed here, and indexed the same way so the
//! weights (steps included) are pbrt-v4's.

use std::sync::LazyLock;

/// Number of entries; entry i holds the weight at r² = i / (SIZE − 1).
const TABLE_SIZE: usize = 128;
const GAUSSIAN_FALLOFF: f32 = 2.0;

static EWA_WEIGHT_TABLE: LazyLock<[f32; TABLE_SIZE]> = LazyLock::new(|| {
    let mut table = [0.0f32; TABLE_SIZE];
    let edge = (-GAUSSIAN_FALLOFF).exp();
    for (i, weight) in table.iter_mut().enumerate() {
        let radius_squared = i as f32 / (TABLE_SIZE - 1) as f32;
        *weight = (-GAUSSIAN_FALLOFF * radius_squared).exp() - edge;
    }
    table
});

/// The weight of a texel at squared elliptical radius `radius_squared`
/// (meaningful in [0, 1); larger values get the last, zero, entry).
#[inline]
pub(crate) fn ewa_weight(radius_squared: f32) -> f32 {
    // `as` saturates, so negative or NaN radii index entry 0.
    let index = ((radius_squared * TABLE_SIZE as f32) as usize).min(TABLE_SIZE - 1);
    EWA_WEIGHT_TABLE[index]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_matches_pbrt_values() {
        // pbrt-v4's published table starts 0.864664733, 0.849040031 and
        // ends ..., 0.0021481365, 0.
        assert!((ewa_weight(0.0) - 0.864_664_73).abs() < 1e-6);
        assert!((ewa_weight(1.0 / 128.0) - 0.849_040_03).abs() < 1e-6);
        assert!((EWA_WEIGHT_TABLE[126] - 0.002_148_136_5).abs() < 1e-6);
        assert_eq!(ewa_weight(0.9999), 0.0);
        assert_eq!(ewa_weight(5.0), 0.0);
        assert!(EWA_WEIGHT_TABLE.windows(2).all(|pair| pair[0] > pair[1]));
    }
}
