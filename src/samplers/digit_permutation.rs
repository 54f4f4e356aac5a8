//! Random permutations of the digits of base-b numbers, one per digit
//! position: the "permutedigits" scrambling of the Halton sampler.

use super::permutation::permutation_element;
use super::primes::{PRIMES, PRIME_TABLE_SIZE};
use crate::math::hash::hash_words;
use std::sync::{Arc, OnceLock};

/// How many base-`base` digits an f32 radical inverse resolves: digits are
/// taken while `1 - (base - 1) / base^i` is still below 1 in f32 (pbrt-v4's
/// rule, so the permutations line up with its digit loops); and `1 / base`
/// to that power, multiplied out as the digit loop does.
fn f32_digits(base: u32) -> (usize, f32) {
    let inverse_base = 1.0 / base as f32;
    let mut inverse_base_power = 1.0f32;
    let mut digits = 0;
    while 1.0 - (base - 1) as f32 * inverse_base_power < 1.0 {
        digits += 1;
        inverse_base_power *= inverse_base;
    }
    (digits, inverse_base_power)
}

/// For each digit position of base-`base` numbers, a permutation of the
/// digit values (pbrt-v4's `DigitPermutation`).
#[derive(Clone, Debug)]
pub struct DigitPermutation {
    base: u32,
    /// `[digit_index * base + digit_value]`.
    permutations: Vec<u16>,
    /// `1 / base` to the digit count ([`f32_digits`]), multiplied out in f32
    /// as the digit loop does.
    inverse_base_power: f32,
    /// For each digit position k (and one past the last), what positions
    /// k onwards append to the reversed digits when every digit there is
    /// 0, as `(multiplier, addend)`: base^(count − k) and the permuted
    /// zeros' sum, both modulo 2⁶⁴ as the loop's wrapping arithmetic.
    zero_tails: Vec<(u64, u64)>,
}

impl DigitPermutation {
    /// The permutations for `base` (below 65536) chosen by `seed`.
    pub fn new(base: u32, seed: u32) -> Self {
        let (digit_count, inverse_base_power) = f32_digits(base);
        let mut permutations = Vec::with_capacity(digit_count * base as usize);
        for digit_index in 0..digit_count {
            let digit_seed = hash_words(&[base, digit_index as u32, seed]) as u32;
            for digit_value in 0..base {
                permutations.push(permutation_element(digit_value, base, digit_seed) as u16);
            }
        }
        let mut zero_tails = vec![(1u64, 0u64); digit_count + 1];
        for k in (0..digit_count).rev() {
            let (multiplier, addend) = zero_tails[k + 1];
            let zero = u64::from(permutations[k * base as usize]);
            zero_tails[k] = (
                multiplier.wrapping_mul(u64::from(base)),
                zero.wrapping_mul(multiplier).wrapping_add(addend),
            );
        }
        DigitPermutation {
            base,
            permutations,
            inverse_base_power,
            zero_tails,
        }
    }

    /// How many digit positions the permutations cover
    /// ([`f32_digits`]).
    #[inline]
    pub fn digit_count(&self) -> usize {
        self.zero_tails.len() - 1
    }

    /// `1 / base` to the power [`Self::digit_count`], as the digit loop
    /// multiplies it out.
    #[inline]
    pub fn inverse_base_power(&self) -> f32 {
        self.inverse_base_power
    }

    /// `reversed`, the permuted digits of positions before `digit_index`,
    /// continued through the last position with zeros (each permuted):
    /// what the digit loop would reach once the index has no digits left.
    #[inline]
    pub fn append_zero_digits(&self, digit_index: usize, reversed: u64) -> u64 {
        let (multiplier, addend) = self.zero_tails[digit_index.min(self.digit_count())];
        reversed.wrapping_mul(multiplier).wrapping_add(addend)
    }

    /// The value digit `digit_value` at position `digit_index` becomes.
    #[inline]
    pub fn permute(&self, digit_index: usize, digit_value: u32) -> u32 {
        let index = digit_index * self.base as usize + digit_value as usize;
        self.permutations
            .get(index)
            .map_or(digit_value, |&p| u32::from(p))
    }
}

/// The digit permutations of every Halton dimension for one seed (pbrt-v4's
/// `ComputeRadicalInversePermutations`), each made on first use and shared
/// by all clones of a sampler.
#[derive(Clone, Debug)]
pub struct RadicalInversePermutations {
    seed: u32,
    per_dimension: Arc<[OnceLock<DigitPermutation>]>,
}

impl RadicalInversePermutations {
    pub fn new(seed: u32) -> Self {
        RadicalInversePermutations {
            seed,
            per_dimension: (0..PRIME_TABLE_SIZE).map(|_| OnceLock::new()).collect(),
        }
    }

    /// The permutations for dimension `dimension` (base `PRIMES[dimension]`);
    /// `dimension` must be below [`PRIME_TABLE_SIZE`].
    pub fn get(&self, dimension: usize) -> &DigitPermutation {
        let dimension = dimension.min(PRIME_TABLE_SIZE - 1);
        self.per_dimension[dimension]
            .get_or_init(|| DigitPermutation::new(PRIMES[dimension], self.seed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digit_counts_cover_f32_precision() {
        // 1 - 2^-k < 1 in f32 for k up to 24.
        assert_eq!(f32_digits(2).0, 25);
        assert!(f32_digits(3).0 >= 15);
        assert!(f32_digits(7919).0 >= 2);
    }

    #[test]
    fn each_position_is_a_permutation() {
        for base in [2u32, 3, 5, 7919] {
            let p = DigitPermutation::new(base, 17);
            for digit_index in 0..f32_digits(base).0 {
                let mut seen = vec![false; base as usize];
                for value in 0..base {
                    let v = p.permute(digit_index, value) as usize;
                    assert!(!seen[v]);
                    seen[v] = true;
                }
            }
        }
    }
}
