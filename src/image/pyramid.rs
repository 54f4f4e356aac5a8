//! Building an image pyramid (the levels of a MIP map) as pbrt-v4 does.
//!
//! The image is decoded to linear, enlarged to power-of-two resolution if
//! needed ([`resize_to_power_of_two`]), then halved repeatedly with a 2×2 box
//! filter down to a single texel. Once a dimension has reached one texel it
//! stays one and the box filter averages along the other dimension only.
//!
//! pbrt-v4 stores every level in the precision of the original image (8-bit
//! with its encoding, half, or float), while each next level is computed from
//! the full-precision version of the previous one. The levels here are
//! rounded through that storage the same way, so lookups return the values
//! pbrt-v4's would.

use super::resample::resize_to_power_of_two;
use super::{ColorEncoding, Image, ImageError, WrapMode};
use rayon::prelude::*;

/// The pyramid of `image`: level 0 is the (power-of-two) base, the last
/// level is 1×1. Every level is linear `f32`.
pub(crate) fn build_pyramid(image: &Image, wrap: WrapMode) -> Result<Vec<Image>, ImageError> {
    let storage_format = image.format();
    let storage_encoding = image.encoding();
    let mut level = resize_to_power_of_two(&image.to_linear(), wrap)?;
    let level_count = 1 + level.width().max(level.height()).ilog2() as usize;

    let mut pyramid = Vec::with_capacity(level_count);
    for _ in 0..level_count - 1 {
        let next = box_filter_half(&level)?;
        pyramid.push(rounded_to_storage(level, storage_format, storage_encoding));
        level = next;
    }
    pyramid.push(rounded_to_storage(level, storage_format, storage_encoding));
    Ok(pyramid)
}

/// The next pyramid level: each texel the average of a 2×2 block, with the
/// block collapsing to the one row or column where there is only one.
fn box_filter_half(level: &Image) -> Result<Image, ImageError> {
    let (width, height) = (level.width() as usize, level.height() as usize);
    let (next_width, next_height) = ((width / 2).max(1), (height / 2).max(1));
    let channel_count = level.channel_count();
    let source = level.data();
    // Offsets from a block's top-left sample to its right, lower and
    // lower-right neighbours (zero where the dimension has one texel).
    let right = if width == 1 { 0 } else { channel_count };
    let down = if height == 1 {
        0
    } else {
        channel_count * width
    };

    let mut data = vec![0.0f32; next_width * next_height * channel_count];
    data.par_chunks_mut(next_width * channel_count)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, pixel) in row.chunks_exact_mut(channel_count).enumerate() {
                let top_left =
                    ((2 * y).min(height - 1) * width + (2 * x).min(width - 1)) * channel_count;
                for (channel, value) in pixel.iter_mut().enumerate() {
                    let at = top_left + channel;
                    *value = 0.25
                        * (source[at]
                            + source[at + right]
                            + source[at + down]
                            + source[at + down + right]);
                }
            }
        });
    Image::from_parts(
        next_width as u32,
        next_height as u32,
        level.channels().to_vec(),
        data,
        ColorEncoding::Linear,
        level.format(),
    )
}

/// `level` with every value replaced by what storing it in the original
/// image's precision would give back.
fn rounded_to_storage(
    mut level: Image,
    format: super::PixelFormat,
    encoding: ColorEncoding,
) -> Image {
    if format != super::PixelFormat::Float {
        for value in level.data_mut() {
            *value = format.round_trip_linear(*value, encoding);
        }
    }
    level
}

#[cfg(test)]
mod tests {
    use super::super::PixelFormat;
    use super::*;

    #[test]
    fn level_count_and_resolutions_for_256_by_128() {
        let image = Image::filled(256, 128, &["Y"], &[0.5]).unwrap();
        let pyramid = build_pyramid(&image, WrapMode::Repeat).unwrap();
        let resolutions: Vec<(u32, u32)> =
            pyramid.iter().map(|l| (l.width(), l.height())).collect();
        assert_eq!(
            resolutions,
            [
                (256, 128),
                (128, 64),
                (64, 32),
                (32, 16),
                (16, 8),
                (8, 4),
                (4, 2),
                (2, 1),
                (1, 1)
            ]
        );
    }

    #[test]
    fn non_power_of_two_images_are_enlarged_first() {
        let image = Image::filled(100, 60, &["Y"], &[0.5]).unwrap();
        let pyramid = build_pyramid(&image, WrapMode::Clamp).unwrap();
        assert_eq!((pyramid[0].width(), pyramid[0].height()), (128, 64));
        assert_eq!(pyramid.len(), 8);
    }

    #[test]
    fn box_filter_averages_blocks_and_collapses_single_rows() {
        let checker = Image::new(2, 2, &["Y"], vec![0.0, 1.0, 1.0, 0.0]).unwrap();
        let pyramid = build_pyramid(&checker, WrapMode::Repeat).unwrap();
        assert_eq!(pyramid[1].data(), [0.5]);

        // 4×1: once height is 1, pairs along x are averaged.
        let row = Image::new(4, 1, &["Y"], vec![1.0, 3.0, 5.0, 7.0]).unwrap();
        let pyramid = build_pyramid(&row, WrapMode::Repeat).unwrap();
        assert_eq!(pyramid[1].data(), [2.0, 6.0]);
        assert_eq!(pyramid[2].data(), [4.0]);
    }

    #[test]
    fn levels_are_rounded_to_the_original_precision() {
        // 8-bit sRGB codes 0 and 255 average to linear 0.5, which 8 bits
        // store as code 188 (linear 0.50289...).
        let image = Image::new(2, 1, &["Y"], vec![0.0, 1.0])
            .unwrap()
            .with_encoding(ColorEncoding::Srgb)
            .with_format(PixelFormat::U8);
        let pyramid = build_pyramid(&image, WrapMode::Clamp).unwrap();
        assert_eq!(pyramid[0].data(), [0.0, 1.0]);
        let stored = super::super::color_encoding::srgb_to_linear(188.0 / 255.0);
        assert_eq!(pyramid[1].data(), [stored]);
        assert_ne!(stored, 0.5);

        // Half: 1/3 is not representable.
        let third = Image::filled(1, 1, &["Y"], &[1.0 / 3.0])
            .unwrap()
            .with_format(PixelFormat::Half);
        let pyramid = build_pyramid(&third, WrapMode::Clamp).unwrap();
        assert_eq!(
            pyramid[0].data(),
            [exr::prelude::f16::from_f32(1.0 / 3.0).to_f32()]
        );
    }
}
