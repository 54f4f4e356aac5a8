//! The Lanczos-windowed sinc filter.

use super::filter_sampler::FilterSampler;
use super::FilterSample;
use crate::math::pcg32::Pcg32;
use glam::Vec2;
use std::f32::consts::PI;

/// sinc windowed by a wider sinc, separable (pbrt-v4's `LanczosSincFilter`,
/// scene name `"sinc"`).
///
/// | parameter   | type  | default |
/// |-------------|-------|---------|
/// | `"xradius"` | float | 4       |
/// | `"yradius"` | float | 4       |
/// | `"tau"`     | float | 3       |
///
/// Has negative lobes; sampled from a table ([`FilterSampler`]).
#[derive(Clone, Debug)]
pub struct LanczosSincFilter {
    radius: Vec2,
    tau: f32,
    integral: f32,
    sampler: FilterSampler,
}

/// sin(πx) / (πx), 1 at 0.
fn sinc(x: f32) -> f32 {
    let x = PI * x;
    if 1.0 - x * x == 1.0 {
        1.0
    } else {
        x.sin() / x
    }
}

/// sinc(x) · sinc(x / tau) within the radius, 0 beyond.
fn windowed_sinc(x: f32, radius: f32, tau: f32) -> f32 {
    if x.abs() > radius {
        0.0
    } else {
        sinc(x) * sinc(x / tau)
    }
}

impl LanczosSincFilter {
    pub const DEFAULT_RADIUS: f32 = 4.0;
    pub const DEFAULT_TAU: f32 = 3.0;

    /// `radius` and `tau` must be positive.
    pub fn new(radius: Vec2, tau: f32) -> Self {
        let mut filter = LanczosSincFilter {
            radius,
            tau,
            integral: 0.0,
            sampler: FilterSampler::new(Vec2::ZERO, |_| 0.0),
        };
        filter.integral = filter.estimate_integral();
        filter.sampler = FilterSampler::new(radius, |p| filter.evaluate(p));
        filter
    }

    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    pub fn evaluate(&self, p: Vec2) -> f32 {
        windowed_sinc(p.x, self.radius.x, self.tau) * windowed_sinc(p.y, self.radius.y, self.tau)
    }

    /// The integral has no closed form: pbrt-v4 estimates it with 64 × 64
    /// jittered samples from its default-seeded generator, as done here.
    fn estimate_integral(&self) -> f32 {
        const SQRT_SAMPLES: u32 = 64;
        let area = 2.0 * self.radius.x * 2.0 * self.radius.y;
        let mut rng = Pcg32::default();
        let mut sum = 0.0f32;
        for y in 0..SQRT_SAMPLES {
            for x in 0..SQRT_SAMPLES {
                let ux = (x as f32 + rng.uniform_f32()) / SQRT_SAMPLES as f32;
                let uy = (y as f32 + rng.uniform_f32()) / SQRT_SAMPLES as f32;
                let p = Vec2::new(
                    (1.0 - ux) * -self.radius.x + ux * self.radius.x,
                    (1.0 - uy) * -self.radius.y + uy * self.radius.y,
                );
                sum += self.evaluate(p);
            }
        }
        sum / (SQRT_SAMPLES * SQRT_SAMPLES) as f32 * area
    }

    pub fn integral(&self) -> f32 {
        self.integral
    }

    pub fn sample(&self, u: Vec2) -> FilterSample {
        self.sampler.sample(u)
    }
}
