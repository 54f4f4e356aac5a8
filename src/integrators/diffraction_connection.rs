//! Direct light through the dual hair model's diffracting ring, connected
//! explicitly (docs/dual-model.md, "Light through the ring").
//!
//! The ring's lobe is M_diff(θ_i, θ_o) N_diff(φ_i − φ_o − π) with N_diff a
//! fraction of a degree wide: in azimuth the ring lets light straight on.
//! Sampled at a surface behind the ring, that light comes only from the
//! rare direction that meets the ring at the one azimuth the lobe accepts
//! (fireflies), and under a delta light never. Here N_diff is taken in its
//! limit δ(φ_i − φ_o − π) and the path x → y (ring) → z (light) is built
//! from the light sample z that next-event estimation drew at x:
//!
//! 1. the shadow ray x → z meets a ring first, at y₀ with tangent t: x is
//!    in that fibre's ring shadow;
//! 2. every y on the (locally straight) fibre with x, y and z in the plane
//!    P spanned by (z − x) and t then satisfies the azimuthal δ: the
//!    direction ω₁ from x is drawn in P, its angle to the cross-section
//!    plane (θ_o at the ring) from M_diff(θ_L, ·) cos θ, θ_L the light's
//!    elevation seen from y₀;
//! 3. ω₁ is traced to the ring hit y₁ and y₁ is joined to z.
//!
//! The δ in azimuth leaves the Jacobian |∂Δφ/∂α|⁻¹ = d_L / (d_x + d_L)
//! (d_x, d_L the distances from x and z to y₁ projected on the fibre's
//! cross-section plane; 1 for a light at infinity), so the estimate is
//!
//!   f_x(ω₁) |cos| · M_diff(θ_L₁, θ_o₁) / M_diff(θ_L₀, θ_o₁) · J · L(z → y₁) / p_light.
//!
//! Paths from a non-specular vertex through one ring to a light are made
//! by this strategy alone; the path integrator drops the same paths when
//! its own samples make them (see `path_li`), except towards a light this
//! vertex cannot sample ([`ConnectionOrigin::covers`]).

use crate::bxdfs::hair::{sample_longitudinal, Longitudinal};
use crate::bxdfs::{TransportMode, BSDF};
use crate::interaction::SurfaceInteraction;
use crate::lights::{Light, LightKind, LightLiSample, LightSampleContext};
use crate::math::{safe_sqrt, sqr};
use crate::samplers::Sampler;
use crate::scene::build::BuiltScene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::textures::TextureEvalContext;
use glam::{Vec2, Vec3};

use super::ray_counts::RayCounts;

/// A non-specular vertex whose light samples are connected through rings:
/// the path integrator asks it, when the ring hit after it sends its own
/// sample to a light, whether the connection covers that light.
#[derive(Clone, Copy, Debug)]
pub struct ConnectionOrigin {
    /// Where its lights are sampled from.
    pub ctx: LightSampleContext,
}

impl ConnectionOrigin {
    /// Whether [`through_ring`] covers the light that reaches this vertex
    /// through one ring from light `light_index`, reached at `emitter` (an
    /// area light's point) or in direction `direction` (an infinite
    /// light): whenever the light can be sampled from here towards it.
    /// Where it cannot (an infinite light that BSDF sampling alone covers,
    /// as pbrt-v4's uniform one does) the path tracer's own sample counts.
    /// Whether the straight shadow ray would meet a ring is not asked: the
    /// finite lobe's paths land beside the limit's (by its width times the
    /// distance), and which of the two a path is would be a coin toss at
    /// every ring's edge; what the limit misses there is approximation 3
    /// of docs/dual-model.md.
    pub fn covers(
        &self,
        scene: &BuiltScene,
        light_index: usize,
        emitter: Option<&SurfaceInteraction>,
        direction: Vec3,
    ) -> bool {
        let toward = match emitter {
            Some(z) => (z.p - self.ctx.p).normalize_or_zero(),
            None => direction.normalize_or_zero(),
        };
        scene.light_sampler.pmf(&self.ctx, light_index) > 0.0
            && scene.lights[light_index].pdf_li(&self.ctx, toward, &scene.shapes, true) > 0.0
    }
}

/// The ring at a hit (its tangent and M_diff), if the hit lies in a
/// diffracting ring.
fn ring_at(
    scene: &BuiltScene,
    si: &SurfaceInteraction,
    lambda: &SampledWavelengths,
) -> Option<(Vec3, Longitudinal)> {
    let prim = &scene.primitives[si.primitive as usize];
    let material = &scene.materials[prim.material as usize];
    // Most blockers are not rings (a fibre's core, other surfaces): they
    // are told apart by h alone, before a BSDF (and the core's trace
    // through the ellipse) is made.
    let d_diff = material.dual_hair()?.d_diff;
    if d_diff <= 0.0 || (-1.0 + 2.0 * si.uv.y).abs() * (1.0 + d_diff) <= 1.0 {
        return None;
    }
    let mut lambda = *lambda;
    // A copy: the caller's hit keeps its shading geometry (a hair
    // material has no bump map to change it anyway).
    let mut si = *si;
    let ctx = TextureEvalContext::at(&si);
    material
        .bsdf(&mut si, &ctx, &mut lambda)?
        .diffracting_ring()
}

/// The part of `v` across the fibre of tangent `t`.
fn across(v: Vec3, t: Vec3) -> Vec3 {
    v - t * v.dot(t)
}

/// M_diff at the ring for light arriving along `to_light` and leaving
/// along `to_viewer` (both unit, render space).
fn m_diff(m: &Longitudinal, t: Vec3, to_light: Vec3, to_viewer: Vec3) -> f32 {
    let sin_i = to_light.dot(t).clamp(-1.0, 1.0);
    let sin_o = to_viewer.dot(t).clamp(-1.0, 1.0);
    m.eval(
        safe_sqrt(1.0 - sqr(sin_i)),
        safe_sqrt(1.0 - sqr(sin_o)),
        sin_i,
        sin_o,
    )
}

/// The light arriving at the ring hit `y` from the light sample `seed`
/// drawn at `ctx_x`: the incident radiance times solid angle per unit
/// sampling density (what `ls.l / ls.pdf` is at x), its direction, and the
/// light point's distance across the fibre (∞ for lights at infinity).
fn light_at_ring(
    scene: &BuiltScene,
    light: &Light,
    seed: &LightLiSample,
    ctx_x: &LightSampleContext,
    y: &SurfaceInteraction,
    u_light: Vec2,
    lambda: &SampledWavelengths,
) -> Option<(SampledSpectrum, Vec3, Vec3, bool)> {
    match light.kind() {
        // Deterministic: the same light point seen from y.
        LightKind::DeltaPosition | LightKind::DeltaDirection => {
            let ctx = LightSampleContext {
                p: y.p,
                p_error: Vec3::ZERO,
                n: y.n,
                ns: y.shading.n,
                time: y.time,
            };
            let ls = light.sample_li(&ctx, u_light, lambda, &scene.shapes, true)?;
            let at_infinity = light.kind() == LightKind::DeltaDirection;
            Some((ls.l.value(lambda), ls.wi, ls.p_light, at_infinity))
        }
        // The direction drawn at x, from y too.
        LightKind::Infinite => Some((seed.l.value(lambda) / seed.pdf, seed.wi, seed.p_light, true)),
        // The point z drawn at x: its density over area is the solid-angle
        // density times cos_z / r², and a diffuse emitter's radiance is the
        // same towards y (on the same side).
        LightKind::Area => {
            let (to_y, r_y) = (y.p - seed.p_light).normalize_and_length();
            let (to_x, r_x) = (ctx_x.p - seed.p_light).normalize_and_length();
            let (cos_y, cos_x) = (seed.n_light.dot(to_y), seed.n_light.dot(to_x));
            if cos_y * cos_x <= 0.0 || r_y <= 0.0 {
                return None;
            }
            // (cos_z,y / r_y²) / (cos_z,x / r_x²): area density to y's solid angle.
            let ratio = (cos_y / cos_x) * sqr(r_x / r_y);
            let wi = -to_y;
            Some((
                seed.l.value(lambda) * (ratio / seed.pdf),
                wi,
                seed.p_light,
                false,
            ))
        }
    }
}

/// Light from the sample `seed` (light `light` chosen with probability
/// `light_pmf`) reaching `x` through the diffracting ring hit `blocker`
/// that stops the shadow ray; `None` when `blocker` is not in a ring or
/// the connection carries nothing.
#[allow(clippy::too_many_arguments)]
pub fn through_ring(
    scene: &BuiltScene,
    x: &SurfaceInteraction,
    bsdf: &BSDF,
    ctx_x: &LightSampleContext,
    light: &Light,
    seed: &LightLiSample,
    light_pmf: f32,
    blocker: &SurfaceInteraction,
    u_light: Vec2,
    lambda: &SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
) -> Option<SampledSpectrum> {
    let (t0, m0) = ring_at(scene, blocker, lambda)?;
    // Drawn only at a ring, so a scene's other samples keep their numbers.
    let u = sampler.get_2d();
    // 1–2. ω₁ in the plane of the seed direction and the fibre, at an angle
    // θ_o from the cross-section plane drawn from M_diff(θ_L₀, θ_o) cos θ_o.
    let w_seed = seed.wi;
    let sin_l0 = w_seed.dot(t0).clamp(-1.0, 1.0);
    let toward = across(w_seed, t0).try_normalize()?;
    let (sin_o, cos_o) = sample_longitudinal(u, m0.v, sin_l0, safe_sqrt(1.0 - sqr(sin_l0)));
    // ω_o at the ring points back to x: (−toward) cos θ_o + t sin θ_o.
    let w1 = (toward * cos_o - t0 * sin_o).normalize();
    let density_m = m_diff(&m0, t0, w_seed, -w1);
    if density_m <= 0.0 {
        return None;
    }
    let f = bsdf.f(x.wo, w1, TransportMode::Radiance) * w1.dot(x.shading.n).abs();
    if f.is_zero() {
        return None;
    }
    // 3. The ring hit y₁ along ω₁, joined to the light.
    rays.closest_hit += 1;
    let (mut y, _) = scene.intersect(&x.spawn_ray(w1), f32::INFINITY)?;
    y.wo = -w1;
    let (t1, m1) = ring_at(scene, &y, lambda)?;
    let (l, w_light, p_light, at_infinity) =
        light_at_ring(scene, light, seed, ctx_x, &y, u_light, lambda)?;
    if l.is_zero() {
        return None;
    }
    let m = m_diff(&m1, t1, w_light, -w1);
    // J = d_L / (d_x + d_L) across the fibre (1 for a light at infinity).
    let jacobian = if at_infinity {
        1.0
    } else {
        let d_x = across(y.p - x.p, t1).length();
        let d_l = across(p_light - y.p, t1).length();
        if d_x + d_l <= 0.0 {
            return None;
        }
        d_l / (d_x + d_l)
    };
    rays.shadow += 1;
    let target = seed_point(&y, p_light, w_light, at_infinity);
    if !scene.unoccluded(&y, true, target, Vec3::ZERO, Vec3::ZERO) {
        return None;
    }
    let value = f * l * (m / (density_m * light_pmf) * jacobian);
    value.0.iter().all(|v| v.is_finite()).then_some(value)
}

/// Where the shadow ray from `y` ends: the light point, or for a light at
/// infinity far along its direction.
fn seed_point(y: &SurfaceInteraction, p_light: Vec3, w_light: Vec3, at_infinity: bool) -> Vec3 {
    if at_infinity {
        // As far as the light's own point, along the direction from y.
        y.p + w_light * (p_light - y.p).length().max(1.0)
    } else {
        p_light
    }
}
