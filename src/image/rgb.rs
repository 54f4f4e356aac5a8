//! RGB views of images, for the renderer and the comparison tools.

use super::{ColorEncoding, Image, ImageError};

impl Image {
    /// A linear RGB image from interleaved values.
    pub fn from_rgb(width: u32, height: u32, data: Vec<f32>) -> Result<Image, ImageError> {
        Image::new(width, height, &["R", "G", "B"], data)
    }

    /// The linear R, G, B values, interleaved (a single-channel image is
    /// repeated in all three); empty if the image has neither.
    pub fn rgb_data(&self) -> Vec<f32> {
        let linear = self.to_linear();
        if let Some(rgb) = linear.select_channels(&["R", "G", "B"]) {
            return rgb.into_data();
        }
        if linear.channel_count() == 1 {
            return linear.data().iter().flat_map(|&v| [v, v, v]).collect();
        }
        Vec::new()
    }

    /// [`Image::rgb_data`], taking the image: a linear image of exactly R,
    /// G and B gives up its own samples rather than a copy of them.
    pub fn into_rgb_data(self) -> Vec<f32> {
        if matches!(self.encoding(), ColorEncoding::Linear) && self.channels() == ["R", "G", "B"] {
            return self.into_data();
        }
        self.rgb_data()
    }
}
