//! The Gaussian filter.

use super::error_function::erf;
use super::filter_sampler::FilterSampler;
use super::FilterSample;
use glam::Vec2;

/// A Gaussian, less its value at the radius so it reaches zero there
/// (pbrt-v4's `GaussianFilter`).
///
/// | parameter   | type  | default |
/// |-------------|-------|---------|
/// | `"xradius"` | float | 1.5     |
/// | `"yradius"` | float | 1.5     |
/// | `"sigma"`   | float | 0.5     |
///
/// Sampled from a table ([`FilterSampler`]).
#[derive(Clone, Debug)]
pub struct GaussianFilter {
    radius: Vec2,
    sigma: f32,
    /// The Gaussian's value at the radius along x and y.
    value_at_radius: Vec2,
    sampler: FilterSampler,
}

/// The normal density with mean 0 and standard deviation `sigma`.
fn gaussian(x: f32, sigma: f32) -> f32 {
    1.0 / (2.0 * std::f32::consts::PI * sigma * sigma).sqrt()
        * (-(x * x) / (2.0 * sigma * sigma)).exp()
}

/// ∫ of [`gaussian`] over [x0, x1].
fn gaussian_integral(x0: f32, x1: f32, sigma: f32) -> f32 {
    let sigma_root_2 = f64::from(sigma) * std::f64::consts::SQRT_2;
    (0.5 * (erf(f64::from(-x0) / sigma_root_2) - erf(f64::from(-x1) / sigma_root_2))) as f32
}

impl GaussianFilter {
    pub const DEFAULT_RADIUS: f32 = 1.5;
    pub const DEFAULT_SIGMA: f32 = 0.5;

    /// `radius` and `sigma` must be positive.
    pub fn new(radius: Vec2, sigma: f32) -> Self {
        let mut filter = GaussianFilter {
            radius,
            sigma,
            value_at_radius: Vec2::new(gaussian(radius.x, sigma), gaussian(radius.y, sigma)),
            sampler: FilterSampler::new(Vec2::ZERO, |_| 0.0),
        };
        filter.sampler = FilterSampler::new(radius, |p| filter.evaluate(p));
        filter
    }

    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    pub fn sigma(&self) -> f32 {
        self.sigma
    }

    pub fn evaluate(&self, p: Vec2) -> f32 {
        (gaussian(p.x, self.sigma) - self.value_at_radius.x).max(0.0)
            * (gaussian(p.y, self.sigma) - self.value_at_radius.y).max(0.0)
    }

    pub fn integral(&self) -> f32 {
        let (r, e) = (self.radius, self.value_at_radius);
        (gaussian_integral(-r.x, r.x, self.sigma) - 2.0 * r.x * e.x)
            * (gaussian_integral(-r.y, r.y, self.sigma) - 2.0 * r.y * e.y)
    }

    pub fn sample(&self, u: Vec2) -> FilterSample {
        self.sampler.sample(u)
    }
}
