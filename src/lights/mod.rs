//! Lights: emitters sampled for direct lighting and hit by escaping or
//! surface-bound rays.

pub mod bvh_sampler;
pub mod create;
pub mod diffuse_area;
pub mod distant;
pub mod emission;
pub mod goniometric;
pub mod image_infinite;
pub mod light_bounds;
pub mod point;
pub mod portal_infinite;
pub mod projection;
pub mod sampler;
pub mod spot;
pub mod uniform_infinite;

pub use create::{create_area_light, create_light, AreaLightAlpha, AreaLightTemplate};
pub use diffuse_area::DiffuseAreaLight;
pub use distant::DistantLight;
pub use goniometric::GoniometricLight;
pub use image_infinite::ImageInfiniteLight;
pub use point::PointLight;
pub use portal_infinite::PortalInfiniteLight;
pub use projection::ProjectionLight;
pub use sampler::LightSampler;
pub use spot::SpotLight;
pub use uniform_infinite::UniformInfiniteLight;

use crate::math::Ray;
use crate::shapes::ShapeStorage;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// The point being lit.
#[derive(Clone, Copy, Debug)]
pub struct LightSampleContext {
    pub p: Vec3,
    pub p_error: Vec3,
    /// Geometric and shading normals (zero for points in media).
    pub n: Vec3,
    pub ns: Vec3,
    pub time: f32,
}

/// A sampled direction towards a light.
#[derive(Clone, Copy)]
pub struct LightLiSample<'a> {
    /// Incident radiance along −wi.
    pub l: Radiance<'a>,
    pub wi: Vec3,
    /// Solid-angle density (1 for delta lights).
    pub pdf: f32,
    /// The point on the light (for the shadow ray), with its normal.
    pub p_light: Vec3,
    pub p_light_error: Vec3,
    pub n_light: Vec3,
}

/// [`LightLiSample`] towards a point source at `position` whose intensity
/// towards a direction ω (leaving the light) is `intensity(ω)`: I(−ω_i)/d²
/// along the one direction ω_i, density 1; none at the light itself or
/// where it sends nothing. The spot, goniometric and projection lights
/// differ only in `intensity`.
pub(crate) fn sample_point_source<'a>(
    position: Vec3,
    ctx: &LightSampleContext,
    intensity: impl FnOnce(Vec3) -> SampledSpectrum,
) -> Option<LightLiSample<'a>> {
    let d = position - ctx.p;
    let dist2 = d.length_squared();
    if dist2 == 0.0 {
        return None;
    }
    let wi = d / dist2.sqrt();
    let l = intensity(-wi) / dist2;
    if l.is_zero() {
        return None;
    }
    Some(LightLiSample {
        l: Radiance::Value(l),
        wi,
        pdf: 1.0,
        p_light: position,
        p_light_error: Vec3::ZERO,
        n_light: Vec3::ZERO,
    })
}

/// A light sample's radiance: its value, or an environment map's texel to
/// read once it is needed. Most of a hair's shadow rays are blocked, and
/// the texel (a cache miss, and a spectrum to make) is wanted only for
/// those that are not.
#[derive(Clone, Copy)]
pub enum Radiance<'a> {
    Value(SampledSpectrum),
    Texel(&'a ImageInfiniteLight, u32),
}

impl Radiance<'_> {
    /// Zero for certain without reading a texel (a texel's radiance is
    /// known only once read).
    pub fn is_known_zero(&self) -> bool {
        matches!(self, Radiance::Value(l) if l.is_zero())
    }

    /// Starts loading what [`Radiance::value`] will read.
    #[inline]
    pub fn prefetch(&self) {
        if let Radiance::Texel(light, i) = self {
            light.prefetch_texel(*i as usize);
        }
    }

    pub fn value(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Radiance::Value(l) => *l,
            Radiance::Texel(light, i) => light.texel_le(*i as usize, lambda),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightKind {
    DeltaPosition,
    DeltaDirection,
    Area,
    Infinite,
}

pub enum Light {
    Point(PointLight),
    Spot(SpotLight),
    Goniometric(GoniometricLight),
    Projection(ProjectionLight),
    Distant(DistantLight),
    UniformInfinite(UniformInfiniteLight),
    ImageInfinite(ImageInfiniteLight),
    PortalInfinite(PortalInfiniteLight),
    DiffuseArea(DiffuseAreaLight),
}

impl Light {
    pub fn kind(&self) -> LightKind {
        match self {
            Light::Point(_) | Light::Spot(_) | Light::Goniometric(_) | Light::Projection(_) => {
                LightKind::DeltaPosition
            }
            Light::Distant(_) => LightKind::DeltaDirection,
            Light::UniformInfinite(_) | Light::ImageInfinite(_) | Light::PortalInfinite(_) => {
                LightKind::Infinite
            }
            Light::DiffuseArea(_) => LightKind::Area,
        }
    }

    /// Whether no ray can reach the light, so that light sampling alone
    /// finds it and its samples are not weighted against the BSDF's: delta
    /// lights, and invisible (alpha 0) area lights, which pbrt-v4 types as
    /// `DeltaPosition` for that reason.
    pub fn sampled_only(&self) -> bool {
        match self {
            Light::DiffuseArea(l) => l.invisible,
            _ => matches!(
                self.kind(),
                LightKind::DeltaPosition | LightKind::DeltaDirection
            ),
        }
    }

    /// Samples incident light at `ctx`. `allow_incomplete_pdf`: the caller
    /// also samples the BSDF with MIS, so a light may skip directions the
    /// BSDF covers (pbrt-v4: uniform infinite lights then return nothing).
    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
        shapes: &ShapeStorage,
        allow_incomplete_pdf: bool,
    ) -> Option<LightLiSample<'_>> {
        match self {
            Light::Point(l) => l.sample_li(ctx, lambda),
            Light::Spot(l) => l.sample_li(ctx, lambda),
            Light::Goniometric(l) => l.sample_li(ctx, lambda),
            Light::Projection(l) => l.sample_li(ctx, lambda),
            Light::Distant(l) => l.sample_li(ctx, lambda),
            Light::UniformInfinite(l) => l.sample_li(ctx, u, lambda, allow_incomplete_pdf),
            Light::ImageInfinite(l) => l.sample_li(ctx, u, allow_incomplete_pdf),
            Light::PortalInfinite(l) => l.sample_li(ctx, u, lambda),
            Light::DiffuseArea(l) => l.sample_li(ctx, u, lambda, shapes),
        }
    }

    /// Starts loading what `sample_li(_, u, _, _, allow_incomplete_pdf)`
    /// will read first where that is a large table (an image light's).
    #[inline]
    pub fn prefetch_sample(&self, u: Vec2, allow_incomplete_pdf: bool) {
        if let Light::ImageInfinite(l) = self {
            l.prefetch_sample(u, allow_incomplete_pdf);
        }
    }

    /// Solid-angle density with which `sample_li` picks `wi`.
    pub fn pdf_li(
        &self,
        ctx: &LightSampleContext,
        wi: Vec3,
        shapes: &ShapeStorage,
        allow_incomplete_pdf: bool,
    ) -> f32 {
        match self {
            Light::Point(_)
            | Light::Spot(_)
            | Light::Goniometric(_)
            | Light::Projection(_)
            | Light::Distant(_) => 0.0,
            Light::UniformInfinite(l) => l.pdf_li(allow_incomplete_pdf),
            Light::ImageInfinite(l) => l.pdf_li(wi, allow_incomplete_pdf),
            Light::PortalInfinite(l) => l.pdf_li(ctx, wi),
            Light::DiffuseArea(l) => l.pdf_li(ctx, wi, shapes),
        }
    }

    /// Radiance arriving along a ray that escapes the scene.
    pub fn le(&self, ray: &Ray, lambda: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Light::UniformInfinite(l) => l.le(lambda),
            Light::ImageInfinite(l) => l.le(ray.direction, lambda),
            Light::PortalInfinite(l) => l.le(ray, lambda),
            _ => SampledSpectrum::ZERO,
        }
    }

    /// Total emitted power (for the power light sampler).
    pub fn phi(&self, lambda: &SampledWavelengths, shapes: &ShapeStorage) -> SampledSpectrum {
        match self {
            Light::Point(l) => l.phi(lambda),
            Light::Spot(l) => l.phi(lambda),
            Light::Goniometric(l) => l.phi(lambda),
            Light::Projection(l) => l.phi(lambda),
            Light::Distant(l) => l.phi(lambda),
            Light::UniformInfinite(l) => l.phi(lambda),
            Light::ImageInfinite(l) => l.phi(lambda),
            Light::PortalInfinite(l) => l.phi(lambda),
            Light::DiffuseArea(l) => l.phi(lambda, shapes),
        }
    }

    /// Lets lights that depend on the scene's size (distant, infinite)
    /// know it.
    pub fn preprocess(&mut self, scene_center: Vec3, scene_radius: f32) {
        match self {
            Light::Distant(l) => l.preprocess(scene_center, scene_radius),
            Light::UniformInfinite(l) => l.preprocess(scene_center, scene_radius),
            Light::ImageInfinite(l) => l.preprocess(scene_center, scene_radius),
            Light::PortalInfinite(l) => l.preprocess(scene_center, scene_radius),
            _ => {}
        }
    }
}
