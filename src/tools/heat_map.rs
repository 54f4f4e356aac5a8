//! False-colour pictures of per-pixel values (error maps), and the helper
//! that makes display-encoded (sRGB) images for the tools' PNG output.

use crate::image::{ColorEncoding, Image, ImageError, PixelFormat};

/// Display colours (sRGB, 0–1) the ramp passes through at 0, ¼, ½, ¾ and 1:
/// black, blue, magenta, orange, light yellow — dark for small errors, and
/// monotonic in brightness so it survives greyscale printing.
const RAMP: [[f32; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [0.15, 0.1, 0.6],
    [0.75, 0.15, 0.55],
    [1.0, 0.55, 0.1],
    [1.0, 1.0, 0.75],
];

/// The ramp's colour for `t` in [0, 1] (clamped).
pub fn false_colour(t: f64) -> [f32; 3] {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        1.0
    } as f32;
    let x = t * (RAMP.len() - 1) as f32;
    let i = (x.floor() as usize).min(RAMP.len() - 2);
    let f = x - i as f32;
    let (a, b) = (RAMP[i], RAMP[i + 1]);
    [0, 1, 2].map(|c| a[c] + (b[c] - a[c]) * f)
}

/// A `width` × `height` heat map of `values` (row-major), 0 black and
/// `scale` (or more) the ramp's end.
pub fn heat_map(values: &[f64], width: u32, height: u32, scale: f64) -> Result<Image, ImageError> {
    let scale = if scale > 0.0 { scale } else { 1.0 };
    let data = values
        .iter()
        .flat_map(|&v| false_colour(v / scale))
        .collect();
    display_image(width, height, data)
}

/// An RGB image of display (sRGB-encoded, 0–1) values, written to PNG as
/// they are.
pub fn display_image(width: u32, height: u32, data: Vec<f32>) -> Result<Image, ImageError> {
    Image::from_parts(
        width,
        height,
        vec!["R".into(), "G".into(), "B".into()],
        data,
        ColorEncoding::Srgb,
        PixelFormat::U8,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_ends_and_brightness_grows() {
        assert_eq!(false_colour(0.0), [0.0; 3]);
        assert_eq!(false_colour(2.0), RAMP[4]);
        assert_eq!(false_colour(f64::NAN), RAMP[4]);
        let brightness = |c: [f32; 3]| c[0] + c[1] + c[2];
        let mut last = -1.0;
        for i in 0..=20 {
            let b = brightness(false_colour(i as f64 / 20.0));
            assert!(b > last, "{i}");
            last = b;
        }
    }
}
