//! OpenEXR files (`.exr`), through the `exr` crate.
//!
//! Reading takes the first layer's largest resolution level. Its channels
//! are put in a canonical order: R, G, B (and A when present) if the layer
//! has R, G and B — the channels pbrt-v4 uses for textures and lights —
//! otherwise Y (and A), otherwise a lone channel of any name. Half and float
//! samples are both read as `f32`; the format records which it was.

use super::pixel_format::saturating_f16;
use super::{ColorEncoding, DataWindow, Image, ImageError, PixelFormat};
use exr::meta::MetaData;
use exr::prelude::{
    read, AnyChannel, AnyChannels, Encoding, FlatSamples, ImageAttributes, IntegerBounds, Layer,
    LayerAttributes, ReadChannels, ReadLayers, Text, Vec2, WritableImage,
};
use std::io::{BufReader, Read, Seek, SeekFrom, Write};
use std::path::Path;

pub(crate) fn read_exr(path: &Path) -> Result<Image, ImageError> {
    read_exr_with_window(path).map(|(image, _)| image)
}

/// The image and where its pixels lie in the full image (OpenEXR's data
/// window within its display window).
pub(crate) fn read_exr_with_window(path: &Path) -> Result<(Image, DataWindow), ImageError> {
    let file = std::fs::File::open(path).map_err(|source| ImageError::Io {
        path: path.into(),
        source,
    })?;
    read_exr_from(BufReader::new(file), path)
}

/// The most samples (pixels × channels) a layer may have: 2³⁰ (4 GiB of
/// floats), and at most 2¹⁶ per byte of the file (far beyond what any
/// compression reaches on real images). The `exr` crate allocates a
/// layer's samples before it reads them, so a header announcing an absurd
/// size would otherwise allocate without bound (found by fuzzing).
const MAX_SAMPLES: u64 = 1 << 30;
const MAX_SAMPLES_PER_BYTE: u64 = 1 << 16;

/// Reads the header and refuses layers too large to allocate; leaves
/// `source` at its start.
fn check_size(source: &mut (impl Read + Seek)) -> Result<(), String> {
    let io = |e: std::io::Error| format!("cannot read OpenEXR data: {e}");
    let length = source.seek(SeekFrom::End(0)).map_err(io)?;
    source.seek(SeekFrom::Start(0)).map_err(io)?;
    let meta = MetaData::read_from_buffered(&mut *source, false)
        .map_err(|error| format!("cannot read OpenEXR data: {error}"))?;
    source.seek(SeekFrom::Start(0)).map_err(io)?;
    let limit = MAX_SAMPLES.min(length.saturating_mul(MAX_SAMPLES_PER_BYTE));
    for header in &meta.headers {
        let (width, height) = (header.layer_size.0 as u64, header.layer_size.1 as u64);
        let channels = header.channels.list.len() as u64;
        let samples = width.saturating_mul(height).saturating_mul(channels);
        if samples > limit {
            return Err(format!(
                "a layer of {width}×{height} pixels and {channels} channels has {samples} samples, \
                 more than the {limit} read from a file of {length} bytes"
            ));
        }
    }
    Ok(())
}

/// Reads OpenEXR data from `source` (`path` names it in errors).
pub(crate) fn read_exr_from(
    mut source: impl Read + Seek,
    path: &Path,
) -> Result<(Image, DataWindow), ImageError> {
    let malformed = |message: String| ImageError::Malformed {
        path: path.into(),
        message,
    };
    check_size(&mut source).map_err(malformed)?;
    let exr_image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(source)
        .map_err(|error| malformed(format!("cannot read OpenEXR data: {error}")))?;
    let display = exr_image.attributes.display_window;
    let layer = exr_image.layer_data;
    let (width, height) = (layer.size.0, layer.size.1);
    let window = DataWindow {
        full_resolution: (display.size.0 as u32, display.size.1 as u32),
        origin: (
            layer.attributes.layer_position.0 - display.position.0,
            layer.attributes.layer_position.1 - display.position.1,
        ),
    };
    let pixel_count = width * height;
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();

    let wanted = canonical_channels(&names)
        .ok_or_else(|| malformed(format!("no R, G, B or Y channels (the file has {names:?})")))?;

    let mut columns = Vec::with_capacity(wanted.len());
    let mut all_half = true;
    for name in &wanted {
        let channel = layer
            .channel_data
            .list
            .iter()
            .find(|channel| channel.name.to_string() == name.as_str())
            .ok_or_else(|| malformed(format!("channel {name} vanished")))?;
        if channel.sampling.0 != 1 || channel.sampling.1 != 1 {
            return Err(malformed(format!(
                "channel {name} is subsampled, which is not supported"
            )));
        }
        let samples: Vec<f32> = match &channel.sample_data {
            FlatSamples::F16(values) => values.iter().map(|value| value.to_f32()).collect(),
            FlatSamples::F32(values) => {
                all_half = false;
                values.clone()
            }
            FlatSamples::U32(values) => {
                all_half = false;
                values.iter().map(|&value| value as f32).collect()
            }
        };
        if samples.len() != pixel_count {
            return Err(malformed(format!(
                "channel {name} has {} samples for {width}×{height} pixels",
                samples.len()
            )));
        }
        columns.push(samples);
    }

    let mut data = Vec::with_capacity(pixel_count * wanted.len());
    for pixel in 0..pixel_count {
        data.extend(columns.iter().map(|column| column[pixel]));
    }
    let (width, height) = match (u32::try_from(width), u32::try_from(height)) {
        (Ok(w), Ok(h)) => (w, h),
        _ => return Err(malformed(format!("resolution {width}×{height} too large"))),
    };
    let format = if all_half {
        PixelFormat::Half
    } else {
        PixelFormat::Float
    };
    let image = Image::from_parts(width, height, wanted, data, ColorEncoding::Linear, format)
        .map_err(|error| malformed(error.to_string()))?;
    Ok((image, window))
}

/// The channels to keep, in canonical order (see the module description).
fn canonical_channels(names: &[String]) -> Option<Vec<String>> {
    let has = |name: &str| names.iter().any(|present| present == name);
    let chosen: Vec<&str> = if has("R") && has("G") && has("B") {
        vec!["R", "G", "B"]
    } else if has("Y") {
        vec!["Y"]
    } else if let [lone] = names {
        return Some(vec![lone.clone()]);
    } else {
        return None;
    };
    let alpha = has("A").then_some("A");
    Some(
        chosen
            .into_iter()
            .chain(alpha)
            .map(str::to_string)
            .collect(),
    )
}

/// Writes every channel of `image` (linear and finite; the caller checks),
/// as half floats if `half` (values beyond the half range written as
/// ±65504, the largest finite half, as pbrt-v4's films clamp them: never
/// ±∞), else 32-bit floats, ZIP-compressed; placed at
/// `window` in a larger display window if given (as pbrt-v4 writes a
/// `--pixelbounds` or `--cropwindow` render).
pub(crate) fn write_exr(
    image: &Image,
    half: bool,
    window: Option<&DataWindow>,
    text_attributes: &[(&str, &str)],
    path: &Path,
    writer: &mut (impl Write + Seek),
) -> Result<(), ImageError> {
    let unwritable = |message: String| ImageError::Unwritable {
        path: path.into(),
        message,
    };
    let width = image.width() as usize;
    let height = image.height() as usize;
    let channel_count = image.channel_count();
    let mut channels = exr::prelude::SmallVec::<[AnyChannel<FlatSamples>; 4]>::new();
    for (index, name) in image.channels().iter().enumerate() {
        let name_text = Text::new_or_none(name)
            .ok_or_else(|| unwritable(format!("channel name {name:?} is not valid in OpenEXR")))?;
        let column = image
            .data()
            .iter()
            .skip(index)
            .step_by(channel_count)
            .copied();
        let samples = if half {
            FlatSamples::F16(column.map(saturating_f16).collect())
        } else {
            FlatSamples::F32(column.collect())
        };
        channels.push(AnyChannel::new(name_text, samples));
    }
    let mut attributes = LayerAttributes::default();
    for (name, value) in text_attributes {
        let text = |t: &str| {
            Text::new_or_none(t)
                .ok_or_else(|| unwritable(format!("attribute {t:?} is not valid in OpenEXR")))
        };
        attributes.other.insert(
            text(name)?,
            exr::meta::attribute::AttributeValue::Text(text(value)?),
        );
    }
    let mut display = IntegerBounds::from_dimensions((width, height));
    if let Some(window) = window {
        attributes.layer_position = Vec2(window.origin.0, window.origin.1);
        display.size = Vec2(
            window.full_resolution.0 as usize,
            window.full_resolution.1 as usize,
        );
    }
    let layer = Layer::new(
        (width, height),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    exr::prelude::Image::new(ImageAttributes::new(display), layer)
        .write()
        .to_buffered(writer)
        .map_err(|error| unwritable(format!("OpenEXR encoding failed: {error}")))
}
