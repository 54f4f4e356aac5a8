//! Diffuse area light: a shape that emits uniformly (`AreaLightSource
//! "diffuse"`).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `L` | spectrum | colour space illuminant | emitted radiance |
//! | `scale` | float | 1 | scale |
//! | `twosided` | bool | false | emit from both sides |
//! | `power` | float | — | if given: total power in W (photometric) |
//! | `filename` | string | — | image of emitted radiance over (u, v): not supported yet |

use super::{LightLiSample, LightSampleContext, Radiance};
use crate::shapes::{Shape, ShapeSampleContext, ShapeStorage};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

pub struct DiffuseAreaLight {
    /// The emitting shape.
    pub shape: Shape,
    pub radiance: Spectrum,
    pub scale: f32,
    pub two_sided: bool,
    pub area: f32,
}

/// The same point, as the shapes' sampling takes it.
fn shape_context(ctx: &LightSampleContext) -> ShapeSampleContext {
    ShapeSampleContext {
        p: ctx.p,
        p_error: ctx.p_error,
        n: ctx.n,
        ns: ctx.ns,
        time: ctx.time,
    }
}

impl DiffuseAreaLight {
    /// Radiance leaving the surface at a point with normal `n` in
    /// direction `w`.
    pub fn l(&self, n: Vec3, w: Vec3, lambda: &SampledWavelengths) -> SampledSpectrum {
        if !self.two_sided && n.dot(w) < 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.radiance.sample(lambda) * self.scale
    }

    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
        shapes: &ShapeStorage,
    ) -> Option<LightLiSample<'_>> {
        let shape_ctx = shape_context(ctx);
        let ss = self.shape.sample_from(shapes, &shape_ctx, u)?;
        if ss.pdf == 0.0 || (ss.p - ctx.p).length_squared() == 0.0 {
            return None;
        }
        let wi = (ss.p - ctx.p).normalize();
        let l = self.l(ss.n, -wi, lambda);
        if l.is_zero() {
            return None;
        }
        Some(LightLiSample {
            l: Radiance::Value(l),
            wi,
            pdf: ss.pdf,
            p_light: ss.p,
            p_light_error: ss.p_error,
            n_light: ss.n,
        })
    }

    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, shapes: &ShapeStorage) -> f32 {
        let shape_ctx = shape_context(ctx);
        self.shape.pdf_from(shapes, &shape_ctx, wi)
    }

    pub fn phi(&self, lambda: &SampledWavelengths, _shapes: &ShapeStorage) -> SampledSpectrum {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        self.radiance.sample(lambda) * (PI * sides * self.area * self.scale)
    }
}
