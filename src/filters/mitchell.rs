//! The Mitchell–Netravali filter.

use super::filter_sampler::FilterSampler;
use super::FilterSample;
use glam::Vec2;

/// Mitchell and Netravali's cubic family, separable (pbrt-v4's
/// `MitchellFilter`).
///
/// | parameter   | type  | default |
/// |-------------|-------|---------|
/// | `"xradius"` | float | 2       |
/// | `"yradius"` | float | 2       |
/// | `"B"`       | float | 1/3     |
/// | `"C"`       | float | 1/3     |
///
/// Has negative lobes; sampled from a table ([`FilterSampler`]).
#[derive(Clone, Debug)]
pub struct MitchellFilter {
    radius: Vec2,
    b: f32,
    c: f32,
    sampler: FilterSampler,
}

impl MitchellFilter {
    pub const DEFAULT_RADIUS: f32 = 2.0;
    pub const DEFAULT_B: f32 = 1.0 / 3.0;
    pub const DEFAULT_C: f32 = 1.0 / 3.0;

    /// `radius` must be positive.
    pub fn new(radius: Vec2, b: f32, c: f32) -> Self {
        let mut filter = MitchellFilter {
            radius,
            b,
            c,
            sampler: FilterSampler::new(Vec2::ZERO, |_| 0.0),
        };
        filter.sampler = FilterSampler::new(radius, |p| filter.evaluate(p));
        filter
    }

    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    /// The 1D cubic on [-2, 2].
    fn mitchell_1d(&self, x: f32) -> f32 {
        let (b, c) = (self.b, self.c);
        let x = x.abs();
        if x <= 1.0 {
            ((12.0 - 9.0 * b - 6.0 * c) * x * x * x
                + (-18.0 + 12.0 * b + 6.0 * c) * x * x
                + (6.0 - 2.0 * b))
                * (1.0 / 6.0)
        } else if x <= 2.0 {
            ((-b - 6.0 * c) * x * x * x
                + (6.0 * b + 30.0 * c) * x * x
                + (-12.0 * b - 48.0 * c) * x
                + (8.0 * b + 24.0 * c))
                * (1.0 / 6.0)
        } else {
            0.0
        }
    }

    pub fn evaluate(&self, p: Vec2) -> f32 {
        self.mitchell_1d(2.0 * p.x / self.radius.x) * self.mitchell_1d(2.0 * p.y / self.radius.y)
    }

    /// Each 1D cubic integrates to 1 over [-2, 2], for any B and C.
    pub fn integral(&self) -> f32 {
        self.radius.x * self.radius.y / 4.0
    }

    pub fn sample(&self, u: Vec2) -> FilterSample {
        self.sampler.sample(u)
    }
}
