//! Four f32 exponentials at once, for a [`SampledSpectrum`]'s four
//! wavelengths (Beer–Lambert transmittance e^{−σ_a ℓ} per wavelength, four
//! to a dozen per hair vertex).
//!
//! libm's `expf` is exact to half an ulp but scalar: four calls cost four
//! times one. This is the Cephes single-precision scheme done four lanes
//! wide with SSE2 (part of every x86-64 CPU): x = n ln 2 + r with
//! |r| ≤ ½ ln 2 (Cody–Waite, two constants), e^r by a degree-7 polynomial,
//! then 2ⁿ put in the exponent bits. Its error is under 2 ulps over the
//! whole range (checked against f64 below). Inputs below −87.3 give 0
//! rather than subnormals, above 88.7 give +∞, and NaN stays NaN. Other
//! targets run the same arithmetic lane by lane, so results agree bit for
//! bit.
//!
//! [`SampledSpectrum`]: crate::spectrum::SampledSpectrum

const LOG2_E: f32 = std::f32::consts::LOG2_E;
/// ln 2 split so that n · LN2_HI is exact for |n| < 2⁹.
const LN2_HI: f32 = 0.693_359_4;
const LN2_LO: f32 = -2.121_944_4e-4;
/// Below this e^x is subnormal (returned as 0); above the next, +∞.
const X_MIN: f32 = -87.336_55;
const X_MAX: f32 = 88.722_83;
/// Cephes' minimax coefficients for (e^r − 1 − r) / r² on |r| ≤ ½ ln 2.
const P: [f32; 6] = [
    1.987_569_1e-4,
    1.398_2e-3,
    8.333_452e-3,
    4.166_579_6e-2,
    0.166_666_65,
    0.5,
];

/// e^x for each lane of `x`.
#[inline]
pub fn exp4(x: [f32; 4]) -> [f32; 4] {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: SSE2 is part of the x86-64 baseline.
        unsafe { exp4_sse2(x) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        x.map(exp1)
    }
}

#[cfg(target_arch = "x86_64")]
#[inline]
unsafe fn exp4_sse2(x: [f32; 4]) -> [f32; 4] {
    use std::arch::x86_64::*;
    let v = _mm_loadu_ps(x.as_ptr());
    let nan = _mm_cmpunord_ps(v, v);
    let low = _mm_cmplt_ps(v, _mm_set1_ps(X_MIN));
    let high = _mm_cmpgt_ps(v, _mm_set1_ps(X_MAX));
    let xc = _mm_min_ps(_mm_max_ps(v, _mm_set1_ps(X_MIN)), _mm_set1_ps(X_MAX));
    // n = round(x log₂e), by truncating x log₂e + ½ and stepping down
    // where truncation went up (negative values).
    let t = _mm_add_ps(_mm_mul_ps(xc, _mm_set1_ps(LOG2_E)), _mm_set1_ps(0.5));
    let ti = _mm_cvttps_epi32(t);
    let tf = _mm_cvtepi32_ps(ti);
    let up = _mm_cmpgt_ps(tf, t);
    let n = _mm_sub_ps(tf, _mm_and_ps(up, _mm_set1_ps(1.0)));
    let ni = _mm_cvttps_epi32(n);
    let r = _mm_sub_ps(
        _mm_sub_ps(xc, _mm_mul_ps(n, _mm_set1_ps(LN2_HI))),
        _mm_mul_ps(n, _mm_set1_ps(LN2_LO)),
    );
    let mut p = _mm_set1_ps(P[0]);
    for &c in &P[1..] {
        p = _mm_add_ps(_mm_mul_ps(p, r), _mm_set1_ps(c));
    }
    let r2 = _mm_mul_ps(r, r);
    let e_r = _mm_add_ps(_mm_add_ps(_mm_mul_ps(p, r2), r), _mm_set1_ps(1.0));
    // 2ⁿ as 2^⌊n/2⌋ · 2^⌈n/2⌉: n runs over [−126, 128] and 2¹²⁸ is not a
    // float, but each half is.
    let half = _mm_srai_epi32(ni, 1);
    let pow2 =
        |k: __m128i| _mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(k, _mm_set1_epi32(127)), 23));
    let (scale, scale_extra) = (pow2(half), pow2(_mm_sub_epi32(ni, half)));
    let mut y = _mm_mul_ps(_mm_mul_ps(e_r, scale), scale_extra);
    y = _mm_andnot_ps(low, y);
    y = _mm_or_ps(
        _mm_andnot_ps(high, y),
        _mm_and_ps(high, _mm_set1_ps(f32::INFINITY)),
    );
    y = _mm_or_ps(_mm_andnot_ps(nan, y), _mm_and_ps(nan, v));
    let mut out = [0.0f32; 4];
    _mm_storeu_ps(out.as_mut_ptr(), y);
    out
}

/// One lane of [`exp4`], with the same operations in the same order.
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
fn exp1(x: f32) -> f32 {
    if x.is_nan() {
        return x;
    }
    if x < X_MIN {
        return 0.0;
    }
    if x > X_MAX {
        return f32::INFINITY;
    }
    let t = x * LOG2_E + 0.5;
    let tf = t as i32 as f32;
    let n = if tf > t { tf - 1.0 } else { tf };
    let r = (x - n * LN2_HI) - n * LN2_LO;
    let mut p = P[0];
    for &c in &P[1..] {
        p = p * r + c;
    }
    let e_r = (p * (r * r) + r) + 1.0;
    let n = n as i32;
    let half = n >> 1;
    let pow2 = |k: i32| f32::from_bits(((k + 127) as u32) << 23);
    e_r * pow2(half) * pow2(n - half)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(got: f32, want: f64) -> f64 {
        if want == 0.0 {
            return if got == 0.0 { 0.0 } else { f64::INFINITY };
        }
        let ulp = (want as f32).abs();
        let ulp = (f32::from_bits(ulp.to_bits() + 1) - ulp) as f64;
        (got as f64 - want).abs() / ulp
    }

    #[test]
    fn within_two_ulps_over_the_range() {
        let mut worst = 0.0f64;
        let n = 200_000;
        for i in 0..n {
            let x = X_MIN + (X_MAX - X_MIN) * i as f32 / n as f32;
            let lanes = [x, -x.abs() * 0.01, x * 0.1, x * 1e-4];
            let got = exp4(lanes);
            for k in 0..4 {
                let want = (lanes[k] as f64).exp();
                if want < f32::MIN_POSITIVE as f64 {
                    continue;
                }
                worst = worst.max(ulps(got[k], want));
                // The portable lane agrees bit for bit.
                assert_eq!(
                    got[k].to_bits(),
                    exp1(lanes[k]).to_bits(),
                    "x = {}",
                    lanes[k]
                );
            }
        }
        eprintln!("exp4: worst error {worst:.2} ulps");
        assert!(worst < 2.0, "{worst}");
    }

    #[test]
    fn edges_zero_infinity_and_nan() {
        let got = exp4([0.0, -1000.0, 1000.0, f32::NAN]);
        assert_eq!(got[0], 1.0);
        assert_eq!(got[1], 0.0);
        assert_eq!(got[2], f32::INFINITY);
        assert!(got[3].is_nan());
        let got = exp4([f32::NEG_INFINITY, f32::INFINITY, -0.0, 1.0]);
        assert_eq!(got[0..3], [0.0, f32::INFINITY, 1.0]);
        assert!((got[3] - std::f32::consts::E).abs() <= f32::EPSILON * 3.0);
        assert!(exp4([X_MAX; 4])[0].is_finite());
    }
}
