//! CIE daylight at any colour temperature: what a film's `whitebalance`
//! temperature means (pbrt-v4's `Spectra::D`).

use super::blackbody::blackbody;
use super::data::illuminants::{DAYLIGHT_S0, DAYLIGHT_S1, DAYLIGHT_S2};
use super::data::UniformTable;
use super::densely_sampled::DenselySampled;
use super::piecewise_linear::PiecewiseLinear;
use super::spectrum::Spectrum;
use super::xyz::spectrum_to_y;

/// The CIE daylight spectrum for a nominal temperature in kelvin, at each
/// whole nanometre over 360–830 nm; `None` for non-positive or non-finite
/// temperatures.
///
/// As in CIE 015 the nominal temperature is first corrected for the
/// revised second radiation constant (× 1.4388/1.4380). Below 4000 K,
/// where the daylight model is undefined, a blackbody normalised to unit
/// luminance stands in, as pbrt-v4 does. Above it the spectrum is
/// S0 + M1 S1 + M2 S2 (scaled by 0.01, about 1 at 560 nm).
pub fn daylight_spectrum(temperature_kelvin: f32) -> Option<DenselySampled> {
    if !(temperature_kelvin.is_finite() && temperature_kelvin > 0.0) {
        return None;
    }
    let cct = f64::from(temperature_kelvin) * 1.4388 / 1.4380;
    if cct < 4000.0 {
        let mut s = DenselySampled::from_fn(|l| blackbody(l, cct as f32));
        let y = spectrum_to_y(&Spectrum::DenselySampled(std::sync::Arc::new(s.clone())));
        if !(y > 0.0 && y.is_finite()) {
            return None;
        }
        s.scale(1.0 / y);
        return Some(s);
    }
    let (x, y) = daylight_chromaticity(cct);
    let m = 0.0241 + 0.2562 * x - 0.7341 * y;
    let m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m;
    let m2 = (0.0300 - 31.4424 * x + 30.0717 * y) / m;
    let s0 = basis(&DAYLIGHT_S0)?;
    let s1 = basis(&DAYLIGHT_S1)?;
    let s2 = basis(&DAYLIGHT_S2)?;
    Some(DenselySampled::from_fn(|l| {
        let v = f64::from(s0.eval(l)) + m1 * f64::from(s1.eval(l)) + m2 * f64::from(s2.eval(l));
        (v * 0.01) as f32
    }))
}

/// The CIE daylight locus: chromaticity of daylight at a (corrected)
/// correlated colour temperature, valid for 4000–25000 K.
pub fn daylight_chromaticity(cct: f64) -> (f64, f64) {
    let t = cct;
    let x = if t <= 7000.0 {
        -4.6070e9 / t.powi(3) + 2.9678e6 / t.powi(2) + 0.09911e3 / t + 0.244063
    } else {
        -2.0064e9 / t.powi(3) + 1.9018e6 / t.powi(2) + 0.24748e3 / t + 0.237040
    };
    let y = -3.000 * x * x + 2.870 * x - 0.275;
    (x, y)
}

fn basis(table: &UniformTable) -> Option<PiecewiseLinear> {
    PiecewiseLinear::from_interleaved(&table.interleaved(), false).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::named::named_spectrum;
    use crate::spectrum::xyz::{spectrum_to_xyz, xyz_to_xy};
    use std::sync::Arc;

    fn xy_of(s: DenselySampled) -> glam::Vec2 {
        xyz_to_xy(spectrum_to_xyz(&Spectrum::DenselySampled(Arc::new(s))))
    }

    #[test]
    fn nominal_6500_kelvin_is_d65() {
        let xy = xy_of(daylight_spectrum(6500.0).unwrap());
        let d65 = xyz_to_xy(spectrum_to_xyz(&named_spectrum("stdillum-D65").unwrap()));
        assert!((xy - d65).abs().max_element() < 5e-4, "{xy} vs {d65}");
    }

    #[test]
    fn follows_the_daylight_locus_above_7000_kelvin() {
        let xy = xy_of(daylight_spectrum(9000.0).unwrap());
        let (x, y) = daylight_chromaticity(9000.0 * 1.4388 / 1.4380);
        assert!(
            (xy.x - x as f32).abs() < 1e-3 && (xy.y - y as f32).abs() < 1e-3,
            "{xy}"
        );
        assert!(xy.x < 0.3, "cooler than D65: {xy}");
    }

    #[test]
    fn low_temperatures_use_a_blackbody() {
        let s = daylight_spectrum(2856.0).unwrap();
        let xy = xy_of(s);
        // Illuminant A is a 2856 K blackbody.
        assert!(
            (xy.x - 0.4476).abs() < 2e-3 && (xy.y - 0.4074).abs() < 2e-3,
            "{xy}"
        );
        assert!(daylight_spectrum(0.0).is_none());
        assert!(daylight_spectrum(f32::NAN).is_none());
    }
}
