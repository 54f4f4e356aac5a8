//! Radical inverses: the digits of an index, in a prime base, mirrored about
//! the radix point (the Halton sequence), plain or scrambled.
//!
//! All arithmetic follows pbrt-v4 in f32 (digit loops stop where f32 stops
//! resolving digits), so values agree bit for bit.

use super::digit_permutation::DigitPermutation;
use super::permutation::permutation_element;
use super::primes::{divide_by_prime, PRIMES, PRIME_RECIPROCALS, PRIME_TABLE_SIZE};
use crate::math::hash::mix_bits;
use crate::math::ONE_MINUS_EPSILON;

/// The base `PRIMES[base_index]` (the last prime past the table) and its
/// reciprocal for `divide_by_prime`.
fn base_of(base_index: usize) -> (u64, u64) {
    let i = base_index.min(PRIME_TABLE_SIZE - 1);
    (u64::from(PRIMES[i]), PRIME_RECIPROCALS[i])
}

/// The radical inverse of `index` in base `PRIMES[base_index]`.
pub fn radical_inverse(base_index: usize, mut index: u64) -> f32 {
    let (base, reciprocal) = base_of(base_index);
    let inverse_base = 1.0 / base as f32;
    let mut inverse_base_power = 1.0f32;
    let mut reversed_digits = 0u64;
    while index != 0 {
        let next = divide_by_prime(index, base, reciprocal);
        let digit = index - next * base;
        reversed_digits = reversed_digits.wrapping_mul(base).wrapping_add(digit);
        inverse_base_power *= inverse_base;
        index = next;
    }
    (reversed_digits as f32 * inverse_base_power).min(ONE_MINUS_EPSILON)
}

/// The index whose first `digit_count` base-`base` digits, reversed, are
/// those of `inverse` (inverts [`radical_inverse`] on those digits).
pub fn inverse_radical_inverse(mut inverse: u64, base: u64, digit_count: u32) -> u64 {
    let mut index = 0u64;
    for _ in 0..digit_count {
        let digit = inverse % base;
        inverse /= base;
        index = index.wrapping_mul(base).wrapping_add(digit);
    }
    index
}

/// The radical inverse with each digit position's values permuted by
/// `permutation` (which must be for the same base), over every digit f32
/// resolves (so leading zero digits are permuted too).
///
/// pbrt-v4 loops over all those positions; here the loop stops where the
/// index has no digits left, and the permuted zeros of the positions after
/// are added at once (`DigitPermutation::append_zero_digits`): the same
/// integer, so the same float (for 256 × 256 pixels at 32 samples, an
/// index has 20 of base 2's 25 positions, 13 of base 3's 16).
pub fn scrambled_radical_inverse(
    base_index: usize,
    mut index: u64,
    permutation: &DigitPermutation,
) -> f32 {
    let (base, reciprocal) = base_of(base_index);
    let digit_count = permutation.digit_count();
    let mut reversed_digits = 0u64;
    let mut digit_index = 0;
    while index != 0 && digit_index < digit_count {
        let next = divide_by_prime(index, base, reciprocal);
        let digit = (index - next * base) as u32;
        reversed_digits = reversed_digits
            .wrapping_mul(base)
            .wrapping_add(u64::from(permutation.permute(digit_index, digit)));
        digit_index += 1;
        index = next;
    }
    let reversed_digits = permutation.append_zero_digits(digit_index, reversed_digits);
    (permutation.inverse_base_power() * reversed_digits as f32).min(ONE_MINUS_EPSILON)
}

/// The radical inverse with Owen scrambling: each digit is permuted by a
/// permutation chosen by `hash` and all the digits before it.
pub fn owen_scrambled_radical_inverse(base_index: usize, mut index: u64, hash: u32) -> f32 {
    let (base, reciprocal) = base_of(base_index);
    let inverse_base = 1.0 / base as f32;
    let mut inverse_base_power = 1.0f32;
    let mut reversed_digits = 0u64;
    while 1.0 - inverse_base_power < 1.0 {
        let next = divide_by_prime(index, base, reciprocal);
        let digit = (index - next * base) as u32;
        let digit_hash = mix_bits(u64::from(hash) ^ reversed_digits) as u32;
        let digit = permutation_element(digit, base as u32, digit_hash);
        reversed_digits = reversed_digits
            .wrapping_mul(base)
            .wrapping_add(u64::from(digit));
        inverse_base_power *= inverse_base;
        index = next;
    }
    (inverse_base_power * reversed_digits as f32).min(ONE_MINUS_EPSILON)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn van_der_corput_and_base_three_values() {
        assert_eq!(radical_inverse(0, 0), 0.0);
        assert_eq!(radical_inverse(0, 1), 0.5);
        assert_eq!(radical_inverse(0, 2), 0.25);
        assert_eq!(radical_inverse(0, 3), 0.75);
        assert_eq!(radical_inverse(0, 6), 0.375);
        assert!((radical_inverse(1, 1) - 1.0 / 3.0).abs() < 1e-7);
        assert!((radical_inverse(1, 5) - 7.0 / 9.0).abs() < 1e-7);
    }

    #[test]
    fn inverse_radical_inverse_inverts_the_leading_digits() {
        for base_index in 0..2 {
            let base = u64::from(PRIMES[base_index]);
            let digits = 5;
            let count = base.pow(digits);
            for index in 0..count {
                let scaled =
                    (radical_inverse(base_index, index) as f64 * count as f64).round() as u64;
                assert_eq!(inverse_radical_inverse(scaled, base, digits), index);
            }
        }
    }

    /// pbrt-v4's loop over every digit position f32 resolves, written out.
    fn scrambled_over_every_position(
        base_index: usize,
        mut index: u64,
        permutation: &DigitPermutation,
    ) -> f32 {
        let base = u64::from(PRIMES[base_index]);
        let inverse_base = 1.0 / base as f32;
        let mut inverse_base_power = 1.0f32;
        let mut reversed_digits = 0u64;
        let mut digit_index = 0;
        while 1.0 - (base - 1) as f32 * inverse_base_power < 1.0 {
            let digit = (index % base) as u32;
            reversed_digits = reversed_digits
                .wrapping_mul(base)
                .wrapping_add(u64::from(permutation.permute(digit_index, digit)));
            inverse_base_power *= inverse_base;
            digit_index += 1;
            index /= base;
        }
        (inverse_base_power * reversed_digits as f32).min(ONE_MINUS_EPSILON)
    }

    /// Stopping at the index's last digit and adding the permuted zeros at
    /// once gives pbrt-v4's loop's value bit for bit: small and huge
    /// indices (more digits than f32 resolves), small and large bases.
    #[test]
    fn scrambled_inverses_match_the_loop_over_every_position() {
        for base_index in [0, 1, 2, 10, 100, 999] {
            let permutation = DigitPermutation::new(PRIMES[base_index], 7 + base_index as u32);
            let mut index = 0u64;
            for step in 0..20_000u64 {
                let ours = scrambled_radical_inverse(base_index, index, &permutation);
                let pbrt = scrambled_over_every_position(base_index, index, &permutation);
                assert_eq!(
                    ours.to_bits(),
                    pbrt.to_bits(),
                    "base {base_index}, index {index}"
                );
                index = if step % 2 == 0 {
                    step
                } else {
                    index.wrapping_mul(6364136223846793005).wrapping_add(step) >> (step % 64)
                };
            }
        }
    }

    #[test]
    fn scrambled_inverses_keep_the_first_digit_stratified() {
        let permutation = DigitPermutation::new(3, 99);
        let mut strata = [0; 3];
        for index in 0..3 {
            let u = scrambled_radical_inverse(1, index, &permutation);
            assert!((0.0..1.0).contains(&u));
            strata[(u * 3.0) as usize] += 1;
        }
        assert_eq!(strata, [1, 1, 1]);
        let mut strata = [0; 9];
        for index in 0..9 {
            let u = owen_scrambled_radical_inverse(1, index, 1234);
            strata[(u * 9.0) as usize] += 1;
        }
        assert_eq!(strata, [1; 9]);
    }
}
