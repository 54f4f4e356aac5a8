//! Spectra at the few wavelengths a camera path carries.

use std::ops::{Add, AddAssign, Div, DivAssign, Index, IndexMut, Mul, MulAssign, Neg, Sub};

/// Wavelengths carried by one camera path (pbrt-v4: 4).
pub const N_SPECTRUM_SAMPLES: usize = 4;
/// The visible range spectra are defined over, in nm.
pub const LAMBDA_MIN: f32 = 360.0;
pub const LAMBDA_MAX: f32 = 830.0;

/// Values of a spectrum at the path's wavelengths.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SampledSpectrum(pub [f32; N_SPECTRUM_SAMPLES]);

impl SampledSpectrum {
    pub const ZERO: SampledSpectrum = SampledSpectrum([0.0; N_SPECTRUM_SAMPLES]);
    pub const ONE: SampledSpectrum = SampledSpectrum([1.0; N_SPECTRUM_SAMPLES]);

    pub fn splat(v: f32) -> Self {
        SampledSpectrum([v; N_SPECTRUM_SAMPLES])
    }

    pub fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
        SampledSpectrum(std::array::from_fn(f))
    }

    pub fn map(self, mut f: impl FnMut(f32) -> f32) -> Self {
        SampledSpectrum(self.0.map(&mut f))
    }

    /// Whether any value is non-zero.
    pub fn is_nonzero(&self) -> bool {
        self.0.iter().any(|&v| v != 0.0)
    }

    pub fn is_zero(&self) -> bool {
        !self.is_nonzero()
    }

    pub fn max_component(&self) -> f32 {
        self.0.iter().copied().fold(f32::NEG_INFINITY, f32::max)
    }

    pub fn min_component(&self) -> f32 {
        self.0.iter().copied().fold(f32::INFINITY, f32::min)
    }

    pub fn average(&self) -> f32 {
        self.0.iter().sum::<f32>() / N_SPECTRUM_SAMPLES as f32
    }

    pub fn has_nan(&self) -> bool {
        self.0.iter().any(|v| v.is_nan())
    }

    /// Division that gives 0 where the divisor is 0 (pbrt's SafeDiv).
    pub fn safe_div(self, d: SampledSpectrum) -> Self {
        SampledSpectrum::from_fn(|i| {
            if d.0[i] != 0.0 {
                self.0[i] / d.0[i]
            } else {
                0.0
            }
        })
    }

    pub fn sqrt(self) -> Self {
        self.map(|v| v.max(0.0).sqrt())
    }

    /// e^v per wavelength, four at once ([`crate::math::exp4`]: within 2
    /// ulps of the exact value).
    pub fn exp(self) -> Self {
        SampledSpectrum(crate::math::exp4::exp4(self.0))
    }

    pub fn clamp_zero(self) -> Self {
        self.map(|v| v.max(0.0))
    }
}

impl Index<usize> for SampledSpectrum {
    type Output = f32;
    fn index(&self, i: usize) -> &f32 {
        &self.0[i]
    }
}

impl IndexMut<usize> for SampledSpectrum {
    fn index_mut(&mut self, i: usize) -> &mut f32 {
        &mut self.0[i]
    }
}

macro_rules! elementwise {
    ($trait:ident, $fn:ident, $assign:ident, $assign_fn:ident, $op:tt) => {
        impl $trait for SampledSpectrum {
            type Output = SampledSpectrum;
            #[inline]
            fn $fn(self, rhs: SampledSpectrum) -> SampledSpectrum {
                SampledSpectrum::from_fn(|i| self.0[i] $op rhs.0[i])
            }
        }
        impl $trait<f32> for SampledSpectrum {
            type Output = SampledSpectrum;
            #[inline]
            fn $fn(self, rhs: f32) -> SampledSpectrum {
                SampledSpectrum::from_fn(|i| self.0[i] $op rhs)
            }
        }
        impl $assign for SampledSpectrum {
            #[inline]
            fn $assign_fn(&mut self, rhs: SampledSpectrum) {
                *self = *self $op rhs;
            }
        }
        impl $assign<f32> for SampledSpectrum {
            #[inline]
            fn $assign_fn(&mut self, rhs: f32) {
                *self = *self $op rhs;
            }
        }
    };
}

elementwise!(Add, add, AddAssign, add_assign, +);
elementwise!(Mul, mul, MulAssign, mul_assign, *);
elementwise!(Div, div, DivAssign, div_assign, /);

impl Sub for SampledSpectrum {
    type Output = SampledSpectrum;
    fn sub(self, rhs: SampledSpectrum) -> SampledSpectrum {
        SampledSpectrum::from_fn(|i| self.0[i] - rhs.0[i])
    }
}

impl Neg for SampledSpectrum {
    type Output = SampledSpectrum;
    fn neg(self) -> SampledSpectrum {
        self.map(|v| -v)
    }
}

impl Mul<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    fn mul(self, rhs: SampledSpectrum) -> SampledSpectrum {
        rhs * self
    }
}

/// The wavelengths a camera path carries, and their sampling densities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    pub lambda: [f32; N_SPECTRUM_SAMPLES],
    pub pdf: [f32; N_SPECTRUM_SAMPLES],
}

impl SampledWavelengths {
    /// Stratified uniform wavelengths over [min, max], from one sample.
    pub fn sample_uniform(u: f32, min: f32, max: f32) -> Self {
        let mut lambda = [0.0; N_SPECTRUM_SAMPLES];
        lambda[0] = crate::math::lerp(u, min, max);
        let delta = (max - min) / N_SPECTRUM_SAMPLES as f32;
        for i in 1..N_SPECTRUM_SAMPLES {
            lambda[i] = lambda[i - 1] + delta;
            if lambda[i] > max {
                lambda[i] = min + (lambda[i] - max);
            }
        }
        SampledWavelengths {
            lambda,
            pdf: [1.0 / (max - min); N_SPECTRUM_SAMPLES],
        }
    }

    /// Wavelengths importance-sampled over the visible range (pbrt-v4's
    /// SampleVisibleWavelengths, density ∝ 1/cosh²(0.0072 (λ − 538))),
    /// stratified from one sample.
    pub fn sample_visible(u: f32) -> Self {
        let mut lambda = [0.0; N_SPECTRUM_SAMPLES];
        let mut pdf = [0.0; N_SPECTRUM_SAMPLES];
        for i in 0..N_SPECTRUM_SAMPLES {
            let mut up = u + i as f32 / N_SPECTRUM_SAMPLES as f32;
            if up > 1.0 {
                up -= 1.0;
            }
            (lambda[i], pdf[i]) = visible_wavelength_and_pdf(up);
        }
        SampledWavelengths { lambda, pdf }
    }

    pub fn pdf(&self) -> SampledSpectrum {
        SampledSpectrum(self.pdf)
    }

    /// Keeps only the first wavelength (at a dispersive interface: the
    /// others would follow other paths). Its density becomes 1/N of what
    /// it was.
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        for i in 1..N_SPECTRUM_SAMPLES {
            self.pdf[i] = 0.0;
        }
        self.pdf[0] /= N_SPECTRUM_SAMPLES as f32;
    }

    pub fn secondary_terminated(&self) -> bool {
        self.pdf[1..].iter().all(|&p| p == 0.0)
    }
}

/// Index of the whole nanometre nearest `lambda` in a table of `len`
/// values at every nanometre from `first`, or `None` outside it (NaN too).
/// Halves round up, as pbrt's lround does for the positive wavelengths it
/// is given; by a cast rather than `f32::round`, which is a libm call on
/// the baseline x86-64 target, taken per wavelength per spectrum lookup.
#[inline]
pub fn nanometre_index(lambda: f32, first: i32, len: usize) -> Option<usize> {
    let offset = (lambda + 0.5) as i32 - first;
    usize::try_from(offset).ok().filter(|&i| i < len)
}

/// pbrt-v4's visible-wavelength density peak, and the affine map from u to
/// the argument of its inverse CDF's atanh.
const VISIBLE_PDF_PEAK: f32 = 0.003_939_804_3;
const VISIBLE_Y0: f32 = 0.856_910_6;
const VISIBLE_Y1: f32 = 1.827_502;

/// Density of [`sample_visible_wavelength`] over [360, 830] nm.
pub fn visible_wavelength_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    VISIBLE_PDF_PEAK / (0.0072 * (lambda - 538.0)).cosh().powi(2)
}

/// Inverse CDF of [`visible_wavelength_pdf`].
pub fn sample_visible_wavelength(u: f32) -> f32 {
    visible_wavelength_and_pdf(u).0
}

/// The wavelength the inverse CDF gives for u, with its density. With
/// λ = 538 − 138.88889 atanh(y) and 0.0072 · 138.88889 = 1, the density
/// 0.0039398 / cosh²(0.0072 (λ − 538)) is 0.0039398 (1 − y²): one atanh per
/// wavelength instead of an atanh and a cosh (together a sixth of a render
/// whose camera rays mostly miss). atanh(y) is taken as ½ ln((1 + y)/(1 − y)):
/// `f32::atanh` calls log1pf, several times slower than logf, and y stays
/// in [−0.971, 0.857], where the quotient loses nothing that matters
/// (below 10⁻³ nm).
fn visible_wavelength_and_pdf(u: f32) -> (f32, f32) {
    let y = VISIBLE_Y0 - VISIBLE_Y1 * u;
    let lambda = 538.0 - 69.444_44 * ((1.0 + y) / (1.0 - y)).ln();
    let pdf = if (LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        VISIBLE_PDF_PEAK * (1.0 - y * y)
    } else {
        0.0
    };
    (lambda, pdf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_visible_density_equals_the_cosh_form() {
        // The 1 − y² form of the density agrees with pbrt-v4's cosh form
        // (and the wavelengths with the inverse CDF) to float rounding.
        for k in 0..=1000 {
            let u = k as f32 / 1000.0 * (1.0 - f32::EPSILON);
            let s = SampledWavelengths::sample_visible(u);
            for i in 0..N_SPECTRUM_SAMPLES {
                let l = s.lambda[i];
                let mut up = u + i as f32 / N_SPECTRUM_SAMPLES as f32;
                if up > 1.0 {
                    up -= 1.0;
                }
                assert_eq!(l, sample_visible_wavelength(up));
                // The ln form of atanh against f64's atanh.
                let y = VISIBLE_Y0 as f64 - VISIBLE_Y1 as f64 * up as f64;
                let exact = 538.0 - 138.888_888_9 * y.atanh();
                assert!((l as f64 - exact).abs() < 1e-3, "u {up}: λ {l} vs {exact}");
                let expected = visible_wavelength_pdf(l);
                assert!(
                    (s.pdf[i] - expected).abs() <= 2e-6 * expected.max(1e-3),
                    "u {u} λ {l}: {} vs {expected}",
                    s.pdf[i]
                );
            }
        }
    }

    #[test]
    fn visible_sampling_matches_its_pdf() {
        // The pdf integrates to ~1 over the range, and the inverse CDF
        // stays in range.
        let n = 4700;
        let integral: f32 = (0..n)
            .map(|i| visible_wavelength_pdf(LAMBDA_MIN + (i as f32 + 0.5) * 0.1) * 0.1)
            .sum();
        assert!((integral - 1.0).abs() < 2e-3, "{integral}");
        for i in 0..100 {
            let l = sample_visible_wavelength((i as f32 + 0.5) / 100.0);
            assert!((LAMBDA_MIN..=LAMBDA_MAX).contains(&l), "{l}");
        }
        let w = SampledWavelengths::sample_visible(0.3);
        assert!(w
            .lambda
            .iter()
            .all(|l| (LAMBDA_MIN..=LAMBDA_MAX).contains(l)));
    }

    #[test]
    fn terminating_secondary_wavelengths() {
        let mut w = SampledWavelengths::sample_visible(0.5);
        let p0 = w.pdf[0];
        w.terminate_secondary();
        assert!(w.secondary_terminated());
        assert!((w.pdf[0] - p0 / 4.0).abs() < 1e-9);
    }

    #[test]
    fn arithmetic() {
        let a = SampledSpectrum([1.0, 2.0, 3.0, 4.0]);
        assert_eq!((a * 2.0).0, [2.0, 4.0, 6.0, 8.0]);
        assert_eq!(
            a.safe_div(SampledSpectrum([1.0, 0.0, 3.0, 2.0])).0,
            [1.0, 0.0, 1.0, 2.0]
        );
        assert_eq!(a.average(), 2.5);
    }
}
