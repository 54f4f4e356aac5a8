//! The first primes, the bases of the Halton sequence's dimensions.

/// How many primes (Halton dimensions) there are: pbrt-v4's `PrimeTableSize`.
pub const PRIME_TABLE_SIZE: usize = 1000;

/// The first [`PRIME_TABLE_SIZE`] primes, 2 to 7919.
pub static PRIMES: [u32; PRIME_TABLE_SIZE] = first_primes();

const fn first_primes() -> [u32; PRIME_TABLE_SIZE] {
    let mut primes = [0u32; PRIME_TABLE_SIZE];
    let mut count = 0;
    let mut candidate = 2u32;
    while count < PRIME_TABLE_SIZE {
        let mut is_prime = true;
        let mut i = 0;
        while i < count && primes[i] * primes[i] <= candidate {
            if candidate % primes[i] == 0 {
                is_prime = false;
                break;
            }
            i += 1;
        }
        if is_prime {
            primes[count] = candidate;
            count += 1;
        }
        candidate += 1;
    }
    primes
}

/// ⌈2⁶⁴ / p⌉ for each prime p: with it, n / p for any 32-bit n is the high
/// half of the 128-bit product (Lemire, Kaser & Kurz 2019), a multiply where
/// the digit loops of the radical inverse would divide (a 64-bit division
/// is tens of cycles).
pub static PRIME_RECIPROCALS: [u64; PRIME_TABLE_SIZE] = reciprocals();

const fn reciprocals() -> [u64; PRIME_TABLE_SIZE] {
    let mut out = [0u64; PRIME_TABLE_SIZE];
    let mut i = 0;
    while i < PRIME_TABLE_SIZE {
        out[i] = u64::MAX / PRIMES[i] as u64 + 1;
        i += 1;
    }
    out
}

/// `n / PRIMES[i]` (`reciprocal` its [`PRIME_RECIPROCALS`] entry).
#[inline]
pub fn divide_by_prime(n: u64, prime: u64, reciprocal: u64) -> u64 {
    if n <= u64::from(u32::MAX) {
        ((u128::from(reciprocal) * u128::from(n)) >> 64) as u64
    } else {
        n / prime
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn division_by_reciprocal_is_exact() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for (i, &p) in PRIMES.iter().enumerate() {
            let p = u64::from(p);
            let r = PRIME_RECIPROCALS[i];
            let check = |n: u64| assert_eq!(divide_by_prime(n, p, r), n / p, "{n} / {p}");
            for n in [
                0,
                1,
                p - 1,
                p,
                p + 1,
                u64::from(u32::MAX),
                u64::from(u32::MAX) + 1,
                u64::MAX,
            ] {
                check(n);
            }
            for _ in 0..2000 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                check(state >> 32);
                check(state >> (state % 64));
            }
        }
    }

    #[test]
    fn table_starts_and_ends_where_it_should() {
        assert_eq!(&PRIMES[..6], &[2, 3, 5, 7, 11, 13]);
        assert_eq!(PRIMES[PRIME_TABLE_SIZE - 1], 7919);
    }
}
