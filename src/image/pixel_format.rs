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

#[cfg(test)]
mod tests {
    use super::*;

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
