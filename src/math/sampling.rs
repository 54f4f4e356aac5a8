//! Warping uniform samples to distributions, with their densities.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI};

/// Uniform point on the unit disk (Shirley–Chiu concentric mapping).
pub fn sample_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}

/// Cosine-weighted direction about +z.
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = sample_uniform_disk_concentric(u);
    let z = (1.0 - d.x * d.x - d.y * d.y).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta * FRAC_1_PI
}

/// Uniform direction on the unit sphere.
pub fn sample_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

pub const UNIFORM_SPHERE_PDF: f32 = 1.0 / (4.0 * PI);

/// Uniform direction on the upper (z ≥ 0) unit hemisphere.
pub fn sample_uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

pub const UNIFORM_HEMISPHERE_PDF: f32 = 1.0 / (2.0 * PI);

/// Uniform barycentrics on a triangle (Heitz's low-distortion mapping, as
/// pbrt-v4 uses).
pub fn sample_uniform_triangle(u: Vec2) -> [f32; 3] {
    let (b0, b1);
    if u.x < u.y {
        b0 = u.x / 2.0;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.0;
        b0 = u.x - b1;
    }
    [b0, b1, 1.0 - b0 - b1]
}

/// Balance heuristic for multiple importance sampling: the weight pbrt-v4's
/// `volpath` gives its samples, dividing by the sum of the densities.
pub fn balance_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    heuristic(nf * f_pdf, ng * g_pdf, |x| x)
}

/// Power heuristic (β = 2) for multiple importance sampling.
pub fn power_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    heuristic(nf * f_pdf, ng * g_pdf, |x| x * x)
}

/// w(f) / (w(f) + w(g)) for the weighted densities f and g, 1 when f is
/// infinite and 0 when both are 0.
#[inline]
fn heuristic(f: f32, g: f32, w: impl Fn(f32) -> f32) -> f32 {
    if f.is_infinite() {
        return 1.0;
    }
    if f == 0.0 && g == 0.0 {
        return 0.0;
    }
    w(f) / (w(f) + w(g))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warps_stay_in_their_domains() {
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                assert!(sample_uniform_disk_concentric(u).length() <= 1.0 + 1e-6);
                let w = sample_cosine_hemisphere(u);
                assert!(w.z >= 0.0 && (w.length() - 1.0).abs() < 1e-5);
                assert!((sample_uniform_sphere(u).length() - 1.0).abs() < 1e-5);
                let h = sample_uniform_hemisphere(u);
                assert!(h.z >= 0.0 && (h.length() - 1.0).abs() < 1e-5);
                let b = sample_uniform_triangle(u);
                assert!(b.iter().all(|&x| (-1e-6..=1.0 + 1e-6).contains(&x)));
            }
        }
    }

    /// Under a uniform density on the hemisphere the mean of cos θ is 1/2.
    #[test]
    fn uniform_hemisphere_mean_cosine_is_half() {
        let n = 64;
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum += sample_uniform_hemisphere(u).z as f64;
            }
        }
        let mean = sum / (n * n) as f64;
        assert!((mean - 0.5).abs() < 1e-3, "{mean}");
    }
}
