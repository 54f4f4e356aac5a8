//! LDR-FLIP (Andersson et al., "FLIP: A Difference Evaluator for
//! Alternating Images", HPG 2020): a per-pixel perceptual difference in
//! [0, 1] between a test image and a reference as a viewer flipping between
//! them would see it. Implemented from the paper's definition (section 4):
//! a colour pipeline (contrast-sensitivity filtering in YCxCz, Hunt-adjusted
//! L*a*b*, HyAB distance, error redistribution) and a feature pipeline
//! (edge and point detectors on achromatic values), combined as
//! ΔE = ΔE_c^(1 − ΔE_f).
//!
//! Inputs are linear RGB; values are clamped to [0, 1] first (LDR-FLIP
//! compares displayable images).

use glam::{Mat3, Vec3};

/// Pixels per degree of visual angle the paper's default observer sees: a
/// 0.7 m wide 4K monitor at 0.7 m.
pub const DEFAULT_PIXELS_PER_DEGREE: f32 = 3840.0 * std::f32::consts::PI / 180.0;

/// The exponents and redistribution points of the paper (q_c, q_f, p_c, p_t).
const COLOR_EXPONENT: f32 = 0.7;
const FEATURE_EXPONENT: f32 = 0.5;
const REDISTRIBUTION_POINT: f32 = 0.4;
const REDISTRIBUTION_TARGET: f32 = 0.95;

/// D65 white in XYZ (Y = 1), normalising XYZ for YCxCz and L*a*b*.
const WHITE: Vec3 = Vec3::new(0.950_428_5, 1.0, 1.088_900_4);

fn xyz_from_linear_srgb() -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.412_390_8, 0.212_639, 0.019_330_8),
        Vec3::new(0.357_584_3, 0.715_168_7, 0.119_194_8),
        Vec3::new(0.180_480_8, 0.072_192_3, 0.950_532_2),
    )
}

/// Linearised CIELAB: like L*a*b* without the cube root (paper eq. 1).
fn ycxcz_from_xyz(xyz: Vec3) -> Vec3 {
    let n = xyz / WHITE;
    Vec3::new(116.0 * n.y - 16.0, 500.0 * (n.x - n.y), 200.0 * (n.y - n.z))
}

fn xyz_from_ycxcz(c: Vec3) -> Vec3 {
    let y = (c.x + 16.0) / 116.0;
    Vec3::new(y + c.y / 500.0, y, y - c.z / 200.0) * WHITE
}

fn lab_from_xyz(xyz: Vec3) -> Vec3 {
    let delta: f32 = 6.0 / 29.0;
    let f = |t: f32| {
        if t > delta.powi(3) {
            t.cbrt()
        } else {
            t / (3.0 * delta * delta) + 4.0 / 29.0
        }
    };
    let n = xyz / WHITE;
    let (fx, fy, fz) = (f(n.x), f(n.y), f(n.z));
    Vec3::new(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz))
}

/// Hunt adjustment: chroma scaled by 0.01 L (paper eq. 3).
fn hunt(lab: Vec3) -> Vec3 {
    Vec3::new(lab.x, 0.01 * lab.x * lab.y, 0.01 * lab.x * lab.z)
}

/// HyAB distance: city block in L, Euclidean in a, b (paper eq. 4).
fn hyab(a: Vec3, b: Vec3) -> f32 {
    let d = a - b;
    d.x.abs() + (d.y * d.y + d.z * d.z).sqrt()
}

/// A square kernel of radius `r`, row-major.
struct Kernel {
    radius: i32,
    weights: Vec<f32>,
}

/// The contrast sensitivity functions of the achromatic, red–green and
/// blue–yellow channels as sums of two Gaussians (paper eq. 2 and table 1),
/// sampled at `ppd` and normalised to sum 1.
fn csf_kernels(ppd: f32) -> [Kernel; 3] {
    // (a1, b1, a2, b2); b2 = 1e-5 where a2 = 0 only avoids a division by 0.
    let params = [
        (1.0, 0.0047, 0.0, 1e-5),
        (1.0, 0.0053, 0.0, 1e-5),
        (34.1, 0.04, 13.5, 0.025),
    ];
    let max_b: f32 = 0.04;
    let pi2 = std::f32::consts::PI * std::f32::consts::PI;
    let radius = (3.0 * (max_b / (2.0 * pi2)).sqrt() * ppd).ceil() as i32;
    params.map(|(a1, b1, a2, b2): (f32, f32, f32, f32)| {
        let gauss =
            |a: f32, b: f32, d2: f32| a * (std::f32::consts::PI / b).sqrt() * (-pi2 * d2 / b).exp();
        let mut weights = Vec::new();
        for y in -radius..=radius {
            for x in -radius..=radius {
                let d2 = ((x * x + y * y) as f32) / (ppd * ppd);
                weights.push(gauss(a1, b1, d2) + gauss(a2, b2, d2));
            }
        }
        let sum: f32 = weights.iter().sum();
        weights.iter_mut().for_each(|w| *w /= sum);
        Kernel { radius, weights }
    })
}

/// The edge (first derivative of a Gaussian) or point (second derivative)
/// detector along x, positive and negative weights each normalised to ±1
/// (paper section 4.2; σ = half of 0.082° peak-to-trough).
fn feature_kernel(ppd: f32, point: bool) -> Kernel {
    let sd = 0.5 * 0.082 * ppd;
    let radius = (3.0 * sd).ceil() as i32;
    let mut weights = Vec::new();
    for y in -radius..=radius {
        for x in -radius..=radius {
            let (xf, yf) = (x as f32, y as f32);
            let g = (-(xf * xf + yf * yf) / (2.0 * sd * sd)).exp();
            weights.push(if point {
                (xf * xf / (sd * sd) - 1.0) * g
            } else {
                -xf * g
            });
        }
    }
    let positive: f32 = weights.iter().filter(|w| **w > 0.0).sum();
    let negative: f32 = -weights.iter().filter(|w| **w < 0.0).sum::<f32>();
    for w in &mut weights {
        *w /= if *w > 0.0 { positive } else { negative };
    }
    Kernel { radius, weights }
}

/// Convolves one channel (clamp-to-edge), optionally with the kernel
/// transposed (the y-direction detector).
fn convolve(
    values: &[f32],
    width: usize,
    height: usize,
    kernel: &Kernel,
    transpose: bool,
) -> Vec<f32> {
    let r = kernel.radius;
    let side = (2 * r + 1) as usize;
    let mut out = vec![0.0; values.len()];
    for y in 0..height {
        for x in 0..width {
            let mut sum = 0.0;
            for ky in -r..=r {
                let sy = (y as i32 + ky).clamp(0, height as i32 - 1) as usize;
                for kx in -r..=r {
                    let sx = (x as i32 + kx).clamp(0, width as i32 - 1) as usize;
                    let (i, j) = ((ky + r) as usize, (kx + r) as usize);
                    let w = if transpose {
                        kernel.weights[j * side + i]
                    } else {
                        kernel.weights[i * side + j]
                    };
                    sum += w * values[sy * width + sx];
                }
            }
            out[y * width + x] = sum;
        }
    }
    out
}

/// Per pixel of one image: Hunt-adjusted L*a*b* after CSF filtering, and
/// the edge and point feature magnitudes.
struct Perceived {
    color: Vec<Vec3>,
    edge: Vec<f32>,
    point: Vec<f32>,
}

fn perceive(rgb: &[f32], width: usize, height: usize, ppd: f32) -> Perceived {
    let m = xyz_from_linear_srgb();
    let pixels = width * height;
    let mut opponent = [vec![0.0; pixels], vec![0.0; pixels], vec![0.0; pixels]];
    for (i, p) in rgb.chunks_exact(3).enumerate() {
        let linear = Vec3::new(p[0], p[1], p[2]).clamp(Vec3::ZERO, Vec3::ONE);
        let c = ycxcz_from_xyz(m * linear);
        for (k, channel) in opponent.iter_mut().enumerate() {
            channel[i] = c[k];
        }
    }
    let kernels = csf_kernels(ppd);
    let filtered: Vec<Vec<f32>> = opponent
        .iter()
        .zip(&kernels)
        .map(|(channel, kernel)| convolve(channel, width, height, kernel, false))
        .collect();
    let inverse = m.inverse();
    let color = (0..pixels)
        .map(|i| {
            let c = Vec3::new(filtered[0][i], filtered[1][i], filtered[2][i]);
            let linear = (inverse * xyz_from_ycxcz(c)).clamp(Vec3::ZERO, Vec3::ONE);
            hunt(lab_from_xyz(m * linear))
        })
        .collect();
    // Features are detected on the unfiltered achromatic channel, in [0, 1].
    let achromatic: Vec<f32> = opponent[0].iter().map(|y| (y + 16.0) / 116.0).collect();
    let magnitude = |point: bool| {
        let kernel = feature_kernel(ppd, point);
        let gx = convolve(&achromatic, width, height, &kernel, false);
        let gy = convolve(&achromatic, width, height, &kernel, true);
        gx.iter().zip(&gy).map(|(x, y)| x.hypot(*y)).collect()
    };
    Perceived {
        color,
        edge: magnitude(false),
        point: magnitude(true),
    }
}

/// The LDR-FLIP error of each pixel (row-major), in [0, 1]. `image` and
/// `reference` are interleaved linear RGB of `width` × `height` pixels.
pub fn flip_map(
    image: &[f32],
    reference: &[f32],
    width: usize,
    height: usize,
    ppd: f32,
) -> Vec<f32> {
    assert_eq!(image.len(), width * height * 3);
    assert_eq!(reference.len(), image.len());
    let test = perceive(image, width, height, ppd);
    let refr = perceive(reference, width, height, ppd);
    // The largest colour difference: pure green against pure blue.
    let m = xyz_from_linear_srgb();
    let green = hunt(lab_from_xyz(m * Vec3::Y));
    let blue = hunt(lab_from_xyz(m * Vec3::Z));
    let cmax = hyab(green, blue).powf(COLOR_EXPONENT);
    let pccmax = REDISTRIBUTION_POINT * cmax;
    (0..width * height)
        .map(|i| {
            let e = hyab(refr.color[i], test.color[i]).powf(COLOR_EXPONENT);
            // Paper eq. 5: compress the large errors into (p_t, 1].
            let color = if e < pccmax {
                REDISTRIBUTION_TARGET / pccmax * e
            } else {
                REDISTRIBUTION_TARGET
                    + (e - pccmax) / (cmax - pccmax) * (1.0 - REDISTRIBUTION_TARGET)
            };
            let feature = (std::f32::consts::FRAC_1_SQRT_2
                * (refr.edge[i] - test.edge[i])
                    .abs()
                    .max((refr.point[i] - test.point[i]).abs()))
            .powf(FEATURE_EXPONENT);
            color.powf(1.0 - feature)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_have_no_error() {
        let a: Vec<f32> = (0..8 * 6 * 3).map(|i| (i as f32 * 0.37).fract()).collect();
        let map = flip_map(&a, &a, 8, 6, DEFAULT_PIXELS_PER_DEGREE);
        assert!(map.iter().all(|&e| e == 0.0), "{map:?}");
    }

    #[test]
    fn black_against_white_is_large_and_bounded() {
        let black = vec![0.0; 16 * 16 * 3];
        let white = vec![1.0; 16 * 16 * 3];
        let map = flip_map(&black, &white, 16, 16, DEFAULT_PIXELS_PER_DEGREE);
        // HyAB(black, white) = 100 in L: (100^0.7 ≈ 25.1) is past p_c c_max,
        // so the error lies in (p_t, 1].
        assert!(map.iter().all(|&e| e > 0.95 && e <= 1.0), "{map:?}");
        let grey = vec![0.2; 16 * 16 * 3];
        let small = flip_map(&grey, &white, 16, 16, DEFAULT_PIXELS_PER_DEGREE);
        assert!(small[0] < map[0] && small[0] > 0.1, "{}", small[0]);
    }

    #[test]
    fn colour_maximum_is_green_against_blue() {
        let m = xyz_from_linear_srgb();
        let green = hunt(lab_from_xyz(m * Vec3::Y));
        let blue = hunt(lab_from_xyz(m * Vec3::Z));
        let red = hunt(lab_from_xyz(m * Vec3::X));
        assert!(hyab(green, blue) > hyab(red, blue));
        assert!(hyab(green, blue) > hyab(red, green));
        // White has L* = 100 and no chroma.
        let white = lab_from_xyz(m * Vec3::ONE);
        assert!(
            (white.x - 100.0).abs() < 1e-3 && white.y.abs() < 1e-2,
            "{white}"
        );
    }
}
