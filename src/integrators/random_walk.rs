//! pbrt-v4's `randomwalk` integrator: a path that leaves each surface in a
//! direction drawn uniformly over the sphere, weighted by the BSDF; light
//! counts only where the path happens to reach an emitter. Unbiased but
//! noisy: a reference for the other integrators, not a practical one.
//!
//! | Parameter | Type | Default | Meaning |
//! |---|---|---|---|
//! | `maxdepth` | integer | 5 | Most scattering events along a path |

use super::ray_counts::RayCounts;
use super::surface_hit::{emitted, texture_context};
use crate::bxdfs::TransportMode;
use crate::cameras::CameraRay;
use crate::math::sampling::{sample_uniform_sphere, UNIFORM_SPHERE_PDF};
use crate::samplers::Sampler;
use crate::scene::build::BuiltScene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Radiance along the camera ray by a uniform random walk.
pub fn random_walk_li(
    scene: &BuiltScene,
    camera_ray: &CameraRay,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
) -> SampledSpectrum {
    let max_depth = scene.integrator.max_depth;
    let mut ray = camera_ray.ray;
    let mut l = SampledSpectrum::ZERO;
    let mut beta = SampledSpectrum::ONE;
    let mut depth = 0;
    let mut from_camera = true;
    loop {
        rays.closest_hit += 1;
        let Some((mut si, prim)) = scene.intersect(&ray, f32::INFINITY) else {
            for &i in &scene.infinite_lights {
                l += beta * scene.lights[i].le(&ray, lambda);
            }
            return l;
        };
        si.wo = -ray.direction.normalize();
        l += beta * emitted(scene, prim, &si, lambda);
        if depth == max_depth {
            return l;
        }
        let ctx = texture_context(scene, camera_ray, &si, from_camera);
        let Some(bsdf) = scene.materials[prim.material as usize].bsdf(&mut si, &ctx, lambda) else {
            // An interface: go on through it at the same depth.
            ray = si.spawn_ray(ray.direction);
            continue;
        };
        from_camera = false;
        let wi = sample_uniform_sphere(sampler.get_2d());
        let f_cos = bsdf.f(si.wo, wi, TransportMode::Radiance) * wi.dot(si.shading.n).abs();
        if f_cos.is_zero() {
            return l;
        }
        beta *= f_cos / UNIFORM_SPHERE_PDF;
        ray = if bsdf.diffracting_ring().is_some() {
            si.spawn_ray_through(wi)
        } else {
            si.spawn_ray(wi)
        };
        depth += 1;
    }
}
