//! How stored pixel values relate to linear light.
//!
//! 8-bit (and 16-bit) files hold *encoded* values; rendering needs linear
//! ones. pbrt-v4 lets a scene say how to decode an image texture
//! (`"string encoding" "sRGB" | "linear" | "gamma 2.2"`) and defaults to sRGB
//! for 8-bit formats, so the readers keep the encoded values and record the
//! encoding; whoever uses the image decides, then calls
//! [`Image::to_linear`](super::Image::to_linear).

/// The transfer function between stored values (in [0, 1]) and linear light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorEncoding {
    /// Stored values are linear already (floating-point formats, or an
    /// 8-bit texture the scene declares `"linear"`).
    Linear,
    /// The sRGB curve (IEC 61966-2-1): what PNG, TGA and JPEG hold unless a
    /// scene says otherwise.
    Srgb,
    /// A pure power law: linear = stored^gamma (pbrt-v4's `"gamma g"`).
    Gamma(f32),
}

impl ColorEncoding {
    /// Parses pbrt-v4's `encoding` parameter values: `"sRGB"`, `"linear"`
    /// or `"gamma <value>"`. `None` for anything else, so the caller can
    /// report the scene location.
    pub fn parse(text: &str) -> Option<ColorEncoding> {
        match text {
            "sRGB" => Some(ColorEncoding::Srgb),
            "linear" => Some(ColorEncoding::Linear),
            _ => {
                let gamma: f32 = text.strip_prefix("gamma ")?.trim().parse().ok()?;
                (gamma.is_finite() && gamma > 0.0).then_some(ColorEncoding::Gamma(gamma))
            }
        }
    }

    /// Decodes one stored value (in [0, 1]) to linear light.
    #[inline]
    pub fn to_linear(self, stored: f32) -> f32 {
        match self {
            ColorEncoding::Linear => stored,
            ColorEncoding::Srgb => srgb_to_linear(stored),
            ColorEncoding::Gamma(gamma) => stored.max(0.0).powf(gamma),
        }
    }

    /// Encodes a linear value and quantises it to 8 bits, clamping to
    /// [0, 1] first (NaN becomes 0). This is how pbrt-v4 stores 8-bit image
    /// data, so MIP levels of 8-bit textures are rounded through it.
    pub fn linear_to_8bit(self, linear: f32) -> u8 {
        match self {
            ColorEncoding::Srgb => linear_to_srgb8(linear),
            ColorEncoding::Linear => quantise_unit_to_8bit(linear),
            ColorEncoding::Gamma(gamma) => {
                if linear.is_nan() || linear <= 0.0 {
                    0
                } else {
                    quantise_unit_to_8bit(linear.powf(1.0 / gamma))
                }
            }
        }
    }
}

/// The exact sRGB decoding curve (linear segment, then a 2.4 power law).
#[inline]
pub fn srgb_to_linear(encoded: f32) -> f32 {
    if encoded <= 0.04045 {
        encoded * (1.0 / 12.92)
    } else {
        ((encoded + 0.055) * (1.0 / 1.055)).powf(2.4)
    }
}

/// The exact sRGB encoding curve, the inverse of [`srgb_to_linear`].
#[inline]
pub fn linear_to_srgb(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        linear * 12.92
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// Linear value → nearest 8-bit sRGB code, clamped to [0, 255] (NaN → 0).
/// pbrt-v4 rounds to nearest as well (its PNG writer adds a blue-noise
/// dither first; this does not).
#[inline]
pub fn linear_to_srgb8(linear: f32) -> u8 {
    if linear.is_nan() || linear <= 0.0 {
        return 0;
    }
    if linear >= 1.0 {
        return 255;
    }
    quantise_unit_to_8bit(linear_to_srgb(linear))
}

/// [0, 1] → nearest of 0..=255, clamped (NaN → 0).
#[inline]
fn quantise_unit_to_8bit(value: f32) -> u8 {
    // `as` saturates and maps NaN to 0, which is the clamping wanted here.
    (value * 255.0).round().clamp(0.0, 255.0) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve_matches_its_definition_and_inverts() {
        // Reference values of the standard: mid-grey code 128 ≈ 0.2158605.
        assert!((srgb_to_linear(128.0 / 255.0) - 0.215_860_5).abs() < 1e-6);
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        // Linear segment below the knee.
        assert!((srgb_to_linear(0.04) - 0.04 / 12.92).abs() < 1e-9);
        for code in 0..=255u8 {
            let linear = srgb_to_linear(code as f32 / 255.0);
            assert_eq!(linear_to_srgb8(linear), code, "code {code}");
        }
    }

    #[test]
    fn eight_bit_quantisation_clamps() {
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        assert_eq!(linear_to_srgb8(7.0), 255);
        assert_eq!(ColorEncoding::Linear.linear_to_8bit(0.5), 128);
        assert_eq!(ColorEncoding::Gamma(2.0).linear_to_8bit(0.25), 128);
        assert_eq!(ColorEncoding::Gamma(2.0).linear_to_8bit(f32::NAN), 0);
    }

    #[test]
    fn parses_pbrt_encoding_names() {
        assert_eq!(ColorEncoding::parse("sRGB"), Some(ColorEncoding::Srgb));
        assert_eq!(ColorEncoding::parse("linear"), Some(ColorEncoding::Linear));
        assert_eq!(
            ColorEncoding::parse("gamma 2.2"),
            Some(ColorEncoding::Gamma(2.2))
        );
        assert_eq!(ColorEncoding::parse("gamma -1"), None);
        assert_eq!(ColorEncoding::parse("srgb"), None);
    }
}
