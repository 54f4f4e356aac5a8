//! The smooth, bounded spectra Jakob & Hanika (2019) use to turn RGB into
//! spectra: a quadratic in wavelength passed through a sigmoid.

use super::sampled::{LAMBDA_MAX, LAMBDA_MIN};

/// s(λ) = sigmoid(c0 λ² + c1 λ + c2), λ in nm, with
/// sigmoid(x) = ½ + x / (2√(1 + x²)) mapping ℝ onto (0, 1): every such
/// spectrum is a valid reflectance.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RgbSigmoidPolynomial {
    pub c0: f32,
    pub c1: f32,
    pub c2: f32,
}

/// ½ + x / (2√(1 + x²)); the infinities (from exactly black or white
/// RGBs) map to 0 and 1.
#[inline]
pub fn sigmoid(x: f32) -> f32 {
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

impl RgbSigmoidPolynomial {
    pub const fn new(c0: f32, c1: f32, c2: f32) -> Self {
        RgbSigmoidPolynomial { c0, c1, c2 }
    }

    /// The value at `lambda` nm.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        sigmoid((self.c0 * lambda + self.c1) * lambda + self.c2)
    }

    /// The largest value over 360–830 nm: at an end, or at the vertex of
    /// the quadratic when it opens downward inside the range.
    pub fn max_value(&self) -> f32 {
        let at_ends = self.eval(LAMBDA_MIN).max(self.eval(LAMBDA_MAX));
        if self.c0 < 0.0 {
            let vertex = -self.c1 / (2.0 * self.c0);
            if (LAMBDA_MIN..=LAMBDA_MAX).contains(&vertex) {
                return at_ends.max(self.eval(vertex));
            }
        }
        at_ends
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigmoid_maps_the_line_onto_the_unit_interval() {
        assert_eq!(sigmoid(0.0), 0.5);
        assert_eq!(sigmoid(f32::INFINITY), 1.0);
        assert_eq!(sigmoid(f32::NEG_INFINITY), 0.0);
        assert!(sigmoid(1e6) > 0.999 && sigmoid(1e6) <= 1.0);
        assert!(sigmoid(-1e6) < 1e-3 && sigmoid(-1e6) >= 0.0);
        assert!((sigmoid(1.0) - (0.5 + 0.5 / 2f32.sqrt())).abs() < 1e-7);
    }

    #[test]
    fn max_value_finds_an_interior_peak() {
        // Peak at 550 nm: -(λ - 550)² / 1000 + 2.
        let p = RgbSigmoidPolynomial::new(-1e-3, 1.1, -550.0 * 550.0 * 1e-3 + 2.0);
        assert!((p.max_value() - sigmoid(2.0)).abs() < 1e-4);
        assert!(p.max_value() > p.eval(LAMBDA_MIN));
        // Upward-opening: the maximum is at an end.
        let q = RgbSigmoidPolynomial::new(1e-4, -0.1, 0.0);
        assert_eq!(q.max_value(), q.eval(LAMBDA_MIN).max(q.eval(LAMBDA_MAX)));
    }
}
