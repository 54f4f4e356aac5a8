//! Fresnel reflectance: the fraction of light a smooth boundary reflects,
//! for unpolarised light (the average of the s and p polarisations).

use crate::math::{safe_sqrt, sqr};
use crate::spectrum::{SampledSpectrum, N_SPECTRUM_SAMPLES};

/// Reflectance of a boundary between two dielectrics. `cos_theta_i` is the
/// cosine of the incident direction with the normal; `eta` is η below the
/// boundary over η above it. A negative cosine means light arrives from
/// below, so the indices swap. Returns 1 under total internal reflection.
pub fn fr_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    let mut cos_theta_i = cos_theta_i.clamp(-1.0, 1.0);
    let mut eta = eta;
    if cos_theta_i < 0.0 {
        eta = 1.0 / eta;
        cos_theta_i = -cos_theta_i;
    }
    let sin2_theta_i = 1.0 - cos_theta_i * cos_theta_i;
    let sin2_theta_t = sin2_theta_i / (eta * eta);
    if sin2_theta_t >= 1.0 {
        return 1.0;
    }
    let cos_theta_t = safe_sqrt(1.0 - sin2_theta_t);
    let r_parallel = (eta * cos_theta_i - cos_theta_t) / (eta * cos_theta_i + cos_theta_t);
    let r_perpendicular = (cos_theta_i - eta * cos_theta_t) / (cos_theta_i + eta * cos_theta_t);
    (r_parallel * r_parallel + r_perpendicular * r_perpendicular) / 2.0
}

/// [`fr_dielectric`] for light from outside (η the inside's index over the
/// outside's) when both cosines are known already: `cos_outside` of the
/// ray outside and `cos_inside` of the refracted one, both with the
/// normal, both ≥ 0. The two reflection coefficients share one division.
/// Under total internal reflection (no ray outside: `cos_outside` = 0) it
/// is exactly 1, and 1 too where both cosines are 0 (a tangent ray).
/// (`fr_dielectric` keeps pbrt-v4's own form: pbrt-v4's circular hair and
/// dielectrics are matched to its rounding.)
#[inline]
pub fn fr_dielectric_cosines(cos_outside: f32, cos_inside: f32, eta: f32) -> f32 {
    // r_∥ = (η c_o − c_i)/(η c_o + c_i), r_⊥ = (c_o − η c_i)/(c_o + η c_i).
    let (num_par, den_par) = (
        eta * cos_outside - cos_inside,
        eta * cos_outside + cos_inside,
    );
    let (num_perp, den_perp) = (
        cos_outside - eta * cos_inside,
        cos_outside + eta * cos_inside,
    );
    let (den_par2, den_perp2) = (den_par * den_par, den_perp * den_perp);
    // With c_o = 0 both terms are the same product: 2x / 2x = 1 exactly.
    let num = num_par * num_par * den_perp2 + num_perp * num_perp * den_par2;
    let den = 2.0 * den_par2 * den_perp2;
    if den > 0.0 {
        num / den
    } else {
        1.0
    }
}

/// The two polarisations' reflectances (R_∥, R_⊥) behind
/// [`fr_dielectric_cosines`] (their mean), with its conventions: both
/// exactly 1 under total internal reflection (`cos_outside` = 0) and at a
/// tangent ray. For paths that carry the polarisations apart (the dual
/// hair model's `fresnel "polarized"`).
#[inline]
pub fn fr_dielectric_cosines_polarized(cos_outside: f32, cos_inside: f32, eta: f32) -> (f32, f32) {
    let den_par = eta * cos_outside + cos_inside;
    let den_perp = cos_outside + eta * cos_inside;
    if den_par <= 0.0 || den_perp <= 0.0 {
        return (1.0, 1.0);
    }
    (
        sqr((eta * cos_outside - cos_inside) / den_par),
        sqr((cos_outside - eta * cos_inside) / den_perp),
    )
}

/// Reflectance of a conductor (or any absorbing medium) with complex index
/// η + i k relative to the outside, lit from outside. The cosine is
/// clamped to [0, 1]: conductors are opaque, so light never arrives from
/// below.
pub fn fr_complex(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    let cos_theta_i = cos_theta_i.clamp(0.0, 1.0);
    let eta = Complex::new(eta, k);
    let sin2_theta_i = 1.0 - cos_theta_i * cos_theta_i;
    // Snell's law with a complex index gives a complex transmitted angle.
    let sin2_theta_t = Complex::real(sin2_theta_i) / (eta * eta);
    let cos_theta_t = (Complex::real(1.0) - sin2_theta_t).sqrt();
    let eta_cos_i = eta * Complex::real(cos_theta_i);
    let r_parallel = (eta_cos_i - cos_theta_t) / (eta_cos_i + cos_theta_t);
    let eta_cos_t = eta * cos_theta_t;
    let cos_i = Complex::real(cos_theta_i);
    let r_perpendicular = (cos_i - eta_cos_t) / (cos_i + eta_cos_t);
    (r_parallel.norm() + r_perpendicular.norm()) / 2.0
}

/// [`fr_complex`] at each of the path's wavelengths.
pub fn fr_complex_spectrum(
    cos_theta_i: f32,
    eta: SampledSpectrum,
    k: SampledSpectrum,
) -> SampledSpectrum {
    let mut result = SampledSpectrum::ZERO;
    for i in 0..N_SPECTRUM_SAMPLES {
        result[i] = fr_complex(cos_theta_i, eta[i], k[i]);
    }
    result
}

/// Just enough complex arithmetic for the conductor Fresnel equations.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Complex {
    re: f32,
    im: f32,
}

impl Complex {
    fn new(re: f32, im: f32) -> Self {
        Complex { re, im }
    }

    fn real(re: f32) -> Self {
        Complex { re, im: 0.0 }
    }

    /// Squared magnitude.
    fn norm(self) -> f32 {
        self.re * self.re + self.im * self.im
    }

    /// Principal square root (non-negative real part), computed without
    /// cancellation for either sign of the real part.
    fn sqrt(self) -> Complex {
        let magnitude = self.norm().sqrt();
        if magnitude == 0.0 {
            return Complex::real(0.0);
        }
        let t1 = (0.5 * (magnitude + self.re.abs())).sqrt();
        let t2 = 0.5 * self.im / t1;
        if self.re >= 0.0 {
            Complex::new(t1, t2)
        } else {
            Complex::new(t2.abs(), t1.copysign(self.im))
        }
    }
}

impl std::ops::Add for Complex {
    type Output = Complex;
    fn add(self, rhs: Complex) -> Complex {
        Complex::new(self.re + rhs.re, self.im + rhs.im)
    }
}

impl std::ops::Sub for Complex {
    type Output = Complex;
    fn sub(self, rhs: Complex) -> Complex {
        Complex::new(self.re - rhs.re, self.im - rhs.im)
    }
}

impl std::ops::Mul for Complex {
    type Output = Complex;
    fn mul(self, rhs: Complex) -> Complex {
        Complex::new(
            self.re * rhs.re - self.im * rhs.im,
            self.re * rhs.im + self.im * rhs.re,
        )
    }
}

impl std::ops::Div for Complex {
    type Output = Complex;
    fn div(self, rhs: Complex) -> Complex {
        let scale = 1.0 / rhs.norm();
        Complex::new(
            scale * (self.re * rhs.re + self.im * rhs.im),
            scale * (self.im * rhs.re - self.re * rhs.im),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_reflectance_at_known_angles() {
        // Normal incidence: ((η − 1)/(η + 1))² = 0.04 for glass.
        assert!((fr_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        // Same from inside (η inverted gives the same normal reflectance).
        assert!((fr_dielectric(-1.0, 1.5) - 0.04).abs() < 1e-6);
        // Brewster's angle: tan θ = η, p-polarised reflectance vanishes, so
        // R = Rs/2 with Rs = sin²(θi − θt)/sin²(θi + θt) = 0.1479.
        let theta_b = 1.5f32.atan();
        assert!((fr_dielectric(theta_b.cos(), 1.5) - 0.073_96).abs() < 2e-4);
        // Grazing: everything is reflected.
        assert!((fr_dielectric(0.0, 1.5) - 1.0).abs() < 1e-6);
        // Past the critical angle from inside: total internal reflection.
        assert_eq!(fr_dielectric(-0.5, 1.5), 1.0);
        // Index-matched: nothing is reflected.
        assert!(fr_dielectric(0.3, 1.0) < 1e-12);
    }

    /// From both cosines it is [`fr_dielectric`] to float rounding, and 1
    /// exactly without a ray outside.
    #[test]
    fn reflectance_from_both_cosines() {
        for eta in [1.0001f32, 1.33, 1.55, 2.4] {
            for i in 0..=200 {
                let cos_outside = i as f32 / 200.0;
                let cos_inside = (1.0 - (1.0 - cos_outside * cos_outside) / (eta * eta)).sqrt();
                let a = fr_dielectric_cosines(cos_outside, cos_inside, eta);
                let b = fr_dielectric(cos_outside, eta);
                assert!(
                    (a - b).abs() <= 4e-7 * b.max(1e-3),
                    "η {eta}, cos {cos_outside}: {a} vs {b}"
                );
            }
            assert_eq!(fr_dielectric_cosines(0.0, 0.3, eta), 1.0);
            assert_eq!(fr_dielectric_cosines(0.0, 0.0, eta), 1.0);
        }
    }

    #[test]
    fn complex_reflectance_reduces_to_the_dielectric_one_without_absorption() {
        for i in 0..=20 {
            let cos = i as f32 / 20.0;
            let a = fr_complex(cos, 1.5, 0.0);
            let b = fr_dielectric(cos, 1.5);
            assert!((a - b).abs() < 1e-5, "cos {cos}: {a} vs {b}");
        }
    }

    #[test]
    fn complex_reflectance_of_a_metal() {
        // Normal incidence: ((η−1)² + k²)/((η+1)² + k²). Gold-ish at 600 nm.
        let (eta, k) = (0.2f32, 3.0f32);
        let expected = ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k);
        assert!((fr_complex(1.0, eta, k) - expected).abs() < 1e-5);
        assert!((fr_complex(0.0, eta, k) - 1.0).abs() < 1e-5);
        let s = fr_complex_spectrum(
            0.5,
            SampledSpectrum::splat(eta),
            SampledSpectrum([k, k, 0.5, 0.5]),
        );
        assert_eq!(s[0], s[1]);
        assert_ne!(s[0], s[2]);
        assert!(s.0.iter().all(|v| (0.0..=1.0).contains(v)));
    }
}
