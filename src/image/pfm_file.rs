//! Portable Float Map files (`.pfm`).
//!
//! A text header — `PF` (RGB) or `Pf` (greyscale), width, height, and a
//! scale whose sign gives the byte order (negative: little-endian) — then
//! exactly one whitespace byte, then 32-bit floats with rows ordered bottom
//! to top. As pbrt-v4 does, samples are multiplied by |scale| when it is not
//! 1, and trailing bytes after the pixel data are ignored.

use super::{ColorEncoding, Image, ImageError, PixelFormat};
use std::io::{Read, Write};
use std::path::Path;

/// Bytes read first from a file for its header: a header that ends within
/// them is parsed there and the samples are read straight into the image
/// (no copy of the file in memory beside it); a file this short is parsed
/// whole, and a longer header (only whitespace makes one) is read with the
/// whole file.
const HEADER_PREFIX: u64 = 4096;

/// Reads a PFM file into a linear float image (top row first in memory).
pub(crate) fn read_pfm(path: &Path) -> Result<Image, ImageError> {
    let io_error = |source| ImageError::Io {
        path: path.into(),
        source,
    };
    let mut file = std::fs::File::open(path).map_err(io_error)?;
    let mut prefix = Vec::new();
    (&mut file)
        .take(HEADER_PREFIX)
        .read_to_end(&mut prefix)
        .map_err(io_error)?;
    if (prefix.len() as u64) < HEADER_PREFIX {
        return read_pfm_bytes(&prefix, path);
    }
    let Ok(header) = parse_header(&prefix) else {
        drop(file);
        let bytes = std::fs::read(path).map_err(io_error)?;
        return read_pfm_bytes(&bytes, path);
    };
    let length = file.metadata().map_err(io_error)?.len();
    let malformed = |message| ImageError::Malformed {
        path: path.into(),
        message,
    };
    header
        .check_length(length.saturating_sub(header.position as u64))
        .map_err(malformed)?;
    let mut pixels = std::io::Cursor::new(&prefix[header.position..]).chain(file);
    let data = header.decode(&mut pixels).map_err(io_error)?;
    header.into_image(data).map_err(malformed)
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
    let header = parse_header(bytes)?;
    let pixel_bytes = &bytes[header.position..];
    header.check_length(pixel_bytes.len() as u64)?;
    let data = header
        .decode(&mut &pixel_bytes[..])
        .map_err(|error| error.to_string())?;
    header.into_image(data)
}

/// What a PFM header says, and where its samples start.
struct Header {
    channels: &'static [&'static str],
    width: u32,
    height: u32,
    scale: f32,
    /// The offset of the first sample byte.
    position: usize,
}

fn parse_header(bytes: &[u8]) -> Result<Header, String> {
    let mut header = HeaderReader { bytes, position: 0 };
    let channels: &'static [&'static str] = match header.word()? {
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
    Ok(Header {
        channels,
        width,
        height,
        scale,
        position: header.position,
    })
}

impl Header {
    /// Samples in one row.
    fn row_samples(&self) -> usize {
        self.width as usize * self.channels.len()
    }

    /// Bytes of sample data the image needs.
    fn needed_bytes(&self) -> Result<usize, String> {
        (self.row_samples() * self.height as usize)
            .checked_mul(4)
            .ok_or_else(|| "image too large".into())
    }

    /// Checks that `available` bytes of data (trailing bytes are ignored,
    /// as pbrt-v4 does) hold the image, before anything is allocated.
    fn check_length(&self, available: u64) -> Result<(), String> {
        let needed = self.needed_bytes()?;
        if available < needed as u64 {
            return Err(format!(
                "premature end of file: {}×{} pixels need {needed} bytes of data, found {available}",
                self.width, self.height
            ));
        }
        Ok(())
    }

    /// The samples, top row first, read row by row from `pixels` (the
    /// file's bottom row first) and scaled by |scale| when it is not 1.
    fn decode(&self, pixels: &mut impl Read) -> std::io::Result<Vec<f32>> {
        let little_endian = self.scale < 0.0;
        let magnitude = self.scale.abs();
        let row_samples = self.row_samples();
        let height = self.height as usize;
        let mut data = vec![0.0f32; row_samples * height];
        let mut row_bytes = vec![0u8; row_samples * 4];
        // File row 0 is the bottom of the image; memory row 0 is the top.
        for file_row in 0..height {
            pixels.read_exact(&mut row_bytes)?;
            let memory_row = height - 1 - file_row;
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
        Ok(data)
    }

    fn into_image(self, data: Vec<f32>) -> Result<Image, String> {
        let channels = self.channels.iter().map(|name| name.to_string()).collect();
        Image::from_parts(
            self.width,
            self.height,
            channels,
            data,
            ColorEncoding::Linear,
            PixelFormat::Float,
        )
        .map_err(|error| error.to_string())
    }
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

    /// A file is read as its bytes are parsed: short files, files longer
    /// than the header's first read (samples read straight into the image),
    /// a header longer than it, and a file cut short.
    #[test]
    fn files_read_as_their_bytes_parse() {
        let dir = std::env::temp_dir().join(format!("rpbrt-test-pfm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("image.pfm");
        let row: Vec<f32> = (0..3 * 40).map(|i| i as f32 * 0.5 - 7.0).collect();
        let rows: Vec<&[f32]> = (0..30).map(|_| row.as_slice()).collect();
        let long_header = format!("PF{}40 30\n-2\n", " ".repeat(5000));
        for (header, rows) in [
            ("PF\n2 1\n-1\n", &rows[..1]),
            ("PF\n40 30\n1.0\n", &rows[..]),
            (long_header.as_str(), &rows[..]),
        ] {
            let header = header.replace("2 1", "40 1");
            let bytes = pfm_bytes(&header, rows, !header.contains('-'));
            std::fs::write(&path, &bytes).unwrap();
            let from_file = read_pfm(&path).unwrap();
            let from_bytes = parse_pfm(&bytes).unwrap();
            assert_eq!(from_file.data(), from_bytes.data());
            assert_eq!(
                (from_file.width(), from_file.height()),
                (40, rows.len() as u32)
            );
            let cut = &bytes[..bytes.len() - 5];
            std::fs::write(&path, cut).unwrap();
            let error = read_pfm(&path).unwrap_err().to_string();
            assert!(error.contains("premature end of file"), "{error}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
