//! The error function, for the Gaussian filter's integral (Rust's standard
//! library has none).

/// erf(x), accurate to about 1e-12: its Maclaurin series near 0, and
/// 1 - erfc(x) from a Chebyshev fit of erfc (relative error below 1.2e-7)
/// where erfc is below 1e-3.
pub fn erf(x: f64) -> f64 {
    if x.is_nan() {
        return x;
    }
    let z = x.abs();
    let value = if z < 2.5 {
        // erf z = 2/√π Σ (-1)^n z^(2n+1) / (n! (2n+1)).
        let z2 = z * z;
        let mut term = z;
        let mut sum = z;
        // At most about 60 terms are needed for z < 2.5.
        for n in 1..100 {
            let n = f64::from(n);
            term *= -z2 / n;
            let contribution = term / (2.0 * n + 1.0);
            sum += contribution;
            if contribution.abs() <= 1e-17 * sum.abs() {
                break;
            }
        }
        sum * 2.0 / std::f64::consts::PI.sqrt()
    } else {
        1.0 - erfc_chebyshev(z)
    };
    value.copysign(x)
}

/// erfc(z) for z ≥ 0 (Press et al.'s Chebyshev approximation).
fn erfc_chebyshev(z: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.5 * z);
    let polynomial = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    t * polynomial.exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        assert_eq!(erf(0.0), 0.0);
        assert!((erf(0.5) - 0.520_499_877_813_046_5).abs() < 1e-13);
        assert!((erf(1.0) - 0.842_700_792_949_714_9).abs() < 1e-13);
        assert!((erf(-2.0) + 0.995_322_265_018_952_7).abs() < 1e-12);
        assert!((erf(3.0) - 0.999_977_909_503_001_4).abs() < 1e-11);
        assert_eq!(erf(40.0), 1.0);
        // Continuous where the methods meet.
        assert!((erf(2.499_999_999) - erf(2.5)).abs() < 1e-9);
    }
}
