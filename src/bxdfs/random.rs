//! The deterministic random numbers the layered BxDF's random walks use.
//!
//! pbrt-v4 seeds a PCG32 generator from hashes of the query (ωo, ωi, or the
//! sample values), so that evaluating f or pdf twice for the same
//! directions gives the same estimate — important because integrators
//! evaluate them separately for MIS weights and throughput. Both
//! algorithms are the published ones: PCG32 (O'Neill, XSH-RR 64/32) and
//! MurmurHash64A (Appleby). The layered BxDF keeps its own generator so
//! its estimates do not depend on any sampler state.

use glam::Vec3;

const PCG32_MULTIPLIER: u64 = 0x5851_f42d_4c95_7f2d;

/// Largest f32 below 1, so a uniform sample is always in [0, 1).
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// The PCG32 generator: 64-bit LCG state, 32-bit permuted output; `inc`
/// selects one of 2^63 independent streams.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// A generator on stream `sequence_index`, started at an offset given
    /// by `seed` (pbrt's `RNG(seqIndex, start)`).
    pub fn new(sequence_index: u64, seed: u64) -> Self {
        let mut rng = Pcg32 {
            state: 0,
            inc: (sequence_index << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed);
        rng.next_u32();
        rng
    }

    pub fn next_u32(&mut self) -> u32 {
        let old_state = self.state;
        self.state = old_state
            .wrapping_mul(PCG32_MULTIPLIER)
            .wrapping_add(self.inc);
        let xor_shifted = (((old_state >> 18) ^ old_state) >> 27) as u32;
        let rotation = (old_state >> 59) as u32;
        xor_shifted.rotate_right(rotation)
    }

    /// Uniform in [0, 1).
    pub fn uniform_f32(&mut self) -> f32 {
        (self.next_u32() as f32 * (1.0 / 4_294_967_296.0)).min(ONE_MINUS_EPSILON)
    }
}

/// MurmurHash64A of `bytes` with the given seed.
pub fn murmur_hash_64a(bytes: &[u8], seed: u64) -> u64 {
    const M: u64 = 0xc6a4_a793_5bd1_e995;
    const R: u32 = 47;
    let mut h = seed ^ (bytes.len() as u64).wrapping_mul(M);
    let mut chunks = bytes.chunks_exact(8);
    for chunk in &mut chunks {
        let mut k = u64::from_le_bytes(chunk.try_into().expect("8-byte chunk"));
        k = k.wrapping_mul(M);
        k ^= k >> R;
        k = k.wrapping_mul(M);
        h ^= k;
        h = h.wrapping_mul(M);
    }
    let tail = chunks.remainder();
    if !tail.is_empty() {
        for (i, &byte) in tail.iter().enumerate() {
            h ^= (byte as u64) << (8 * i);
        }
        h = h.wrapping_mul(M);
    }
    h ^= h >> R;
    h = h.wrapping_mul(M);
    h ^= h >> R;
    h
}

/// Hash of a sequence of 4-byte values laid out back to back, as pbrt's
/// variadic `Hash(...)` lays out its arguments' bytes (little-endian).
pub fn hash_words(words: &[u32]) -> u64 {
    let mut bytes = [0u8; 32];
    assert!(words.len() <= 8, "hash_words takes at most 8 words");
    for (i, word) in words.iter().enumerate() {
        bytes[4 * i..4 * i + 4].copy_from_slice(&word.to_le_bytes());
    }
    murmur_hash_64a(&bytes[..4 * words.len()], 0)
}

/// Hash of a direction (its three floats' bits).
pub fn hash_vector(v: Vec3) -> u64 {
    hash_words(&[v.x.to_bits(), v.y.to_bits(), v.z.to_bits()])
}

/// Hash of an integer seed followed by a direction.
pub fn hash_seed_and_vector(seed: i32, v: Vec3) -> u64 {
    hash_words(&[seed as u32, v.x.to_bits(), v.y.to_bits(), v.z.to_bits()])
}

/// Hash of a list of floats.
pub fn hash_floats(values: &[f32]) -> u64 {
    let mut words = [0u32; 8];
    for (word, value) in words.iter_mut().zip(values) {
        *word = value.to_bits();
    }
    hash_words(&words[..values.len()])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pcg32_matches_the_reference_stream() {
        // The PCG reference demo (pcg32-demo, seeded with initstate 42,
        // initseq 54) prints these first outputs.
        let mut rng = Pcg32::new(54, 42);
        let expected = [
            0xa15c_02b7u32,
            0x7b47_f409,
            0xba1d_3330,
            0x83d2_f293,
            0xbfa4_784b,
            0xcbed_606e,
        ];
        for e in expected {
            assert_eq!(rng.next_u32(), e);
        }
    }

    #[test]
    fn uniform_floats_stay_below_one_and_look_uniform() {
        let mut rng = Pcg32::new(1, 2);
        let n = 100_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let u = rng.uniform_f32();
            assert!((0.0..1.0).contains(&u));
            sum += u as f64;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.005);
    }

    #[test]
    fn murmur_hash_is_sensitive_to_every_byte_and_the_tail() {
        // Known value: MurmurHash64A of the empty input with seed 0 is 0.
        assert_eq!(murmur_hash_64a(&[], 0), 0);
        let a = hash_vector(Vec3::new(0.1, 0.2, 0.3));
        assert_eq!(a, hash_vector(Vec3::new(0.1, 0.2, 0.3)));
        assert_ne!(a, hash_vector(Vec3::new(0.1, 0.2, 0.300_000_03)));
        assert_ne!(a, hash_seed_and_vector(0, Vec3::new(0.1, 0.2, 0.3)));
        assert_ne!(
            hash_floats(&[1.0, 2.0, 3.0]),
            hash_floats(&[1.0, 2.0, 3.000_000_2])
        );
    }
}
