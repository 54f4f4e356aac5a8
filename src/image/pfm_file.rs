//! Portable Float Map files (`.pfm`).
//!
//! A text header — `PF` (RGB) or `Pf` (greyscale), width, height, and a
//! scale whose sign gives the byte order (negative: little-endian) — then
//! exactly one whitespace byte, then 32-bit floats with rows ordered bottom
//! to top. As pbrt-v4 does, samples are multiplied by |scale| when it is not
//! 1, and trailing bytes after the pixel data are ignored.

use super::{ColorEncoding, Image, ImageError, PixelFormat};
use std::io::Write;
use std::path::Path;

/// Reads a PFM file into a linear float image (top row first in memory).
pub(crate) fn read_pfm(path: &Path) -> Result<Image, ImageError> {
    let bytes = std::fs::read(path).map_err(|source| ImageError::Io {
        path: path.into(),
        source,
    })?;
    read_pfm_bytes(&bytes, path)
}

/// Reads PFM bytes held in memory (`path` names them in errors).
pub(crate) fn read_pfm_bytes(bytes: &[u8], path: &Path) -> Result<Image, ImageError> {
    parse_pfm(bytes).map_err(|message| ImageError::Malformed {
        path: path.into(),
        message,
    })
}

/// Parses PFM bytes; errors say what is wrong (the caller adds the file).
fn parse_pfm(bytes: &[u8]) -> Result<Image, String> {
    let mut header = HeaderReader { bytes, position: 0 };
    let channels: &[&str] = match header.word()? {
        b"PF" => &["R", "G", "B"],
        b"Pf" => &["Y"],
        other => {
            return Err(format!(
                "not a PFM file: it starts with {:?} instead of \"PF\" or \"Pf\"",
                String::from_utf8_lossy(&other[..other.len().min(16)])
            ))
        }
    };
    let width = header.positive_integer("width")?;
    let height = header.positive_integer("height")?;
    let scale_word = header.word()?;
    let scale: f32 = std::str::from_utf8(scale_word)
        .ok()
        .and_then(|text| text.parse().ok())
        .filter(|scale: &f32| scale.is_finite() && *scale != 0.0)
        .ok_or_else(|| {
            format!(
                "invalid scale {:?} (a non-zero number)",
                String::from_utf8_lossy(scale_word)
            )
        })?;
    // `word` consumed the single whitespace byte that ends the header.
    let little_endian = scale < 0.0;

    let row_samples = width as usize * channels.len();
    let sample_count = row_samples * height as usize;
    let pixel_bytes = &bytes[header.position..];
    let needed = sample_count.checked_mul(4).ok_or("image too large")?;
    if pixel_bytes.len() < needed {
        return Err(format!(
            "premature end of file: {width}×{height} pixels need {needed} bytes of data, found {}",
            pixel_bytes.len()
        ));
    }

    let magnitude = scale.abs();
    let mut data = vec![0.0f32; sample_count];
    // File row 0 is the bottom of the image; memory row 0 is the top.
    for (file_row, row_bytes) in pixel_bytes[..needed]
        .chunks_exact(row_samples * 4)
        .enumerate()
    {
        let memory_row = height as usize - 1 - file_row;
        let destination = &mut data[memory_row * row_samples..(memory_row + 1) * row_samples];
        for (sample, chunk) in destination.iter_mut().zip(row_bytes.chunks_exact(4)) {
            let raw = [chunk[0], chunk[1], chunk[2], chunk[3]];
            let value = if little_endian {
                f32::from_le_bytes(raw)
            } else {
                f32::from_be_bytes(raw)
            };
            *sample = if magnitude == 1.0 {
                value
            } else {
                value * magnitude
            };
        }
    }
    let channels = channels.iter().map(|name| name.to_string()).collect();
    Image::from_parts(
        width,
        height,
        channels,
        data,
        ColorEncoding::Linear,
        PixelFormat::Float,
    )
    .map_err(|error| error.to_string())
}

/// Reads the whitespace-separated words of a PFM header.
struct HeaderReader<'a> {
    bytes: &'a [u8],
    position: usize,
}

impl<'a> HeaderReader<'a> {
    /// The next word; leading whitespace is skipped, and exactly one
    /// whitespace byte after the word is consumed.
    fn word(&mut self) -> Result<&'a [u8], String> {
        while self
            .bytes
            .get(self.position)
            .is_some_and(u8::is_ascii_whitespace)
        {
            self.position += 1;
        }
        let start = self.position;
        while self
            .bytes
            .get(self.position)
            .is_some_and(|byte| !byte.is_ascii_whitespace())
        {
            self.position += 1;
            if self.position - start > 64 {
                return Err("malformed header (a header word longer than 64 bytes)".into());
            }
        }
        if self.position == start || self.position >= self.bytes.len() {
            return Err("premature end of file in the header".into());
        }
        let word = &self.bytes[start..self.position];
        self.position += 1;
        Ok(word)
    }

    fn positive_integer(&mut self, what: &str) -> Result<u32, String> {
        let word = self.word()?;
        std::str::from_utf8(word)
            .ok()
            .and_then(|text| text.parse::<u32>().ok())
            .filter(|&value| value > 0 && value <= i32::MAX as u32)
            .ok_or_else(|| format!("invalid {what} {:?}", String::from_utf8_lossy(word)))
    }
}

/// Writes `image` as PFM: `PF` from its R, G, B channels, or `Pf` from a
/// single channel; little-endian, bottom row first. The image must be
/// linear and finite (the caller checks).
pub(crate) fn write_pfm(
    image: &Image,
    path: &Path,
    writer: &mut impl Write,
) -> Result<(), ImageError> {
    let (selected, tag) = if let Some(rgb) = image.select_channels(&["R", "G", "B"]) {
        (rgb, "PF")
    } else if image.channel_count() == 1 {
        (image.clone(), "Pf")
    } else {
        return Err(ImageError::Unwritable {
            path: path.into(),
            message: format!(
                "PFM holds R, G, B or a single channel; the image has {:?}",
                image.channels()
            ),
        });
    };
    let io_error = |source| ImageError::Io {
        path: path.into(),
        source,
    };
    write!(
        writer,
        "{tag}\n{} {}\n-1\n",
        selected.width(),
        selected.height()
    )
    .map_err(io_error)?;
    let row_samples = selected.width() as usize * selected.channel_count();
    let mut row_bytes = Vec::with_capacity(row_samples * 4);
    for row in selected.data().chunks_exact(row_samples).rev() {
        row_bytes.clear();
        row_bytes.extend(row.iter().flat_map(|value| value.to_le_bytes()));
        writer.write_all(&row_bytes).map_err(io_error)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pfm_bytes(header: &str, rows_bottom_first: &[&[f32]], big_endian: bool) -> Vec<u8> {
        let mut bytes = header.as_bytes().to_vec();
        for row in rows_bottom_first {
            for value in *row {
                bytes.extend(if big_endian {
                    value.to_be_bytes()
                } else {
                    value.to_le_bytes()
                });
            }
        }
        bytes
    }

    #[test]
    fn rows_are_stored_bottom_to_top() {
        // 1×3 greyscale: the file lists the bottom row (3) first.
        let bytes = pfm_bytes("Pf\n1 3\n-1.0\n", &[&[3.0], &[2.0], &[1.0]], false);
        let image = parse_pfm(&bytes).unwrap();
        assert_eq!(image.channels(), ["Y"]);
        assert_eq!((image.width(), image.height()), (1, 3));
        assert_eq!(image.data(), [1.0, 2.0, 3.0], "top row first in memory");
    }

    #[test]
    fn reads_both_byte_orders_and_applies_the_scale() {
        let rows: [&[f32]; 1] = [&[0.25, 0.5, 0.75, 1.0, 2.0, 3.0]];
        let little = parse_pfm(&pfm_bytes("PF\n2 1\n-1\n", &rows, false)).unwrap();
        let big = parse_pfm(&pfm_bytes("PF 2 1 1.0\n", &rows, true)).unwrap();
        assert_eq!(little.data(), rows[0]);
        assert_eq!(big.data(), rows[0]);
        assert_eq!(little.channels(), ["R", "G", "B"]);
        let scaled = parse_pfm(&pfm_bytes("PF\n2 1\n-2.0\n", &rows, false)).unwrap();
        assert_eq!(scaled.data(), [0.5, 1.0, 1.5, 2.0, 4.0, 6.0]);
    }

    #[test]
    fn malformed_files_are_described() {
        let short = pfm_bytes("PF\n2 2\n-1\n", &[&[1.0; 6]], false);
        assert!(parse_pfm(&short)
            .unwrap_err()
            .contains("premature end of file"));
        assert!(parse_pfm(b"P6\n2 2\n255\n")
            .unwrap_err()
            .contains("not a PFM file"));
        assert!(parse_pfm(b"PF\n-2 2\n-1\n").unwrap_err().contains("width"));
        assert!(parse_pfm(b"PF\n2 2\n0\n").unwrap_err().contains("scale"));
        assert!(parse_pfm(b"PF\n2").unwrap_err().contains("premature end"));
        // A huge declared size is rejected without allocating it.
        assert!(parse_pfm(b"PF\n2000000000 2000000000\n-1\n").is_err());
    }
}
