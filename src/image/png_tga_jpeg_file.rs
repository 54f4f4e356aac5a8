//! 8- and 16-bit formats decoded by the `image` crate (PNG, TGA, JPEG), and
//! PNG writing.
//!
//! Samples are kept encoded (code / 255, or code / 65535 for 16 bits) and
//! marked sRGB, which is how pbrt-v4 interprets these files unless a texture
//! says otherwise. Channels follow pbrt-v4: greyscale with alpha keeps only
//! Y; RGBA keeps its alpha for PNG but drops it for TGA and JPEG (pbrt-v4
//! reads those through a different loader that discards it). 16-bit PNGs
//! are marked [`PixelFormat::Half`]: pbrt-v4 decodes them into half floats.

use super::{color_encoding::linear_to_srgb8, ColorEncoding, Image, ImageError, PixelFormat};
use ::image::{DynamicImage, ImageEncoder, ImageFormat, ImageReader, Limits};
use std::io::{BufRead, BufReader, Seek, SeekFrom, Write};
use std::path::Path;

/// The most bytes a decoded image may take per byte of its file.
const MAX_BYTES_PER_FILE_BYTE: u64 = 1 << 16;

/// Reads a PNG, TGA or JPEG file (`format` says which).
pub(crate) fn read_with_image_crate(path: &Path, format: ImageFormat) -> Result<Image, ImageError> {
    let file = std::fs::File::open(path).map_err(|source| ImageError::Io {
        path: path.into(),
        source,
    })?;
    read_with_image_crate_from(BufReader::new(file), path, format)
}

/// Decodes PNG, TGA or JPEG data from `source` (`path` names it in errors).
pub(crate) fn read_with_image_crate_from(
    mut source: impl BufRead + Seek,
    path: &Path,
    format: ImageFormat,
) -> Result<Image, ImageError> {
    let malformed = |message: String| ImageError::Malformed {
        path: path.into(),
        message,
    };
    let io = |source: std::io::Error| ImageError::Io {
        path: path.into(),
        source,
    };
    let length = source.seek(SeekFrom::End(0)).map_err(io)?;
    source.seek(SeekFrom::Start(0)).map_err(io)?;
    // The decoded image may take at most 2¹⁶ bytes per byte of the file
    // (far beyond what real compression reaches) within the crate's
    // default 512 MiB: a few hundred bytes of truncated JPEG announcing a
    // huge image otherwise decoded into hundreds of megabytes (found by
    // fuzzing).
    let mut limits = Limits::default();
    limits.max_alloc = Some(
        limits
            .max_alloc
            .unwrap_or(u64::MAX)
            .min(length.saturating_mul(MAX_BYTES_PER_FILE_BYTE)),
    );
    let mut reader = ImageReader::with_format(source, format);
    reader.limits(limits);
    let decoded = reader
        .decode()
        .map_err(|error| malformed(format!("cannot decode {format:?} data: {error}")))?;
    let (width, height) = (decoded.width(), decoded.height());

    let (channels, samples, format_of_samples): (&[&str], Vec<f32>, PixelFormat) = match decoded {
        DynamicImage::ImageLuma8(buffer) => (&["Y"], from_8bit(buffer.as_raw()), PixelFormat::U8),
        DynamicImage::ImageLumaA8(buffer) => {
            (&["Y", "A"], from_8bit(buffer.as_raw()), PixelFormat::U8)
        }
        DynamicImage::ImageRgb8(buffer) => (
            &["R", "G", "B"],
            from_8bit(buffer.as_raw()),
            PixelFormat::U8,
        ),
        DynamicImage::ImageRgba8(buffer) => (
            &["R", "G", "B", "A"],
            from_8bit(buffer.as_raw()),
            PixelFormat::U8,
        ),
        DynamicImage::ImageLuma16(buffer) => {
            (&["Y"], from_16bit(buffer.as_raw()), PixelFormat::Half)
        }
        DynamicImage::ImageLumaA16(buffer) => {
            (&["Y", "A"], from_16bit(buffer.as_raw()), PixelFormat::Half)
        }
        DynamicImage::ImageRgb16(buffer) => (
            &["R", "G", "B"],
            from_16bit(buffer.as_raw()),
            PixelFormat::Half,
        ),
        DynamicImage::ImageRgba16(buffer) => (
            &["R", "G", "B", "A"],
            from_16bit(buffer.as_raw()),
            PixelFormat::Half,
        ),
        other => {
            return Err(malformed(format!(
                "unsupported pixel layout {:?}",
                other.color()
            )));
        }
    };
    let channel_names = channels.iter().map(|name| name.to_string()).collect();
    let image = Image::from_parts(
        width,
        height,
        channel_names,
        samples,
        ColorEncoding::Srgb,
        format_of_samples,
    )
    .map_err(|error| malformed(error.to_string()))?;

    let keep: &[&str] = match (channels.len(), format) {
        (2, _) => &["Y"],
        (4, ImageFormat::Png) => &["R", "G", "B", "A"],
        (4, _) => &["R", "G", "B"],
        _ => return Ok(image),
    };
    image
        .select_channels(keep)
        .ok_or_else(|| malformed(format!("missing channels {keep:?}")))
}

fn from_8bit(codes: &[u8]) -> Vec<f32> {
    codes.iter().map(|&code| code as f32 / 255.0).collect()
}

fn from_16bit(codes: &[u16]) -> Vec<f32> {
    codes.iter().map(|&code| code as f32 / 65535.0).collect()
}

/// Writes an 8-bit sRGB PNG: RGB from the R, G, B channels (alpha is
/// dropped, as pbrt-v4 does), or greyscale from a single channel. Linear
/// values are clamped to [0, 1] and sRGB-encoded; values already
/// sRGB-encoded are written as they are. The image must be finite.
pub(crate) fn write_png(
    image: &Image,
    path: &Path,
    writer: &mut impl Write,
) -> Result<(), ImageError> {
    let unwritable = |message: String| ImageError::Unwritable {
        path: path.into(),
        message,
    };
    let (selected, color_type) = if let Some(rgb) = image.select_channels(&["R", "G", "B"]) {
        (rgb, ::image::ExtendedColorType::Rgb8)
    } else if image.channel_count() == 1 {
        (image.clone(), ::image::ExtendedColorType::L8)
    } else {
        return Err(unwritable(format!(
            "PNG output holds R, G, B or a single channel; the image has {:?}",
            image.channels()
        )));
    };
    let codes: Vec<u8> = match selected.encoding() {
        ColorEncoding::Srgb => selected
            .data()
            .iter()
            .map(|&encoded| (encoded * 255.0).round().clamp(0.0, 255.0) as u8)
            .collect(),
        _ => selected
            .to_linear()
            .data()
            .iter()
            .map(|&linear| linear_to_srgb8(linear))
            .collect(),
    };
    ::image::codecs::png::PngEncoder::new(writer)
        .write_image(&codes, selected.width(), selected.height(), color_type)
        .map_err(|error| unwritable(format!("PNG encoding failed: {error}")))
}
