//! The triangle (tent) filter.

use super::FilterSample;
use crate::math::ONE_MINUS_EPSILON;
use glam::Vec2;

/// Weight falling linearly to zero at the radius along each axis (pbrt-v4's
/// `TriangleFilter`).
///
/// | parameter   | type  | default |
/// |-------------|-------|---------|
/// | `"xradius"` | float | 2       |
/// | `"yradius"` | float | 2       |
///
/// Sampled exactly (a tent distribution per axis), with weight 1.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleFilter {
    radius: Vec2,
}

/// A sample of the linear density on [0, 1] from `a` at 0 to `b` at 1.
fn sample_linear(u: f32, a: f32, b: f32) -> f32 {
    if u == 0.0 && a == 0.0 {
        return 0.0;
    }
    let x = u * (a + b) / (a + ((1.0 - u) * a * a + u * b * b).sqrt());
    x.min(ONE_MINUS_EPSILON)
}

/// A sample of the tent density on [-radius, radius].
fn sample_tent(u: f32, radius: f32) -> f32 {
    // Choose a side with probability 1/2 and reuse u within it.
    if u < 0.5 {
        let u = (u / 0.5).min(ONE_MINUS_EPSILON);
        -radius + radius * sample_linear(u, 0.0, 1.0)
    } else {
        let u = ((u - 0.5) / 0.5).min(ONE_MINUS_EPSILON);
        radius * sample_linear(u, 1.0, 0.0)
    }
}

impl TriangleFilter {
    pub const DEFAULT_RADIUS: f32 = 2.0;

    pub fn new(radius: Vec2) -> Self {
        TriangleFilter { radius }
    }

    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    pub fn evaluate(&self, p: Vec2) -> f32 {
        (self.radius.x - p.x.abs()).max(0.0) * (self.radius.y - p.y.abs()).max(0.0)
    }

    pub fn integral(&self) -> f32 {
        self.radius.x * self.radius.x * self.radius.y * self.radius.y
    }

    pub fn sample(&self, u: Vec2) -> FilterSample {
        FilterSample {
            p: Vec2::new(
                sample_tent(u.x, self.radius.x),
                sample_tent(u.y, self.radius.y),
            ),
            weight: 1.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tent_sampling_inverts_the_tent_cdf() {
        // The tent's CDF on [-1, 1] is (1 + x)²/2 left of 0.
        for i in 1..100 {
            let u = i as f32 / 200.0;
            let x = sample_tent(u, 1.0);
            assert!(((1.0 + x) * (1.0 + x) / 2.0 - u).abs() < 1e-5);
        }
        assert_eq!(sample_tent(0.0, 2.0), -2.0);
        assert!(sample_tent(ONE_MINUS_EPSILON, 2.0) < 2.0);
    }
}
