//! Image error metrics of `../shared/refs/README.md`.

/// MRSE (pbrt-v4 imgtool's): mean over pixels and channels of
/// (x − r)² / (r² + 0.01).
pub fn mrse(image: &[f32], reference: &[f32]) -> f64 {
    assert_eq!(image.len(), reference.len());
    let sum: f64 = image
        .iter()
        .zip(reference)
        .map(|(&x, &r)| {
            let (x, r) = (x as f64, r as f64);
            (x - r) * (x - r) / (r * r + 0.01)
        })
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
}
