//! Textures: values that vary over surfaces. A parameter that takes a
//! texture may also be given as a constant value.

use crate::error::{scene_error, Result};
use crate::scene::description::{ColorSpaceName, Entity, TextureValue};
use crate::scene::spectrum_param::spectrum_param;
use crate::scene::ParamSet;
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec2;
use pbrt_parser::ParamType;
use std::collections::HashMap;
use std::path::Path;

/// Where a texture is evaluated.
#[derive(Clone, Copy, Debug, Default)]
pub struct TextureEvalContext {
    pub uv: Vec2,
}

/// A float-valued texture.
#[derive(Clone, Debug)]
pub enum FloatTexture {
    Constant(f32),
    /// `tex × scale`.
    Scale(Box<FloatTexture>, Box<FloatTexture>),
    /// 2D checkerboard over (u, v) scaled by `uscale`, `vscale`.
    Checkerboard {
        tex1: Box<FloatTexture>,
        tex2: Box<FloatTexture>,
        scale: Vec2,
        delta: Vec2,
    },
}

/// A spectrum-valued texture.
#[derive(Clone, Debug)]
pub enum SpectrumTexture {
    Constant(Spectrum),
    Scale(Box<SpectrumTexture>, Box<FloatTexture>),
    Checkerboard {
        tex1: Box<SpectrumTexture>,
        tex2: Box<SpectrumTexture>,
        scale: Vec2,
        delta: Vec2,
    },
}

fn checker(ctx: &TextureEvalContext, scale: Vec2, delta: Vec2) -> bool {
    let st = ctx.uv * scale + delta;
    ((st.x.floor() as i64 + st.y.floor() as i64) & 1) == 0
}

impl FloatTexture {
    pub fn evaluate(&self, ctx: &TextureEvalContext) -> f32 {
        match self {
            FloatTexture::Constant(v) => *v,
            FloatTexture::Scale(t, s) => t.evaluate(ctx) * s.evaluate(ctx),
            FloatTexture::Checkerboard {
                tex1,
                tex2,
                scale,
                delta,
            } => {
                if checker(ctx, *scale, *delta) {
                    tex1.evaluate(ctx)
                } else {
                    tex2.evaluate(ctx)
                }
            }
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
                scale,
                delta,
            } => {
                if checker(ctx, *scale, *delta) {
                    tex1.evaluate(ctx, lambda)
                } else {
                    tex2.evaluate(ctx, lambda)
                }
            }
        }
    }
}

/// Named textures of the scene, created in file order (a texture may use
/// those before it).
#[derive(Default)]
pub struct NamedTextures {
    pub float: HashMap<String, FloatTexture>,
    /// Spectrum textures are made once per spectrum kind they are read as.
    pub spectrum: HashMap<(String, SpectrumKindKey), SpectrumTexture>,
    /// The descriptions, to create spectrum textures on demand for a kind.
    pub spectrum_entities: HashMap<String, Entity>,
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

    pub fn spectrum_texture(
        &self,
        name: &str,
        default: Option<Spectrum>,
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
        Ok(s.or(default).map(SpectrumTexture::Constant))
    }
}

/// Creates a texture from its description.
pub fn create_texture(
    entity: &Entity,
    value: TextureValue,
    textures: &NamedTextures,
    base_directory: &Path,
    kind: SpectrumKind,
) -> Result<Option<(Option<FloatTexture>, Option<SpectrumTexture>)>> {
    let tp = TextureParams {
        params: &entity.params,
        color_space: entity.color_space,
        textures,
        base_directory,
    };
    let loc = &entity.location.0;
    let uv_scale = |p: &ParamSet| -> Result<(Vec2, Vec2)> {
        Ok((
            Vec2::new(
                p.float("uscale", 1.0)? as f32,
                p.float("vscale", 1.0)? as f32,
            ),
            Vec2::new(
                p.float("udelta", 0.0)? as f32,
                p.float("vdelta", 0.0)? as f32,
            ),
        ))
    };
    let mapping = entity.params.string("mapping", "uv")?;
    if mapping != "uv" {
        return scene_error(
            format!("texture mapping \"{mapping}\" is not supported yet (supported: uv)"),
            loc,
        );
    }
    let result = match (entity.kind.as_str(), value) {
        ("constant", TextureValue::Float) => (Some(tp.float_texture("value", 1.0)?), None),
        ("constant", TextureValue::Spectrum) => (None, tp.spectrum_texture("value", Some(Spectrum::Constant(1.0)), kind)?),
        ("scale", TextureValue::Float) => (
            Some(FloatTexture::Scale(Box::new(tp.float_texture("tex", 1.0)?), Box::new(tp.float_texture("scale", 1.0)?))),
            None,
        ),
        ("scale", TextureValue::Spectrum) => {
            let tex = tp.spectrum_texture("tex", Some(Spectrum::Constant(1.0)), kind)?.unwrap_or(SpectrumTexture::Constant(Spectrum::Constant(1.0)));
            (None, Some(SpectrumTexture::Scale(Box::new(tex), Box::new(tp.float_texture("scale", 1.0)?))))
        }
        ("checkerboard", v) => {
            let dimension = entity.params.int("dimension", 2)?;
            if dimension != 2 {
                return scene_error("3D checkerboard textures are not supported yet", loc);
            }
            let (scale, delta) = uv_scale(&entity.params)?;
            match v {
                TextureValue::Float => (
                    Some(FloatTexture::Checkerboard {
                        tex1: Box::new(tp.float_texture("tex1", 1.0)?),
                        tex2: Box::new(tp.float_texture("tex2", 0.0)?),
                        scale,
                        delta,
                    }),
                    None,
                ),
                TextureValue::Spectrum => {
                    let one = SpectrumTexture::Constant(Spectrum::Constant(1.0));
                    let zero = SpectrumTexture::Constant(Spectrum::Constant(0.0));
                    (
                        None,
                        Some(SpectrumTexture::Checkerboard {
                            tex1: Box::new(tp.spectrum_texture("tex1", None, kind)?.unwrap_or(one)),
                            tex2: Box::new(tp.spectrum_texture("tex2", None, kind)?.unwrap_or(zero)),
                            scale,
                            delta,
                        }),
                    )
                }
            }
        }
        (other, _) => {
            return scene_error(format!("texture \"{other}\" is not supported yet (supported: constant, scale, checkerboard)"), loc)
        }
    };
    Ok(Some(result))
}
