//! The `checkerboard` texture: `tex1` on the squares (2D) or cubes (3D)
//! whose integer cell coordinates sum to an even number, `tex2` on the
//! others, box-filtered over the pixel footprint as pbrt-v4 does (the
//! closed-form integral of the checker function against a filter 1.5 × the
//! footprint wide, per axis).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `tex1` | float/spectrum texture | 1 | value on even cells |
//! | `tex2` | float/spectrum texture | 0 | value on odd cells |
//! | `dimension` | integer | 2 | 2: squares in (s, t) from a 2D mapping; 3: cubes in texture space |
//! | `mapping` … | | `uv` | the 2D mapping (see [`super::mapping`]); `dimension` 3 uses the texture-space point ([`super::mapping_3d`]) |

use super::mapping::TextureMapping2D;
use super::mapping_3d::TextureMapping3D;
use super::{TextureEvalContext, TextureOf, TextureParams};
use crate::error::{scene_error, Result};
use crate::spectrum::color_space::SpectrumKind;
use glam::Mat4;
use pbrt_parser::Location;

/// Where the checks lie: on the 2D texture coordinates, or in texture space.
#[derive(Clone, Debug, PartialEq)]
pub enum CheckerboardMapping {
    Planar(TextureMapping2D),
    Solid(TextureMapping3D),
}

/// A checkerboard of two float or two spectrum textures.
#[derive(Clone, Debug)]
pub struct CheckerboardTexture<T> {
    pub tex1: Box<T>,
    pub tex2: Box<T>,
    pub mapping: CheckerboardMapping,
}

impl<T: TextureOf> CheckerboardTexture<T> {
    pub fn create(
        tp: &TextureParams,
        render_from_texture: Mat4,
        kind: SpectrumKind,
        location: &Location,
    ) -> Result<Self> {
        let dimension = tp.params.int("dimension", 2)?;
        let mapping = match dimension {
            2 => CheckerboardMapping::Planar(TextureMapping2D::create(
                tp.params,
                render_from_texture,
                location,
            )?),
            3 => CheckerboardMapping::Solid(TextureMapping3D::new(render_from_texture)),
            other => {
                return scene_error(
                    format!("checkerboard \"dimension\" must be 2 or 3, not {other}"),
                    location,
                )
            }
        };
        Ok(CheckerboardTexture {
            tex1: Box::new(T::parameter(tp, "tex1", 1.0, kind)?),
            tex2: Box::new(T::parameter(tp, "tex2", 0.0, kind)?),
            mapping,
        })
    }

    /// The weights of `tex1` and `tex2` at `ctx`.
    pub fn weights(&self, ctx: &TextureEvalContext) -> (f32, f32) {
        let w = checkerboard_weight(ctx, &self.mapping);
        (1.0 - w, w)
    }
}

/// The integral of the ±1 square wave of period 2 (+1 on [0, 1)).
fn square_wave_integral(x: f32) -> f32 {
    let y = x / 2.0 - (x / 2.0).floor() - 0.5;
    x / 2.0 + y * (1.0 - 2.0 * y.abs())
}

/// The square wave filtered over radius `r` about `x`: its exact value
/// where [x − r, x + r] stays within one cell, else pbrt-v4's closed form
/// (d(x + r) − 2d(x) + d(x − r)) / r² with d the wave's integral.
fn filtered_square_wave(x: f32, r: f32) -> f32 {
    if (x - r).floor() == (x + r).floor() {
        return 1.0 - 2.0 * ((x.floor() as i64 & 1) as f32);
    }
    (square_wave_integral(x + r) - 2.0 * square_wave_integral(x) + square_wave_integral(x - r))
        / (r * r)
}

/// The weight of `tex2` at `ctx`: 0 inside a `tex1` cell, 1 inside a
/// `tex2` cell, in between where the footprint straddles a boundary.
pub fn checkerboard_weight(ctx: &TextureEvalContext, mapping: &CheckerboardMapping) -> f32 {
    match mapping {
        CheckerboardMapping::Planar(mapping) => {
            let c = mapping.map(ctx);
            let ds = 1.5 * c.dsdx.abs().max(c.dsdy.abs());
            let dt = 1.5 * c.dtdx.abs().max(c.dtdy.abs());
            0.5 - filtered_square_wave(c.st.x, ds) * filtered_square_wave(c.st.y, dt) / 2.0
        }
        CheckerboardMapping::Solid(mapping) => {
            let c = mapping.map(ctx);
            let r = 1.5 * c.dpdx.abs().max(c.dpdy.abs());
            0.5 - 0.5
                * filtered_square_wave(c.p.x, r.x)
                * filtered_square_wave(c.p.y, r.y)
                * filtered_square_wave(c.p.z, r.z)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    #[test]
    fn sharp_without_footprint_and_grey_over_many_squares() {
        let mapping = CheckerboardMapping::Planar(TextureMapping2D::Uv {
            scale: Vec2::splat(4.0),
            delta: Vec2::ZERO,
        });
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

    /// In 3D the cell (i, j, k) = ⌊p⌋ is `tex1`'s when i + j + k is even,
    /// in texture space (here scaled by ½ from render space, so cells are
    /// 2 render units wide).
    #[test]
    fn solid_checks_follow_the_parity_of_the_cell() {
        let mapping =
            CheckerboardMapping::Solid(TextureMapping3D::new(Mat4::from_scale(Vec3::splat(2.0))));
        let cells = [-3i32, -2, -1, 0, 1, 2];
        for i in cells {
            for j in cells {
                for k in cells {
                    // The centre of texture-space cell (i, j, k), in render space.
                    let p = 2.0 * (Vec3::new(i as f32, j as f32, k as f32) + 0.5);
                    let ctx = TextureEvalContext {
                        p,
                        ..Default::default()
                    };
                    let expected = ((i + j + k).rem_euclid(2)) as f32;
                    assert_eq!(checkerboard_weight(&ctx, &mapping), expected, "{i} {j} {k}");
                }
            }
        }
        // A footprint spanning many cells in every axis averages to grey.
        let ctx = TextureEvalContext {
            p: Vec3::new(0.3, 0.7, 0.2),
            dpdx: Vec3::splat(40.0),
            ..Default::default()
        };
        let w = checkerboard_weight(&ctx, &mapping);
        assert!((w - 0.5).abs() < 0.05, "{w}");
    }
}
