//! Spectra tabulated at every whole nanometre: constant-time lookup for
//! spectra evaluated on every path (a colour space's illuminant, lights).

use super::sampled::{
    nanometre_index, SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN,
};

/// Values at each whole nanometre from `lambda_min` to `lambda_max`,
/// looked up at the nearest one; zero outside (pbrt-v4's
/// `DenselySampledSpectrum`).
#[derive(Clone, Debug, PartialEq)]
pub struct DenselySampled {
    lambda_min: i32,
    values: Vec<f32>,
}

impl DenselySampled {
    /// Samples `f` at each whole nanometre over the visible range,
    /// 360–830 nm.
    pub fn from_fn(f: impl FnMut(f32) -> f32) -> Self {
        Self::from_fn_over(LAMBDA_MIN as i32, LAMBDA_MAX as i32, f)
    }

    /// Samples `f` at each whole nanometre of `lambda_min..=lambda_max`.
    pub fn from_fn_over(lambda_min: i32, lambda_max: i32, mut f: impl FnMut(f32) -> f32) -> Self {
        let values = (lambda_min..=lambda_max).map(|l| f(l as f32)).collect();
        DenselySampled { lambda_min, values }
    }

    pub fn lambda_min(&self) -> i32 {
        self.lambda_min
    }

    pub fn lambda_max(&self) -> i32 {
        self.lambda_min + self.values.len() as i32 - 1
    }

    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// Multiplies every value by `factor`.
    pub fn scale(&mut self, factor: f32) {
        for v in &mut self.values {
            *v *= factor;
        }
    }

    /// The value at the whole nanometre nearest `lambda`.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        nanometre_index(lambda, self.lambda_min, self.values.len()).map_or(0.0, |i| self.values[i])
    }

    #[inline]
    pub fn sample(&self, w: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::from_fn(|i| self.eval(w.lambda[i]))
    }

    pub fn max_value(&self) -> f32 {
        self.values.iter().copied().fold(0.0_f32, f32::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn looks_up_the_nearest_nanometre() {
        let s = DenselySampled::from_fn(|l| l - 300.0);
        assert_eq!(s.lambda_min(), 360);
        assert_eq!(s.lambda_max(), 830);
        assert_eq!(s.eval(360.0), 60.0);
        assert_eq!(s.eval(500.49), 200.0);
        assert_eq!(s.eval(500.5), 201.0);
        assert_eq!(s.eval(830.4), 530.0);
        assert_eq!(s.eval(830.5), 0.0);
        assert_eq!(s.eval(359.4), 0.0);
        assert_eq!(s.eval(f32::NAN), 0.0);
        assert_eq!(s.max_value(), 530.0);
    }
}
