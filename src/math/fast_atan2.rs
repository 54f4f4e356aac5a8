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

use glam::Vec4;
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

/// The angle of (x, y) in (−π, π], as `f32::atan2(y, x)`: one lane of
/// [`fast_atan2_x4`] (the same instructions as a scalar version, without
/// its octant branches, which follow the directions and were mispredicted
/// about half the time).
#[inline]
pub fn fast_atan2(y: f32, x: f32) -> f32 {
    fast_atan2_x4(Vec4::splat(y), Vec4::splat(x)).x
}

/// The angle of each lane's (x, y), as [`fast_atan2`], four at once (the
/// dual hair model's trace takes its three lobe azimuths together). The
/// octant tests are selects: the ratio of the smaller to the larger
/// |coordinate| goes through the polynomial, then π/2 − r where |y| > |x|,
/// π − r where x is negative (−0 included), and y's sign.
#[inline]
pub fn fast_atan2_x4(y: Vec4, x: Vec4) -> Vec4 {
    let (ax, ay) = (x.abs(), y.abs());
    let swap = ay.cmpgt(ax);
    let num = Vec4::select(swap, ax, ay);
    let den = Vec4::select(swap, ay, ax);
    let ratio = num / den;
    // A NaN ratio from 0/0 (both zero: the angle of ±0) or ∞/∞ (both
    // infinite: the diagonal) is 0 or 1; one from a NaN input stays NaN.
    let input_nan = x.cmpne(x) | y.cmpne(y);
    let special = ratio.cmpne(ratio) & !input_nan;
    let t = Vec4::select(
        special,
        Vec4::select(num.cmpeq(Vec4::ZERO), Vec4::ZERO, Vec4::ONE),
        ratio,
    );
    let t2 = t * t;
    let mut p = Vec4::splat(A[7]);
    for &c in A[..7].iter().rev() {
        p = p * t2 + Vec4::splat(c);
    }
    let mut r = t + t * t2 * p;
    r = Vec4::select(swap, Vec4::splat(FRAC_PI_2) - r, r);
    // The sign bit of x, as `is_sign_negative` (−0 included).
    let x_negative = Vec4::ONE.copysign(x).cmplt(Vec4::ZERO);
    r = Vec4::select(x_negative, Vec4::splat(PI) - r, r);
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

    /// Each lane is its own: a lane of a mixed vector has the bits of its
    /// values alone, around the circle and at the special values.
    #[test]
    fn four_lanes_are_independent() {
        let mut ys = Vec::new();
        let mut xs = Vec::new();
        for i in 0..20_000 {
            let phi = -PI + 2.0 * PI * (i as f32 + 0.5) / 20_000.0;
            ys.push(phi.sin() * 3.0);
            xs.push(phi.cos() * 3.0);
        }
        let special = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            f32::INFINITY,
            -f32::INFINITY,
            f32::NAN,
        ];
        for &y in &special {
            for &x in &special {
                ys.push(y);
                xs.push(x);
            }
        }
        while ys.len() % 4 != 0 {
            ys.push(1.0);
            xs.push(1.0);
        }
        for (y, x) in ys.chunks(4).zip(xs.chunks(4)) {
            let got = fast_atan2_x4(Vec4::from_slice(y), Vec4::from_slice(x));
            for k in 0..4 {
                let want = fast_atan2(y[k], x[k]);
                assert!(
                    got[k].to_bits() == want.to_bits() || got[k].is_nan() && want.is_nan(),
                    "atan2({}, {}): {} vs {}",
                    y[k],
                    x[k],
                    got[k],
                    want
                );
            }
        }
    }
}
