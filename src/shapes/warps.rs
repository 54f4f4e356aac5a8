//! Linear and bilinear warps of the unit square, with their densities and
//! inverses. pbrt-v4 uses the bilinear warp to approximate the cos θ factor
//! at the receiving point when sampling triangles and rectangles by solid
//! angle, and to sample non-rectangular bilinear patches by area.
//!
//! The four bilinear weights are the density's values at the corners
//! (0,0), (1,0), (0,1), (1,1), in that order.

use crate::math::{lerp, ONE_MINUS_EPSILON};

/// A sample of the density proportional to `lerp(x, a, b)` on [0, 1].
pub fn sample_linear(u: f32, a: f32, b: f32) -> f32 {
    if u == 0.0 && a == 0.0 {
        return 0.0;
    }
    let x = u * (a + b) / (a + lerp(u, a * a, b * b).sqrt());
    x.min(ONE_MINUS_EPSILON)
}

/// The density of [`sample_linear`] at `x`.
pub fn linear_pdf(x: f32, a: f32, b: f32) -> f32 {
    if !(0.0..=1.0).contains(&x) {
        return 0.0;
    }
    2.0 * lerp(x, a, b) / (a + b)
}

/// The `u` that [`sample_linear`] maps to `x` (the CDF at `x`).
pub fn invert_linear_sample(x: f32, a: f32, b: f32) -> f32 {
    x * (a * (2.0 - x) + b * x) / (a + b)
}

/// Bilinear interpolation of the corner weights at `p`.
pub fn bilerp(p: [f32; 2], w: [f32; 4]) -> f32 {
    let (x, y) = (p[0], p[1]);
    (1.0 - x) * (1.0 - y) * w[0] + x * (1.0 - y) * w[1] + (1.0 - x) * y * w[2] + x * y * w[3]
}

/// A sample of the density proportional to the bilinear interpolation of
/// `w`: v from the marginal, then u from the conditional.
pub fn sample_bilinear(u: [f32; 2], w: [f32; 4]) -> [f32; 2] {
    let y = sample_linear(u[1], w[0] + w[1], w[2] + w[3]);
    let x = sample_linear(u[0], lerp(y, w[0], w[2]), lerp(y, w[1], w[3]));
    [x, y]
}

/// The density of [`sample_bilinear`] at `p`.
pub fn bilinear_pdf(p: [f32; 2], w: [f32; 4]) -> f32 {
    if !(0.0..=1.0).contains(&p[0]) || !(0.0..=1.0).contains(&p[1]) {
        return 0.0;
    }
    let sum = w[0] + w[1] + w[2] + w[3];
    if sum == 0.0 {
        return 1.0;
    }
    4.0 * bilerp(p, w) / sum
}

/// The `u` that [`sample_bilinear`] maps to `p`.
pub fn invert_bilinear_sample(p: [f32; 2], w: [f32; 4]) -> [f32; 2] {
    [
        invert_linear_sample(p[0], lerp(p[1], w[0], w[2]), lerp(p[1], w[1], w[3])),
        invert_linear_sample(p[1], w[0] + w[1], w[2] + w[3]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_warp_inverts_and_its_density_integrates_to_one() {
        for &(a, b) in &[(1.0, 1.0), (0.2, 3.0), (5.0, 0.0), (0.0, 1.0)] {
            let n = 1000;
            let mut integral = 0.0;
            for i in 0..n {
                let u = (i as f32 + 0.5) / n as f32;
                let x = sample_linear(u, a, b);
                assert!((0.0..1.0).contains(&x));
                assert!(
                    (invert_linear_sample(x, a, b) - u).abs() < 1e-4,
                    "{a} {b} {u}"
                );
                integral += linear_pdf(u, a, b) / n as f32;
            }
            assert!((integral - 1.0).abs() < 1e-3, "{integral}");
        }
    }

    #[test]
    fn bilinear_warp_inverts_and_its_density_integrates_to_one() {
        let w = [0.1, 2.0, 0.7, 0.01];
        let n = 100;
        let mut integral = 0.0;
        for i in 0..n {
            for j in 0..n {
                let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                let p = sample_bilinear(u, w);
                let back = invert_bilinear_sample(p, w);
                assert!((back[0] - u[0]).abs() < 1e-3 && (back[1] - u[1]).abs() < 1e-3);
                integral += bilinear_pdf(u, w) / (n * n) as f32;
            }
        }
        assert!((integral - 1.0).abs() < 1e-3, "{integral}");
    }
}
