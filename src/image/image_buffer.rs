//! The in-memory image: size, named channels and interleaved `f32` samples.

use super::{ColorEncoding, ImageError, PixelFormat, WrapMode};
use glam::{IVec2, Vec2};

/// A rectangular image with named channels (`["R","G","B"]`,
/// `["R","G","B","A"]`, `["Y"]`, ...).
///
/// Samples are interleaved, row-major, top row first. They are linear light
/// when [`encoding`](Image::encoding) is [`ColorEncoding::Linear`];
/// otherwise they are encoded values in [0, 1] (an 8-bit code k is stored as
/// k/255), kept as the file had them so the caller can choose the decoding
/// (pbrt-v4's `encoding` texture parameter) before calling
/// [`to_linear`](Image::to_linear).
///
/// Invariants: width and height are at least 1, there is at least one
/// channel, and `data.len() == width * height * channels`.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    width: u32,
    height: u32,
    channels: Vec<String>,
    data: Vec<f32>,
    encoding: ColorEncoding,
    format: PixelFormat,
}

/// A NaN or infinite sample found in an image, and where.
#[derive(Clone, Debug, PartialEq)]
pub struct NonFiniteSample {
    pub x: u32,
    pub y: u32,
    pub channel: String,
    pub value: f32,
}

impl Image {
    /// A linear, 32-bit float image from interleaved samples.
    pub fn new(
        width: u32,
        height: u32,
        channels: &[&str],
        data: Vec<f32>,
    ) -> Result<Image, ImageError> {
        let channels = channels.iter().map(|name| name.to_string()).collect();
        Image::from_parts(
            width,
            height,
            channels,
            data,
            ColorEncoding::Linear,
            PixelFormat::Float,
        )
    }

    /// An image from all its parts, checking the invariants.
    pub fn from_parts(
        width: u32,
        height: u32,
        channels: Vec<String>,
        data: Vec<f32>,
        encoding: ColorEncoding,
        format: PixelFormat,
    ) -> Result<Image, ImageError> {
        if width == 0 || height == 0 {
            return Err(ImageError::Invalid(format!(
                "empty resolution {width}×{height}"
            )));
        }
        if channels.is_empty() {
            return Err(ImageError::Invalid("no channels".into()));
        }
        let expected = (width as usize)
            .checked_mul(height as usize)
            .and_then(|pixels| pixels.checked_mul(channels.len()));
        if expected != Some(data.len()) {
            return Err(ImageError::Invalid(format!(
                "{width}×{height} pixels of {} channels need {} samples, got {}",
                channels.len(),
                expected.map_or("too many".to_string(), |n| n.to_string()),
                data.len()
            )));
        }
        Ok(Image {
            width,
            height,
            channels,
            data,
            encoding,
            format,
        })
    }

    /// A constant image (every pixel `values`, one per channel).
    pub fn filled(
        width: u32,
        height: u32,
        channels: &[&str],
        values: &[f32],
    ) -> Result<Image, ImageError> {
        if values.len() != channels.len() {
            return Err(ImageError::Invalid(format!(
                "{} fill values for {} channels",
                values.len(),
                channels.len()
            )));
        }
        let pixels = width as usize * height as usize;
        let data = values
            .iter()
            .copied()
            .cycle()
            .take(pixels * values.len())
            .collect();
        Image::new(width, height, channels, data)
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// (width, height) as the signed vector texel arithmetic uses.
    pub fn resolution(&self) -> IVec2 {
        IVec2::new(self.width as i32, self.height as i32)
    }

    pub fn channels(&self) -> &[String] {
        &self.channels
    }

    pub fn channel_count(&self) -> usize {
        self.channels.len()
    }

    /// Index of the channel called `name`.
    pub fn channel_index(&self, name: &str) -> Option<usize> {
        self.channels.iter().position(|channel| channel == name)
    }

    /// All samples, interleaved, row-major, top row first.
    pub fn data(&self) -> &[f32] {
        &self.data
    }

    pub fn data_mut(&mut self) -> &mut [f32] {
        &mut self.data
    }

    pub fn into_data(self) -> Vec<f32> {
        self.data
    }

    pub fn encoding(&self) -> ColorEncoding {
        self.encoding
    }

    pub fn format(&self) -> PixelFormat {
        self.format
    }

    /// The same samples, declared to be in another encoding (for example an
    /// 8-bit texture the scene marks `"linear"`). Values are not changed.
    pub fn with_encoding(mut self, encoding: ColorEncoding) -> Image {
        self.encoding = encoding;
        self
    }

    /// The same samples, declared to come from storage of another precision
    /// (this decides how MIP levels are rounded). Values are not changed.
    pub fn with_format(mut self, format: PixelFormat) -> Image {
        self.format = format;
        self
    }

    /// The image decoded to linear light (a copy; the format is kept, as it
    /// still describes the precision the values came from).
    pub fn to_linear(&self) -> Image {
        let encoding = self.encoding;
        let data = match encoding {
            ColorEncoding::Linear => self.data.clone(),
            _ => self
                .data
                .iter()
                .map(|&stored| encoding.to_linear(stored))
                .collect(),
        };
        Image {
            data,
            encoding: ColorEncoding::Linear,
            ..self.clone_without_data()
        }
    }

    /// The named channels, in the order asked for; `None` if one is missing.
    pub fn select_channels(&self, names: &[&str]) -> Option<Image> {
        let indices: Vec<usize> = names
            .iter()
            .map(|name| self.channel_index(name))
            .collect::<Option<_>>()?;
        if indices.iter().copied().eq(0..self.channel_count()) {
            return Some(self.clone());
        }
        let data = self
            .data
            .chunks_exact(self.channel_count())
            .flat_map(|pixel| indices.iter().map(move |&index| pixel[index]))
            .collect();
        Some(Image {
            channels: names.iter().map(|name| name.to_string()).collect(),
            data,
            ..self.clone_without_data()
        })
    }

    /// Offset of channel 0 of pixel `p` (which must be inside).
    #[inline]
    fn pixel_offset(&self, p: IVec2) -> usize {
        (p.y as usize * self.width as usize + p.x as usize) * self.channels.len()
    }

    /// The stored (possibly encoded) samples of pixel (x, y).
    ///
    /// Panics if the pixel is outside the image (a caller bug: use
    /// [`channel`](Image::channel) for coordinates that may be outside).
    pub fn pixel(&self, x: u32, y: u32) -> &[f32] {
        let offset = self.pixel_offset(IVec2::new(x as i32, y as i32));
        &self.data[offset..offset + self.channels.len()]
    }

    /// Linear value of `channel` at texel `p`, which may lie outside the
    /// image: `wrap` decides what is there. This decodes on every call; for
    /// many lookups into an encoded image, convert it with
    /// [`to_linear`](Image::to_linear) first.
    #[inline]
    pub fn channel(&self, p: IVec2, channel: usize, wrap: WrapMode) -> f32 {
        debug_assert!(
            channel < self.channels.len(),
            "channel {channel} of {:?}",
            self.channels
        );
        let Some(p) = wrap.remap(p, self.resolution()) else {
            return 0.0;
        };
        let stored = self
            .data
            .get(self.pixel_offset(p) + channel)
            .copied()
            .unwrap_or(0.0);
        self.encoding.to_linear(stored)
    }

    /// Bilinear interpolation of `channel` at continuous coordinates `st`
    /// ∈ [0, 1]² (beyond is handled by `wrap`). Texel (i, j) has its centre
    /// at ((i + ½)/width, (j + ½)/height), as in pbrt-v4.
    pub fn bilerp_channel(&self, st: Vec2, channel: usize, wrap: WrapMode) -> f32 {
        let x = st.x * self.width as f32 - 0.5;
        let y = st.y * self.height as f32 - 0.5;
        let (x_floor, y_floor) = (x.floor(), y.floor());
        let (dx, dy) = (x - x_floor, y - y_floor);
        // `as` saturates (and maps NaN to 0), so wild coordinates stay safe.
        let (xi, yi) = (x_floor as i32, y_floor as i32);
        let texel = |offset_x: i32, offset_y: i32| {
            self.channel(
                IVec2::new(xi.saturating_add(offset_x), yi.saturating_add(offset_y)),
                channel,
                wrap,
            )
        };
        (1.0 - dx) * (1.0 - dy) * texel(0, 0)
            + dx * (1.0 - dy) * texel(1, 0)
            + (1.0 - dx) * dy * texel(0, 1)
            + dx * dy * texel(1, 1)
    }

    /// The first NaN or infinite sample in row-major order, if any.
    pub fn first_non_finite(&self) -> Option<NonFiniteSample> {
        let index = self.data.iter().position(|value| !value.is_finite())?;
        let channel_count = self.channels.len();
        let pixel = index / channel_count;
        Some(NonFiniteSample {
            x: (pixel % self.width as usize) as u32,
            y: (pixel / self.width as usize) as u32,
            channel: self.channels[index % channel_count].clone(),
            value: self.data[index],
        })
    }

    /// A copy of everything but the samples (to rebuild with new samples).
    fn clone_without_data(&self) -> Image {
        Image {
            width: self.width,
            height: self.height,
            channels: self.channels.clone(),
            data: Vec::new(),
            encoding: self.encoding,
            format: self.format,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constructor_checks_sizes() {
        assert!(Image::new(2, 2, &["R", "G", "B"], vec![0.0; 12]).is_ok());
        assert!(matches!(
            Image::new(2, 2, &["R", "G", "B"], vec![0.0; 11]),
            Err(ImageError::Invalid(_))
        ));
        assert!(matches!(
            Image::new(0, 2, &["Y"], vec![]),
            Err(ImageError::Invalid(_))
        ));
        assert!(matches!(
            Image::new(1, 1, &[], vec![]),
            Err(ImageError::Invalid(_))
        ));
    }

    #[test]
    fn selects_and_reorders_channels() {
        let image = Image::new(2, 1, &["B", "G", "R"], vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]).unwrap();
        let rgb = image.select_channels(&["R", "G", "B"]).unwrap();
        assert_eq!(rgb.channels(), ["R", "G", "B"]);
        assert_eq!(rgb.data(), [3.0, 2.0, 1.0, 6.0, 5.0, 4.0]);
        assert!(image.select_channels(&["A"]).is_none());
    }

    #[test]
    fn to_linear_decodes_srgb() {
        let image = Image::new(1, 1, &["Y"], vec![128.0 / 255.0])
            .unwrap()
            .with_encoding(ColorEncoding::Srgb);
        assert!((image.channel(IVec2::ZERO, 0, WrapMode::Clamp) - 0.215_860_5).abs() < 1e-6);
        let linear = image.to_linear();
        assert_eq!(linear.encoding(), ColorEncoding::Linear);
        assert!((linear.data()[0] - 0.215_860_5).abs() < 1e-6);
    }

    /// 2×2 checker [[0, 1], [1, 0]]: texel centres give the texels, the
    /// midpoints between two texels of different value give ½.
    #[test]
    fn bilinear_interpolation_has_texel_centres_at_half_integers() {
        let checker = Image::new(2, 2, &["Y"], vec![0.0, 1.0, 1.0, 0.0]).unwrap();
        let at = |s: f32, t: f32, wrap| checker.bilerp_channel(Vec2::new(s, t), 0, wrap);
        for wrap in [WrapMode::Clamp, WrapMode::Repeat, WrapMode::Black] {
            assert_eq!(at(0.25, 0.25, wrap), 0.0);
            assert_eq!(at(0.75, 0.25, wrap), 1.0);
            assert_eq!(at(0.25, 0.75, wrap), 1.0);
            assert_eq!(at(0.75, 0.75, wrap), 0.0);
            assert_eq!(at(0.5, 0.25, wrap), 0.5);
            assert_eq!(at(0.25, 0.5, wrap), 0.5);
            assert_eq!(at(0.5, 0.5, wrap), 0.5);
            assert!((at(0.375, 0.25, wrap) - 0.25).abs() < 1e-6);
        }
        // On the left edge, half of the weight lies outside the image.
        assert_eq!(at(0.0, 0.25, WrapMode::Clamp), 0.0);
        assert_eq!(at(0.0, 0.25, WrapMode::Repeat), 0.5);
        assert_eq!(at(0.0, 0.75, WrapMode::Black), 0.5);
        assert_eq!(at(0.0, 0.75, WrapMode::Clamp), 1.0);
        // Non-finite coordinates neither panic nor index out of bounds.
        let _ = at(f32::NAN, f32::INFINITY, WrapMode::Repeat);
        let _ = at(f32::NEG_INFINITY, f32::NAN, WrapMode::OctahedralSphere);
        assert!(at(-1e30, 1e30, WrapMode::OctahedralSphere).is_finite());
    }

    #[test]
    fn finds_the_first_non_finite_sample() {
        let mut image = Image::filled(3, 2, &["R", "G", "B"], &[0.5, 0.5, 0.5]).unwrap();
        assert_eq!(image.first_non_finite(), None);
        image.data_mut()[3 * 4 + 2] = f32::INFINITY; // pixel (1, 1), B
        image.data_mut()[3 * 5] = f32::NAN; // later
        let bad = image.first_non_finite().unwrap();
        assert_eq!((bad.x, bad.y, bad.channel.as_str()), (1, 1, "B"));
        assert_eq!(bad.value, f32::INFINITY);
    }
}
