//! Textures: values that vary over surfaces. A parameter that takes a
//! texture may also be given as a constant value.
//!
//! `constant` (`value`, default 1) and `scale` (`tex` × `scale`, both
//! default 1) are here; every other texture has its own file (`bilerp`,
//! `checkerboard`, `directionmix`, `dots`, `fbm`, `imagemap`, `marble`,
//! `mix`, `windy`, `wrinkled`), as do the 2D and 3D texture mappings and
//! Perlin noise. Textures that combine others (checkerboard, dots, mix,
//! directionmix) are generic over [`TextureOf`], so one type serves the
//! float and the spectrum variant; `fbm`, `wrinkled` and `windy` are
//! float-only and `marble` spectrum-only, as in pbrt-v4.

pub mod bilerp;
pub mod checkerboard;
pub mod direction_mix;
pub mod dots;
pub mod fbm;
pub mod image_map;
pub mod mapping;
pub mod mapping_3d;
pub mod marble;
pub mod mix;
pub mod noise;
pub mod windy;
pub mod wrinkled;

use crate::error::{scene_error, Result};
use crate::interaction::SurfaceInteraction;
use crate::scene_description::ParamSet;
use crate::scene_description::{ColorSpaceName, Entity, TextureValue};
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::parameter::spectrum_param;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use bilerp::BilerpTexture;
use checkerboard::CheckerboardTexture;
use direction_mix::DirectionMixTexture;
use dots::DotsTexture;
use fbm::FbmTexture;
use glam::{Mat4, Vec2, Vec3};
pub use image_map::{ImageCache, ImageTexture};
pub use mapping::TextureMapping2D;
use marble::MarbleTexture;
use mix::MixTexture;
use pbrt_parser::ParamType;
use std::collections::HashMap;
use std::path::Path;
use windy::WindyTexture;
use wrinkled::WrinkledTexture;

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
    Checkerboard(CheckerboardTexture<FloatTexture>),
    Image(Box<ImageTexture>),
    Bilerp(Box<BilerpTexture<f32>>),
    Dots(Box<DotsTexture<FloatTexture>>),
    Mix(MixTexture<FloatTexture>),
    DirectionMix(DirectionMixTexture<FloatTexture>),
    Fbm(FbmTexture),
    Wrinkled(WrinkledTexture),
    Windy(WindyTexture),
}

/// A spectrum-valued texture (made for one spectrum kind).
#[derive(Clone, Debug)]
pub enum SpectrumTexture {
    Constant(Spectrum),
    Scale(Box<SpectrumTexture>, Box<FloatTexture>),
    Checkerboard(CheckerboardTexture<SpectrumTexture>),
    Image(Box<ImageTexture>, SpectrumKind),
    Bilerp(Box<BilerpTexture<Spectrum>>),
    Dots(Box<DotsTexture<SpectrumTexture>>),
    Mix(MixTexture<SpectrumTexture>),
    DirectionMix(DirectionMixTexture<SpectrumTexture>),
    Marble(Box<MarbleTexture>),
}

/// What float and spectrum textures share, so that the textures combining
/// others are written once for both.
pub trait TextureOf: Sized {
    /// The texture given for parameter `name` (a texture or a constant),
    /// else the constant `default`; spectra are read as `kind`.
    fn parameter(tp: &TextureParams, name: &str, default: f32, kind: SpectrumKind) -> Result<Self>;
}

impl TextureOf for FloatTexture {
    fn parameter(tp: &TextureParams, name: &str, default: f32, _: SpectrumKind) -> Result<Self> {
        tp.float_texture(name, default)
    }
}

impl TextureOf for SpectrumTexture {
    fn parameter(tp: &TextureParams, name: &str, default: f32, kind: SpectrumKind) -> Result<Self> {
        tp.spectrum_texture(name, Spectrum::Constant(default), kind)
    }
}

/// wa·a + wb·b, evaluating each texture only where its weight is non-zero
/// (as pbrt-v4: it saves lookups, and an unused side's infinite or NaN
/// value stays out).
fn blend_float(
    (wa, wb): (f32, f32),
    a: &FloatTexture,
    b: &FloatTexture,
    ctx: &TextureEvalContext,
) -> f32 {
    let va = if wa != 0.0 { a.evaluate(ctx) } else { 0.0 };
    let vb = if wb != 0.0 { b.evaluate(ctx) } else { 0.0 };
    wa * va + wb * vb
}

/// [`blend_float`] for spectrum textures.
fn blend_spectrum(
    (wa, wb): (f32, f32),
    a: &SpectrumTexture,
    b: &SpectrumTexture,
    ctx: &TextureEvalContext,
    lambda: &SampledWavelengths,
) -> SampledSpectrum {
    let va = if wa != 0.0 {
        a.evaluate(ctx, lambda)
    } else {
        SampledSpectrum::ZERO
    };
    let vb = if wb != 0.0 {
        b.evaluate(ctx, lambda)
    } else {
        SampledSpectrum::ZERO
    };
    va * wa + vb * wb
}

impl FloatTexture {
    pub fn evaluate(&self, ctx: &TextureEvalContext) -> f32 {
        match self {
            FloatTexture::Constant(v) => *v,
            FloatTexture::Scale(t, s) => t.evaluate(ctx) * s.evaluate(ctx),
            FloatTexture::Checkerboard(c) => blend_float(c.weights(ctx), &c.tex1, &c.tex2, ctx),
            FloatTexture::Image(image) => image.evaluate_float(ctx),
            FloatTexture::Bilerp(b) => b.evaluate(ctx),
            FloatTexture::Dots(d) => d.select(ctx).evaluate(ctx),
            FloatTexture::Mix(m) => blend_float(m.weights(ctx), &m.tex1, &m.tex2, ctx),
            FloatTexture::DirectionMix(m) => blend_float(m.weights(ctx), &m.tex1, &m.tex2, ctx),
            FloatTexture::Fbm(t) => t.evaluate(ctx),
            FloatTexture::Wrinkled(t) => t.evaluate(ctx),
            FloatTexture::Windy(t) => t.evaluate(ctx),
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
            SpectrumTexture::Checkerboard(c) => {
                blend_spectrum(c.weights(ctx), &c.tex1, &c.tex2, ctx, lambda)
            }
            SpectrumTexture::Image(image, kind) => image.evaluate_spectrum(ctx, *kind, lambda),
            SpectrumTexture::Bilerp(b) => b
                .weights(ctx)
                .iter()
                .zip(&b.values)
                .fold(SampledSpectrum::ZERO, |sum, (w, v)| {
                    sum + v.sample(lambda) * *w
                }),
            SpectrumTexture::Dots(d) => d.select(ctx).evaluate(ctx, lambda),
            SpectrumTexture::Mix(m) => {
                blend_spectrum(m.weights(ctx), &m.tex1, &m.tex2, ctx, lambda)
            }
            SpectrumTexture::DirectionMix(m) => {
                blend_spectrum(m.weights(ctx), &m.tex1, &m.tex2, ctx, lambda)
            }
            SpectrumTexture::Marble(m) => m.evaluate(ctx, lambda),
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
        let tex_name = p
            .strings()
            .first()
            .map_or_else(String::new, |s| s.to_string());
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
                let tex_name = p
                    .strings()
                    .first()
                    .map_or_else(String::new, |s| s.to_string());
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
        ("checkerboard", TextureValue::Float) => (Some(FloatTexture::Checkerboard(CheckerboardTexture::create(&tp, render_from_texture, kind, loc)?)), None),
        ("checkerboard", TextureValue::Spectrum) => (None, Some(SpectrumTexture::Checkerboard(CheckerboardTexture::create(&tp, render_from_texture, kind, loc)?))),
        ("dots", TextureValue::Float) => (Some(FloatTexture::Dots(Box::new(DotsTexture::create(&tp, render_from_texture, kind, loc)?))), None),
        ("dots", TextureValue::Spectrum) => (None, Some(SpectrumTexture::Dots(Box::new(DotsTexture::create(&tp, render_from_texture, kind, loc)?)))),
        ("mix", TextureValue::Float) => (Some(FloatTexture::Mix(MixTexture::create(&tp, kind)?)), None),
        ("mix", TextureValue::Spectrum) => (None, Some(SpectrumTexture::Mix(MixTexture::create(&tp, kind)?))),
        ("directionmix", TextureValue::Float) => (Some(FloatTexture::DirectionMix(DirectionMixTexture::create(&tp, render_from_texture, kind, loc)?)), None),
        ("directionmix", TextureValue::Spectrum) => (None, Some(SpectrumTexture::DirectionMix(DirectionMixTexture::create(&tp, render_from_texture, kind, loc)?))),
        ("bilerp", TextureValue::Float) => {
            let value = |name: &str, default: f32| -> Result<f32> { Ok(entity.params.float(name, default as f64)? as f32) };
            (Some(FloatTexture::Bilerp(Box::new(BilerpTexture::create(&entity.params, render_from_texture, loc, value)?))), None)
        }
        ("bilerp", TextureValue::Spectrum) => {
            let value = |name: &str, default: f32| -> Result<Spectrum> {
                Ok(spectrum_param(&entity.params, name, kind, entity.color_space, base_directory)?.unwrap_or(Spectrum::Constant(default)))
            };
            (None, Some(SpectrumTexture::Bilerp(Box::new(BilerpTexture::create(&entity.params, render_from_texture, loc, value)?))))
        }
        ("fbm", TextureValue::Float) => (Some(FloatTexture::Fbm(FbmTexture::create(&entity.params, render_from_texture, loc)?)), None),
        ("wrinkled", TextureValue::Float) => (Some(FloatTexture::Wrinkled(WrinkledTexture::create(&entity.params, render_from_texture, loc)?)), None),
        ("windy", TextureValue::Float) => (Some(FloatTexture::Windy(WindyTexture::create(render_from_texture))), None),
        ("marble", TextureValue::Spectrum) => (None, Some(SpectrumTexture::Marble(Box::new(MarbleTexture::create(&entity.params, render_from_texture, loc)?)))),
        (kind @ ("fbm" | "wrinkled" | "windy"), TextureValue::Spectrum) => {
            return scene_error(format!("\"{kind}\" is a float texture (pbrt-v4 has no spectrum \"{kind}\")"), loc)
        }
        ("marble", TextureValue::Float) => {
            return scene_error("\"marble\" is a spectrum texture (pbrt-v4 has no float \"marble\")", loc)
        }
        (other, _) => {
            return scene_error(format!("texture \"{other}\" is not supported yet (supported: constant, scale, checkerboard, imagemap, bilerp, dots, mix, directionmix, fbm, wrinkled, windy, marble)"), loc)
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

    /// The named textures of a scene given as text (after `WorldBegin`),
    /// created as the renderer does, with the error of the first that fails.
    fn scene_textures(world: &str) -> Result<NamedTextures> {
        let text = format!("Camera \"perspective\"\nWorldBegin\n{world}");
        let loaded = crate::scene::load_text(Path::new("t.pbrt"), &text)?;
        let mut textures = NamedTextures::default();
        for t in &loaded.scene.textures {
            let render_from_texture = t.world_from_texture.to_mat4();
            if let Some((f, s)) = create_texture(
                &t.entity,
                t.value,
                &mut textures,
                render_from_texture,
                Path::new("."),
                SpectrumKind::Albedo,
            )? {
                if let Some(f) = f {
                    textures.float.insert(t.name.clone(), f);
                }
                if let Some(s) = s {
                    textures
                        .spectrum
                        .insert((t.name.clone(), kind_key(SpectrumKind::Albedo)), s);
                }
            }
        }
        Ok(textures)
    }

    fn float_at(textures: &NamedTextures, name: &str, ctx: &TextureEvalContext) -> f32 {
        textures.float[name].evaluate(ctx)
    }

    fn at_uv(u: f32, v: f32) -> TextureEvalContext {
        TextureEvalContext {
            uv: Vec2::new(u, v),
            n: Vec3::Z,
            ..Default::default()
        }
    }

    #[test]
    fn mix_blends_by_amount_with_pbrt_defaults() {
        let t = scene_textures(
            "Texture \"ramp\" \"float\" \"bilerp\"\n\
             Texture \"m\" \"float\" \"mix\" \"float tex1\" 2 \"float tex2\" 6 \"texture amount\" \"ramp\"\n\
             Texture \"d\" \"float\" \"mix\"\n\
             Texture \"s\" \"spectrum\" \"mix\" \"rgb tex1\" [0.2 0.2 0.2] \"float amount\" 0.25",
        )
        .unwrap();
        // bilerp's defaults (0, 0, 1, 1) make amount = v.
        assert_eq!(float_at(&t, "m", &at_uv(0.7, 0.0)), 2.0);
        assert_eq!(float_at(&t, "m", &at_uv(0.7, 1.0)), 6.0);
        assert_eq!(float_at(&t, "m", &at_uv(0.2, 0.25)), 3.0);
        // tex1 0, tex2 1, amount ½.
        assert_eq!(float_at(&t, "d", &at_uv(0.3, 0.3)), 0.5);
        // 0.75·(0.2 reflectance) + 0.25·(constant 1).
        let lambda = SampledWavelengths::sample_visible(0.3);
        let s = t.spectrum[&("s".to_string(), 0)].evaluate(&at_uv(0.0, 0.0), &lambda);
        let grey = Spectrum::Constant(1.0);
        for i in 0..4 {
            let expected = 0.75 * 0.2 + 0.25 * grey.sample(&lambda)[i];
            assert!((s[i] - expected).abs() < 0.01, "{} vs {expected}", s[i]);
        }
    }

    #[test]
    fn directionmix_weights_by_the_normal_along_dir() {
        let t = scene_textures(
            "Texture \"d\" \"float\" \"directionmix\" \"float tex1\" 10 \"float tex2\" 20 \"vector3 dir\" [0 0 2]\n\
             Rotate 90 1 0 0\n\
             Texture \"r\" \"float\" \"directionmix\" \"float tex1\" 10 \"float tex2\" 20",
        )
        .unwrap();
        let with_normal = |n: Vec3| TextureEvalContext {
            n: n.normalize(),
            ..Default::default()
        };
        assert_eq!(float_at(&t, "d", &with_normal(Vec3::Z)), 10.0);
        assert_eq!(float_at(&t, "d", &with_normal(Vec3::NEG_Z)), 10.0);
        assert_eq!(float_at(&t, "d", &with_normal(Vec3::X)), 20.0);
        // |n·dir| = cos 60° = ½.
        let n = Vec3::new(3f32.sqrt(), 0.0, 1.0);
        assert!((float_at(&t, "d", &with_normal(n)) - 15.0).abs() < 1e-5);
        // The default dir (0, 1, 0), in the texture's coordinate system:
        // rotated 90° about x, it is render-space +z.
        assert!((float_at(&t, "r", &with_normal(Vec3::Z)) - 10.0).abs() < 1e-5);
        assert!((float_at(&t, "r", &with_normal(Vec3::Y)) - 20.0).abs() < 1e-5);
    }

    #[test]
    fn bilerp_reads_its_corner_values() {
        let t = scene_textures(
            "Texture \"b\" \"float\" \"bilerp\" \"float v00\" 1 \"float v10\" 2 \"float v01\" 3 \"float v11\" 4 \"float uscale\" 2",
        )
        .unwrap();
        // s = 2u.
        assert_eq!(float_at(&t, "b", &at_uv(0.0, 0.0)), 1.0);
        assert_eq!(float_at(&t, "b", &at_uv(0.5, 0.0)), 2.0);
        assert_eq!(float_at(&t, "b", &at_uv(0.25, 0.5)), 2.5);
        assert_eq!(float_at(&t, "b", &at_uv(0.5, 1.0)), 4.0);
    }

    /// pbrt-v4 shows `outside` in the dots and `inside` between them.
    #[test]
    fn dots_show_the_values_as_pbrt_v4_does() {
        let t = scene_textures(
            "Texture \"d\" \"float\" \"dots\" \"float inside\" 5 \"float outside\" 7\n\
             Texture \"default\" \"float\" \"dots\"",
        )
        .unwrap();
        let mut seen = (false, false);
        for i in 0..40 {
            let (u, v) = (i as f32 * 0.37, i as f32 * 0.61);
            let in_dot = dots::inside_polka_dot(Vec2::new(u, v));
            let value = float_at(&t, "d", &at_uv(u, v));
            assert_eq!(value, if in_dot { 7.0 } else { 5.0 });
            let default = float_at(&t, "default", &at_uv(u, v));
            assert_eq!(default, if in_dot { 0.0 } else { 1.0 });
            if in_dot {
                seen.0 = true;
            } else {
                seen.1 = true;
            }
        }
        assert!(seen.0 && seen.1);
    }

    /// A 3D checkerboard in the coordinate system of its directive.
    #[test]
    fn solid_checkerboard_from_a_scene() {
        let t = scene_textures(
            "Scale 0.5 0.5 0.5\n\
             Texture \"c\" \"float\" \"checkerboard\" \"integer dimension\" 3 \"float tex1\" 3 \"float tex2\" 4",
        )
        .unwrap();
        let at = |p: Vec3| TextureEvalContext {
            p,
            ..Default::default()
        };
        // Texture-space cells are half a unit wide in render space.
        assert_eq!(float_at(&t, "c", &at(Vec3::new(0.25, 0.25, 0.25))), 3.0);
        assert_eq!(float_at(&t, "c", &at(Vec3::new(0.75, 0.25, 0.25))), 4.0);
        assert_eq!(float_at(&t, "c", &at(Vec3::new(0.75, 0.75, 0.25))), 3.0);
        assert_eq!(float_at(&t, "c", &at(Vec3::new(-0.25, 0.25, 0.25))), 4.0);
    }

    #[test]
    fn noise_textures_are_created_with_their_kinds() {
        let t = scene_textures(
            "Texture \"f\" \"float\" \"fbm\" \"integer octaves\" 4 \"float roughness\" 0.7\n\
             Texture \"w\" \"float\" \"wrinkled\"\n\
             Texture \"y\" \"float\" \"windy\"\n\
             Texture \"m\" \"spectrum\" \"marble\" \"float scale\" 3 \"float variation\" 0.5",
        )
        .unwrap();
        assert!(matches!(&t.float["f"], FloatTexture::Fbm(f) if f.octaves == 4 && f.omega == 0.7));
        assert!(
            matches!(&t.float["w"], FloatTexture::Wrinkled(w) if w.octaves == 8 && w.omega == 0.5)
        );
        assert!(matches!(&t.float["y"], FloatTexture::Windy(_)));
        assert!(matches!(
            &t.spectrum[&("m".to_string(), 0)],
            SpectrumTexture::Marble(m) if m.scale == 3.0 && m.variation == 0.5 && m.octaves == 8
        ));
    }

    /// Bad values, the wrong kind of value, and parameters a texture does
    /// not have are errors at the texture's or the parameter's file:line:col.
    #[test]
    fn bad_textures_are_located_errors() {
        for (text, message) in [
            ("Texture \"f\" \"spectrum\" \"fbm\"", "float texture"),
            ("Texture \"f\" \"float\" \"marble\"", "spectrum texture"),
            (
                "Texture \"f\" \"float\" \"checkerboard\" \"integer dimension\" 4",
                "dimension",
            ),
            (
                "Texture \"f\" \"float\" \"fbm\" \"integer octaves\" -2",
                "octaves",
            ),
            (
                "Texture \"f\" \"float\" \"wrinkled\" \"float uscale\" 2",
                "uscale",
            ),
            (
                "Texture \"f\" \"float\" \"directionmix\" \"vector3 dir\" [0 0 0]",
                "dir",
            ),
            (
                "Texture \"f\" \"float\" \"bilerp\" \"texture v00\" \"x\"",
                "v00",
            ),
            (
                "Texture \"f\" \"float\" \"dots\" \"string mapping\" \"cubic\"",
                "cubic",
            ),
        ] {
            let err = scene_textures(text).err().expect(text).to_string();
            assert!(err.contains("t.pbrt:3:"), "{text}: {err}");
            assert!(err.contains(message), "{text}: {err}");
        }
    }
}
