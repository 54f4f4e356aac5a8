//! Spectra given as (wavelength, value) samples joined by straight lines:
//! what scene files and spectrum files hold, and the form of pbrt-v4's
//! named spectra.

use std::path::Path;

use super::cie::{cie_y, CIE_Y_INTEGRAL};
use super::sampled::{SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};

/// Linear interpolation between samples at strictly increasing
/// wavelengths; zero outside the sampled range (pbrt-v4's
/// `PiecewiseLinearSpectrum`).
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseLinear {
    lambdas: Vec<f32>,
    values: Vec<f32>,
}

impl PiecewiseLinear {
    /// Samples at `lambdas` (nm, strictly increasing). Errors if the two
    /// lengths differ, there are none, or the wavelengths do not increase.
    pub fn new(lambdas: Vec<f32>, values: Vec<f32>) -> Result<Self, String> {
        if lambdas.len() != values.len() {
            return Err(format!(
                "spectrum has {} wavelengths but {} values",
                lambdas.len(),
                values.len()
            ));
        }
        if lambdas.is_empty() {
            return Err("spectrum has no samples".to_string());
        }
        if let Some(i) = lambdas.iter().position(|l| !l.is_finite()) {
            return Err(format!("spectrum wavelength {} is not finite", lambdas[i]));
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!("spectrum value {} is not finite", values[i]));
        }
        if let Some(i) = (1..lambdas.len()).find(|&i| lambdas[i] <= lambdas[i - 1]) {
            return Err(format!(
                "spectrum wavelengths must increase: entry {i} has {} after {}",
                lambdas[i],
                lambdas[i - 1]
            ));
        }
        Ok(PiecewiseLinear { lambdas, values })
    }

    /// A spectrum from interleaved (λ, value) pairs, as a scene file's
    /// `"spectrum"` parameter or pbrt's built-in tables give them.
    ///
    /// As pbrt-v4's `FromInterleaved` does, samples that start after
    /// 360 nm or end before 830 nm are extended with their end values to
    /// just past the visible range (so a CIE F-series lamp tabulated over
    /// 380–780 nm still emits at its ends). With `normalize` the spectrum is
    /// scaled to luminance Y = 1 (∫ s ȳ dλ = ∫ ȳ dλ): the convention for
    /// named illuminants, so that their brightness comes only from a
    /// light's `scale`/`power`.
    pub fn from_interleaved(samples: &[f64], normalize: bool) -> Result<Self, String> {
        if samples.len() % 2 != 0 {
            return Err(format!(
                "spectrum needs (wavelength, value) pairs but has {} numbers",
                samples.len()
            ));
        }
        if samples.is_empty() {
            return Err("spectrum has no samples".to_string());
        }
        let pairs = samples.chunks_exact(2);
        let mut lambdas = Vec::with_capacity(pairs.len() + 2);
        let mut values = Vec::with_capacity(pairs.len() + 2);
        if samples[0] > f64::from(LAMBDA_MIN) {
            lambdas.push(LAMBDA_MIN - 1.0);
            values.push(samples[1] as f32);
        }
        for pair in pairs {
            lambdas.push(pair[0] as f32);
            values.push(pair[1] as f32);
        }
        let last_lambda = samples[samples.len() - 2];
        if last_lambda < f64::from(LAMBDA_MAX) {
            lambdas.push(LAMBDA_MAX + 1.0);
            values.push(samples[samples.len() - 1] as f32);
        }
        let mut spectrum = PiecewiseLinear::new(lambdas, values)?;
        if normalize {
            let y = spectrum.integrate_against_y();
            if !(y.is_finite() && y > 0.0) {
                return Err("spectrum has no luminance to normalise".to_string());
            }
            spectrum.scale(CIE_Y_INTEGRAL / y);
        }
        Ok(spectrum)
    }

    /// Multiplies every value by `factor`.
    pub fn scale(&mut self, factor: f32) {
        for v in &mut self.values {
            *v *= factor;
        }
    }

    /// ∫ s(λ) ȳ(λ) dλ by a 1 nm sum over 360–830 nm (pbrt's `InnerProduct`
    /// with the ȳ spectrum).
    fn integrate_against_y(&self) -> f32 {
        (LAMBDA_MIN as i32..=LAMBDA_MAX as i32)
            .map(|l| self.eval(l as f32) * cie_y(l as f32))
            .sum()
    }

    pub fn lambdas(&self) -> &[f32] {
        &self.lambdas
    }

    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The value at `lambda` (nm); zero outside the samples.
    pub fn eval(&self, lambda: f32) -> f32 {
        let (Some(&first), Some(&last)) = (self.lambdas.first(), self.lambdas.last()) else {
            return 0.0;
        };
        // The negated form also sends NaN to zero.
        if !(lambda >= first && lambda <= last) {
            return 0.0;
        }
        // Largest i with lambdas[i] <= lambda, kept one short of the end so
        // that i + 1 is valid.
        let i = self
            .lambdas
            .partition_point(|&l| l <= lambda)
            .saturating_sub(1)
            .min(self.lambdas.len().saturating_sub(2));
        if self.lambdas.len() == 1 {
            return self.values[0];
        }
        let (l0, l1) = (self.lambdas[i], self.lambdas[i + 1]);
        let t = (lambda - l0) / (l1 - l0);
        (1.0 - t) * self.values[i] + t * self.values[i + 1]
    }

    pub fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::from_fn(|i| self.eval(w.lambda[i]))
    }

    pub fn max_value(&self) -> f32 {
        self.values.iter().copied().fold(0.0_f32, f32::max)
    }
}

/// Reads a spectrum file in pbrt's format: whitespace-separated numbers,
/// read as (wavelength nm, value) pairs with strictly increasing
/// wavelengths; `#` starts a comment that runs to the end of the line.
/// Like pbrt-v4's `PiecewiseLinearSpectrum::Read`, the samples are used as
/// given (no extension past their range, no normalisation).
pub fn read_spectrum_file(path: impl AsRef<Path>) -> Result<PiecewiseLinear, String> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: unable to read spectrum file: {e}", path.display()))?;
    parse_spectrum_text(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The parsing half of [`read_spectrum_file`].
pub fn parse_spectrum_text(text: &str) -> Result<PiecewiseLinear, String> {
    let mut numbers = Vec::new();
    for (line_index, line) in text.lines().enumerate() {
        let content = line.split('#').next().unwrap_or("");
        for token in content.split_whitespace() {
            let value: f32 = token
                .parse()
                .map_err(|_| format!("line {}: \"{token}\" is not a number", line_index + 1))?;
            numbers.push(value);
        }
    }
    if numbers.is_empty() {
        return Err("spectrum file has no samples".to_string());
    }
    if numbers.len() % 2 != 0 {
        return Err(format!(
            "spectrum file has an odd count of numbers ({}): expected wavelength/value pairs",
            numbers.len()
        ));
    }
    let (lambdas, values) = numbers.chunks_exact(2).map(|p| (p[0], p[1])).unzip();
    PiecewiseLinear::new(lambdas, values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_between_samples_and_is_zero_outside() {
        let s = PiecewiseLinear::new(vec![400.0, 500.0, 600.0], vec![1.0, 3.0, 2.0]).unwrap();
        assert_eq!(s.eval(400.0), 1.0);
        assert_eq!(s.eval(450.0), 2.0);
        assert_eq!(s.eval(500.0), 3.0);
        assert_eq!(s.eval(575.0), 2.25);
        assert_eq!(s.eval(600.0), 2.0);
        assert_eq!(s.eval(399.9), 0.0);
        assert_eq!(s.eval(600.1), 0.0);
        assert_eq!(s.eval(f32::NAN), 0.0);
        assert_eq!(s.max_value(), 3.0);
    }

    #[test]
    fn rejects_malformed_samples() {
        assert!(PiecewiseLinear::new(vec![500.0, 400.0], vec![1.0, 1.0]).is_err());
        assert!(PiecewiseLinear::new(vec![400.0, 400.0], vec![1.0, 1.0]).is_err());
        assert!(PiecewiseLinear::new(vec![400.0], vec![1.0, 1.0]).is_err());
        assert!(PiecewiseLinear::from_interleaved(&[400.0, 1.0, 500.0], false).is_err());
        assert!(PiecewiseLinear::from_interleaved(&[], false).is_err());
        assert!(PiecewiseLinear::from_interleaved(&[400.0, 0.0, 500.0, 0.0], true).is_err());
    }

    #[test]
    fn interleaved_samples_extend_over_the_visible_range() {
        let s = PiecewiseLinear::from_interleaved(&[400.0, 2.0, 700.0, 4.0], false).unwrap();
        assert_eq!(s.eval(360.0), 2.0);
        assert_eq!(s.eval(550.0), 3.0);
        assert_eq!(s.eval(830.0), 4.0);
        assert_eq!(s.lambdas().first(), Some(&359.0));
        assert_eq!(s.lambdas().last(), Some(&831.0));
    }

    #[test]
    fn normalised_spectra_have_unit_luminance() {
        let s = PiecewiseLinear::from_interleaved(&[300.0, 5.0, 900.0, 5.0], true).unwrap();
        // A constant spectrum normalised to Y = 1 is 1 everywhere.
        assert!((s.eval(555.0) - 1.0).abs() < 1e-5, "{}", s.eval(555.0));
        let tilted = PiecewiseLinear::from_interleaved(&[360.0, 1.0, 830.0, 9.0], true).unwrap();
        let y = tilted.integrate_against_y() / CIE_Y_INTEGRAL;
        assert!((y - 1.0).abs() < 1e-5, "{y}");
    }

    #[test]
    fn parses_spectrum_files_with_comments() {
        let text = "# measured\n400 0.5 # first\n  500\t0.75\n\n600 1.0e0\n";
        let s = parse_spectrum_text(text).unwrap();
        assert_eq!(s.lambdas(), &[400.0, 500.0, 600.0]);
        assert_eq!(s.values(), &[0.5, 0.75, 1.0]);
        assert!(parse_spectrum_text("400 0.5 500").is_err());
        assert!(parse_spectrum_text("400 0.5 300 1").is_err());
        assert!(parse_spectrum_text("400 x").is_err());
        assert!(parse_spectrum_text("# nothing\n").is_err());
        assert!(read_spectrum_file("/nonexistent/spectrum.spd").is_err());
    }
}
