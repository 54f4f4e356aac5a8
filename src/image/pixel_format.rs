//! The precision an image's samples are stored at.
//!
//! Pixel data is held as `f32` here, but pbrt-v4 keeps each image in the
//! precision its file had (8-bit, half or float) and stores every MIP level
//! in that same precision. Recording the format lets the pyramid round its
//! levels the way pbrt-v4's storage does, so filtered texture values match.

use super::color_encoding::ColorEncoding;
use exr::prelude::f16;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelFormat {
    /// 8 bits per sample, holding encoded values (see [`ColorEncoding`]).
    U8,
    /// IEEE half floats (half EXRs; also 16-bit PNGs, which pbrt-v4 decodes
    /// to linear half floats).
    Half,
    /// 32-bit floats.
    Float,
}

impl PixelFormat {
    /// The linear value that comes back after storing `linear` in this
    /// format with `encoding` (the encoding matters only for 8 bits).
    #[inline]
    pub fn round_trip_linear(self, linear: f32, encoding: ColorEncoding) -> f32 {
        match self {
            PixelFormat::U8 => encoding.to_linear(encoding.linear_to_8bit(linear) as f32 / 255.0),
            PixelFormat::Half => f16::from_f32(linear).to_f32(),
            PixelFormat::Float => linear,
        }
    }
}

/// The largest finite half float.
pub const HALF_MAX: f32 = 65504.0;

/// `value` as a half float, saturating: beyond ±[`HALF_MAX`] it is
/// ±`HALF_MAX`, never ±∞ (pbrt-v4's films clamp so before writing half
/// EXRs).
#[inline]
pub fn saturating_f16(value: f32) -> f16 {
    f16::from_f32(value.clamp(-HALF_MAX, HALF_MAX))
}

/// How many of `values` lie beyond ±[`HALF_MAX`]: those that
/// [`saturating_f16`] clamps.
pub fn count_beyond_half(values: &[f32]) -> u64 {
    values.iter().filter(|v| v.abs() > HALF_MAX).count() as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_saturate_at_the_largest_finite_half() {
        for (value, half) in [
            (1e6, HALF_MAX),
            (f32::INFINITY, HALF_MAX),
            (-1e9, -HALF_MAX),
            (65519.0, HALF_MAX),
            (HALF_MAX, HALF_MAX),
            (1.5, 1.5),
        ] {
            assert_eq!(saturating_f16(value).to_f32(), half, "{value}");
        }
        assert!(f16::from_f32(1e6).to_f32().is_infinite());
        assert_eq!(count_beyond_half(&[1e6, -1e6, HALF_MAX, 0.0, 65505.0]), 3);
    }

    #[test]
    fn round_trips_quantise_as_the_storage_would() {
        let value = 0.123_456_7;
        assert_eq!(
            PixelFormat::Float.round_trip_linear(value, ColorEncoding::Linear),
            value
        );
        let half = PixelFormat::Half.round_trip_linear(value, ColorEncoding::Linear);
        assert!(half != value && (half - value).abs() < 1e-4);
        let eight_bit = PixelFormat::U8.round_trip_linear(value, ColorEncoding::Srgb);
        let code = (super::super::color_encoding::linear_to_srgb(eight_bit) * 255.0).round();
        assert!(
            (super::super::color_encoding::srgb_to_linear(code / 255.0) - eight_bit).abs() < 1e-7
        );
        assert!((eight_bit - value).abs() < 2e-3);
        assert_eq!(
            PixelFormat::U8.round_trip_linear(0.5, ColorEncoding::Linear),
            128.0 / 255.0
        );
    }
}
