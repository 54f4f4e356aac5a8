//! Random permutations of `0..length` evaluated one element at a time,
//! without storing the permutation (Kensler's hash-based permutation, as
//! pbrt-v4's `PermutationElement`).

/// Element `index` of the permutation of `0..length` chosen by `seed`.
/// `length` must be at least 1 (0 gives 0).
pub fn permutation_element(index: u32, length: u32, seed: u32) -> u32 {
    if length <= 1 {
        return 0;
    }
    let mut mask = length - 1;
    mask |= mask >> 1;
    mask |= mask >> 2;
    mask |= mask >> 4;
    mask |= mask >> 8;
    mask |= mask >> 16;
    let mut i = index;
    // Cycle-walk: permute within the next power of two until in range.
    loop {
        i ^= seed;
        i = i.wrapping_mul(0xe170_893d);
        i ^= seed >> 16;
        i ^= (i & mask) >> 4;
        i ^= seed >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= seed >> 23;
        i ^= (i & mask) >> 1;
        i = i.wrapping_mul(1 | seed >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & mask) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & mask) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & mask) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= mask;
        i ^= i >> 5;
        if i < length {
            break;
        }
    }
    ((u64::from(i) + u64::from(seed)) % u64::from(length)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn is_a_permutation_for_many_lengths_and_seeds() {
        for length in [1u32, 2, 3, 5, 16, 17, 100, 1000] {
            for seed in [0u32, 1, 0xdead_beef, 12345] {
                let mut seen = vec![false; length as usize];
                for i in 0..length {
                    let p = permutation_element(i, length, seed);
                    assert!(p < length);
                    assert!(!seen[p as usize], "repeat at length {length} seed {seed}");
                    seen[p as usize] = true;
                }
            }
        }
    }

    #[test]
    fn different_seeds_give_different_permutations() {
        let a: Vec<u32> = (0..16).map(|i| permutation_element(i, 16, 1)).collect();
        let b: Vec<u32> = (0..16).map(|i| permutation_element(i, 16, 2)).collect();
        assert_ne!(a, b);
    }
}
