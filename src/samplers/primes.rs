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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_starts_and_ends_where_it_should() {
        assert_eq!(&PRIMES[..6], &[2, 3, 5, 7, 11, 13]);
        assert_eq!(PRIMES[PRIME_TABLE_SIZE - 1], 7919);
    }
}
