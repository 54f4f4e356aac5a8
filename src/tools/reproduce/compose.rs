//! Labelled side-by-side comparison images: rendered panels (linear RGB)
//! tone-mapped with one exposure for the whole figure, so brightness can be
//! compared across panels, joined left to right with a caption strip under
//! each. Text is drawn with the public-domain 8 × 8 bitmap font of the
//! `font8x8` crate, scaled up.

use crate::image::color_encoding::linear_to_srgb;
use crate::image::{ColorEncoding, Image, ImageError, PixelFormat};
use font8x8::UnicodeFonts;

/// Pixels between panels.
const GAP: usize = 6;
/// The title is drawn at twice the font's 8 × 8 pixels, captions at its size.
const TITLE_SCALE: usize = 2;
const CAPTION_SCALE: usize = 1;
/// Height of the title line and of a caption line.
const LINE: usize = 8 * TITLE_SCALE + 4;
const CAPTION_LINE: usize = 8 * CAPTION_SCALE + 3;

/// One panel: its linear RGB pixels and the caption lines under it.
pub struct Panel<'a> {
    pub width: usize,
    pub height: usize,
    /// Linear RGB, row-major, 3 floats per pixel.
    pub rgb: &'a [f32],
    pub caption: Vec<String>,
}

/// An sRGB canvas being drawn on (encoded values in [0, 1]).
struct Canvas {
    width: usize,
    height: usize,
    data: Vec<f32>,
}

impl Canvas {
    fn set(&mut self, x: usize, y: usize, colour: [f32; 3]) {
        if x < self.width && y < self.height {
            let i = (y * self.width + x) * 3;
            self.data[i..i + 3].copy_from_slice(&colour);
        }
    }

    /// `text` with its top-left corner at (x, y), at `scale` times the
    /// font's size; characters the font lacks are drawn as '?'.
    fn text(&mut self, x: usize, y: usize, text: &str, scale: usize, colour: [f32; 3]) {
        for (k, c) in text.chars().enumerate() {
            let rows = font8x8::BASIC_FONTS
                .get(c)
                .or_else(|| font8x8::LATIN_FONTS.get(c))
                .or_else(|| font8x8::GREEK_FONTS.get(c))
                .or_else(|| font8x8::BASIC_FONTS.get('?'))
                .unwrap_or([0; 8]);
            for (row, bits) in rows.iter().enumerate() {
                for col in 0..8 {
                    if bits & (1 << col) != 0 {
                        for dy in 0..scale {
                            for dx in 0..scale {
                                self.set(
                                    x + (k * 8 + col) * scale + dx,
                                    y + row * scale + dy,
                                    colour,
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Width in pixels of `text` drawn at `scale`.
pub fn text_width(text: &str, scale: usize) -> usize {
    text.chars().count() * 8 * scale
}

/// `text` broken at spaces into lines of at most `width` pixels at the
/// caption's size (a word longer than that gets a line of its own).
pub fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(line) if text_width(&format!("{line} {word}"), CAPTION_SCALE) <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// The panels side by side on a white background, each tone-mapped as
/// `exposure × linear` then sRGB-encoded (values above 1 clip), with its
/// caption lines under it (wrapped to its width); `title` above them all.
pub fn side_by_side(title: &str, panels: &[Panel], exposure: f32) -> Result<Image, ImageError> {
    let captions: Vec<Vec<String>> = panels
        .iter()
        .map(|p| {
            p.caption
                .iter()
                .flat_map(|line| wrap(line, p.width))
                .collect()
        })
        .collect();
    let caption_lines = captions.iter().map(Vec::len).max().unwrap_or(0);
    let panel_height = panels.iter().map(|p| p.height).max().unwrap_or(0);
    let panels_width: usize =
        panels.iter().map(|p| p.width).sum::<usize>() + GAP * (panels.len() + 1);
    let width = panels_width.max(text_width(title, TITLE_SCALE) + 2 * GAP);
    let height = LINE + GAP + panel_height + GAP + caption_lines * CAPTION_LINE + GAP;
    let mut canvas = Canvas {
        width,
        height,
        data: vec![1.0; width * height * 3],
    };
    let ink = [0.0; 3];
    canvas.text(GAP, GAP / 2, title, TITLE_SCALE, ink);
    let mut x0 = GAP;
    let top = LINE + GAP;
    for (panel, caption) in panels.iter().zip(&captions) {
        for y in 0..panel.height {
            for x in 0..panel.width {
                let i = (y * panel.width + x) * 3;
                let colour = match panel.rgb.get(i..i + 3) {
                    Some(c) => [0, 1, 2].map(|k| {
                        let v = c[k] * exposure;
                        // A NaN never reaches a PNG: shown black.
                        if v.is_finite() {
                            linear_to_srgb(v.clamp(0.0, 1.0))
                        } else {
                            0.0
                        }
                    }),
                    None => [0.0; 3],
                };
                canvas.set(x0 + x, top + y, colour);
            }
        }
        for (line, text) in caption.iter().enumerate() {
            let y = top + panel_height + GAP + line * CAPTION_LINE;
            canvas.text(x0, y, text, CAPTION_SCALE, ink);
        }
        x0 += panel.width + GAP;
    }
    Image::from_parts(
        width as u32,
        height as u32,
        vec!["R".into(), "G".into(), "B".into()],
        canvas.data,
        ColorEncoding::Srgb,
        PixelFormat::U8,
    )
}

/// The relative difference |b − a| / max(a, ε) of the two images'
/// luminances, each averaged over a 5 × 5 box first (so the panel shows
/// where the models differ rather than where the noise does), as a
/// black-to-red false colour panel (`scale` → full red).
pub fn difference_panel(width: usize, height: usize, a: &[f32], b: &[f32], scale: f32) -> Vec<f32> {
    let (la, lb) = (
        box_luminance(width, height, a),
        box_luminance(width, height, b),
    );
    la.iter()
        .zip(&lb)
        .flat_map(|(la, lb)| {
            let relative = (lb - la).abs() / la.max(1e-3);
            let t = (relative / scale).clamp(0.0, 1.0);
            [t, t * t * 0.3, 0.0]
        })
        .collect()
}

/// Luminance averaged over the 5 × 5 box around each pixel (clipped at
/// the borders).
fn box_luminance(width: usize, height: usize, rgb: &[f32]) -> Vec<f32> {
    const RADIUS: usize = 2;
    let lum: Vec<f32> = rgb.chunks_exact(3).map(luminance).collect();
    let mut out = vec![0.0; width * height];
    for y in 0..height {
        for x in 0..width {
            let (mut sum, mut n) = (0.0, 0.0);
            for yy in y.saturating_sub(RADIUS)..(y + RADIUS + 1).min(height) {
                for xx in x.saturating_sub(RADIUS)..(x + RADIUS + 1).min(width) {
                    if let Some(v) = lum.get(yy * width + xx) {
                        sum += v;
                        n += 1.0;
                    }
                }
            }
            out[y * width + x] = sum / n;
        }
    }
    out
}

/// Rec. 709 / sRGB luminance of linear RGB.
pub fn luminance(rgb: &[f32]) -> f32 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_sit_side_by_side_with_their_captions() {
        let red = [1.0, 0.0, 0.0].repeat(20 * 10);
        let blue = [0.0, 0.0, 1.0].repeat(30 * 10);
        let panels = [
            Panel {
                width: 20,
                height: 10,
                rgb: &red,
                caption: vec!["a".into()],
            },
            Panel {
                width: 30,
                height: 10,
                rgb: &blue,
                caption: vec!["b".into(), "d_diff 1".into()],
            },
        ];
        let image = side_by_side("Fig", &panels, 1.0).unwrap();
        assert_eq!(image.width() as usize, 20 + 30 + 3 * GAP);
        assert_eq!(
            image.height() as usize,
            LINE + GAP + 10 + GAP + 3 * CAPTION_LINE + GAP,
            "\"d_diff 1\" is wrapped to two lines under a 30-pixel panel"
        );
        // As 8-bit codes, as the PNG stores them.
        let at = |x: usize, y: usize| {
            let i = (y * image.width() as usize + x) * 3;
            image.data()[i..i + 3]
                .iter()
                .map(|v| (v * 255.0).round() as u8)
                .collect::<Vec<u8>>()
        };
        let top = LINE + GAP;
        assert_eq!(at(GAP, top), [255, 0, 0]);
        assert_eq!(at(GAP + 20 + GAP, top + 9), [0, 0, 255]);
        assert_eq!(at(GAP + 20, top), [255, 255, 255], "the gap is white");
        // The caption "b" has ink under the second panel.
        let caption_rows = top + 10 + GAP..top + 10 + GAP + CAPTION_LINE;
        let x_range = GAP + 20 + GAP..GAP + 20 + GAP + text_width("b", CAPTION_SCALE);
        assert!(caption_rows
            .flat_map(|y| x_range.clone().map(move |x| (x, y)))
            .any(|(x, y)| at(x, y) == [0, 0, 0]));
    }

    #[test]
    fn captions_wrap_at_spaces() {
        assert_eq!(wrap("ab cd ef", 40), ["ab cd", "ef"]);
        assert_eq!(wrap("abcdefgh", 16), ["abcdefgh"]);
    }

    #[test]
    fn exposure_scales_and_non_finite_is_black() {
        let pixels = [0.25, f32::NAN, 2.0];
        let panels = [Panel {
            width: 1,
            height: 1,
            rgb: &pixels,
            caption: vec![],
        }];
        let image = side_by_side("", &panels, 2.0).unwrap();
        let i = ((LINE + GAP) * image.width() as usize + GAP) * 3;
        let px = &image.data()[i..i + 3];
        assert!((px[0] - linear_to_srgb(0.5)).abs() < 1e-6);
        assert_eq!(px[1], 0.0);
        assert_eq!((px[2] * 255.0).round(), 255.0, "clipped at 1");
    }

    #[test]
    fn difference_is_relative_to_the_first_image() {
        // Two pixels far apart (a 1 × 7 image) so their boxes do not mix.
        let mut a = vec![0.5; 21];
        let mut b = vec![0.5; 21];
        a[..3].copy_from_slice(&[1.0; 3]);
        b[..3].copy_from_slice(&[1.1; 3]);
        let d = difference_panel(7, 1, &a, &b, 0.2);
        // The first pixel's box holds pixels 0–2: means 2/3 and 2.1/3.
        let expected = (0.1 / 3.0) / (2.0 / 3.0) / 0.2;
        assert!((d[0] - expected).abs() < 1e-5, "{d:?}");
        assert_eq!(d[6 * 3], 0.0);
    }
}
