//! 2D texture mappings: surface point → texture coordinates (s, t) and
//! their screen-space differentials (pbrt-v4's `TextureMapping2D`).
//!
//! | `mapping` | parameters (defaults) | (s, t) |
//! |---|---|---|
//! | `uv` (default) | `uscale` 1, `vscale` 1, `udelta` 0, `vdelta` 0 | (uscale·u + udelta, vscale·v + vdelta) |
//! | `spherical` | — | (θ/π, φ/2π) about the texture-space origin |
//! | `cylindrical` | — | ((π + atan2(y, x))/2π, z) in texture space |
//! | `planar` | `v1` (1,0,0), `v2` (0,1,0), `udelta` 0, `vdelta` 0 | (udelta + p·v1, vdelta + p·v2) |
//!
//! Texture space is the coordinate system in force at the `Texture`
//! directive.

use super::TextureEvalContext;
use crate::error::{scene_error, Result};
use crate::scene_description::ParamSet;
use glam::{Mat4, Vec2, Vec3};
use pbrt_parser::Location;
use std::f32::consts::PI;

/// Texture coordinates and how they change per pixel in x and y.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TexCoord2D {
    pub st: Vec2,
    pub dsdx: f32,
    pub dsdy: f32,
    pub dtdx: f32,
    pub dtdy: f32,
}

#[derive(Clone, Debug, PartialEq)]
pub enum TextureMapping2D {
    Uv {
        scale: Vec2,
        delta: Vec2,
    },
    Spherical {
        texture_from_render: Mat4,
    },
    Cylindrical {
        texture_from_render: Mat4,
    },
    Planar {
        texture_from_render: Mat4,
        vs: Vec3,
        vt: Vec3,
        delta: Vec2,
    },
}

impl TextureMapping2D {
    /// The mapping a texture's parameters name (`render_from_texture`: the
    /// transform at the `Texture` directive, in render space).
    pub fn create(
        params: &ParamSet,
        render_from_texture: Mat4,
        location: &Location,
    ) -> Result<Self> {
        let texture_from_render = render_from_texture.inverse();
        let delta = |params: &ParamSet| -> Result<Vec2> {
            Ok(Vec2::new(
                params.float("udelta", 0.0)? as f32,
                params.float("vdelta", 0.0)? as f32,
            ))
        };
        Ok(match params.string("mapping", "uv")?.as_str() {
            "uv" => TextureMapping2D::Uv {
                scale: Vec2::new(
                    params.float("uscale", 1.0)? as f32,
                    params.float("vscale", 1.0)? as f32,
                ),
                delta: delta(params)?,
            },
            "spherical" => TextureMapping2D::Spherical { texture_from_render },
            "cylindrical" => TextureMapping2D::Cylindrical { texture_from_render },
            "planar" => {
                let vector = |name: &str, default: Vec3| -> Result<Vec3> {
                    match params.vector3s(name)?.as_slice() {
                        [] => Ok(default),
                        [v] => Ok(v.as_vec3()),
                        _ => scene_error(format!("\"{name}\": expected one vector"), location),
                    }
                };
                TextureMapping2D::Planar {
                    texture_from_render,
                    vs: vector("v1", Vec3::X)?,
                    vt: vector("v2", Vec3::Y)?,
                    delta: delta(params)?,
                }
            }
            other => {
                return scene_error(
                    format!("2D texture mapping \"{other}\" unknown (expected uv, spherical, cylindrical or planar)"),
                    location,
                )
            }
        })
    }

    pub fn map(&self, ctx: &TextureEvalContext) -> TexCoord2D {
        match self {
            TextureMapping2D::Uv { scale, delta } => TexCoord2D {
                st: ctx.uv * *scale + *delta,
                dsdx: scale.x * ctx.dudx,
                dsdy: scale.x * ctx.dudy,
                dtdx: scale.y * ctx.dvdx,
                dtdy: scale.y * ctx.dvdy,
            },
            TextureMapping2D::Spherical {
                texture_from_render,
            } => {
                let pt = texture_from_render.transform_point3(ctx.p);
                let x2y2 = pt.x * pt.x + pt.y * pt.y;
                let sqrt_x2y2 = x2y2.sqrt();
                // As pbrt-v4: ∂s/∂p is that of φ/2π and ∂t/∂p that of θ/π,
                // while s is θ/π and t is φ/2π.
                let dsdp = Vec3::new(-pt.y, pt.x, 0.0) / (2.0 * PI * x2y2);
                let dtdp = Vec3::new(pt.x * pt.z / sqrt_x2y2, pt.y * pt.z / sqrt_x2y2, -sqrt_x2y2)
                    / (PI * (x2y2 + pt.z * pt.z));
                let v = pt.normalize_or_zero();
                let theta = v.z.clamp(-1.0, 1.0).acos();
                let phi = v.y.atan2(v.x);
                let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
                differentials(
                    Vec2::new(theta / PI, phi / (2.0 * PI)),
                    dsdp,
                    dtdp,
                    texture_from_render,
                    ctx,
                )
            }
            TextureMapping2D::Cylindrical {
                texture_from_render,
            } => {
                let pt = texture_from_render.transform_point3(ctx.p);
                let x2y2 = pt.x * pt.x + pt.y * pt.y;
                let dsdp = Vec3::new(-pt.y, pt.x, 0.0) / (2.0 * PI * x2y2);
                differentials(
                    Vec2::new((PI + pt.y.atan2(pt.x)) / (2.0 * PI), pt.z),
                    dsdp,
                    Vec3::Z,
                    texture_from_render,
                    ctx,
                )
            }
            TextureMapping2D::Planar {
                texture_from_render,
                vs,
                vt,
                delta,
            } => {
                let p = texture_from_render.transform_point3(ctx.p);
                differentials(
                    *delta + Vec2::new(p.dot(*vs), p.dot(*vt)),
                    *vs,
                    *vt,
                    texture_from_render,
                    ctx,
                )
            }
        }
    }
}

/// (s, t) with differentials from the gradients ∂s/∂p, ∂t/∂p (texture
/// space) and the context's ∂p/∂x, ∂p/∂y (render space).
fn differentials(
    st: Vec2,
    dsdp: Vec3,
    dtdp: Vec3,
    texture_from_render: &Mat4,
    ctx: &TextureEvalContext,
) -> TexCoord2D {
    let dpdx = texture_from_render.transform_vector3(ctx.dpdx);
    let dpdy = texture_from_render.transform_vector3(ctx.dpdy);
    TexCoord2D {
        st,
        dsdx: dsdp.dot(dpdx),
        dsdy: dsdp.dot(dpdy),
        dtdx: dtdp.dot(dpdx),
        dtdy: dtdp.dot(dpdy),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_mapping_scales_and_offsets_coordinates_and_differentials() {
        let mapping = TextureMapping2D::Uv {
            scale: Vec2::new(2.0, 4.0),
            delta: Vec2::new(0.5, -1.0),
        };
        let ctx = TextureEvalContext {
            uv: Vec2::new(0.25, 0.5),
            dudx: 0.1,
            dvdy: 0.01,
            ..Default::default()
        };
        let c = mapping.map(&ctx);
        assert_eq!(c.st, Vec2::new(1.0, 1.0));
        assert_eq!((c.dsdx, c.dsdy, c.dtdx, c.dtdy), (0.2, 0.0, 0.0, 0.04));
    }

    #[test]
    fn planar_and_cylindrical_mappings_follow_the_point() {
        let planar = TextureMapping2D::Planar {
            texture_from_render: Mat4::from_translation(Vec3::new(1.0, 0.0, 0.0)),
            vs: Vec3::X,
            vt: Vec3::Z,
            delta: Vec2::new(0.5, 0.0),
        };
        let ctx = TextureEvalContext {
            p: Vec3::new(1.0, 2.0, 3.0),
            dpdx: Vec3::new(0.0, 0.0, 0.5),
            ..Default::default()
        };
        let c = planar.map(&ctx);
        assert_eq!(c.st, Vec2::new(2.5, 3.0));
        assert_eq!((c.dsdx, c.dtdx), (0.0, 0.5));

        let cylindrical = TextureMapping2D::Cylindrical {
            texture_from_render: Mat4::IDENTITY,
        };
        let ctx = TextureEvalContext {
            p: Vec3::new(0.0, 1.0, 0.25),
            ..Default::default()
        };
        let c = cylindrical.map(&ctx);
        assert!((c.st - Vec2::new(0.75, 0.25)).length() < 1e-6, "{:?}", c.st);
    }

    #[test]
    fn spherical_mapping_gives_polar_angle_then_azimuth() {
        let spherical = TextureMapping2D::Spherical {
            texture_from_render: Mat4::IDENTITY,
        };
        let ctx = TextureEvalContext {
            p: Vec3::new(0.0, 2.0, 0.0),
            ..Default::default()
        };
        let c = spherical.map(&ctx);
        assert!((c.st - Vec2::new(0.5, 0.25)).length() < 1e-6, "{:?}", c.st);
    }
}
