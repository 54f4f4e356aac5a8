//! atan2 in f32 by a polynomial, within 3·10⁻⁷ rad of the exact angle:
//! glibc's `atan2f` is correctly rounded but costs about 170 instructions,
//! and the dual hair model takes several azimuths per path vertex.
//!
//! The ratio of the smaller to the larger |coordinate| lies in [0, 1], where
//! atan t / t is a polynomial in t² (Abramowitz & Stegun 4.4.49, error
//! ≤ 2·10⁻⁸); the octant then comes from the signs and from which
//! coordinate was larger. Signed zeros and infinities follow `f32::atan2`
//! where it matters here (atan2(±0, x) for x ≥ 0 is ±0, for x < 0 it is
//! ±π); NaN gives NaN.

use std::f32::consts::{FRAC_PI_2, PI};

/// A&S 4.4.49: atan t ≈ t (1 + Σ a_{2k} t^{2k}), k = 1…8, on [0, 1].
const A: [f32; 8] = [
    -0.333_331_45,
    0.199_935_5,
    -0.142_089,
    0.106_562_64,
    -0.075_289_64,
    0.042_909_614,
    -0.016_165_737,
    0.002_866_225_7,
];

/// The angle of (x, y) in (−π, π], as `f32::atan2(y, x)`.
#[inline]
pub fn fast_atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let swap = ay > ax;
    let (num, den) = if swap { (ax, ay) } else { (ay, ax) };
    let mut t = num / den;
    // The rare cases, off the common path: a NaN input (its ratio is NaN),
    // both coordinates zero (0/0: the angle of ±0) or both infinite (∞/∞:
    // the diagonal).
    if t.is_nan() {
        if x.is_nan() || y.is_nan() {
            return f32::NAN;
        }
        t = if num == 0.0 { 0.0 } else { 1.0 };
    }
    let t2 = t * t;
    let mut p = A[7];
    for &c in A[..7].iter().rev() {
        p = p * t2 + c;
    }
    let mut r = t + t * t2 * p;
    if swap {
        r = FRAC_PI_2 - r;
    }
    if x.is_sign_negative() {
        r = PI - r;
    }
    r.copysign(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn within_3e7_of_f64_around_the_circle() {
        let mut worst = 0.0f64;
        let n = 400_000;
        for i in 0..n {
            let phi = -PI as f64 + 2.0 * PI as f64 * (i as f64 + 0.5) / n as f64;
            for r in [1e-3f64, 1.0, 37.0] {
                let (x, y) = ((r * phi.cos()) as f32, (r * phi.sin()) as f32);
                let exact = (y as f64).atan2(x as f64);
                let e = (fast_atan2(y, x) as f64 - exact).abs();
                // ±π are the same angle.
                let e = e.min((e - 2.0 * std::f64::consts::PI).abs());
                worst = worst.max(e);
            }
        }
        eprintln!("fast_atan2: worst error {worst:.2e} rad");
        assert!(worst < 3e-7, "{worst}");
    }

    #[test]
    fn axes_zeros_infinities_and_nan_as_atan2() {
        for (y, x) in [
            (0.0f32, 1.0f32),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, 0.0),
            (-0.0, 0.0),
            (0.0, -0.0),
            (1.0, f32::INFINITY),
            (f32::INFINITY, 1.0),
            (f32::INFINITY, f32::INFINITY),
            (-f32::INFINITY, -f32::INFINITY),
        ] {
            let (got, want) = (fast_atan2(y, x), y.atan2(x));
            assert!(
                (got - want).abs() <= 3e-7 && got.is_sign_negative() == want.is_sign_negative(),
                "atan2({y}, {x}): {got} vs {want}"
            );
        }
        assert!(fast_atan2(f32::NAN, 1.0).is_nan());
        assert!(fast_atan2(1.0, f32::NAN).is_nan());
    }
}
