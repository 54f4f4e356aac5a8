//! Enlarging an image to power-of-two resolution, as pbrt-v4 does before
//! building a MIP map.
//!
//! A power-of-two base makes every pyramid level exactly half the previous
//! one. pbrt-v4 gets there by resampling with a Lanczos-windowed sinc
//! (radius 2 texels, window τ = 2): each output texel takes four input
//! texels per axis, with weights normalised to sum to one, and the result is
//! clamped to be non-negative (the sinc's negative lobes can ring below zero
//! at sharp edges). Texels outside the input follow the wrap mode, so a
//! tiling texture resamples seamlessly.

use super::{ColorEncoding, Image, ImageError, WrapMode};
use glam::IVec2;
use rayon::prelude::*;
use std::f32::consts::PI;

/// Where one output texel's four input texels start, and their weights.
#[derive(Clone, Copy, Debug)]
struct ResampleWeights {
    first_texel: i32,
    weights: [f32; 4],
}

/// sin(x)/x, exactly 1 where the quotient would round to it anyway.
fn sin_x_over_x(x: f32) -> f32 {
    if 1.0 + x * x == 1.0 {
        1.0
    } else {
        x.sin() / x
    }
}

fn sinc(x: f32) -> f32 {
    sin_x_over_x(PI * x)
}

/// The sinc, windowed by a wider sinc (Lanczos), zero beyond `radius`.
fn windowed_sinc(x: f32, radius: f32, tau: f32) -> f32 {
    if x.abs() > radius {
        return 0.0;
    }
    sinc(x) * sinc(x / tau)
}

/// Weights taking `old_resolution` texels to `new_resolution` (≥ old).
fn resample_weights(old_resolution: u32, new_resolution: u32) -> Vec<ResampleWeights> {
    const FILTER_RADIUS: f32 = 2.0;
    const WINDOW_TAU: f32 = 2.0;
    (0..new_resolution)
        .map(|i| {
            let centre = (i as f32 + 0.5) * old_resolution as f32 / new_resolution as f32;
            let first_texel = ((centre - FILTER_RADIUS) + 0.5).floor() as i32;
            let mut weights = [0.0f32; 4];
            for (j, weight) in weights.iter_mut().enumerate() {
                let position = first_texel as f32 + j as f32 + 0.5;
                *weight = windowed_sinc(position - centre, FILTER_RADIUS, WINDOW_TAU);
            }
            let inverse_sum = 1.0 / weights.iter().sum::<f32>();
            for weight in &mut weights {
                *weight *= inverse_sum;
            }
            ResampleWeights {
                first_texel,
                weights,
            }
        })
        .collect()
}

/// The image enlarged to the next power of two in each dimension (a copy
/// when it already is one). `image` must be linear.
pub(crate) fn resize_to_power_of_two(image: &Image, wrap: WrapMode) -> Result<Image, ImageError> {
    debug_assert_eq!(image.encoding(), ColorEncoding::Linear);
    let too_large = || {
        ImageError::Invalid(format!(
            "{}×{} is too large to enlarge to a power of two",
            image.width(),
            image.height()
        ))
    };
    let new_width = image
        .width()
        .checked_next_power_of_two()
        .ok_or_else(too_large)?;
    let new_height = image
        .height()
        .checked_next_power_of_two()
        .ok_or_else(too_large)?;
    if (new_width, new_height) == (image.width(), image.height()) {
        return Ok(image.clone());
    }
    let x_weights = resample_weights(image.width(), new_width);
    let y_weights = resample_weights(image.height(), new_height);
    let channel_count = image.channel_count();
    let resolution = image.resolution();
    let source = image.data();
    let source_texel = |x: i32, y: i32, channel: usize| -> f32 {
        match wrap.remap(IVec2::new(x, y), resolution) {
            Some(p) => {
                source[(p.y as usize * resolution.x as usize + p.x as usize) * channel_count
                    + channel]
            }
            None => 0.0,
        }
    };

    let mut data = vec![0.0f32; new_width as usize * new_height as usize * channel_count];
    data.par_chunks_mut(new_width as usize * channel_count)
        .zip(y_weights.par_iter())
        .for_each(|(row, y_weight)| {
            for (x_weight, pixel) in x_weights.iter().zip(row.chunks_exact_mut(channel_count)) {
                for (channel, value) in pixel.iter_mut().enumerate() {
                    let mut sum = 0.0;
                    for (k, &wy) in y_weight.weights.iter().enumerate() {
                        let y = y_weight.first_texel + k as i32;
                        // Filter along x first, then y, as pbrt-v4 does.
                        let row_sum: f32 = x_weight
                            .weights
                            .iter()
                            .enumerate()
                            .map(|(j, &wx)| {
                                wx * source_texel(x_weight.first_texel + j as i32, y, channel)
                            })
                            .sum();
                        sum += wy * row_sum;
                    }
                    *value = sum.max(0.0);
                }
            }
        });
    Image::from_parts(
        new_width,
        new_height,
        image.channels().to_vec(),
        data,
        ColorEncoding::Linear,
        image.format(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_are_normalised_and_centred() {
        for (old, new) in [(3, 4), (5, 8), (100, 128), (7, 7)] {
            for weights in resample_weights(old, new) {
                assert!((weights.weights.iter().sum::<f32>() - 1.0).abs() < 1e-5);
            }
        }
        // Same resolution: the filter reproduces each texel exactly.
        for (i, weights) in resample_weights(4, 4).iter().enumerate() {
            assert_eq!(weights.first_texel, i as i32 - 1);
            assert!((weights.weights[1] - 1.0).abs() < 1e-6, "{weights:?}");
        }
    }

    #[test]
    fn constant_images_stay_constant() {
        let image = Image::filled(3, 5, &["R", "G", "B"], &[0.25, 1.0, 3.0]).unwrap();
        for wrap in [
            WrapMode::Clamp,
            WrapMode::Repeat,
            WrapMode::OctahedralSphere,
        ] {
            let resized = resize_to_power_of_two(&image, wrap).unwrap();
            assert_eq!((resized.width(), resized.height()), (4, 8));
            for pixel in resized.data().chunks_exact(3) {
                for (value, expected) in pixel.iter().zip([0.25, 1.0, 3.0]) {
                    assert!(
                        (value - expected).abs() < 1e-5 * expected,
                        "{value} vs {expected}"
                    );
                }
            }
        }
    }

    #[test]
    fn ringing_is_clamped_to_zero() {
        // A spike on a background of 1: the sinc's negative lobes undershoot
        // below zero beside it, so only the clamp can produce a zero.
        let mut data = vec![1.0; 9];
        data[4] = 100.0;
        let image = Image::new(9, 1, &["Y"], data).unwrap();
        let resized = resize_to_power_of_two(&image, WrapMode::Clamp).unwrap();
        assert_eq!((resized.width(), resized.height()), (16, 1));
        assert!(resized.data().iter().all(|&value| value >= 0.0));
        assert!(
            resized.data().iter().any(|&value| value == 0.0),
            "{:?}",
            resized.data()
        );
        assert!(resized.data().iter().cloned().fold(0.0, f32::max) > 50.0);
    }
}
