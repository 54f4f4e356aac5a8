//! The `checkerboard` texture (2D): `tex1` on squares whose integer (s, t)
//! cells sum to an even number, `tex2` on the others, box-filtered over
//! the pixel footprint as pbrt-v4 does (the closed-form integral of the
//! checker function against a tent filter of 1.5 × the footprint).
//!
//! | parameter | type | default |
//! |---|---|---|
//! | `tex1` | float/spectrum texture | 1 |
//! | `tex2` | float/spectrum texture | 0 |
//! | `dimension` | integer | 2 (3 is not supported yet) |
//! | `mapping` … | | `uv` (see [`super::mapping`]) |

use super::mapping::TextureMapping2D;
use super::TextureEvalContext;

/// The weight of `tex2` at `ctx`: 0 inside a `tex1` square, 1 inside a
/// `tex2` square, in between where the footprint straddles an edge.
pub fn checkerboard_weight(ctx: &TextureEvalContext, mapping: &TextureMapping2D) -> f32 {
    // Integral of the ±1 square wave of period 2.
    let d = |x: f32| {
        let y = x / 2.0 - (x / 2.0).floor() - 0.5;
        x / 2.0 + y * (1.0 - 2.0 * y.abs())
    };
    // Square wave filtered over [x − r, x + r].
    let filtered = |x: f32, r: f32| -> f32 {
        if (x - r).floor() == (x + r).floor() {
            return 1.0 - 2.0 * ((x.floor() as i64 & 1) as f32);
        }
        (d(x + r) - 2.0 * d(x) + d(x - r)) / (r * r)
    };
    let c = mapping.map(ctx);
    let ds = 1.5 * c.dsdx.abs().max(c.dsdy.abs());
    let dt = 1.5 * c.dtdx.abs().max(c.dtdy.abs());
    0.5 - filtered(c.st.x, ds) * filtered(c.st.y, dt) / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    #[test]
    fn sharp_without_footprint_and_grey_over_many_squares() {
        let mapping = TextureMapping2D::Uv {
            scale: Vec2::splat(4.0),
            delta: Vec2::ZERO,
        };
        let at = |u: f32, v: f32, du: f32| TextureEvalContext {
            uv: Vec2::new(u, v),
            dudx: du,
            dvdy: du,
            ..Default::default()
        };
        assert_eq!(checkerboard_weight(&at(0.1, 0.1, 0.0), &mapping), 0.0);
        assert_eq!(checkerboard_weight(&at(0.3, 0.1, 0.0), &mapping), 1.0);
        // A footprint of many squares averages to grey.
        let w = checkerboard_weight(&at(0.3, 0.1, 3.0), &mapping);
        assert!((w - 0.5).abs() < 0.05, "{w}");
    }
}
