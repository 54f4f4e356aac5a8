//! Materials: textures and parameters → a BSDF at a surface point.
//!
//! | material | parameters (pbrt-v4 defaults) |
//! |---|---|
//! | `diffuse` | `reflectance` 0.5 |
//! | `conductor` | `eta` metal-Cu-eta, `k` metal-Cu-k, or `reflectance`; `roughness` 0 (or `uroughness`/`vroughness`); `remaproughness` true |
//! | `dielectric` | `eta` 1.5 (float or spectrum); `roughness` 0; `remaproughness` true |
//! | `thindielectric` | `eta` 1.5 |
//! | `coateddiffuse` | `reflectance` 0.5, `roughness` 0, `thickness` 0.01, `eta` 1.5, `albedo` 0, `g` 0, `maxdepth` 10, `nsamples` 1, `remaproughness` true |
//! | `coatedconductor` | `interface.roughness` 0 (or `interface.uroughness`/`interface.vroughness`), `interface.eta` 1.5 (float or spectrum), `thickness` 0.01, `conductor.eta` metal-Cu-eta, `conductor.k` metal-Cu-k, or `reflectance` (not with them); `conductor.roughness` 0 (or `conductor.uroughness`/`conductor.vroughness`), `albedo` 0, `g` 0 (clamped to [−1, 1]), `maxdepth` 10, `nsamples` 1, `remaproughness` true |
//! | `mix` | `materials` (two named materials), `amount` 0.5: see [`mix`] |
//! | `diffusetransmission` | `reflectance` 0.25, `transmittance` 0.25, `scale` 1 |
//! | `hair` | `sigma_a`, or `reflectance` (alias `color`), or `eumelanin`/`pheomelanin` (default eumelanin 1.3 when none is given); `eta` 1.55, `beta_m` 0.3, `beta_n` 0.3 (both clamped to [0.01, 1]), `alpha` 2° |
//! | `hair` (dual model) | `ellipse_a`, `ellipse_b`, `d_diff`, `ellipse_orientation`, `diffraction`, `variant`, `internal_fresnel`, `fresnel`, `residual`: see [`dual_hair`] |
//! | `measured` | `filename`: an RGL database `.bsdf` file: see [`measured`] |
//! | `interface` | none: marks a boundary between media; rays pass through |
//!
//! All but `interface`, `hair` and `mix` also take `displacement` (a bump
//! map) and `normalmap` (a normal map): see [`shading_normal`]; such a
//! material is wrapped in [`Material::Bumped`].
//!
//! Under `Option "forcediffuse" true` every material but `interface` is
//! wrapped in [`Material::ForceDiffuse`] ([`force_diffuse`]).

use crate::bxdfs::dual_hair::{axis_from_reference, DualHairBxDF, DualHairParams};
use crate::bxdfs::hair::{CircularHairBxDF, HairBxDF, HairLobes};
use crate::bxdfs::{
    BxDF, CoatedConductorBxDF, CoatedDiffuseBxDF, ConductorBxDF, DielectricBxDF, DiffuseBxDF,
    DiffuseTransmissionBxDF, ThinDielectricBxDF, TrowbridgeReitzDistribution, BSDF,
};
use crate::error::{scene_error, Result};
use crate::interaction::SurfaceInteraction;
use crate::scene_description::ColorSpaceName;
use crate::scene_description::Entity;
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::{named_spectrum, SampledSpectrum, SampledWavelengths, Spectrum};
use crate::textures::{
    FloatTexture, NamedTextures, SpectrumTexture, TextureEvalContext, TextureParams,
};
use normal_map::NormalMapCache;
use shading_normal::{Bumped, ShadingNormal};
use std::path::Path;

pub mod bump_map;
pub mod dual_hair;
pub mod force_diffuse;
pub mod measured;
pub mod mix;
pub mod normal_map;
pub mod shading_normal;

/// Roughness given as (u, v) textures, remapped to α or not.
#[derive(Clone, Debug)]
pub struct Roughness {
    pub u: FloatTexture,
    pub v: FloatTexture,
    pub remap: bool,
}

impl Roughness {
    fn read(tp: &TextureParams, prefix: &str, default: f32) -> Result<Self> {
        let r = tp.float_texture_opt(&format!("{prefix}roughness"))?;
        let u = tp.float_texture_opt(&format!("{prefix}uroughness"))?;
        let v = tp.float_texture_opt(&format!("{prefix}vroughness"))?;
        let base = r.unwrap_or(FloatTexture::Constant(default));
        Ok(Roughness {
            u: u.unwrap_or_else(|| base.clone()),
            v: v.unwrap_or(base),
            remap: tp.params.bool("remaproughness", true)?,
        })
    }

    fn distribution(&self, ctx: &TextureEvalContext) -> TrowbridgeReitzDistribution {
        let (mut u, mut v) = (self.u.evaluate(ctx), self.v.evaluate(ctx));
        if self.remap {
            u = TrowbridgeReitzDistribution::roughness_to_alpha(u);
            v = TrowbridgeReitzDistribution::roughness_to_alpha(v);
        }
        TrowbridgeReitzDistribution::new(u, v)
    }
}

/// An index of refraction: a constant or a spectrum.
#[derive(Clone, Debug)]
pub enum Eta {
    Constant(f32),
    Spectrum(Spectrum),
}

#[derive(Clone, Debug)]
pub enum Material {
    Interface,
    Diffuse {
        reflectance: SpectrumTexture,
    },
    DiffuseTransmission {
        reflectance: SpectrumTexture,
        transmittance: SpectrumTexture,
        scale: f32,
    },
    Conductor {
        eta: SpectrumTexture,
        k: SpectrumTexture,
        reflectance: Option<SpectrumTexture>,
        roughness: Roughness,
    },
    Dielectric {
        eta: Eta,
        roughness: Roughness,
    },
    ThinDielectric {
        eta: Eta,
    },
    Hair {
        sigma_a: Option<SpectrumTexture>,
        reflectance: Option<SpectrumTexture>,
        eumelanin: Option<FloatTexture>,
        pheomelanin: Option<FloatTexture>,
        eta: FloatTexture,
        beta_m: FloatTexture,
        beta_n: FloatTexture,
        alpha: FloatTexture,
        /// The roughness and tilt terms, made once when β_m, β_n and α are
        /// constant.
        lobes: Option<HairLobes>,
        /// The dual model's parameters and ellipse orientation (cos, sin);
        /// `None` is pbrt-v4's hair.
        dual: Option<(DualHairParams, glam::Vec2)>,
        /// Where a strand's reference across the fibre comes from.
        axis_frame: dual_hair::AxisFrame,
    },
    CoatedDiffuse {
        reflectance: SpectrumTexture,
        albedo: SpectrumTexture,
        roughness: Roughness,
        thickness: FloatTexture,
        g: FloatTexture,
        eta: Eta,
        max_depth: u32,
        n_samples: u32,
    },
    CoatedConductor(Box<CoatedConductor>),
    /// A measured BRDF ([`measured`]).
    Measured(measured::MeasuredMaterial),
    /// One of two materials, chosen per hit ([`mix`]).
    Mix(Box<mix::MixMaterial>),
    /// pbrt-v4's `forcediffuse`: the material's BSDF replaced by a diffuse
    /// one of its albedo ([`force_diffuse`]). The shapes stay as the
    /// material makes them (a dual hair fibre keeps its widened curve and
    /// its orientation), but no BSDF has a diffracting ring.
    ForceDiffuse(Box<Material>),
    /// A material whose shading normal comes from a bump or normal map
    /// ([`shading_normal`]).
    Bumped(Box<Bumped>),
}

/// A dielectric coating over a conductor (pbrt-v4's `coatedconductor`).
#[derive(Clone, Debug)]
pub struct CoatedConductor {
    pub interface_roughness: Roughness,
    pub interface_eta: Eta,
    pub thickness: FloatTexture,
    pub conductor_eta: SpectrumTexture,
    pub conductor_k: SpectrumTexture,
    /// Replaces η and k when given.
    pub reflectance: Option<SpectrumTexture>,
    pub conductor_roughness: Roughness,
    pub albedo: SpectrumTexture,
    pub g: FloatTexture,
    pub max_depth: u32,
    pub n_samples: u32,
}

/// A conductor's η and k: given, or (pbrt-v4) from a reflectance r as
/// η = 1, k = 2√r / √(1 − r), r clamped below 1.
fn conductor_eta_k(
    eta: &SpectrumTexture,
    k: &SpectrumTexture,
    reflectance: &Option<SpectrumTexture>,
    ctx: &TextureEvalContext,
    lambda: &SampledWavelengths,
) -> (SampledSpectrum, SampledSpectrum) {
    match reflectance {
        Some(r) => {
            let r = r.evaluate(ctx, lambda).map(|v| v.clamp(0.0, 0.9999));
            (
                SampledSpectrum::ONE,
                (r.sqrt() * 2.0) / (SampledSpectrum::ONE - r).sqrt(),
            )
        }
        None => (eta.evaluate(ctx, lambda), k.evaluate(ctx, lambda)),
    }
}

fn eta_param(tp: &TextureParams, name: &str) -> Result<Eta> {
    use pbrt_parser::ParamType;
    if let Some(p) = tp.params.find(
        name,
        &[
            ParamType::Float,
            ParamType::Spectrum,
            ParamType::Rgb,
            ParamType::Blackbody,
            ParamType::Texture,
        ],
    )? {
        match p.ty {
            ParamType::Float => {
                return Ok(Eta::Constant(
                    p.numbers().first().copied().unwrap_or(1.5) as f32
                ))
            }
            ParamType::Spectrum => {
                if let Some(s) = crate::spectrum::parameter::spectrum_param(
                    tp.params,
                    name,
                    SpectrumKind::Unbounded,
                    tp.color_space,
                    tp.base_directory,
                )? {
                    // A constant spectrum is a constant index.
                    if let Spectrum::Constant(c) = s {
                        return Ok(Eta::Constant(c));
                    }
                    return Ok(Eta::Spectrum(s));
                }
            }
            _ => {
                return scene_error(
                    format!(
                        "\"{} {name}\": the index of refraction must be a float or a spectrum",
                        p.ty.name()
                    ),
                    &p.location,
                )
            }
        }
    }
    Ok(Eta::Constant(1.5))
}

/// The hair absorption σ_a of eumelanin and pheomelanin concentrations
/// (pbrt-v4: an sRGB colour made an unbounded spectrum).
fn melanin_sigma_a(eumelanin: f32, pheomelanin: f32) -> Spectrum {
    let rgb = HairBxDF::sigma_a_from_concentration(eumelanin, pheomelanin);
    crate::spectrum::color_space::get(ColorSpaceName::Srgb)
        .rgb_to_spectrum(glam::Vec3::from(rgb), SpectrumKind::Unbounded)
}

impl Material {
    /// How much wider than written this material's curves are: 1 + d_diff
    /// for the dual hair model's diffracting outer cylinder, else 1.
    pub fn curve_width_scale(&self) -> f32 {
        match self {
            Material::ForceDiffuse(inner) => inner.curve_width_scale(),
            Material::Bumped(bumped) => bumped.material.curve_width_scale(),
            Material::Hair {
                dual: Some((params, _)),
                ..
            } => 1.0 + params.d_diff,
            _ => 1.0,
        }
    }

    /// The dual hair model's parameters, if the material is that model.
    pub fn dual_hair(&self) -> Option<&DualHairParams> {
        match self {
            Material::Hair {
                dual: Some((params, _)),
                ..
            } => Some(params),
            _ => None,
        }
    }

    /// Where an elliptical fibre's strands take their reference across the
    /// fibre from, if the material needs one ([`Self::needs_fibre_frame`]).
    pub fn axis_frame(&self) -> Option<&dual_hair::AxisFrame> {
        match self {
            Material::ForceDiffuse(inner) => inner.axis_frame(),
            Material::Bumped(bumped) => bumped.material.axis_frame(),
            Material::Hair { axis_frame, .. } if self.needs_fibre_frame() => Some(axis_frame),
            _ => None,
        }
    }

    /// Whether the material is the dual hair model with a diffracting
    /// ring (d_diff > 0).
    pub fn has_diffracting_ring(&self) -> bool {
        matches!(self, Material::Hair { dual: Some((params, _)), .. } if params.d_diff > 0.0)
    }

    /// Whether `bsdf` always gives a BSDF with a non-specular lobe (so a
    /// path tracer always samples a light at its hits): hair, whose lobes
    /// are all glossy.
    pub fn always_non_specular(&self) -> bool {
        matches!(self, Material::Hair { .. })
    }

    /// Whether the material can scatter perfectly specularly (a smooth
    /// conductor, dielectric or coating: constant roughness whose α is
    /// below pbrt-v4's "effectively smooth" 10⁻³; a thin dielectric).
    pub fn can_be_specular(&self) -> bool {
        let smooth = |r: &Roughness| {
            [&r.u, &r.v].iter().all(|t| match t {
                FloatTexture::Constant(x) => {
                    let alpha = if r.remap { x.max(0.0).sqrt() } else { *x };
                    alpha < 1e-3
                }
                _ => false,
            })
        };
        match self {
            Material::Conductor { roughness, .. }
            | Material::Dielectric { roughness, .. }
            | Material::CoatedDiffuse { roughness, .. } => smooth(roughness),
            Material::CoatedConductor(c) => smooth(&c.interface_roughness),
            Material::Mix(m) => m.materials().iter().any(Material::can_be_specular),
            Material::ThinDielectric { .. } => true,
            Material::ForceDiffuse(_) => false,
            Material::Bumped(bumped) => bumped.material.can_be_specular(),
            _ => false,
        }
    }

    /// Whether hits need a view-independent direction across the curve
    /// (`SurfaceInteraction::fibre_reference`): an elliptical fibre of the
    /// dual hair model is oriented by it.
    pub fn needs_fibre_frame(&self) -> bool {
        match self {
            Material::ForceDiffuse(inner) => return inner.needs_fibre_frame(),
            Material::Bumped(bumped) => return bumped.material.needs_fibre_frame(),
            _ => {}
        }
        matches!(self, Material::Hair { dual: Some((params, _)), .. } if params.ellipse.a != params.ellipse.b)
    }

    /// The material `entity` describes, its textures from `textures` and
    /// its files relative to `base_directory`; normal map images are
    /// shared through `normal_maps`.
    pub fn create(
        entity: &Entity,
        textures: &NamedTextures,
        base_directory: &Path,
        normal_maps: &mut NormalMapCache,
    ) -> Result<Material> {
        let tp = TextureParams {
            params: &entity.params,
            color_space: entity.color_space,
            textures,
            base_directory,
        };
        let p = &entity.params;
        let loc = &entity.location.0;
        // pbrt-v4 reads every material's normal map file, also where the
        // material then takes none.
        let normal_map = match p.string_at("normalmap")? {
            Some((name, at)) if !name.is_empty() => {
                Some(normal_maps.get(&pbrt_parser::resolve_path(base_directory, &name), &at)?)
            }
            _ => None,
        };
        p.string("type", "")?;
        let m = match entity.kind.as_str() {
            "interface" | "" | "none" => Material::Interface,
            "diffuse" => Material::Diffuse {
                reflectance: tp.spectrum_texture(
                    "reflectance",
                    Spectrum::Constant(0.5),
                    SpectrumKind::Albedo,
                )?,
            },
            "diffusetransmission" => Material::DiffuseTransmission {
                reflectance: tp.spectrum_texture(
                    "reflectance",
                    Spectrum::Constant(0.25),
                    SpectrumKind::Albedo,
                )?,
                transmittance: tp.spectrum_texture(
                    "transmittance",
                    Spectrum::Constant(0.25),
                    SpectrumKind::Albedo,
                )?,
                scale: p.float("scale", 1.0)? as f32,
            },
            "conductor" => {
                let reflectance = tp.spectrum_texture_opt("reflectance", SpectrumKind::Albedo)?;
                let eta = tp
                    .spectrum_texture_opt("eta", SpectrumKind::Unbounded)?
                    .or_else(|| named_spectrum("metal-Cu-eta").map(SpectrumTexture::Constant));
                let k = tp
                    .spectrum_texture_opt("k", SpectrumKind::Unbounded)?
                    .or_else(|| named_spectrum("metal-Cu-k").map(SpectrumTexture::Constant));
                let (Some(eta), Some(k)) = (eta, k) else {
                    return scene_error("conductor: the default copper spectra are not available; give \"eta\" and \"k\" or \"reflectance\"", loc);
                };
                Material::Conductor {
                    eta,
                    k,
                    reflectance,
                    roughness: Roughness::read(&tp, "", 0.0)?,
                }
            }
            "dielectric" => Material::Dielectric {
                eta: eta_param(&tp, "eta")?,
                roughness: Roughness::read(&tp, "", 0.0)?,
            },
            "thindielectric" => Material::ThinDielectric {
                eta: eta_param(&tp, "eta")?,
            },
            "coateddiffuse" => Material::CoatedDiffuse {
                reflectance: tp.spectrum_texture(
                    "reflectance",
                    Spectrum::Constant(0.5),
                    SpectrumKind::Albedo,
                )?,
                albedo: tp.spectrum_texture(
                    "albedo",
                    Spectrum::Constant(0.0),
                    SpectrumKind::Albedo,
                )?,
                roughness: Roughness::read(&tp, "", 0.0)?,
                thickness: tp.float_texture("thickness", 0.01)?,
                g: tp.float_texture("g", 0.0)?,
                eta: eta_param(&tp, "eta")?,
                max_depth: p.int("maxdepth", 10)?.max(1) as u32,
                n_samples: p.int("nsamples", 1)?.max(1) as u32,
            },
            "coatedconductor" => {
                let reflectance = tp.spectrum_texture_opt("reflectance", SpectrumKind::Albedo)?;
                let eta = tp.spectrum_texture_opt("conductor.eta", SpectrumKind::Unbounded)?;
                let k = tp.spectrum_texture_opt("conductor.k", SpectrumKind::Unbounded)?;
                if reflectance.is_some() && (eta.is_some() || k.is_some()) {
                    return scene_error("coatedconductor: \"reflectance\" cannot be given with \"conductor.eta\" or \"conductor.k\"", loc);
                }
                let eta =
                    eta.or_else(|| named_spectrum("metal-Cu-eta").map(SpectrumTexture::Constant));
                let k = k.or_else(|| named_spectrum("metal-Cu-k").map(SpectrumTexture::Constant));
                let (Some(conductor_eta), Some(conductor_k)) = (eta, k) else {
                    return scene_error("coatedconductor: the default copper spectra are not available; give \"conductor.eta\" and \"conductor.k\" or \"reflectance\"", loc);
                };
                Material::CoatedConductor(Box::new(CoatedConductor {
                    interface_roughness: Roughness::read(&tp, "interface.", 0.0)?,
                    interface_eta: eta_param(&tp, "interface.eta")?,
                    thickness: tp.float_texture("thickness", 0.01)?,
                    conductor_eta,
                    conductor_k,
                    reflectance,
                    conductor_roughness: Roughness::read(&tp, "conductor.", 0.0)?,
                    albedo: tp.spectrum_texture(
                        "albedo",
                        Spectrum::Constant(0.0),
                        SpectrumKind::Albedo,
                    )?,
                    g: tp.float_texture("g", 0.0)?,
                    max_depth: p.int("maxdepth", 10)?.max(1) as u32,
                    n_samples: p.int("nsamples", 1)?.max(1) as u32,
                }))
            }
            "mix" => Material::Mix(Box::new(mix::MixMaterial::create(&tp, loc)?)),
            "measured" => Material::Measured(measured::MeasuredMaterial::create(&tp, loc)?),
            "hair" => {
                let sigma_a = tp.spectrum_texture_opt("sigma_a", SpectrumKind::Unbounded)?;
                let reflectance = tp.spectrum_texture_opt("reflectance", SpectrumKind::Albedo)?;
                let mut eumelanin = tp.float_texture_opt("eumelanin")?;
                let pheomelanin = tp.float_texture_opt("pheomelanin")?;
                if sigma_a.is_none()
                    && reflectance.is_none()
                    && eumelanin.is_none()
                    && pheomelanin.is_none()
                {
                    eumelanin = Some(FloatTexture::Constant(1.3));
                }
                // Constant melanin concentrations: σ_a's spectrum is made
                // here once instead of at every hit (the same values).
                let concentration = |t: &Option<FloatTexture>| match t {
                    None => Some(0.0),
                    Some(FloatTexture::Constant(c)) => Some(c.max(0.0)),
                    Some(_) => None,
                };
                let sigma_a = match (
                    sigma_a,
                    &reflectance,
                    concentration(&eumelanin),
                    concentration(&pheomelanin),
                ) {
                    (None, None, Some(ce), Some(cp)) => {
                        Some(SpectrumTexture::Constant(melanin_sigma_a(ce, cp)))
                    }
                    (sigma_a, ..) => sigma_a,
                };
                let beta_m = tp.float_texture("beta_m", 0.3)?;
                let beta_n = tp.float_texture("beta_n", 0.3)?;
                let alpha = tp.float_texture("alpha", 2.0)?;
                let lobes = match (&beta_m, &beta_n, &alpha) {
                    (
                        FloatTexture::Constant(bm),
                        FloatTexture::Constant(bn),
                        FloatTexture::Constant(a),
                    ) => Some(HairLobes::new(bm.clamp(0.01, 1.0), bn.clamp(0.01, 1.0), *a)),
                    _ => None,
                };
                Material::Hair {
                    sigma_a,
                    reflectance,
                    eumelanin,
                    pheomelanin,
                    eta: tp.float_texture("eta", 1.55)?,
                    beta_m,
                    beta_n,
                    alpha,
                    lobes,
                    dual: dual_hair::read(p)?,
                    axis_frame: dual_hair::read_axis_frame(p)?,
                }
            }
            other => return scene_error(format!("material \"{other}\" is not supported yet"), loc),
        };
        let takes_maps = !matches!(
            m,
            Material::Interface | Material::Hair { .. } | Material::Mix(_)
        );
        let m = if takes_maps {
            let displacement = tp.float_texture_opt("displacement")?;
            match ShadingNormal::choose(normal_map, displacement) {
                Some(shading_normal) => Material::Bumped(Box::new(Bumped {
                    shading_normal,
                    material: m,
                })),
                None => m,
            }
        } else {
            m
        };
        p.report_unused(|| format!("material \"{}\"", entity.kind))?;
        Ok(m)
    }

    /// The material under pbrt-v4's `Option "forcediffuse"`: wrapped in
    /// [`Material::ForceDiffuse`], except `interface` (no BSDF to replace).
    pub fn forced_diffuse(self) -> Material {
        match self {
            Material::Interface | Material::ForceDiffuse(_) => self,
            other => Material::ForceDiffuse(Box::new(other)),
        }
    }

    /// The BSDF at `si`, its textures evaluated in `ctx` (which carries
    /// the hit's screen-space differentials); `None` for `interface` (the
    /// ray continues). Dispersive materials terminate the secondary
    /// wavelengths. A bump or normal map changes the shading geometry of
    /// `si` first (as pbrt-v4 does), so the caller sees the mapped normal.
    pub fn bsdf(
        &self,
        si: &mut SurfaceInteraction,
        ctx: &TextureEvalContext,
        lambda: &mut SampledWavelengths,
    ) -> Option<BSDF> {
        let clamp01 = |s: SampledSpectrum| s.map(|v| v.clamp(0.0, 1.0));
        let bxdf = match self {
            Material::Interface => return None,
            Material::Mix(m) => return m.choose(si, ctx).bsdf(si, ctx, lambda),
            Material::Bumped(bumped) => {
                bumped.shading_normal.apply(si, ctx);
                return bumped.material.bsdf(si, ctx, lambda);
            }
            Material::CoatedConductor(c) => {
                // As pbrt-v4: the conductor's η and k relative to the
                // coating's η (an η of 0 read as 1).
                let mut ieta = eval_eta(&c.interface_eta, lambda);
                if ieta == 0.0 {
                    ieta = 1.0;
                }
                let (ce, ck) = conductor_eta_k(
                    &c.conductor_eta,
                    &c.conductor_k,
                    &c.reflectance,
                    ctx,
                    lambda,
                );
                BxDF::CoatedConductor(CoatedConductorBxDF::new(
                    DielectricBxDF::new(ieta, c.interface_roughness.distribution(ctx)),
                    ConductorBxDF::new(
                        c.conductor_roughness.distribution(ctx),
                        ce / ieta,
                        ck / ieta,
                    ),
                    c.thickness.evaluate(ctx).max(f32::MIN_POSITIVE),
                    clamp01(c.albedo.evaluate(ctx, lambda)),
                    c.g.evaluate(ctx).clamp(-1.0, 1.0),
                    c.max_depth,
                    c.n_samples,
                ))
            }
            Material::ForceDiffuse(inner) => {
                let bsdf = inner.bsdf(si, ctx, lambda)?;
                return Some(force_diffuse::diffuse_equivalent(&bsdf, si, lambda));
            }
            Material::Measured(m) => m.bxdf(lambda),
            Material::Diffuse { reflectance } => {
                BxDF::Diffuse(DiffuseBxDF::new(clamp01(reflectance.evaluate(ctx, lambda))))
            }
            Material::DiffuseTransmission {
                reflectance,
                transmittance,
                scale,
            } => BxDF::DiffuseTransmission(DiffuseTransmissionBxDF::new(
                clamp01(reflectance.evaluate(ctx, lambda) * *scale),
                clamp01(transmittance.evaluate(ctx, lambda) * *scale),
            )),
            Material::Conductor {
                eta,
                k,
                reflectance,
                roughness,
            } => {
                let distrib = roughness.distribution(ctx);
                let (etas, ks) = conductor_eta_k(eta, k, reflectance, ctx, lambda);
                BxDF::Conductor(ConductorBxDF::new(distrib, etas, ks))
            }
            Material::Dielectric { eta, roughness } => {
                let e = eval_eta(eta, lambda);
                BxDF::Dielectric(DielectricBxDF::new(e, roughness.distribution(ctx)))
            }
            Material::ThinDielectric { eta } => {
                BxDF::ThinDielectric(ThinDielectricBxDF::new(eval_eta(eta, lambda)))
            }
            Material::Hair {
                sigma_a,
                reflectance,
                eumelanin,
                pheomelanin,
                eta,
                beta_m,
                beta_n,
                alpha,
                lobes,
                dual,
                ..
            } => {
                let bn = beta_n.evaluate(ctx).clamp(0.01, 1.0);
                // Precedence as pbrt-v4: σa, then reflectance, then melanin.
                let sig_a = if let Some(s) = sigma_a {
                    s.evaluate(ctx, lambda).clamp_zero()
                } else if let Some(r) = reflectance {
                    HairBxDF::sigma_a_from_reflectance(clamp01(r.evaluate(ctx, lambda)), bn)
                } else {
                    let ce = eumelanin.as_ref().map_or(0.0, |t| t.evaluate(ctx)).max(0.0);
                    let cp = pheomelanin
                        .as_ref()
                        .map_or(0.0, |t| t.evaluate(ctx))
                        .max(0.0);
                    melanin_sigma_a(ce, cp).sample(lambda)
                };
                let h = -1.0 + 2.0 * si.uv.y;
                let lobes = lobes.unwrap_or_else(|| {
                    let bm = beta_m.evaluate(ctx).clamp(0.01, 1.0);
                    HairLobes::new(bm, bn, alpha.evaluate(ctx))
                });
                let base = HairBxDF::from_lobes(h, eta.evaluate(ctx), sig_a, &lobes);
                let circular = CircularHairBxDF::new(base);
                // The BSDF's own frame, for ω_o in local space: both models
                // compute what depends on ω_o alone once, here.
                let frame = BSDF::frame(si.shading.n, si.shading.dpdu);
                let wo = frame.to_local(si.wo);
                match dual {
                    None => BxDF::Hair(circular.with_outgoing(wo)),
                    Some((params, orientation)) => {
                        // The major axis from the strand's stable reference
                        // (the shading normal where a shape has none), in
                        // the local frame's azimuth φ = atan2(z, y).
                        let r = frame.to_local(si.fibre_reference);
                        BxDF::DualHair(
                            DualHairBxDF::new(
                                base,
                                *params,
                                axis_from_reference(r.y, r.z, *orientation),
                                lambda.lambda,
                            )
                            .with_outgoing(wo),
                        )
                    }
                }
            }
            Material::CoatedDiffuse {
                reflectance,
                albedo,
                roughness,
                thickness,
                g,
                eta,
                max_depth,
                n_samples,
            } => {
                let e = eval_eta(eta, lambda);
                BxDF::CoatedDiffuse(CoatedDiffuseBxDF::new(
                    DielectricBxDF::new(e, roughness.distribution(ctx)),
                    DiffuseBxDF::new(clamp01(reflectance.evaluate(ctx, lambda))),
                    thickness.evaluate(ctx).max(f32::MIN_POSITIVE),
                    clamp01(albedo.evaluate(ctx, lambda)),
                    g.evaluate(ctx),
                    *max_depth,
                    *n_samples,
                ))
            }
        };
        Some(BSDF::new(si.shading.n, si.shading.dpdu, bxdf))
    }
}

/// η at the path's first wavelength; a wavelength-dependent η terminates
/// the others (they would refract elsewhere).
fn eval_eta(eta: &Eta, lambda: &mut SampledWavelengths) -> f32 {
    match eta {
        Eta::Constant(e) => *e,
        Eta::Spectrum(s) => {
            let e = s.eval(lambda.lambda[0]);
            lambda.terminate_secondary();
            e
        }
    }
}
