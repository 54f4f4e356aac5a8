//! Bit manipulations the samplers share: Morton (Z-order) codes.

/// Spreads the 32 bits of `x` to the even bit positions of a 64-bit value.
#[inline]
fn spread_to_even_bits(x: u32) -> u64 {
    let mut x = u64::from(x);
    x = (x ^ (x << 16)) & 0x0000_ffff_0000_ffff;
    x = (x ^ (x << 8)) & 0x00ff_00ff_00ff_00ff;
    x = (x ^ (x << 4)) & 0x0f0f_0f0f_0f0f_0f0f;
    x = (x ^ (x << 2)) & 0x3333_3333_3333_3333;
    x = (x ^ (x << 1)) & 0x5555_5555_5555_5555;
    x
}

/// The Morton code of `(x, y)`: bits of `x` at even positions, of `y` at
/// odd ones (pbrt-v4's 64-bit `EncodeMorton2`).
#[inline]
pub fn encode_morton_2(x: u32, y: u32) -> u64 {
    (spread_to_even_bits(y) << 1) | spread_to_even_bits(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interleaves_bits() {
        assert_eq!(encode_morton_2(0, 0), 0);
        assert_eq!(encode_morton_2(1, 0), 1);
        assert_eq!(encode_morton_2(0, 1), 2);
        assert_eq!(encode_morton_2(3, 3), 15);
        assert_eq!(encode_morton_2(0b101, 0b010), 0b01_10_01);
        assert_eq!(encode_morton_2(u32::MAX, 0), 0x5555_5555_5555_5555);
    }
}
