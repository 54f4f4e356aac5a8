//! Textures: values that vary over surfaces. A parameter that takes a
//! texture may also be given as a constant value.
//!
//! `constant` (`value`, default 1) and `scale` (`tex` × `scale`, both
//! default 1) are here; `checkerboard` and `imagemap` have their own files,
//! texture mappings theirs.

pub mod checkerboard;
pub mod image_map;
pub mod mapping;

use crate::error::{scene_error, Result};
use crate::interaction::SurfaceInteraction;
use crate::scene_description::ParamSet;
use crate::scene_description::{ColorSpaceName, Entity, TextureValue};
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::parameter::spectrum_param;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use checkerboard::checkerboard_weight;
use glam::{Mat4, Vec2, Vec3};
pub use image_map::{ImageCache, ImageTexture};
pub use mapping::TextureMapping2D;
use pbrt_parser::ParamType;
use std::collections::HashMap;
use std::path::Path;

/// Where a texture is evaluated, and how that point moves from one pixel
/// to the next (pbrt-v4's `TextureEvalContext`; zero differentials mean
/// an unfiltered lookup).
#[derive(Clone, Copy, Debug, Default)]
pub struct TextureEvalContext {
    pub p: Vec3,
    pub dpdx: Vec3,
    pub dpdy: Vec3,
    pub n: Vec3,
    pub uv: Vec2,
    pub dudx: f32,
    pub dudy: f32,
    pub dvdx: f32,
    pub dvdy: f32,
}

impl TextureEvalContext {
    /// At a hit, without differentials (as pbrt-v4 evaluates alpha).
    pub fn at(si: &SurfaceInteraction) -> Self {
        TextureEvalContext {
            p: si.p,
            n: si.n,
            uv: si.uv,
            ..Default::default()
        }
    }

    /// At a hit whose position changes by `dpdx`, `dpdy` per pixel: the
    /// (u, v) differentials are the least-squares solution of
    /// ∂p/∂x = ∂p/∂u ∂u/∂x + ∂p/∂v ∂v/∂x (pbrt-v4's `ComputeDifferentials`),
    /// clamped to ±10⁸ and zero where not finite.
    pub fn with_differentials(si: &SurfaceInteraction, dpdx: Vec3, dpdy: Vec3) -> Self {
        let ata00 = si.dpdu.dot(si.dpdu);
        let ata01 = si.dpdu.dot(si.dpdv);
        let ata11 = si.dpdv.dot(si.dpdv);
        let inv_det = 1.0 / (ata00 * ata11 - ata01 * ata01);
        let inv_det = if inv_det.is_finite() { inv_det } else { 0.0 };
        let solve = |d: Vec3| {
            let (b0, b1) = (si.dpdu.dot(d), si.dpdv.dot(d));
            let clean = |x: f32| {
                if x.is_finite() {
                    x.clamp(-1e8, 1e8)
                } else {
                    0.0
                }
            };
            (
                clean((ata11 * b0 - ata01 * b1) * inv_det),
                clean((ata00 * b1 - ata01 * b0) * inv_det),
            )
        };
        let (dudx, dvdx) = solve(dpdx);
        let (dudy, dvdy) = solve(dpdy);
        TextureEvalContext {
            p: si.p,
            dpdx,
            dpdy,
            n: si.n,
            uv: si.uv,
            dudx,
            dudy,
            dvdx,
            dvdy,
        }
    }
}

/// A float-valued texture.
#[derive(Clone, Debug)]
pub enum FloatTexture {
    Constant(f32),
    /// `tex × scale`.
    Scale(Box<FloatTexture>, Box<FloatTexture>),
    Checkerboard {
        tex1: Box<FloatTexture>,
        tex2: Box<FloatTexture>,
        mapping: TextureMapping2D,
    },
    Image(Box<ImageTexture>),
}

/// A spectrum-valued texture (made for one spectrum kind).
#[derive(Clone, Debug)]
pub enum SpectrumTexture {
    Constant(Spectrum),
    Scale(Box<SpectrumTexture>, Box<FloatTexture>),
    Checkerboard {
        tex1: Box<SpectrumTexture>,
        tex2: Box<SpectrumTexture>,
        mapping: TextureMapping2D,
    },
    Image(Box<ImageTexture>, SpectrumKind),
}

impl FloatTexture {
    pub fn evaluate(&self, ctx: &TextureEvalContext) -> f32 {
        match self {
            FloatTexture::Constant(v) => *v,
            FloatTexture::Scale(t, s) => t.evaluate(ctx) * s.evaluate(ctx),
            FloatTexture::Checkerboard {
                tex1,
                tex2,
                mapping,
            } => {
                let w = checkerboard_weight(ctx, mapping);
                let t1 = if w != 1.0 { tex1.evaluate(ctx) } else { 0.0 };
                let t2 = if w != 0.0 { tex2.evaluate(ctx) } else { 0.0 };
                (1.0 - w) * t1 + w * t2
            }
            FloatTexture::Image(image) => image.evaluate_float(ctx),
        }
    }

    /// The value, if the texture is a constant.
    pub fn constant(&self) -> Option<f32> {
        match self {
            FloatTexture::Constant(v) => Some(*v),
            _ => None,
        }
    }
}

impl SpectrumTexture {
    pub fn evaluate(
        &self,
        ctx: &TextureEvalContext,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        match self {
            SpectrumTexture::Constant(s) => s.sample(lambda),
            SpectrumTexture::Scale(t, s) => t.evaluate(ctx, lambda) * s.evaluate(ctx),
            SpectrumTexture::Checkerboard {
                tex1,
                tex2,
                mapping,
            } => {
                let w = checkerboard_weight(ctx, mapping);
                let t1 = if w != 1.0 {
                    tex1.evaluate(ctx, lambda)
                } else {
                    SampledSpectrum::ZERO
                };
                let t2 = if w != 0.0 {
                    tex2.evaluate(ctx, lambda)
                } else {
                    SampledSpectrum::ZERO
                };
                t1 * (1.0 - w) + t2 * w
            }
            SpectrumTexture::Image(image, kind) => image.evaluate_spectrum(ctx, *kind, lambda),
        }
    }
}

/// Named textures of the scene, created in file order (a texture may use
/// those before it), and the images they share.
#[derive(Default)]
pub struct NamedTextures {
    pub float: HashMap<String, FloatTexture>,
    /// Spectrum textures are made once per spectrum kind they are read as.
    pub spectrum: HashMap<(String, SpectrumKindKey), SpectrumTexture>,
    /// The descriptions, to create spectrum textures on demand for a kind.
    pub spectrum_entities: HashMap<String, Entity>,
    pub images: ImageCache,
}

/// `SpectrumKind` as a map key.
pub type SpectrumKindKey = u8;

fn kind_key(kind: SpectrumKind) -> SpectrumKindKey {
    match kind {
        SpectrumKind::Albedo => 0,
        SpectrumKind::Unbounded => 1,
        SpectrumKind::Illuminant => 2,
    }
}

/// Looks up texture and constant parameters while creating materials and
/// textures.
pub struct TextureParams<'a> {
    pub params: &'a ParamSet,
    pub color_space: ColorSpaceName,
    pub textures: &'a NamedTextures,
    pub base_directory: &'a Path,
}

impl TextureParams<'_> {
    pub fn float_texture(&self, name: &str, default: f32) -> Result<FloatTexture> {
        Ok(self
            .float_texture_opt(name)?
            .unwrap_or(FloatTexture::Constant(default)))
    }

    pub fn float_texture_opt(&self, name: &str) -> Result<Option<FloatTexture>> {
        let Some(p) = self
            .params
            .find(name, &[ParamType::Float, ParamType::Texture])?
        else {
            return Ok(None);
        };
        if p.ty == ParamType::Float {
            return match p.numbers() {
                [v] => Ok(Some(FloatTexture::Constant(*v as f32))),
                _ => scene_error(format!("\"float {name}\": expected one value"), &p.location),
            };
        }
        let tex_name = p.strings().first().cloned().unwrap_or_default();
        match self.textures.float.get(&tex_name) {
            Some(t) => Ok(Some(t.clone())),
            None => scene_error(
                format!("float texture \"{tex_name}\" for \"{name}\" is not defined"),
                &p.location,
            ),
        }
    }

    /// The spectrum texture or constant `name` (a named texture of the
    /// spectrum `kind`, or an `rgb`, `spectrum` or `blackbody` value), if
    /// the entity gives it.
    pub fn spectrum_texture_opt(
        &self,
        name: &str,
        kind: SpectrumKind,
    ) -> Result<Option<SpectrumTexture>> {
        if let Some(p) = self.params.find(
            name,
            &[
                ParamType::Texture,
                ParamType::Rgb,
                ParamType::Spectrum,
                ParamType::Blackbody,
            ],
        )? {
            if p.ty == ParamType::Texture {
                let tex_name = p.strings().first().cloned().unwrap_or_default();
                return match self
                    .textures
                    .spectrum
                    .get(&(tex_name.clone(), kind_key(kind)))
                {
                    Some(t) => Ok(Some(t.clone())),
                    None => scene_error(
                        format!("spectrum texture \"{tex_name}\" for \"{name}\" is not defined"),
                        &p.location,
                    ),
                };
            }
        }
        let s = spectrum_param(
            self.params,
            name,
            kind,
            self.color_space,
            self.base_directory,
        )?;
        Ok(s.map(SpectrumTexture::Constant))
    }

    /// The spectrum texture or constant `name`, `default` where the entity
    /// does not give it.
    pub fn spectrum_texture(
        &self,
        name: &str,
        default: Spectrum,
        kind: SpectrumKind,
    ) -> Result<SpectrumTexture> {
        Ok(self
            .spectrum_texture_opt(name, kind)?
            .unwrap_or(SpectrumTexture::Constant(default)))
    }
}

/// Creates a texture from its description (`render_from_texture`: the
/// transform in force at its `Texture` directive).
pub fn create_texture(
    entity: &Entity,
    value: TextureValue,
    textures: &mut NamedTextures,
    render_from_texture: Mat4,
    base_directory: &Path,
    kind: SpectrumKind,
) -> Result<Option<(Option<FloatTexture>, Option<SpectrumTexture>)>> {
    let loc = &entity.location.0;
    if entity.kind == "imagemap" {
        let image = Box::new(ImageTexture::create(
            &entity.params,
            render_from_texture,
            base_directory,
            &mut textures.images,
            loc,
        )?);
        entity
            .params
            .report_unused(|| format!("texture \"{}\"", entity.kind))?;
        return Ok(Some(match value {
            TextureValue::Float => (Some(FloatTexture::Image(image)), None),
            TextureValue::Spectrum => (None, Some(SpectrumTexture::Image(image, kind))),
        }));
    }
    let tp = TextureParams {
        params: &entity.params,
        color_space: entity.color_space,
        textures,
        base_directory,
    };
    let result = match (entity.kind.as_str(), value) {
        ("constant", TextureValue::Float) => (Some(tp.float_texture("value", 1.0)?), None),
        ("constant", TextureValue::Spectrum) => (None, Some(tp.spectrum_texture("value", Spectrum::Constant(1.0), kind)?)),
        ("scale", TextureValue::Float) => (
            Some(FloatTexture::Scale(Box::new(tp.float_texture("tex", 1.0)?), Box::new(tp.float_texture("scale", 1.0)?))),
            None,
        ),
        ("scale", TextureValue::Spectrum) => {
            let tex = tp.spectrum_texture("tex", Spectrum::Constant(1.0), kind)?;
            (None, Some(SpectrumTexture::Scale(Box::new(tex), Box::new(tp.float_texture("scale", 1.0)?))))
        }
        ("checkerboard", v) => {
            let dimension = entity.params.int("dimension", 2)?;
            if dimension != 2 {
                return scene_error("3D checkerboard textures are not supported yet", loc);
            }
            let mapping = TextureMapping2D::create(&entity.params, render_from_texture, loc)?;
            match v {
                TextureValue::Float => (
                    Some(FloatTexture::Checkerboard {
                        tex1: Box::new(tp.float_texture("tex1", 1.0)?),
                        tex2: Box::new(tp.float_texture("tex2", 0.0)?),
                        mapping,
                    }),
                    None,
                ),
                TextureValue::Spectrum => {
                    let one = SpectrumTexture::Constant(Spectrum::Constant(1.0));
                    let zero = SpectrumTexture::Constant(Spectrum::Constant(0.0));
                    (
                        None,
                        Some(SpectrumTexture::Checkerboard {
                            tex1: Box::new(tp.spectrum_texture_opt("tex1", kind)?.unwrap_or(one)),
                            tex2: Box::new(tp.spectrum_texture_opt("tex2", kind)?.unwrap_or(zero)),
                            mapping,
                        }),
                    )
                }
            }
        }
        (other, _) => {
            return scene_error(format!("texture \"{other}\" is not supported yet (supported: constant, scale, checkerboard, imagemap)"), loc)
        }
    };
    entity
        .params
        .report_unused(|| format!("texture \"{}\"", entity.kind))?;
    Ok(Some(result))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_differentials_solve_for_the_surface_parametrisation() {
        let si = SurfaceInteraction {
            dpdu: Vec3::new(2.0, 0.0, 0.0),
            dpdv: Vec3::new(1.0, 4.0, 0.0),
            ..Default::default()
        };
        // Moving by ∂p/∂u·½ + ∂p/∂v·¼ per pixel in x, by ∂p/∂v·(−½) in y.
        let ctx = TextureEvalContext::with_differentials(
            &si,
            si.dpdu * 0.5 + si.dpdv * 0.25,
            si.dpdv * -0.5,
        );
        let close = |a: f32, b: f32| (a - b).abs() < 1e-6;
        assert!(close(ctx.dudx, 0.5) && close(ctx.dvdx, 0.25), "{ctx:?}");
        assert!(close(ctx.dudy, 0.0) && close(ctx.dvdy, -0.5), "{ctx:?}");
        // A degenerate parametrisation gives zero, not NaN.
        let flat = SurfaceInteraction::default();
        let ctx = TextureEvalContext::with_differentials(&flat, Vec3::X, Vec3::Y);
        assert_eq!((ctx.dudx, ctx.dvdy), (0.0, 0.0));
    }
}
