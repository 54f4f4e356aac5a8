//! The box filter.

use super::FilterSample;
use glam::Vec2;

/// Constant weight over a rectangle (pbrt-v4's `BoxFilter`).
///
/// | parameter   | type  | default |
/// |-------------|-------|---------|
/// | `"xradius"` | float | 0.5     |
/// | `"yradius"` | float | 0.5     |
///
/// Sampled uniformly, with weight 1.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxFilter {
    radius: Vec2,
}

impl BoxFilter {
    pub const DEFAULT_RADIUS: f32 = 0.5;

    pub fn new(radius: Vec2) -> Self {
        BoxFilter { radius }
    }

    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    pub fn evaluate(&self, p: Vec2) -> f32 {
        if p.x.abs() <= self.radius.x && p.y.abs() <= self.radius.y {
            1.0
        } else {
            0.0
        }
    }

    pub fn integral(&self) -> f32 {
        2.0 * self.radius.x * 2.0 * self.radius.y
    }

    pub fn sample(&self, u: Vec2) -> FilterSample {
        let p = (Vec2::ONE - u) * -self.radius + u * self.radius;
        FilterSample { p, weight: 1.0 }
    }
}
