//! Perlin's improved gradient noise and the sums of its octaves that the
//! procedural textures use (pbrt-v4's `Noise`, `FBm` and `Turbulence`).
//!
//! Noise is a smooth function of 3D position, zero at every integer lattice
//! point and within about ±1 elsewhere: each lattice corner of the cell
//! holding the point contributes the dot product of a pseudo-random gradient
//! (one of the 12 edge directions of a cube, chosen by hashing the corner
//! through Perlin's permutation table) with the offset from that corner, and
//! the eight contributions are blended with the quintic 6t⁵ − 15t⁴ + 10t³,
//! whose first and second derivatives vanish at the cell faces.
//!
//! Fractional Brownian motion adds octaves of noise at frequencies growing
//! by 1.99 and amplitudes shrinking by ω; turbulence adds their absolute
//! values. Both stop at the octave whose features would be smaller than the
//! pixel footprint (∂p/∂x, ∂p/∂y), fading the last one in, so that they do
//! not alias.

use crate::math::lerp;
use glam::Vec3;

/// Perlin's permutation of 0..=255 (from "Improving Noise", 2002), the
/// published constant that pbrt-v4 also uses; indices wrap by repeating it.
const PERMUTATION: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

/// The permutation at `i`, wrapping: the table is used as if written twice
/// in a row, as the nested lookups reach up to index 511.
fn permutation(i: usize) -> usize {
    PERMUTATION[i & 255] as usize
}

/// The contribution of lattice corner (x, y, z) (each in 0..=256) to a
/// point at offset `d` from it: the dot product of the corner's gradient
/// with `d`. The hash's low four bits pick one of 12 cube-edge gradients
/// (with four repeated to make 16), each the sum of ± two of the offset's
/// components.
fn gradient_dot(x: usize, y: usize, z: usize, d: Vec3) -> f32 {
    let hash = permutation(permutation(permutation(x) + y) + z) & 15;
    let first = if hash < 8 || hash == 12 || hash == 13 {
        d.x
    } else {
        d.y
    };
    let second = if hash < 4 || hash == 12 || hash == 13 {
        d.y
    } else {
        d.z
    };
    let first = if hash & 1 != 0 { -first } else { first };
    let second = if hash & 2 != 0 { -second } else { second };
    first + second
}

/// The quintic blend 6t⁵ − 15t⁴ + 10t³ of the eight corner contributions.
fn blend_weight(t: f32) -> f32 {
    let t3 = t * t * t;
    t3 * (t * (6.0 * t - 15.0) + 10.0)
}

/// Perlin noise at `p`.
pub fn noise(p: Vec3) -> f32 {
    // Coordinates are first reduced modulo 2³⁰ so the cell index fits an
    // i32 (and the offsets keep their precision) far from the origin.
    const PERIOD: f32 = (1u32 << 30) as f32;
    let p = Vec3::new(p.x % PERIOD, p.y % PERIOD, p.z % PERIOD);
    let cell = p.floor();
    let d = p - cell;
    // Cells repeat every 256 along each axis; two's complement masking
    // keeps negative cells in range too.
    let index = |c: f32| (c as i32 & 255) as usize;
    let (ix, iy, iz) = (index(cell.x), index(cell.y), index(cell.z));
    let corner = |ox: usize, oy: usize, oz: usize| {
        gradient_dot(
            ix + ox,
            iy + oy,
            iz + oz,
            d - Vec3::new(ox as f32, oy as f32, oz as f32),
        )
    };
    let (wx, wy, wz) = (blend_weight(d.x), blend_weight(d.y), blend_weight(d.z));
    let x00 = lerp(wx, corner(0, 0, 0), corner(1, 0, 0));
    let x10 = lerp(wx, corner(0, 1, 0), corner(1, 1, 0));
    let x01 = lerp(wx, corner(0, 0, 1), corner(1, 0, 1));
    let x11 = lerp(wx, corner(0, 1, 1), corner(1, 1, 1));
    let y0 = lerp(wy, x00, x10);
    let y1 = lerp(wy, x01, x11);
    lerp(wz, y0, y1)
}

/// Noise in the plane z = ½ (pbrt-v4's two-argument `Noise`, whose third
/// coordinate defaults to ½, as the `dots` texture calls it).
pub fn noise_2d(x: f32, y: f32) -> f32 {
    noise(Vec3::new(x, y, 0.5))
}

/// Hermite smooth step of `x` from `a` to `b`: 0 below, 1 above.
fn smooth_step(x: f32, a: f32, b: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Ratio of successive octaves' frequencies: just under 2, so the lattices
/// of different octaves do not line up.
const LACUNARITY: f32 = 1.99;

/// How many octaves the footprint allows, as a real number: octave i has
/// features of size about 2⁻ⁱ, and those smaller than twice the footprint
/// (the Nyquist limit) are dropped; at most `max_octaves`. A zero footprint
/// allows all of them.
fn octave_count(dpdx: Vec3, dpdy: Vec3, max_octaves: i32) -> f32 {
    let footprint_squared = dpdx.length_squared().max(dpdy.length_squared());
    let n = -1.0 - footprint_squared.log2() / 2.0;
    // NaN (from a NaN footprint) counts as no octaves rather than all.
    if n.is_nan() {
        return 0.0;
    }
    n.clamp(0.0, max_octaves.max(0) as f32)
}

/// Fractional Brownian motion: Σ ωⁱ noise(1.99ⁱ p) over the octaves the
/// footprint allows, the last partial one faded in by a smooth step of its
/// fraction over [0.3, 0.7].
pub fn fbm(p: Vec3, dpdx: Vec3, dpdy: Vec3, omega: f32, max_octaves: i32) -> f32 {
    let n = octave_count(dpdx, dpdy, max_octaves);
    let whole = n.floor() as i32;
    let (mut sum, mut frequency, mut amplitude) = (0.0, 1.0, 1.0);
    for _ in 0..whole {
        sum += amplitude * noise(frequency * p);
        frequency *= LACUNARITY;
        amplitude *= omega;
    }
    let fade = smooth_step(n - whole as f32, 0.3, 0.7);
    sum + amplitude * fade * noise(frequency * p)
}

/// Turbulence: Σ ωⁱ |noise(1.99ⁱ p)| over the octaves the footprint
/// allows. The partial octave blends from 0.2 (about the mean of |noise|)
/// to its value, and each octave cut off by the footprint adds that mean,
/// so the texture's average brightness does not change with distance.
/// As pbrt-v4, the partial term is added even when the footprint allows
/// every octave, where it is ωⁿ·0.2.
pub fn turbulence(p: Vec3, dpdx: Vec3, dpdy: Vec3, omega: f32, max_octaves: i32) -> f32 {
    let n = octave_count(dpdx, dpdy, max_octaves);
    let whole = n.floor() as i32;
    let (mut sum, mut frequency, mut amplitude) = (0.0, 1.0, 1.0);
    for _ in 0..whole {
        sum += amplitude * noise(frequency * p).abs();
        frequency *= LACUNARITY;
        amplitude *= omega;
    }
    let fade = smooth_step(n - whole as f32, 0.3, 0.7);
    sum += amplitude * lerp(fade, 0.2, noise(frequency * p).abs());
    for _ in whole..max_octaves {
        sum += amplitude * 0.2;
        amplitude *= omega;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator for test points (no dependency on
    /// the renderer's samplers).
    fn points(count: usize, scale: f32) -> Vec<Vec3> {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..count)
            .map(|_| (Vec3::new(next(), next(), next()) - 0.5) * 2.0 * scale)
            .collect()
    }

    #[test]
    fn permutation_is_a_permutation() {
        let mut seen = [false; 256];
        for &v in &PERMUTATION {
            assert!(!seen[v as usize], "{v} twice");
            seen[v as usize] = true;
        }
    }

    #[test]
    fn noise_is_zero_at_lattice_points() {
        for x in -3..4 {
            for y in -3..4 {
                for z in [-300, -1, 0, 2, 255, 256, 1000] {
                    let p = Vec3::new(x as f32, y as f32, z as f32);
                    assert_eq!(noise(p), 0.0, "{p}");
                }
            }
        }
    }

    #[test]
    fn noise_is_bounded_varied_and_continuous() {
        let mut largest: f32 = 0.0;
        let mut sum = 0.0;
        let samples = points(20_000, 50.0);
        for &p in &samples {
            let v = noise(p);
            largest = largest.max(v.abs());
            sum += v;
            // Smooth: a tiny step changes it by at most the gradient bound
            // (each corner term changes by ≤ 2·step, the blend is smooth).
            let step = Vec3::splat(1e-3);
            assert!((noise(p + step) - v).abs() < 0.02, "{p}");
        }
        // The improved noise's extremes are about ±1 (|∑ ± two offset
        // components| ≤ 2 at a corner, damped by the blend).
        assert!(largest <= 1.1 && largest > 0.6, "{largest}");
        assert!((sum / samples.len() as f32).abs() < 0.02);
    }

    #[test]
    fn noise_repeats_every_256_cells() {
        for p in points(100, 30.0) {
            let a = noise(p);
            let b = noise(p + Vec3::new(256.0, -512.0, 256.0));
            assert!((a - b).abs() < 1e-3, "{p}: {a} vs {b}");
        }
    }

    /// A corner's contribution by the definition of Perlin's 12 gradients:
    /// hash h picks gradient g(h) and the contribution is g · d.
    #[test]
    fn corner_contributions_are_gradient_dot_products() {
        let gradients = [
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(0.0, -1.0, 1.0),
            Vec3::new(0.0, 1.0, -1.0),
            Vec3::new(0.0, -1.0, -1.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, -1.0),
            Vec3::new(0.0, -1.0, -1.0),
        ];
        let d = Vec3::new(0.3, -0.7, 0.45);
        for x in 0..20 {
            for (y, z) in [(0, 0), (3, 7), (255, 256)] {
                let hash = PERMUTATION
                    [(PERMUTATION[(PERMUTATION[x & 255] as usize + y) & 255] as usize + z) & 255]
                    as usize
                    & 15;
                let expected = gradients[hash].dot(d);
                assert!((gradient_dot(x, y, z, d) - expected).abs() < 1e-6);
            }
        }
    }

    /// With a zero footprint every octave is summed in full: fbm is then
    /// Σ ωⁱ noise(1.99ⁱ p) and turbulence Σ ωⁱ |noise(1.99ⁱ p)| + 0.2 ωⁿ.
    #[test]
    fn octave_sums_match_direct_evaluation_without_footprint() {
        for p in points(200, 10.0) {
            for (omega, octaves) in [(0.5f32, 8), (0.7, 3), (0.25, 1)] {
                let mut direct_fbm = 0.0;
                let mut direct_turbulence = 0.0;
                for i in 0..octaves {
                    let v = noise(1.99f32.powi(i) * p);
                    direct_fbm += omega.powi(i) * v;
                    direct_turbulence += omega.powi(i) * v.abs();
                }
                direct_turbulence += 0.2 * omega.powi(octaves);
                let f = fbm(p, Vec3::ZERO, Vec3::ZERO, omega, octaves);
                let t = turbulence(p, Vec3::ZERO, Vec3::ZERO, omega, octaves);
                assert!((f - direct_fbm).abs() < 1e-4, "{f} vs {direct_fbm}");
                assert!(
                    (t - direct_turbulence).abs() < 1e-4,
                    "{t} vs {direct_turbulence}"
                );
            }
        }
    }

    /// A footprint of 2⁻⁴ allows n = −1 − log2(2⁻⁸)/2 = 3 octaves: fbm keeps
    /// three (the partial fourth fades to zero) and turbulence puts 0.2 in
    /// place of each of the dropped ones (with the fourth at weight 0).
    #[test]
    fn footprint_limits_the_octaves() {
        let footprint = Vec3::new(0.0625, 0.0, 0.0);
        for p in points(50, 5.0) {
            let omega: f32 = 0.5;
            let three: f32 = (0..3)
                .map(|i| omega.powi(i) * noise(1.99f32.powi(i) * p))
                .sum();
            let f = fbm(p, footprint, Vec3::ZERO, omega, 8);
            assert!((f - three).abs() < 1e-4, "{f} vs {three}");
            let three_abs: f32 = (0..3)
                .map(|i| omega.powi(i) * noise(1.99f32.powi(i) * p).abs())
                .sum();
            let dropped: f32 = (3..8).map(|i| 0.2 * omega.powi(i)).sum();
            let expected = three_abs + 0.2 * omega.powi(3) + dropped;
            let t = turbulence(p, footprint, Vec3::ZERO, omega, 8);
            assert!((t - expected).abs() < 1e-4, "{t} vs {expected}");
        }
        // A footprint larger than the largest feature leaves fbm at zero.
        let huge = Vec3::new(10.0, 0.0, 0.0);
        assert_eq!(fbm(Vec3::new(0.3, 0.2, 0.1), huge, huge, 0.5, 8), 0.0);
    }
}
