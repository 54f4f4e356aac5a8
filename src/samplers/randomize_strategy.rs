//! How a low-discrepancy sampler randomizes its points (pbrt-v4's
//! `RandomizeStrategy`, the samplers' `"randomization"` parameter).

use crate::math::hash::mix_bits;

/// A randomization, as named by the `"randomization"` parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RandomizeStrategy {
    /// `"none"`: the raw sequence (the same points in every pixel).
    None,
    /// `"permutedigits"`: a random permutation of each digit's values
    /// (for base 2, an XOR with a random mask).
    PermuteDigits,
    /// `"fastowen"`: Laine–Karras-style hashed nested scrambling of the bits
    /// (base 2 only).
    FastOwen,
    /// `"owen"`: full Owen (nested uniform) scrambling.
    Owen,
}

impl RandomizeStrategy {
    /// The strategy called `name`, if it is one.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "none" => Some(RandomizeStrategy::None),
            "permutedigits" => Some(RandomizeStrategy::PermuteDigits),
            "fastowen" => Some(RandomizeStrategy::FastOwen),
            "owen" => Some(RandomizeStrategy::Owen),
            _ => Option::None,
        }
    }
}

/// A randomization of the 32 bits of a base-2 sample, with its seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinaryScrambler {
    /// Leave the bits as they are.
    None,
    /// XOR with a mask (a random permutation of each binary digit).
    XorMask(u32),
    /// Hash-based approximation of Owen scrambling, from a seed.
    FastOwen(u32),
    /// Owen scrambling: each bit flipped by a hash of the bits above it.
    Owen(u32),
}

impl BinaryScrambler {
    /// The scrambler for `strategy` with `seed` (the seed is unused for
    /// [`RandomizeStrategy::None`]).
    pub fn new(strategy: RandomizeStrategy, seed: u32) -> Self {
        match strategy {
            RandomizeStrategy::None => BinaryScrambler::None,
            RandomizeStrategy::PermuteDigits => BinaryScrambler::XorMask(seed),
            RandomizeStrategy::FastOwen => BinaryScrambler::FastOwen(seed),
            RandomizeStrategy::Owen => BinaryScrambler::Owen(seed),
        }
    }

    /// The scrambled bits (the most significant bit is the first binary
    /// digit after the radix point).
    #[inline]
    pub fn scramble(self, bits: u32) -> u32 {
        match self {
            BinaryScrambler::None => bits,
            BinaryScrambler::XorMask(mask) => bits ^ mask,
            BinaryScrambler::FastOwen(seed) => fast_owen_scramble(bits, seed),
            BinaryScrambler::Owen(seed) => owen_scramble(bits, seed),
        }
    }
}

/// pbrt-v4's `FastOwenScrambler`: a hash applied to the bit-reversed value
/// whose every output bit depends only on the input bits below it, which,
/// reversed back, makes each digit depend only on the digits before it.
fn fast_owen_scramble(bits: u32, seed: u32) -> u32 {
    let mut v = bits.reverse_bits();
    v ^= v.wrapping_mul(0x3d20_adea);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x0552_6c56);
    v ^= v.wrapping_mul(0x53a2_2864);
    v.reverse_bits()
}

/// pbrt-v4's `OwenScrambler`: the first bit flips with the seed's lowest
/// bit; bit `b` flips according to a hash of the seed and the bits above.
fn owen_scramble(mut bits: u32, seed: u32) -> u32 {
    if seed & 1 != 0 {
        bits ^= 1 << 31;
    }
    for b in 1..32 {
        let higher_bits = u32::MAX << (32 - b);
        if (mix_bits(u64::from((bits & higher_bits) ^ seed)) as u32) & (1 << b) != 0 {
            bits ^= 1 << (31 - b);
        }
    }
    bits
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for (name, strategy) in [
            ("none", RandomizeStrategy::None),
            ("permutedigits", RandomizeStrategy::PermuteDigits),
            ("fastowen", RandomizeStrategy::FastOwen),
            ("owen", RandomizeStrategy::Owen),
        ] {
            assert_eq!(RandomizeStrategy::from_name(name), Some(strategy));
        }
        assert_eq!(
            RandomizeStrategy::from_name("cranleypatterson"),
            Option::None
        );
    }

    /// A nested scrambling maps each dyadic interval [k/2^j, (k+1)/2^j) onto
    /// another one: values that share their top j bits still do after.
    #[test]
    fn owen_scramblers_are_nested() {
        for scrambler in [
            BinaryScrambler::Owen(0x1234_5678),
            BinaryScrambler::FastOwen(0x9abc_def1),
        ] {
            for prefix_bits in 1..8 {
                let shift = 32 - prefix_bits;
                for prefix in 0..(1u32 << prefix_bits) {
                    let a = scrambler.scramble(prefix << shift);
                    let b = scrambler.scramble((prefix << shift) | ((1 << shift) - 1));
                    assert_eq!(a >> shift, b >> shift);
                }
            }
        }
    }
}
