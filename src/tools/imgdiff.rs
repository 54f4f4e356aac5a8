//! Image error metrics: those of `../shared/refs/README.md` (MRSE, block
//! bias), the plain MSE and MAE, and LDR-FLIP ([`super::flip`]).

/// A whole-image error: the mean of a per-pixel error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Metric {
    /// Mean squared error, (x − r)².
    Mse,
    /// Mean relative squared error, (x − r)² / (r² + 0.01) (pbrt-v4 imgtool's).
    Mrse,
    /// Mean absolute error, |x − r|.
    Mae,
    /// NVIDIA's LDR-FLIP, in [0, 1], at the paper's default viewing distance.
    Flip,
}

impl Metric {
    pub fn name(self) -> &'static str {
        match self {
            Metric::Mse => "MSE",
            Metric::Mrse => "MRSE",
            Metric::Mae => "MAE",
            Metric::Flip => "FLIP",
        }
    }

    /// Each pixel's error (the mean over R, G, B for the per-value metrics).
    /// `image` and `reference` are interleaved linear RGB, row-major.
    pub fn pixel_errors(
        self,
        image: &[f32],
        reference: &[f32],
        width: usize,
        height: usize,
    ) -> Vec<f64> {
        assert_eq!(image.len(), width * height * 3);
        assert_eq!(reference.len(), image.len());
        let per_value = |f: fn(f64, f64) -> f64| {
            image
                .chunks_exact(3)
                .zip(reference.chunks_exact(3))
                .map(|(x, r)| (0..3).map(|c| f(x[c] as f64, r[c] as f64)).sum::<f64>() / 3.0)
                .collect()
        };
        match self {
            Metric::Mse => per_value(|x, r| (x - r) * (x - r)),
            Metric::Mrse => per_value(relative_squared_error),
            Metric::Mae => per_value(|x, r| (x - r).abs()),
            Metric::Flip => super::flip::flip_map(
                image,
                reference,
                width,
                height,
                super::flip::DEFAULT_PIXELS_PER_DEGREE,
            )
            .into_iter()
            .map(f64::from)
            .collect(),
        }
    }

    /// The image's error: the mean of [`Metric::pixel_errors`].
    pub fn mean(self, image: &[f32], reference: &[f32], width: usize, height: usize) -> f64 {
        let errors = self.pixel_errors(image, reference, width, height);
        errors.iter().sum::<f64>() / errors.len().max(1) as f64
    }
}

fn relative_squared_error(x: f64, r: f64) -> f64 {
    (x - r) * (x - r) / (r * r + 0.01)
}

/// MRSE (pbrt-v4 imgtool's): mean over pixels and channels of
/// (x − r)² / (r² + 0.01).
pub fn mrse(image: &[f32], reference: &[f32]) -> f64 {
    assert_eq!(image.len(), reference.len());
    let sum: f64 = image
        .iter()
        .zip(reference)
        .map(|(&x, &r)| relative_squared_error(x as f64, r as f64))
        .sum();
    sum / image.len().max(1) as f64
}

/// Block bias: both images averaged over `block` × `block` pixel blocks per
/// channel; mean over blocks and channels of |x̄ − r̄| / (r̄ + 0.01).
/// `channels`-interleaved, row-major; partial blocks at the edges count.
pub fn block_bias(
    image: &[f32],
    reference: &[f32],
    width: usize,
    height: usize,
    channels: usize,
    block: usize,
) -> f64 {
    assert_eq!(image.len(), width * height * channels);
    assert_eq!(reference.len(), image.len());
    let mut total = 0.0;
    let mut count = 0usize;
    for by in (0..height).step_by(block) {
        for bx in (0..width).step_by(block) {
            for c in 0..channels {
                let (mut sx, mut sr, mut n) = (0.0f64, 0.0f64, 0usize);
                for y in by..(by + block).min(height) {
                    for x in bx..(bx + block).min(width) {
                        let i = (y * width + x) * channels + c;
                        sx += image[i] as f64;
                        sr += reference[i] as f64;
                        n += 1;
                    }
                }
                let (mx, mr) = (sx / n as f64, sr / n as f64);
                total += (mx - mr).abs() / (mr + 0.01);
                count += 1;
            }
        }
    }
    total / count.max(1) as f64
}

/// How many samples above `sample_value` an image of `spp` samples per
/// pixel holds, judged against `reference` (RGB-interleaved): one sample of
/// value S lifts its pixel's mean by S/spp, so the pixels whose mean RGB
/// exceeds the reference's by more than `sample_value / spp` are counted.
/// Counted both ways between two renders at equal spp (each as the other's
/// reference), this compares the tails of their sample distributions, which
/// MRSE at low spp sees only by the luck of a few samples.
pub fn bright_samples(image: &[f32], reference: &[f32], spp: u32, sample_value: f64) -> usize {
    assert_eq!(image.len(), reference.len());
    let threshold = 3.0 * sample_value / spp as f64;
    image
        .chunks_exact(3)
        .zip(reference.chunks_exact(3))
        .filter(|(x, r)| {
            let excess: f64 = x.iter().zip(r.iter()).map(|(&a, &b)| (a - b) as f64).sum();
            excess > threshold
        })
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_have_no_error() {
        let a: Vec<f32> = (0..48).map(|i| i as f32 / 7.0).collect();
        assert_eq!(mrse(&a, &a), 0.0);
        assert_eq!(block_bias(&a, &a, 4, 4, 3, 2), 0.0);
    }

    #[test]
    fn known_values() {
        // x = 1.1, r = 1: (0.01)/(1.01) per value.
        let r = vec![1.0f32; 12];
        let x = vec![1.1f32; 12];
        assert!((mrse(&x, &r) - 0.01 / 1.01).abs() < 1e-6);
        assert!((block_bias(&x, &r, 2, 2, 3, 16) - 0.1 / 1.01).abs() < 1e-6);
        // Zero-mean noise within a block cancels in block bias.
        let noisy = [1.2f32, 0.8, 1.2, 0.8];
        assert!(block_bias(&noisy, &[1.0; 4], 2, 2, 1, 2) < 1e-6);
        assert!(mrse(&noisy, &[1.0; 4]) > 0.03);
    }

    #[test]
    fn bright_samples_are_counted_by_their_lift() {
        let reference = vec![0.5f32; 12];
        let mut image = reference.clone();
        // At 10 spp a sample of value 30 lifts its pixel by 3 (all channels).
        image[3..6].copy_from_slice(&[3.5, 3.5, 3.5]);
        // One of 20, in one channel only: a mean RGB lift of 2/3.
        image[6] += 2.0;
        assert_eq!(bright_samples(&image, &reference, 10, 25.0), 1);
        assert_eq!(bright_samples(&image, &reference, 10, 5.0), 2);
        assert_eq!(bright_samples(&reference, &image, 10, 5.0), 0);
    }

    #[test]
    fn metrics_of_synthetic_images() {
        // 2 × 1 pixels; reference 1 everywhere, image off by 0.5 in one pixel
        // (all channels) and by −0.1 in the other's red only.
        let r = vec![1.0f32; 6];
        let x = [1.5f32, 1.5, 1.5, 0.9, 1.0, 1.0];
        let mse = (3.0 * 0.25 + 0.01) / 6.0;
        let mae = (3.0 * 0.5 + 0.1) / 6.0;
        assert!((Metric::Mse.mean(&x, &r, 2, 1) - mse).abs() < 1e-7);
        assert!((Metric::Mae.mean(&x, &r, 2, 1) - mae).abs() < 1e-7);
        assert!((Metric::Mrse.mean(&x, &r, 2, 1) - mse / 1.01).abs() < 1e-7);
        assert!((Metric::Mrse.mean(&x, &r, 2, 1) - mrse(&x, &r)).abs() < 1e-12);
        let pixels = Metric::Mae.pixel_errors(&x, &r, 2, 1);
        assert!((pixels[0] - 0.5).abs() < 1e-7 && (pixels[1] - 0.1 / 3.0).abs() < 1e-7);
        for metric in [Metric::Mse, Metric::Mrse, Metric::Mae, Metric::Flip] {
            assert_eq!(metric.mean(&r, &r, 2, 1), 0.0, "{metric:?}");
        }
    }
}
