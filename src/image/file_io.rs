//! Choosing a file format by extension, and the rules every write follows:
//! refuse non-finite values, and write atomically.

use super::atomic_write::write_atomically;
use super::{exr_file, pfm_file, png_tga_jpeg_file, DataWindow, Image, ImageError};
use ::image::ImageFormat;
use std::path::Path;

const READABLE_EXTENSIONS: &str = ".exr, .pfm, .png, .tga, .jpg, .jpeg";
const WRITABLE_EXTENSIONS: &str = ".exr, .pfm, .png";

/// The file's extension, lower-cased.
fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|extension| extension.to_str())
        .map(str::to_ascii_lowercase)
}

impl Image {
    /// Reads an image file, choosing the format by its extension
    /// (case-insensitive): `.exr`, `.pfm`, `.png`, `.tga`, `.jpg`/`.jpeg`.
    /// 8- and 16-bit formats come back sRGB-encoded (see
    /// [`Image::to_linear`]); floating-point formats come back linear.
    pub fn read(path: impl AsRef<Path>) -> Result<Image, ImageError> {
        let path = path.as_ref();
        match extension(path).as_deref() {
            Some("exr") => exr_file::read_exr(path),
            Some("pfm") => pfm_file::read_pfm(path),
            Some("png") => png_tga_jpeg_file::read_with_image_crate(path, ImageFormat::Png),
            Some("tga") => png_tga_jpeg_file::read_with_image_crate(path, ImageFormat::Tga),
            Some("jpg" | "jpeg") => {
                png_tga_jpeg_file::read_with_image_crate(path, ImageFormat::Jpeg)
            }
            _ => Err(ImageError::UnsupportedExtension {
                path: path.into(),
                supported: READABLE_EXTENSIONS,
            }),
        }
    }

    /// Reads an image file's bytes held in memory, exactly as
    /// [`Image::read`] reads the file `path` (whose extension chooses the
    /// format and which names the data in errors). For fuzzing and tests.
    pub fn read_from_bytes(bytes: &[u8], path: impl AsRef<Path>) -> Result<Image, ImageError> {
        let path = path.as_ref();
        let cursor = || std::io::Cursor::new(bytes);
        match extension(path).as_deref() {
            Some("exr") => exr_file::read_exr_from(cursor(), path).map(|(image, _)| image),
            Some("pfm") => pfm_file::read_pfm_bytes(bytes, path),
            Some("png") => {
                png_tga_jpeg_file::read_with_image_crate_from(cursor(), path, ImageFormat::Png)
            }
            Some("tga") => {
                png_tga_jpeg_file::read_with_image_crate_from(cursor(), path, ImageFormat::Tga)
            }
            Some("jpg" | "jpeg") => {
                png_tga_jpeg_file::read_with_image_crate_from(cursor(), path, ImageFormat::Jpeg)
            }
            _ => Err(ImageError::UnsupportedExtension {
                path: path.into(),
                supported: READABLE_EXTENSIONS,
            }),
        }
    }

    /// Writes the image, choosing the format by extension: `.exr` (half
    /// floats), `.pfm` (32-bit floats) or `.png` (8-bit sRGB). See
    /// [`Image::write_exr`] for the rules all writers follow.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), ImageError> {
        let path = path.as_ref();
        match extension(path).as_deref() {
            Some("exr") => self.write_exr(path, true),
            Some("pfm") => self.write_pfm(path),
            Some("png") => self.write_png(path),
            _ => Err(ImageError::UnsupportedExtension {
                path: path.into(),
                supported: WRITABLE_EXTENSIONS,
            }),
        }
    }

    /// Writes an OpenEXR file with all channels, as half floats if `half`,
    /// else as 32-bit floats. Encoded images are decoded to linear first.
    ///
    /// Like every writer here it refuses images holding NaN or infinite
    /// values (the error names the first bad pixel), and it writes
    /// atomically: the file appears complete or not at all, and a previous
    /// file of that name survives a failed write.
    pub fn write_exr(&self, path: impl AsRef<Path>, half: bool) -> Result<(), ImageError> {
        self.write_exr_in_window(path, half, None)
    }

    /// [`Image::write_exr`], placing the image at `window` of a larger
    /// image: OpenEXR's data window inside its display window, as pbrt-v4
    /// writes renders of part of the film (`--pixelbounds`, `--cropwindow`).
    pub fn write_exr_in_window(
        &self,
        path: impl AsRef<Path>,
        half: bool,
        window: Option<&DataWindow>,
    ) -> Result<(), ImageError> {
        self.write_exr_with_attributes(path, half, window, &[])
    }

    /// [`Image::write_exr_in_window`], with text attributes (name, value)
    /// in the file's header (such as a spectral image's layout version).
    pub fn write_exr_with_attributes(
        &self,
        path: impl AsRef<Path>,
        half: bool,
        window: Option<&DataWindow>,
        attributes: &[(&str, &str)],
    ) -> Result<(), ImageError> {
        let path = path.as_ref();
        self.refuse_non_finite(path)?;
        let linear = self.to_linear();
        write_atomically(path, |writer| {
            exr_file::write_exr(&linear, half, window, attributes, path, writer)
        })
    }

    /// Reads an OpenEXR file and where its pixels lie in the full image
    /// (its data window in its display window).
    pub fn read_exr_with_window(path: impl AsRef<Path>) -> Result<(Image, DataWindow), ImageError> {
        exr_file::read_exr_with_window(path.as_ref())
    }

    /// Writes a PFM file (32-bit floats; `PF` from R, G, B or `Pf` from a
    /// single channel). Same rules as [`Image::write_exr`].
    pub fn write_pfm(&self, path: impl AsRef<Path>) -> Result<(), ImageError> {
        let path = path.as_ref();
        self.refuse_non_finite(path)?;
        let linear = self.to_linear();
        write_atomically(path, |writer| pfm_file::write_pfm(&linear, path, writer))
    }

    /// Writes an 8-bit sRGB PNG (RGB from R, G, B, or greyscale from a
    /// single channel), clamping linear values to [0, 1]. Same rules as
    /// [`Image::write_exr`].
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), ImageError> {
        let path = path.as_ref();
        self.refuse_non_finite(path)?;
        write_atomically(path, |writer| {
            png_tga_jpeg_file::write_png(self, path, writer)
        })
    }

    fn refuse_non_finite(&self, path: &Path) -> Result<(), ImageError> {
        match self.first_non_finite() {
            Some(sample) => Err(ImageError::NonFinite {
                path: path.into(),
                sample,
            }),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::atomic_write::test_directory::TestDirectory;
    use super::super::color_encoding::{linear_to_srgb8, srgb_to_linear};
    use super::super::{ColorEncoding, PixelFormat};
    use super::*;

    /// A small image with distinct, non-trivial values in every sample.
    fn gradient(width: u32, height: u32, channels: &[&str]) -> Image {
        let count = (width * height) as usize * channels.len();
        let data = (0..count)
            .map(|i| 0.013 + (i as f32 * 0.377).fract() * 1.7)
            .collect();
        Image::new(width, height, channels, data).unwrap()
    }

    #[test]
    fn exr_float_round_trip_is_exact() {
        let directory = TestDirectory::new("exr-float");
        for channels in [&["R", "G", "B"][..], &["R", "G", "B", "A"], &["Y"]] {
            let image = gradient(5, 3, channels);
            let path = directory.join("float.exr");
            image.write_exr(&path, false).unwrap();
            let read = Image::read(&path).unwrap();
            assert_eq!(
                read.channels(),
                image.channels(),
                "channel order is canonical"
            );
            assert_eq!((read.width(), read.height()), (5, 3));
            assert_eq!(read.data(), image.data());
            assert_eq!(read.format(), PixelFormat::Float);
            assert_eq!(read.encoding(), ColorEncoding::Linear);
        }
        assert_eq!(directory.file_names(), ["float.exr"]);
    }

    #[test]
    fn exr_data_window_round_trips() {
        let directory = TestDirectory::new("exr-window");
        let path = directory.join("tile.exr");
        let tile = gradient(3, 2, &["R", "G", "B"]);
        let window = DataWindow {
            full_resolution: (10, 8),
            origin: (4, 5),
        };
        tile.write_exr_in_window(&path, false, Some(&window))
            .unwrap();
        let (read, read_window) = Image::read_exr_with_window(&path).unwrap();
        assert_eq!(read, tile);
        assert_eq!(read_window, window);
        // A plain write is its own whole image.
        tile.write_exr(&path, false).unwrap();
        let (_, whole) = Image::read_exr_with_window(&path).unwrap();
        assert_eq!(whole, DataWindow::whole(3, 2));
    }

    #[test]
    fn exr_half_round_trip_is_within_half_precision() {
        let directory = TestDirectory::new("exr-half");
        let image = gradient(7, 4, &["R", "G", "B"]);
        let path = directory.join("half.EXR");
        image.write(&path).unwrap(); // `.exr` means half by default
        let read = Image::read(&path).unwrap();
        assert_eq!(read.format(), PixelFormat::Half);
        assert_eq!(read.channels(), ["R", "G", "B"]);
        for (&written, &back) in image.data().iter().zip(read.data()) {
            // Half floats keep 11 significant bits: relative error ≤ 2⁻¹¹.
            assert!(
                (back - written).abs() <= written.abs() * 4.9e-4,
                "{written} → {back}"
            );
        }
        // Values a half represents exactly come back exactly.
        let exact = Image::new(2, 1, &["Y"], vec![0.5, 1024.0]).unwrap();
        exact.write(&path).unwrap();
        assert_eq!(Image::read(&path).unwrap().data(), [0.5, 1024.0]);
    }

    #[test]
    fn half_exrs_clamp_values_beyond_the_half_range() {
        let directory = TestDirectory::new("exr-half-clamp");
        let path = directory.join("bright.exr");
        let bright = Image::new(4, 1, &["Y"], vec![1e6, -3e5, 65519.0, 2.0]).unwrap();
        bright.write_exr(&path, true).unwrap();
        assert_eq!(
            Image::read(&path).unwrap().data(),
            [65504.0, -65504.0, 65504.0, 2.0]
        );
        // 32-bit floats keep them.
        bright.write_exr(&path, false).unwrap();
        assert_eq!(Image::read(&path).unwrap().data(), bright.data());
    }

    #[test]
    fn pfm_round_trip_is_exact_and_keeps_orientation() {
        let directory = TestDirectory::new("pfm");
        let path = directory.join("image.pfm");
        let rgb = gradient(4, 3, &["R", "G", "B"]);
        rgb.write(&path).unwrap();
        assert_eq!(Image::read(&path).unwrap(), rgb);
        let grey = gradient(3, 5, &["Y"]);
        grey.write(&path).unwrap();
        assert_eq!(Image::read(&path).unwrap(), grey);

        // The file's first row of pixels is the image's bottom row.
        let top_bright = Image::new(1, 2, &["Y"], vec![1.0, 0.0]).unwrap();
        top_bright.write(&path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let pixels = &bytes[bytes.len() - 8..];
        assert_eq!(
            pixels,
            [0.0f32.to_le_bytes(), 1.0f32.to_le_bytes()].concat()
        );
        assert!(bytes.starts_with(b"Pf\n1 2\n-1\n"));
    }

    #[test]
    fn png_round_trip_is_within_8bit_quantisation() {
        let directory = TestDirectory::new("png");
        let path = directory.join("image.png");
        let image = gradient(6, 5, &["R", "G", "B"]);
        image.write(&path).unwrap();
        let read = Image::read(&path).unwrap();
        assert_eq!(read.channels(), ["R", "G", "B"]);
        assert_eq!(
            (read.encoding(), read.format()),
            (ColorEncoding::Srgb, PixelFormat::U8)
        );
        for (&linear, &encoded) in image.data().iter().zip(read.data()) {
            let code = (encoded * 255.0).round();
            assert_eq!(code / 255.0, encoded, "8-bit codes are kept exactly");
            assert_eq!(
                code as u8,
                linear_to_srgb8(linear),
                "nearest sRGB code of {linear}"
            );
            let decoded = srgb_to_linear(encoded);
            // Within half a code step of the clamped original.
            let clamped = linear.min(1.0);
            let step = srgb_to_linear((code + 0.5).min(255.0) / 255.0)
                - srgb_to_linear((code - 0.5).max(0.0) / 255.0);
            assert!((decoded - clamped).abs() <= step, "{linear} → {decoded}");
        }
        // Reading keeps the codes, so writing again reproduces the file.
        let again = directory.join("again.png");
        read.write(&again).unwrap();
        assert_eq!(Image::read(&again).unwrap(), read);

        let grey = gradient(3, 2, &["Y"]);
        grey.write(&path).unwrap();
        let read = Image::read(&path).unwrap();
        assert_eq!(read.channels(), ["Y"]);
        assert_eq!(read.to_linear().data().len(), 6);
    }

    #[test]
    fn refuses_non_finite_values_and_writes_nothing() {
        let directory = TestDirectory::new("nan");
        let mut image = gradient(4, 3, &["R", "G", "B"]);
        image.data_mut()[(4 + 2) * 3 + 1] = f32::NAN; // pixel (2, 1), channel G
        image.data_mut()[(2 * 4 + 3) * 3] = f32::INFINITY; // later in row-major order
        for name in ["bad.exr", "bad.pfm", "bad.png"] {
            let path = directory.join(name);
            let error = image.write(&path).unwrap_err();
            let ImageError::NonFinite { sample, .. } = &error else {
                panic!("expected a non-finite error, got {error}");
            };
            assert_eq!((sample.x, sample.y, sample.channel.as_str()), (2, 1, "G"));
            let message = error.to_string();
            assert!(
                message.contains(name) && message.contains("(2, 1)"),
                "{message}"
            );
        }
        let mut infinite = gradient(2, 2, &["Y"]);
        infinite.data_mut()[1] = f32::NEG_INFINITY;
        assert!(matches!(
            infinite.write_exr(directory.join("inf.exr"), false),
            Err(ImageError::NonFinite { .. })
        ));
        assert!(
            directory.file_names().is_empty(),
            "{:?}",
            directory.file_names()
        );
    }

    #[test]
    fn failed_write_removes_its_temporary_file() {
        let directory = TestDirectory::new("unwritable");
        let path = directory.join("two.png");
        let two_channels = gradient(2, 2, &["Y", "A"]);
        assert!(matches!(
            two_channels.write(&path),
            Err(ImageError::Unwritable { .. })
        ));
        assert!(matches!(
            two_channels.write(directory.join("two.pfm")),
            Err(ImageError::Unwritable { .. })
        ));
        assert!(
            directory.file_names().is_empty(),
            "{:?}",
            directory.file_names()
        );
    }

    #[test]
    fn errors_name_the_file() {
        let directory = TestDirectory::new("errors");
        let missing = directory.join("missing.exr");
        let error = Image::read(&missing).unwrap_err();
        assert!(
            matches!(error, ImageError::Io { .. }) && error.to_string().contains("missing.exr")
        );
        let garbage = directory.join("garbage.png");
        std::fs::write(&garbage, b"not a png at all").unwrap();
        let error = Image::read(&garbage).unwrap_err();
        assert!(
            matches!(error, ImageError::Malformed { .. })
                && error.to_string().contains("garbage.png")
        );
        let garbage_exr = directory.join("garbage.exr");
        std::fs::write(&garbage_exr, b"nope").unwrap();
        assert!(matches!(
            Image::read(&garbage_exr),
            Err(ImageError::Malformed { .. })
        ));
        let unknown = directory.join("picture.gif");
        let error = Image::read(&unknown).unwrap_err();
        assert!(matches!(error, ImageError::UnsupportedExtension { .. }));
        assert!(error.to_string().contains("picture.gif"));
        assert!(matches!(
            gradient(1, 1, &["Y"]).write(&unknown),
            Err(ImageError::UnsupportedExtension { .. })
        ));
    }

    #[test]
    fn reads_tga_and_drops_alpha_like_pbrt() {
        let directory = TestDirectory::new("tga");
        let path = directory.join("image.tga");
        let rgba: Vec<u8> = vec![
            255, 0, 0, 10, 0, 255, 0, 20, 0, 0, 255, 30, 128, 128, 128, 255,
        ];
        ::image::save_buffer_with_format(
            &path,
            &rgba,
            2,
            2,
            ::image::ExtendedColorType::Rgba8,
            ImageFormat::Tga,
        )
        .unwrap();
        let image = Image::read(&path).unwrap();
        assert_eq!(image.channels(), ["R", "G", "B"]);
        assert_eq!(image.pixel(1, 1), [128.0 / 255.0; 3]);
        assert_eq!(image.pixel(0, 0), [1.0, 0.0, 0.0]);

        // PNG keeps alpha.
        let png = directory.join("image.png");
        ::image::save_buffer_with_format(
            &png,
            &rgba,
            2,
            2,
            ::image::ExtendedColorType::Rgba8,
            ImageFormat::Png,
        )
        .unwrap();
        let image = Image::read(&png).unwrap();
        assert_eq!(image.channels(), ["R", "G", "B", "A"]);
        assert_eq!(image.pixel(1, 0)[3], 20.0 / 255.0);
    }

    #[test]
    fn reads_16bit_png_as_encoded_half_precision() {
        let directory = TestDirectory::new("png16");
        let path = directory.join("deep.png");
        let codes: [u16; 2] = [0, 65535];
        let bytes: Vec<u8> = codes.iter().flat_map(|code| code.to_ne_bytes()).collect();
        ::image::save_buffer_with_format(
            &path,
            &bytes,
            2,
            1,
            ::image::ExtendedColorType::L16,
            ImageFormat::Png,
        )
        .unwrap();
        let image = Image::read(&path).unwrap();
        assert_eq!(image.format(), PixelFormat::Half);
        assert_eq!(image.encoding(), ColorEncoding::Srgb);
        assert_eq!(image.data(), [0.0, 1.0]);
    }
}
