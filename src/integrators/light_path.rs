//! pbrt-v4's `lightpath` integrator: paths traced from the lights only.
//! Each pixel sample starts a path at a light (chosen by power), and every
//! surface it reaches is joined to a point on the camera's lens; what
//! arrives is splatted onto the film where that ray lands
//! ([`crate::film::splat`]). Light seen directly is joined from the point
//! on the light. Point and diffuse area lights and the perspective camera.
//!
//! | Parameter | Type | Default | Meaning |
//! |---|---|---|---|
//! | `maxdepth` | integer | 5 | Most scattering events along a path |

use super::ray_counts::RayCounts;
use crate::bxdfs::{BxDFReflTransFlags, TransportMode};
use crate::cameras::importance::SampleBounds;
use crate::film::splat::SplatBuffer;
use crate::interaction::SurfaceInteraction;
use crate::lights::LightSampleContext;
use crate::samplers::Sampler;
use crate::scene::build::BuiltScene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::textures::TextureEvalContext;
use glam::{Vec2, Vec3};

/// The raster region splats may land in: the pixel bounds widened by the
/// filter's reach, as pbrt-v4's film sample bounds.
pub fn sample_bounds(scene: &BuiltScene) -> SampleBounds {
    let (lo, hi) = scene.film.pixel_bounds;
    let r = scene.filter.radius() - Vec2::splat(0.5);
    (lo.as_vec2() - r, hi.as_vec2() + r)
}

/// Traces one light path at wavelengths `lambda` and splats what reaches
/// the camera.
pub fn trace_light_path(
    scene: &BuiltScene,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    splats: &SplatBuffer,
    rays: &mut RayCounts,
) {
    let Some(camera) = scene.camera.as_perspective() else {
        return;
    };
    let bounds = sample_bounds(scene);
    let splat = |p: Vec2, l: SampledSpectrum, lambda: &SampledWavelengths| {
        if l.has_nan() || l.0.iter().any(|v| v.is_infinite()) {
            return;
        }
        splats.add(p, scene.film.sensor_rgb(l, lambda), &scene.filter);
    };
    let anywhere = LightSampleContext {
        p: Vec3::ZERO,
        p_error: Vec3::ZERO,
        n: Vec3::ZERO,
        ns: Vec3::ZERO,
        time: 0.5,
    };
    let Some((light_index, p_light)) = scene.light_sampler.sample(&anywhere, sampler.get_1d())
    else {
        return;
    };
    let light = &scene.lights[light_index];
    // The time: without motion it changes nothing, but its number is drawn.
    sampler.skip(1);
    let (u_pos, u_dir) = (sampler.get_2d(), sampler.get_2d());
    let Some(les) = light.sample_le(u_pos, u_dir, lambda, &scene.shapes) else {
        return;
    };
    if les.pdf_pos == 0.0 || les.pdf_dir == 0.0 || les.l.is_zero() {
        return;
    }
    let cos_light = |w: Vec3| {
        if les.n == Vec3::ZERO {
            1.0
        } else {
            les.n.dot(w).abs()
        }
    };
    // The light seen directly, from the sampled point on it (area lights).
    if les.n != Vec3::ZERO {
        if let Some(cs) = camera.sample_wi(les.p, sampler.get_2d(), bounds) {
            let le = match light {
                crate::lights::Light::DiffuseArea(area) => {
                    area.l(les.p, les.n, les.uv, cs.wi, lambda)
                }
                _ => SampledSpectrum::ZERO,
            };
            if le.is_nonzero() && cs.pdf > 0.0 {
                let from = SurfaceInteraction {
                    p: les.p,
                    p_error: les.p_error,
                    n: les.n,
                    ..Default::default()
                };
                rays.shadow += 1;
                if scene.unoccluded(&from, false, cs.p_lens, Vec3::ZERO, Vec3::ZERO) {
                    let l = le * (cs.we * cos_light(cs.wi) / (p_light * les.pdf_pos * cs.pdf));
                    splat(cs.p_raster, l, lambda);
                }
            }
        }
    }
    let mut beta = les.l * (cos_light(les.dir) / (p_light * les.pdf_pos * les.pdf_dir));
    let from = SurfaceInteraction {
        p: les.p,
        p_error: les.p_error,
        n: les.n,
        ..Default::default()
    };
    let mut ray = if les.n == Vec3::ZERO {
        crate::math::Ray::new(les.p, les.dir, 0.5)
    } else {
        from.spawn_ray(les.dir)
    };
    let mut depth = 0;
    while depth < scene.integrator.max_depth && beta.is_nonzero() {
        rays.closest_hit += 1;
        let Some((mut si, prim)) = scene.intersect(&ray, f32::INFINITY) else {
            break;
        };
        si.wo = -ray.direction.normalize();
        let ctx = TextureEvalContext::at(&si);
        let Some(bsdf) = scene.materials[prim.material as usize].bsdf(&mut si, &ctx, lambda) else {
            // An interface: on through it, not counted as a bounce.
            ray = si.spawn_ray(ray.direction);
            continue;
        };
        let through = bsdf.diffracting_ring().is_some();
        // Join this vertex to the lens.
        if let Some(cs) = camera.sample_wi(si.p, sampler.get_2d(), bounds) {
            if cs.pdf > 0.0 {
                let f = bsdf.f(si.wo, cs.wi, TransportMode::Importance);
                let l = beta * f * (cs.wi.dot(si.shading.n).abs() * cs.we / cs.pdf);
                if l.is_nonzero() {
                    rays.shadow += 1;
                    if scene.unoccluded(&si, through, cs.p_lens, Vec3::ZERO, Vec3::ZERO) {
                        splat(cs.p_raster, l, lambda);
                    }
                }
            }
        }
        let u = sampler.get_1d();
        let Some(bs) = bsdf.sample_f(
            si.wo,
            u,
            sampler.get_2d(),
            TransportMode::Importance,
            BxDFReflTransFlags::All,
        ) else {
            break;
        };
        beta *= bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
        ray = if through {
            si.spawn_ray_through(bs.wi)
        } else {
            si.spawn_ray(bs.wi)
        };
        depth += 1;
    }
}
