//! pbrt-v4's `simplepath` integrator: a path tracer without multiple
//! importance sampling or Russian roulette. At each surface it may sample
//! one light, chosen uniformly (`samplelights`), and continue by sampling
//! the BSDF (`samplebsdf`) or else by a uniform direction on the side(s)
//! the BSDF scatters to. Emission found by the path counts only where no
//! light sample could have found it (the camera ray, a specular bounce, or
//! with `samplelights` off).
//!
//! | Parameter | Type | Default | Meaning |
//! |---|---|---|---|
//! | `maxdepth` | integer | 5 | Most scattering events along a path |
//! | `samplelights` | bool | true | Sample a light at each non-specular surface |
//! | `samplebsdf` | bool | true | Continue by the BSDF's samples (else uniform directions) |

use super::ray_counts::RayCounts;
use super::surface_hit::{emitted, texture_context};
use crate::bxdfs::{BxDFReflTransFlags, TransportMode};
use crate::cameras::CameraRay;
use crate::lights::LightSampleContext;
use crate::math::sampling::{
    sample_uniform_hemisphere, sample_uniform_sphere, UNIFORM_HEMISPHERE_PDF, UNIFORM_SPHERE_PDF,
};
use crate::samplers::Sampler;
use crate::scene::build::{BuiltScene, SimplePathSettings};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Radiance along the camera ray by pbrt-v4's simple path tracer.
pub fn simple_path_li(
    scene: &BuiltScene,
    settings: &SimplePathSettings,
    camera_ray: &CameraRay,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
) -> SampledSpectrum {
    let max_depth = scene.integrator.max_depth;
    let mut ray = camera_ray.ray;
    let mut l = SampledSpectrum::ZERO;
    let mut beta = SampledSpectrum::ONE;
    // The camera ray counts as specular: what it sees directly is counted.
    let mut specular_bounce = true;
    let mut depth = 0;
    let mut from_camera = true;
    while !beta.is_zero() {
        rays.closest_hit += 1;
        let count_emission = !settings.sample_lights || specular_bounce;
        let Some((mut si, prim)) = scene.intersect(&ray, f32::INFINITY) else {
            if count_emission {
                for &i in &scene.infinite_lights {
                    l += beta * scene.lights[i].le(&ray, lambda);
                }
            }
            break;
        };
        si.wo = -ray.direction.normalize();
        if count_emission {
            l += beta * emitted(scene, prim, &si, lambda);
        }
        if depth == max_depth {
            break;
        }
        depth += 1;
        let ctx = texture_context(scene, camera_ray, &si, from_camera);
        let Some(bsdf) = scene.materials[prim.material as usize].bsdf(&mut si, &ctx, lambda) else {
            // An interface: on through it, as after a specular bounce (it
            // counts towards the depth, as in pbrt-v4's simple tracer).
            specular_bounce = true;
            ray = si.spawn_ray(ray.direction);
            continue;
        };
        from_camera = false;
        let wo = si.wo;
        let through = bsdf.diffracting_ring().is_some();
        if settings.sample_lights {
            let light_ctx = LightSampleContext {
                p: si.p,
                p_error: si.p_error,
                n: si.n,
                ns: si.shading.n,
                time: si.time,
            };
            if let Some((i, p_light)) = scene.light_sampler.sample(&light_ctx, sampler.get_1d()) {
                let u_light = sampler.get_2d();
                let light = &scene.lights[i];
                if let Some(ls) = light.sample_li(&light_ctx, u_light, lambda, &scene.shapes, false)
                {
                    let le = ls.l.value(lambda);
                    if le.is_nonzero() && ls.pdf > 0.0 {
                        let f = bsdf.f(wo, ls.wi, TransportMode::Radiance)
                            * ls.wi.dot(si.shading.n).abs();
                        if f.is_nonzero() {
                            rays.shadow += 1;
                            if scene.unoccluded(
                                &si,
                                through,
                                ls.p_light,
                                ls.p_light_error,
                                ls.n_light,
                            ) {
                                l += beta * f * le / (p_light * ls.pdf);
                            }
                        }
                    }
                }
            }
        }
        let wi = if settings.sample_bsdf {
            let u = sampler.get_1d();
            let Some(bs) = bsdf.sample_f(
                wo,
                u,
                sampler.get_2d(),
                TransportMode::Radiance,
                BxDFReflTransFlags::All,
            ) else {
                break;
            };
            beta *= bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
            specular_bounce = bs.is_specular();
            bs.wi
        } else {
            // A uniform direction on the side(s) the BSDF scatters to: one
            // on the render-space +z hemisphere, turned to the right side
            // (either of ±ω is on it), as pbrt-v4 draws it.
            let flags = bsdf.flags();
            let u = sampler.get_2d();
            let (wi, pdf) = if flags.is_reflective() && flags.is_transmissive() {
                (sample_uniform_sphere(u), UNIFORM_SPHERE_PDF)
            } else {
                let mut wi = sample_uniform_hemisphere(u);
                let side = wo.dot(si.n) * wi.dot(si.n);
                if (flags.is_reflective() && side < 0.0) || (flags.is_transmissive() && side > 0.0)
                {
                    wi = -wi;
                }
                (wi, UNIFORM_HEMISPHERE_PDF)
            };
            beta *= bsdf.f(wo, wi, TransportMode::Radiance) * (wi.dot(si.shading.n).abs() / pdf);
            specular_bounce = false;
            wi
        };
        ray = if through {
            si.spawn_ray_through(wi)
        } else {
            si.spawn_ray(wi)
        };
    }
    l
}
