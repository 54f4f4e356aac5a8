//! Planck's law: the emission of an ideal radiator at a temperature.

use super::sampled::{SampledSpectrum, SampledWavelengths};

/// Speed of light in vacuum, m/s.
const SPEED_OF_LIGHT: f64 = 299_792_458.0;
/// Planck's constant, J·s (the values pbrt-v4 uses).
const PLANCK: f64 = 6.626_069_57e-34;
/// Boltzmann's constant, J/K.
const BOLTZMANN: f64 = 1.380_648_8e-23;
/// Wien's displacement constant, m·K: the peak of a blackbody at T kelvin
/// is at this / T metres.
pub const WIEN_DISPLACEMENT: f64 = 2.897_772_1e-3;

/// Spectral radiance of a blackbody at `temperature_kelvin`, at
/// `lambda_nm`, in W/(sr·m²·m). Zero for non-positive temperatures.
pub fn blackbody(lambda_nm: f32, temperature_kelvin: f32) -> f32 {
    blackbody_f64(f64::from(lambda_nm), f64::from(temperature_kelvin)) as f32
}

fn blackbody_f64(lambda_nm: f64, temperature_kelvin: f64) -> f64 {
    if !(temperature_kelvin > 0.0) || !(lambda_nm > 0.0) {
        return 0.0;
    }
    let l = lambda_nm * 1e-9;
    let c = SPEED_OF_LIGHT;
    let exponent = (PLANCK * c) / (l * BOLTZMANN * temperature_kelvin);
    // exp_m1 keeps precision where the exponent is small (long wavelengths,
    // hot bodies).
    let radiance = (2.0 * PLANCK * c * c) / (l.powi(5) * exponent.exp_m1());
    if radiance.is_finite() {
        radiance
    } else {
        0.0
    }
}

/// A blackbody's spectrum scaled so its peak (at Wien's wavelength) is 1:
/// the colour of a temperature, with brightness set elsewhere (pbrt-v4's
/// `BlackbodySpectrum`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlackbodySpectrum {
    temperature_kelvin: f32,
    normalization: f32,
}

impl BlackbodySpectrum {
    /// The normalised spectrum at `temperature_kelvin`; a non-positive or
    /// non-finite temperature gives a black spectrum.
    pub fn new(temperature_kelvin: f32) -> Self {
        let t = f64::from(temperature_kelvin);
        let peak = if t.is_finite() && t > 0.0 {
            blackbody_f64(Self::peak_wavelength_nm_f64(t), t)
        } else {
            0.0
        };
        let normalization = if peak > 0.0 { (1.0 / peak) as f32 } else { 0.0 };
        BlackbodySpectrum {
            temperature_kelvin,
            normalization,
        }
    }

    fn peak_wavelength_nm_f64(t: f64) -> f64 {
        WIEN_DISPLACEMENT / t * 1e9
    }

    /// Where the spectrum peaks, in nm.
    pub fn peak_wavelength_nm(&self) -> f32 {
        Self::peak_wavelength_nm_f64(f64::from(self.temperature_kelvin)) as f32
    }

    pub fn temperature_kelvin(&self) -> f32 {
        self.temperature_kelvin
    }

    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        if self.normalization == 0.0 {
            return 0.0;
        }
        (blackbody_f64(f64::from(lambda), f64::from(self.temperature_kelvin))
            * f64::from(self.normalization)) as f32
    }

    pub fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::from_fn(|i| self.eval(w.lambda[i]))
    }

    /// 1 by construction (0 for a black spectrum).
    pub fn max_value(&self) -> f32 {
        if self.normalization == 0.0 {
            0.0
        } else {
            1.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peaks_at_one_at_wiens_wavelength() {
        for t in [2700.0, 5500.0, 6500.0] {
            let b = BlackbodySpectrum::new(t);
            let peak = b.peak_wavelength_nm();
            assert!((b.eval(peak) - 1.0).abs() < 1e-5, "T {t}: {}", b.eval(peak));
            assert!(b.eval(peak - 20.0) < 1.0 && b.eval(peak + 20.0) < 1.0);
            assert_eq!(b.max_value(), 1.0);
        }
        // 5800 K peaks near 500 nm (Wien: 2.8978e-3 / 5800 m).
        let sun = BlackbodySpectrum::new(5800.0);
        assert!((sun.peak_wavelength_nm() - 499.6).abs() < 0.1);
    }

    #[test]
    fn absolute_radiance_follows_plancks_law() {
        // B(500 nm, 5000 K) = 1.21e13 W/(sr·m³) from the closed form.
        let b = blackbody(500.0, 5000.0);
        assert!((b / 1.2107e13 - 1.0).abs() < 1e-3, "{b}");
        // Hotter is brighter at every wavelength.
        assert!(blackbody(500.0, 6000.0) > b);
    }

    #[test]
    fn non_physical_temperatures_are_black() {
        for t in [0.0, -100.0, f32::NAN, f32::INFINITY] {
            let b = BlackbodySpectrum::new(t);
            assert_eq!(b.eval(550.0), 0.0, "T {t}");
            assert_eq!(b.max_value(), 0.0);
        }
        assert_eq!(blackbody(550.0, 0.0), 0.0);
    }
}
