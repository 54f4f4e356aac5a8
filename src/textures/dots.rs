//! The `dots` texture: polka dots of one texture on a background of
//! another, in the 2D texture coordinates.
//!
//! Each unit cell centred on an integer (s, t) holds a dot when noise at
//! the cell (Perlin noise at (s + ½, t + ½, ½)) is positive; the dot has
//! radius 0.35 and its centre is moved within the cell by up to 0.15 in s
//! and t by noise at two other points of the cell.
//!
//! | parameter | type | default | meaning (as pbrt-v4 renders it) |
//! |---|---|---|---|
//! | `inside` | float/spectrum texture | 1 | the value **between** the dots |
//! | `outside` | float/spectrum texture | 0 | the value **in** the dots |
//! | `mapping` … | | `uv` | the 2D mapping (see [`super::mapping`]) |
//!
//! pbrt-v4's `DotsTexture::Create` passes `inside` and `outside` to a
//! constructor that takes them in the other order, so the names read the
//! wrong way round; rpbrt renders what pbrt-v4 renders (with the defaults:
//! dots of 0 on 1), which is what scenes written for it expect.

use super::mapping::TextureMapping2D;
use super::noise::noise_2d;
use super::{TextureEvalContext, TextureOf, TextureParams};
use crate::error::Result;
use crate::spectrum::color_space::SpectrumKind;
use glam::{Mat4, Vec2};
use pbrt_parser::Location;

/// Dots of one float or spectrum texture on a background of another.
#[derive(Clone, Debug)]
pub struct DotsTexture<T> {
    pub mapping: TextureMapping2D,
    /// The texture shown in the dots (pbrt-v4 reads it from `outside`).
    pub in_dots: Box<T>,
    /// The texture shown between them (read from `inside`).
    pub between_dots: Box<T>,
}

impl<T: TextureOf> DotsTexture<T> {
    pub fn create(
        tp: &TextureParams,
        render_from_texture: Mat4,
        kind: SpectrumKind,
        location: &Location,
    ) -> Result<Self> {
        let mapping = TextureMapping2D::create(tp.params, render_from_texture, location)?;
        Ok(DotsTexture {
            mapping,
            between_dots: Box::new(T::parameter(tp, "inside", 1.0, kind)?),
            in_dots: Box::new(T::parameter(tp, "outside", 0.0, kind)?),
        })
    }

    /// The texture to evaluate at `ctx`.
    pub fn select(&self, ctx: &TextureEvalContext) -> &T {
        if inside_polka_dot(self.mapping.map(ctx).st) {
            &self.in_dots
        } else {
            &self.between_dots
        }
    }
}

/// Radius of a dot, in cells.
const DOT_RADIUS: f32 = 0.35;

/// Whether texture coordinates `st` fall in a dot.
pub fn inside_polka_dot(st: Vec2) -> bool {
    // The cell whose centre (an integer point) is nearest.
    let cell = (st + 0.5).floor();
    if noise_2d(cell.x + 0.5, cell.y + 0.5) <= 0.0 {
        return false;
    }
    // The dot may move off the cell's centre as far as keeps it inside.
    let max_shift = 0.5 - DOT_RADIUS;
    let centre = cell
        + max_shift
            * Vec2::new(
                noise_2d(cell.x + 1.5, cell.y + 2.8),
                noise_2d(cell.x + 4.5, cell.y + 9.8),
            );
    (st - centre).length_squared() < DOT_RADIUS * DOT_RADIUS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dots_are_where_the_cell_noise_puts_them() {
        let mut cells_with_dots = 0;
        for i in -10..10 {
            for j in -10..10 {
                let cell = Vec2::new(i as f32, j as f32);
                let has_dot = noise_2d(cell.x + 0.5, cell.y + 0.5) > 0.0;
                let centre = cell
                    + 0.15
                        * Vec2::new(
                            noise_2d(cell.x + 1.5, cell.y + 2.8),
                            noise_2d(cell.x + 4.5, cell.y + 9.8),
                        );
                // The dot's centre and points just within its radius are
                // in it; points just beyond it, and the cell's corners, are not.
                assert_eq!(inside_polka_dot(centre), has_dot, "{cell}");
                for angle in [0.0f32, 1.0, 2.5, 4.0] {
                    let direction = Vec2::new(angle.cos(), angle.sin());
                    assert_eq!(inside_polka_dot(centre + 0.34 * direction), has_dot);
                    assert!(!inside_polka_dot(centre + 0.36 * direction));
                }
                assert!(!inside_polka_dot(cell + Vec2::splat(0.49)));
                cells_with_dots += has_dot as i32;
            }
        }
        // About half the cells have a dot.
        assert!((100..300).contains(&cells_with_dots), "{cells_with_dots}");
    }
}
